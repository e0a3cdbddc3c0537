"""Forward dynamics: the motion that the definition's ``bodies`` and
``loads`` produce, the method :meth:`loopkin.Mechanism.forward` and its
result, :class:`Trajectory`."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._values import Options, _opts

if TYPE_CHECKING:  # pragma: no cover
    from ._model import Pose
    from ._sweep import Sweep

__all__ = ["Trajectory"]


def _event_items(stop_when: Any) -> List[Tuple[Any, ...]]:
    """``stop_when`` as a list of (key, value[, direction]): a mapping's
    items (a value may be a (value, direction) pair), or a sequence of
    tuples as they are."""
    if stop_when is None:
        return []
    if isinstance(stop_when, Mapping):
        pair = (tuple, list)
        return [(k, *v) if isinstance(v, pair) else (k, v) for k, v in stop_when.items()]
    return [tuple(item) for item in stop_when]


def _seconds(value: Union[float, str]) -> float:
    """A time in seconds: a number, or a string ending in ``s`` or ``ms``."""
    if isinstance(value, str):
        text = value.strip()
        factor = 1.0
        if text.endswith("ms"):
            text, factor = text[:-2], 1e-3
        elif text.endswith("s"):
            text = text[:-1]
        try:
            return float(text) * factor
        except ValueError:
            raise ValueError(f"until={value!r}: give a time in seconds (3.0, '3s', '250ms')") from None
    return float(value)


class Trajectory:
    """The result of :meth:`loopkin.Mechanism.forward`.

    ``sweep`` holds the samples as a :class:`Sweep` in time (variable
    ``t``: every column, plot and table of a sweep); ``t``, ``kinetic``
    and ``potential`` are numpy arrays, one value per sample (s, J, J);
    ``work`` the work done since the start by each load and prescribed
    driver (samples × works, J), named by ``work_names``; ``effort`` each
    driver's effort (samples × drivers; zero for a free driver);
    ``ended`` is ``"complete"``, ``"event"`` (then ``event`` is the index
    of the event in ``stop_when``), ``"failed"`` (``sweep.stop`` says
    why) or ``"step limit"``, at time ``at``; ``steps``, ``rejected`` and
    ``evaluations`` count the integration's work; ``compiled`` and
    ``summed`` how many evaluations of the mass matrix and the efforts
    (the integration's and the samples') came from the model's compiled
    equations of motion and how many from the sums over its bodies and
    loads (``summed`` is 0 for a model's own ``bodies`` and ``loads``
    sections). With
    ``sensitivities=True``, ``parameters`` names the definition's
    sensitivity parameters and ``position_sensitivity`` and
    ``rate_sensitivity`` hold ∂d/∂p and ∂ḋ/∂p of the free drivers
    (samples × parameters × free drivers), integrated with the motion.
    ``impacts`` lists the impacts at the ``stops``: (t, index of the stop
    among the events, the coordinate's rate before, after).
    """

    def __init__(self, sweep: "Sweep", d: Dict[str, Any]) -> None:
        self.sweep = sweep
        self.t: np.ndarray = d["t"]
        self.kinetic: np.ndarray = d["kinetic"]
        self.potential: np.ndarray = d["potential"]
        self.work: np.ndarray = d["work"]
        self.work_names: List[str] = list(d["work_names"])
        self.effort: np.ndarray = d["effort"]
        self.ended: str = d["ended"]
        self.event: Optional[int] = d["event"]
        self.at: float = d["at"]
        self.steps: int = d["steps"]
        self.rejected: int = d["rejected"]
        self.evaluations: int = d["evaluations"]
        self.compiled: int = d["compiled"]
        self.summed: int = d["summed"]
        self._energy_error: float = d["energy_error"]
        self.parameters: List[str] = list(d.get("parameters", []))
        self.impacts: List[Tuple[float, int, float, float]] = [tuple(i) for i in d.get("impacts", [])]  # type: ignore[misc]
        self.position_sensitivity: np.ndarray = d.get("position_sensitivity", np.zeros((0, 0, 0)))
        self.rate_sensitivity: np.ndarray = d.get("rate_sensitivity", np.zeros((0, 0, 0)))

    @property
    def balance(self) -> np.ndarray:
        """T + V − ΣW at each sample: constant in an exact solution."""
        return self.kinetic + self.potential - self.work.sum(axis=1)

    def energy_error(self) -> float:
        """The largest change of :attr:`balance`, relative to the largest
        of |T|, |V| and the works."""
        return self._energy_error

    def __repr__(self) -> str:
        return f"Trajectory({len(self.t)} samples, ended {self.ended!r} at t = {self.at:g} s)"


class _Forward:
    """:meth:`forward`, mixed into :class:`loopkin.Mechanism`."""

    __slots__ = ()
    _m: "_native.Model"

    if TYPE_CHECKING:  # pragma: no cover

        @classmethod
        def driver_names(cls) -> Tuple[str, ...]: ...

        def pose(
            self, pose: Optional[Mapping[str, Union[float, str]]] = None, **values: Union[float, str]
        ) -> "Pose": ...

        def _quantity(self, name: str, value: Union[float, str], order: int) -> float: ...

    def _event(self, item: Tuple[Any, ...]) -> Tuple[str, bool, float, int]:
        """One event of ``stop_when``, (key, value[, direction]), as the
        native call takes it: (coordinate, of its rate, value, direction)."""
        if len(item) not in (2, 3) or not isinstance(item[0], str):
            raise ValueError(
                f"stop_when: {item!r} is not (coordinate, value) or (coordinate, value, direction), "
                'e.g. ("th4", "60deg", "increasing")'
            )
        key, value = item[0], item[1]
        direction = item[2] if len(item) == 3 else None
        if isinstance(direction, str):
            direction = direction.strip()
        rate = key.startswith("rate(") and key.endswith(")")
        name = key[5:-1].strip() if rate else key
        signs = {None: 0, "increasing": 1, "decreasing": -1}
        if direction not in signs:
            raise ValueError(
                f"stop_when: the direction of {key!r} is {direction!r}; give \"increasing\" or "
                '"decreasing" (or none, for either)'
            )
        return (name, rate, self._quantity(name, value, 1 if rate else 0), signs[direction])

    def forward(
        self,
        *,
        start: Mapping[str, Union[float, str]],
        until: Union[float, str],
        rates: Optional[Mapping[str, Union[float, str]]] = None,
        free: Optional[Iterable[str]] = None,
        samples: int = 100,
        tolerance: float = 1e-9,
        stop_when: Optional[
            Union[
                Mapping[str, Union[float, str, Tuple[Union[float, str], str], List[Union[float, str]]]],
                Sequence[Tuple[Union[str, float], ...]],
            ]
        ] = None,
        method: str = "explicit",
        max_step: Optional[float] = None,
        sensitivities: bool = False,
        stops: Optional[Mapping[str, Tuple[Union[float, str], float]]] = None,
        options: Optional[Options] = None,
    ) -> Trajectory:
        """The motion the definition's ``bodies`` and ``loads`` produce
        from the pose ``start`` (forward dynamics): the drivers in ``free``
        (every driver by default; the others stay at their start values)
        move under the loads from the ``rates`` given (zero otherwise)
        until ``until`` seconds (a number, or ``"3s"``), sampled at
        ``samples`` equal intervals. The mechanism is assembled at every
        evaluation, the free drivers' accelerations solve
        M(q) d̈ = −b(q, q̇) (the mass matrix from the exact partial
        velocities, b the efforts at zero free acceleration), integrated
        by Dormand–Prince 5(4) at relative and absolute ``tolerance``.
        ``stop_when`` ends the run where a coordinate reaches a value
        (``{"th4": "60deg"}``), or a rate (``{"rate(phi)": "1400rpm"}``),
        from either side, or only in one direction: ``{"th4": ("60deg",
        "increasing")}`` (or ``"decreasing"``); a list of tuples
        (``[("th4", "60deg", "increasing"), ("th4", "-60deg")]``) gives
        several events on one coordinate; the first that happens ends it.
        ``method="implicit"`` integrates by TR-BDF2, for stiff motions (a
        stiff spring, heavy damping); ``max_step`` bounds the step (s).
        ``sensitivities=True`` integrates, with the motion, the free
        drivers' sensitivities to the parameters of the definition's
        ``sensitivities`` section (the forward sensitivity equations: the
        efforts' partial derivatives compiled, the state's by central
        differences of the equations of motion). ``stops`` are stops the
        motion bounces off: ``{"phi": ("-90deg", 0.5)}`` (coordinate:
        value, coefficient of restitution); an impact is Newton's law with
        the mechanism's own inertia, its energy loss reported as the work
        ``impacts at phi``.

        Raises:
            InvalidDynamicsError: no ``bodies``/``loads`` section, an event
                or a free driver the definition does not have, or a free
                driver that moves no mass.
            InvalidOptionError: a time, tolerance, step or sample count out
                of range (a ``ValueError``).
            ValueError: a method that is neither ``"explicit"`` nor
                ``"implicit"``, a time that cannot be read, an event that
                is not (coordinate, value) or (coordinate, value,
                direction), or a direction neither ``"increasing"`` nor
                ``"decreasing"``.
        """
        q = self.pose(start)
        drivers = self.driver_names()
        r = [0.0] * len(drivers)
        for name, value in (rates or {}).items():
            if name not in drivers:
                raise KeyError(f"{name!r} is not a driver of {type(self).__name__}: they are {list(drivers)}")
            r[drivers.index(name)] = self._quantity(name, value, 1)
        events = [self._event(item) for item in _event_items(stop_when)]
        stop_list: List[Tuple[str, float, float]] = [
            (name, self._quantity(name, value, 0), float(e)) for name, (value, e) in (stops or {}).items()
        ]
        sweep, d = _native.forward(
            self._m,
            q.array.tolist(),
            r,
            list(free or []),
            _seconds(until),
            int(samples),
            float(tolerance),
            events,
            str(method),
            None if max_step is None else float(max_step),
            bool(sensitivities),
            stop_list,
            _opts(options),
        )
        from ._sweep import Sweep

        return Trajectory(Sweep(type(self), self, sweep), d)  # type: ignore[arg-type]
