"""Batches of designs: the method :meth:`loopkin.Mechanism.batch`, many
designs of one mechanism run in native code on every core."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, ClassVar, Dict, Iterable, List, Mapping, Optional, Tuple, Type, Union, cast

import numpy as np

from ._values import Options, Pose, _opts

if TYPE_CHECKING:  # pragma: no cover
    from . import _native
    from ._model import Mechanism

__all__: List[str] = []


class _Batch:
    """:meth:`batch`, mixed into :class:`loopkin.Mechanism`."""

    __slots__ = ()
    _m: "_native.Model"

    if TYPE_CHECKING:  # pragma: no cover
        _where: ClassVar[Dict[str, int]]
        _nd: ClassVar[int]

        @classmethod
        def parameter_names(cls) -> Tuple[str, ...]: ...

        @classmethod
        def driver_names(cls) -> Tuple[str, ...]: ...

        def pose(
            self, pose: Optional[Mapping[str, Union[float, str]]] = None, **values: Union[float, str]
        ) -> "Pose": ...

        def _driver_values(
            self,
            what: str,
            one: Optional[Union[float, str]],
            many: Optional[Mapping[str, Union[float, str]]],
            default: float,
        ) -> List[float]: ...

    def batch(
        self,
        params: Mapping[str, ArrayLike],
        *,
        start: Mapping[str, Union[float, str]],
        sweep: Optional[Mapping[str, Any]] = None,
        rate: Optional[Union[float, str]] = None,
        acceleration: Optional[Union[float, str]] = None,
        rates: Optional[Mapping[str, Union[float, str]]] = None,
        accelerations: Optional[Mapping[str, Union[float, str]]] = None,
        outputs: Optional[Iterable[str]] = None,
        options: Optional[Options] = None,
        reduce: Optional[str] = None,
        positions_only: bool = False,
    ) -> "Batch":
        """Runs many designs on every core, in native code with the
        interpreter released.

        ``params`` maps parameter names to arrays of one value per design
        (a parameter not given keeps this design's value). Each design is
        assembled at ``start`` and analysed (one sample), or swept when
        ``sweep`` is given: ``dict(driver="phi", turn=True, steps=360)``
        with the keys of :meth:`sweep` (``from_``, ``to``, ``turn``,
        ``turns``, ``steps``, ``rpm``, ``change_points``), the rate and
        acceleration of the driver from ``rate``/``rpm``, ``acceleration``.

        ``outputs`` names what to keep: a coordinate ("th3"), its rate
        ("th3.rate") or acceleration ("th3.acceleration"), a point's
        position ("P"), velocity ("P.velocity") or acceleration
        ("P.acceleration"), or "conditioning". By default every
        coordinate and every point's position.

        ``reduce`` keeps one value per design instead of every sample:
        ``"max"`` or ``"min"`` of each component over the samples, or
        ``"peak"``, the largest magnitude (the norm of a point's vector).

        ``positions_only=True`` assembles each sample and evaluates the
        points' positions alone, as :meth:`poses` does (no rates,
        accelerations or conditioning; a change point passed on the branch
        the closed forms carry, whatever ``change_points`` says; the rate
        not read): coupler curves for less than a step costs. The outputs
        are then coordinates and points' positions only.

        With several outputs, each array is a view of one block of the
        designs' records (not C-contiguous; ``np.ascontiguousarray`` copies
        one out).

        Returns a :class:`Batch` whose arrays have a row per design (and a
        column per sample of a sweep, unless reduced); a design that stops
        early has NaN past its last sample (its reduction is over the
        samples it has), and says why in :attr:`Batch.stops`.
        """
        names = self.parameter_names()
        arrays = {k: np.asarray(v, dtype=float).reshape(-1) for k, v in params.items()}
        for k in arrays:
            if k not in names:
                raise KeyError(f"{k!r} is not a parameter of {type(self).__name__}: they are {list(names)}")
        sizes = {a.size for a in arrays.values()}
        if len(sizes) > 1:
            raise ValueError(f"every parameter array must have one value per design; the sizes are {sorted(sizes)}")
        n = sizes.pop() if sizes else 1
        table = np.empty((n, len(names)))
        base = self._m.values
        for i, name in enumerate(names):
            table[:, i] = arrays[name] if name in arrays else base[i]
        spec = None
        # A mixin: the class of a design is a compiled Mechanism.
        kept = _outputs(cast("Type[Mechanism]", type(self)), outputs)
        rate_values = self._driver_values("rate", rate, rates, 0.0)
        if sweep is not None:
            s = dict(sweep)
            driver = s.pop("driver")
            if self._where.get(driver, self._nd) >= self._nd:
                raise KeyError(f"{driver!r} is not a driver of {type(self).__name__}")
            j = self.driver_names().index(driver)
            swept_rate, rpm = s.pop("rate", None), s.pop("rpm", None)
            if swept_rate is not None and rpm is not None:
                raise TypeError("give the sweep's rate or its rpm, not both")
            if rpm is not None:
                rate_values[j] = rpm * 2.0 * math.pi / 60.0
            elif swept_rate is not None:
                rate_values[j] = float(swept_rate)
            swept_acceleration = s.pop("acceleration", None)
            if swept_acceleration is not None:
                if acceleration is not None or accelerations is not None:
                    raise TypeError("give the driver's acceleration in the sweep or as an argument, not both")
                accelerations = {driver: float(swept_acceleration)}
            turns = s.pop("turns", None)
            if s.pop("turn", False) and turns is None:
                turns = 1.0
            spec = (
                driver,
                s.pop("from_", None),
                s.pop("to", None),
                turns,
                int(s.pop("steps", 360)),
                s.pop("change_points", "stop"),
            )
            if s:
                raise TypeError(f"unknown sweep key(s): {sorted(s)}")
        q = self.pose(start)
        d = self._m.batch(
            np.ascontiguousarray(table),
            q.array.tolist(),
            rate_values,
            self._driver_values("acceleration", acceleration, accelerations, 0.0),
            spec,
            [k for _, k in kept],
            _opts(options),
            reduce,
            bool(positions_only),
        )
        return Batch(table, names, [name for name, _ in kept], d)


# The array type of `_model`, defined before it imports this module; the
# result class and the outputs' parser of `_sweep`, which reads the
# classes `_model` imported before this module (so that the annotations
# resolve at run time too, for `typing.get_type_hints`).
from ._model import ArrayLike  # noqa: E402
from ._sweep import Batch, _outputs  # noqa: E402
