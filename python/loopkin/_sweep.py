"""Sweeps and batches: their columns as numpy arrays."""

from __future__ import annotations

import math
import os
from functools import cached_property
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Type, Union

import numpy as np

from . import _native
from ._model import FrameMotion, Values, _readonly

if TYPE_CHECKING:  # pragma: no cover
    import pandas

    from ._model import Mechanism
    from .merit import DeadCentre, MechanicalAdvantage, Stroke, TimeRatio, Transmission

__all__ = ["Sweep", "ForceSweep", "ReactionColumns", "Poses", "Stop", "PointColumns", "Deviations", "Batch", "Link"]


class Link(Tuple[Tuple[str, ...], bool]):
    """A link found from the motion: ``points``, the names of the points
    that move rigidly together, and ``frame``, whether it is the frame
    (the points that do not move)."""

    __slots__ = ()

    def __new__(cls, points: Tuple[str, ...], frame: bool) -> "Link":
        return tuple.__new__(cls, (points, frame))

    @property
    def points(self) -> Tuple[str, ...]:
        return self[0]

    @property
    def frame(self) -> bool:
        return self[1]

    def __repr__(self) -> str:
        kind = "frame " if self.frame else ""
        return f"Link({kind}{{{', '.join(self.points)}}})"


def _pairs(links: Optional[Iterable[Union[Tuple[str, str], str]]]) -> Optional[List[Tuple[str, str]]]:
    """Point pairs as the native module takes them: each a pair of names or
    the text ``"A-B"``, as the command writes a link; ``None`` kept."""
    if links is None:
        return None
    pairs = []
    for x in links:
        ends = x.split("-") if isinstance(x, str) else list(x)
        if len(ends) != 2 or not all(isinstance(e, str) for e in ends):
            raise ValueError(f"a link is two point names, (\"A\", \"B\") or \"A-B\", not {x!r}")
        pairs.append((ends[0].strip(), ends[1].strip()))
    return pairs


class Stop:
    """Why a sweep stopped before its end.

    Attributes:
        kind: "limit_position" (past ``at`` the block of ``unknowns`` has no
            real solution), "change_point" (two branches meet between
            ``from_`` and ``to``), "singular", "not_assembled" or "invalid".
        at: the driver's value where it stopped.
        message: the library's explanation.
        unknowns: the block's unknowns, for a limit position.
        from_, to: the last sample before a change point and the first
            value past it.
    """

    __slots__ = ("kind", "at", "message", "unknowns", "from_", "to")

    def __init__(self, d: Mapping[str, Any]) -> None:
        self.kind: str = d["kind"]
        self.at: float = float(d["at"])
        self.message: str = d["message"]
        self.unknowns: Optional[str] = d.get("unknowns")
        self.from_: Optional[float] = d.get("from")
        self.to: Optional[float] = d.get("to")

    def __str__(self) -> str:
        return self.message

    def __repr__(self) -> str:
        return f"Stop(kind={self.kind!r}, at={self.at!r})"


class PointColumns:
    """A point over a sweep or a run of poses: its position, velocity and
    acceleration as arrays of shape (samples, dim); the velocity and
    acceleration are ``None`` for positions only (:class:`Poses`). As an
    array (``np.asarray(point)``) it is its positions."""

    __slots__ = ("position", "velocity", "acceleration")

    def __init__(
        self, position: np.ndarray, velocity: Optional[np.ndarray] = None, acceleration: Optional[np.ndarray] = None
    ) -> None:
        self.position = _readonly(position)
        self.velocity = None if velocity is None else _readonly(velocity)
        self.acceleration = None if acceleration is None else _readonly(acceleration)

    @classmethod
    def _of(cls, values: np.ndarray) -> "PointColumns":
        """From a sweep's (samples, 3, dim) block of r, v, a."""
        return cls(values[:, 0, :].copy(), values[:, 1, :].copy(), values[:, 2, :].copy())

    def _motion(self, what: str) -> np.ndarray:
        got = getattr(self, what)
        if got is None:
            raise ValueError(f"positions only: a sweep (Mechanism.sweep) gives the {what} too")
        return got

    @property
    def speed(self) -> np.ndarray:
        """|v| per sample."""
        return np.linalg.norm(self._motion("velocity"), axis=1)

    @property
    def acceleration_magnitude(self) -> np.ndarray:
        """|a| per sample."""
        return np.linalg.norm(self._motion("acceleration"), axis=1)

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        if copy:
            return np.array(self.position, dtype=dtype, copy=True)
        return np.asarray(self.position, dtype=dtype)

    def __len__(self) -> int:
        return len(self.position)

    def __getitem__(self, index: Any) -> Any:
        """The positions indexed as an array: ``point[:, 0]`` the x."""
        return self.position[index]

    @property
    def shape(self) -> Tuple[int, ...]:
        """The positions' shape, (samples, dim)."""
        return self.position.shape

    @property
    def T(self) -> np.ndarray:  # noqa: N802 (numpy's name)
        """The positions transposed, (dim, samples): ``plt.plot(*point.T)``."""
        return self.position.T

    def __repr__(self) -> str:
        kind = "positions" if self.velocity is None else "positions, velocities and accelerations"
        return f"<PointColumns: {len(self)} samples of {kind}>"


class Deviations:
    """First-order deviations of a point over a sweep for parameter
    tolerances ±t_k: worst case Σ_k |∂r_c/∂p_k| t_k and root-sum-square
    √(Σ_k (∂r_c/∂p_k t_k)²) per component, and the worst case of the
    distance from the nominal position (and the same for the velocity).
    Arrays of shape (samples,) or (samples, dim)."""

    __slots__ = (
        "at",
        "position_worst",
        "position_components",
        "position_rss",
        "velocity_worst",
        "velocity_components",
        "velocity_rss",
    )
    at: np.ndarray
    position_worst: np.ndarray
    position_components: np.ndarray
    position_rss: np.ndarray
    velocity_worst: np.ndarray
    velocity_components: np.ndarray
    velocity_rss: np.ndarray

    def __init__(self, d: Mapping[str, np.ndarray]) -> None:
        for k in self.__slots__:
            object.__setattr__(self, k, _readonly(np.asarray(d[k])))


class _Columns(Mapping[str, np.ndarray]):
    """Columns by coordinate name (values, rates or accelerations)."""

    __slots__ = ("_names", "_table")

    def __init__(self, names: Tuple[str, ...], table: np.ndarray) -> None:
        self._names = names
        self._table = table

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self._table[:, self._names.index(name)]
        except ValueError:
            raise KeyError(f"{name!r} is not a coordinate: they are {list(self._names)}") from None

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)


class Sweep:
    """The samples of a sweep, as numpy columns.

    ``sw["th3"]`` is a coordinate's values (``sw.qd["th3"]``,
    ``sw.qdd["th3"]`` its rates and accelerations); ``sw.at`` the swept
    driver's values; ``sw.point("P")`` a point's position, velocity and
    acceleration; ``sw.stop`` ``None`` or the :class:`Stop` that ended it
    early; ``sw.to_pandas()`` a DataFrame with units in the column names.
    """

    def __init__(self, cls: Type["Mechanism"], design: "Mechanism", native: "_native.Sweep") -> None:
        self._cls = cls
        self.design = design
        self._native = native

    # Each column is made an array when first read (the native arrays are
    # read-only already: they hold the data the figures and tables read
    # back), then kept as an attribute.

    @cached_property
    def variable(self) -> str:
        """The swept variable's name (the driver's, or ``t``)."""
        return self._native.variable

    @cached_property
    def at(self) -> np.ndarray:
        """The swept variable's value at each sample."""
        return self._native.column(0)

    @cached_property
    def q(self) -> "_Columns":
        """The coordinates' values, by name: ``sw.q["th3"]``."""
        return _Columns(self._cls._coords, self._native.column(1))

    @cached_property
    def qd(self) -> "_Columns":
        """The coordinates' rates, by name."""
        return _Columns(self._cls._coords, self._native.column(2))

    @cached_property
    def qdd(self) -> "_Columns":
        """The coordinates' accelerations, by name."""
        return _Columns(self._cls._coords, self._native.column(3))

    @cached_property
    def _points(self) -> np.ndarray:
        return self._native.column(4)

    @cached_property
    def conditioning(self) -> np.ndarray:
        """The conditioning of the unknowns' Jacobian at each sample:
        1/‖Φ̃_u⁻¹‖∞ of the scaled Jacobian, 0 at a singular pose."""
        return self._native.column(5)

    @cached_property
    def det_sign(self) -> np.ndarray:
        """The sign of det Φ_u at each sample (the assembly branch)."""
        return self._native.column(6)

    @cached_property
    def residual(self) -> np.ndarray:
        """The loop-closure residual max |Φ_i| / S_i at each sample."""
        return self._native.column(7)

    @cached_property
    def _frames(self) -> np.ndarray:
        return self._native.column(8)

    @cached_property
    def stop(self) -> Optional[Stop]:
        """``None`` where the sweep ran to its end, else why it stopped."""
        s = self._native.stop()
        return None if s is None else Stop(s)

    @cached_property
    def change_points(self) -> List[float]:
        """The change points passed (the driver's value at each)."""
        return self._native.change_points

    def __len__(self) -> int:
        return len(self._native)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.q[name]

    def point(self, name: str) -> PointColumns:
        """The point ``name`` over the sweep."""
        names = self._cls._points
        if name not in names:
            raise KeyError(f"{name!r} is not a point: they are {list(names)}")
        return PointColumns._of(self._points[:, names.index(name)])

    def frame(self, name: str) -> FrameMotion:
        """The frame ``name`` over the sweep (each attribute with a leading
        axis of samples)."""
        names = self._cls._frames
        if name not in names:
            raise KeyError(f"{name!r} is not a frame: they are {list(names)}")
        return FrameMotion(self._frames[:, names.index(name)])

    def pose(self, i: int) -> "Values":
        """The pose of sample ``i``."""
        from ._model import Pose

        return Pose(self.q._names, np.asarray(self.q._table[i]))

    def to_csv(
        self, path: Optional[Union[str, "os.PathLike[str]"]] = None, unit: str = "m", degrees: bool = False
    ) -> str:
        """The samples as CSV (a header with units, lengths in ``unit``,
        angles in degrees with ``degrees=True``: ``phi_deg``,
        ``phi_deg_s``, …; 13 significant digits), written to ``path`` when
        given."""
        text = self._native.to_csv(unit, bool(degrees))
        if path is not None:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        return text

    def to_text(self, every: int = 1) -> str:
        """An aligned text table of every ``every``-th sample."""
        return self._native.to_text(int(every))

    def to_pandas(self, unit: str = "m", degrees: bool = False) -> "pandas.DataFrame":
        """The samples as a pandas DataFrame, the CSV's columns (units in
        their names; angles in degrees with ``degrees=True``). Needs pandas
        (``pip install loopkin[pandas]``)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover
            raise ImportError("to_pandas needs pandas: pip install pandas") from e
        headers, rows = self._native.table(unit, bool(degrees))
        return pd.DataFrame(np.asarray(rows), columns=headers)

    def links(self) -> List["Link"]:
        """The links found from the motion: the largest sets of points
        whose distances do not change over the sweep (the frame, which
        holds the points that do not move, first marked ``frame``)."""
        return [Link(tuple(points), frame) for points, frame in self._native.links()]

    def write_animation(
        self,
        path: Union[str, "os.PathLike[str]"],
        links: Optional[Iterable[Union[Tuple[str, str], str]]] = None,
        projection: str = "xy",
    ) -> None:
        """Writes a self-contained HTML animation of the sweep (no network
        needed): the points, ground pivots and sliders, and the links
        ``links`` (pairs of point names; by default those found from the
        motion, :meth:`links`) drawn between them."""
        self._native.write_animation(os.fspath(path), _pairs(links), projection)

    def write_dxf(
        self,
        path: Union[str, "os.PathLike[str]"],
        links: Optional[Iterable[Union[Tuple[str, str], str]]] = None,
        sample: int = 0,
        projection: str = "xy",
    ) -> None:
        """Writes a DXF drawing (release 12, ASCII) for a CAD program: the
        skeleton at sample ``sample`` (a ``LINE`` per link of ``links``,
        by default those found from the motion; a ``CIRCLE`` per point,
        ground pivots on layer ``PIVOTS``, the others on ``JOINTS``; the
        names on ``NAMES``) and every moving point's path over the sweep
        as a ``POLYLINE`` on layer ``PATHS`` (closed over a full turn), in
        the definition's length unit."""
        if not 0 <= sample < len(self):
            raise IndexError(f"sample {sample} of a sweep of {len(self)} samples")
        self._native.write_dxf(os.fspath(path), _pairs(links), sample, projection)

    def forces(self) -> "ForceSweep":
        """The forces at every sample (as :meth:`Mechanism.forces` gives
        them at one), from the definition's ``bodies`` and ``loads``
        sections: the drivers' efforts over the cycle, their mean, the
        energy a flywheel must absorb, the CSV table and the plot.

        Raises:
            InvalidDynamicsError: the definition has neither section.
            ValueError: the samples are a simulation's (in time): take
                :meth:`Mechanism.forces` of each motion instead.
        """
        if self.variable not in self._cls.driver_names():
            raise ValueError(
                "forces along a sweep need the samples of a driver's sweep (Mechanism.sweep); "
                "these are a simulation's, in time: call Mechanism.forces on each sample's motion"
            )
        return ForceSweep(self._native.forces())

    def effort_sensitivities(self) -> Dict[str, np.ndarray]:
        """How each driver's effort at every sample changes with each
        parameter of the definition's ``sensitivities`` section, the
        drivers' motion held (as :meth:`Mechanism.effort_sensitivities`
        gives them at one motion): ∂Q_k/∂p by parameter, an array of shape
        (samples, drivers). Their mean over a cycle is the slope of the
        mean effort; with the efforts of :meth:`forces`, the gradient of
        any measure of the torque curve (its RMS, its peak) for the design
        of counterweights and links. Empty without the section.

        Raises:
            InvalidDynamicsError: the definition has neither a ``bodies``
                nor a ``loads`` section.
            ValueError: the samples are a simulation's (in time).
        """
        if self.variable not in self._cls.driver_names():
            raise ValueError(
                "effort sensitivities along a sweep need the samples of a driver's sweep "
                "(Mechanism.sweep); these are a simulation's: call "
                "Mechanism.effort_sensitivities on each sample's motion"
            )
        return {p: _readonly(v) for p, v in self._native.effort_sensitivities().items()}

    def deviations(self, point: str, tolerances: Mapping[str, float]) -> Deviations:
        """The first-order deviations of ``point`` over the sweep for the
        parameter tolerances ``{name: ±t}`` (parameters of the
        ``sensitivities`` section; one not given is exact)."""
        return Deviations(self._native.deviations(point, [(k, float(v)) for k, v in tolerances.items()]))

    # -- figures of merit --------------------------------------------------

    def dead_centres(self, name: str) -> List["DeadCentre"]:
        """The dead centres of coordinate ``name``: where its rate changes
        sign (a limit of its motion), located between samples on the cubic
        Hermite interpolant of dq/dφ; for a sweep of one turn, the interval
        from the last sample back to the first too.

        Raises:
            InvalidGeometryError: ``name`` is not a coordinate, or the
                sweep has fewer than two samples.
        """
        from .merit import DeadCentre

        return [DeadCentre(at, v, m) for at, v, m in self._native.figure("dead_centres", [name])]

    def stroke(self, name: str) -> "Stroke":
        """The least and largest values of coordinate ``name`` over the
        sweep (a slider's travel, a rocker's swing), dead centres between
        samples included."""
        from .merit import Stroke

        lo, hi = self._native.figure("stroke", [name])
        return Stroke(lo, hi)

    def time_ratio(self, name: str) -> "TimeRatio":
        """The time ratio of output ``name`` (a quick-return's forward over
        return stroke at constant input speed), from a sweep of one turn.

        Raises:
            InvalidGeometryError: the sweep is not one turn of an angle
                driver, or the output has not exactly two dead centres.
        """
        from .merit import TimeRatio

        rising, falling = self._native.figure("time_ratio", [name])
        return TimeRatio(rising, falling)

    def transmission(self, first: str, second: str) -> "Transmission":
        """The transmission angle μ = arccos(cos(θ₂ − θ₁)) between the links
        whose directions are the angles ``first`` and ``second`` (a
        four-bar's coupler and output link) at every sample, with its
        extremes.

        Raises:
            InvalidGeometryError: a name that is not an angle coordinate.
        """
        from .merit import _transmission

        return _transmission(self._native.figure("transmission", [first, second]))

    def mechanical_advantage(self, output: str) -> "MechanicalAdvantage":
        """The mechanical advantage of the coordinate ``output`` at every
        sample: MA = φ'/q', the swept driver's rate over the output's,
        which is the ratio of the output's effort to the input's with no
        losses and no inertia (N·m per N·m for an angle output, N per N·m
        for a length; ±inf at the output's dead centres), with its least
        magnitude and where it occurs.

        Raises:
            InvalidGeometryError: a name that is not a coordinate, or the
                swept driver itself.
        """
        from .merit import MechanicalAdvantage

        values, (at, least) = self._native.figure("mechanical_advantage", [output])
        values.flags.writeable = False
        return MechanicalAdvantage(values, least, at)

    def __repr__(self) -> str:
        end = "" if self.stop is None else f", stopped: {self.stop.kind} at {self.stop.at:.6g}"
        return f"<Sweep of {self.variable}: {len(self)} samples{end}>"


class ReactionColumns:
    """One joint's reaction over a sweep: ``force`` and ``moment`` (samples
    × 3, in the fixed axes: what the joint's first body exerts on its
    second), and ``effort`` (the driver's, one per sample, or ``None``
    where no driver acts in the joint)."""

    def __init__(self, d: Mapping[str, Any]) -> None:
        self.force: np.ndarray = _readonly(d["force"])
        self.moment: np.ndarray = _readonly(d["moment"])
        self.effort: Optional[np.ndarray] = None if d["effort"] is None else _readonly(d["effort"])

    def magnitude(self) -> np.ndarray:
        """|F| at every sample (N): the load the joint's bearing carries."""
        return np.linalg.norm(self.force, axis=1)

    def __repr__(self) -> str:
        return f"<ReactionColumns: {len(self.force)} samples>"


class ForceSweep:
    """The forces along a sweep (:meth:`Sweep.forces`), as numpy columns.

    ``at`` is the swept driver's values; ``effort["phi"]`` a driver's
    effort at every sample (N·m for an angle driver, N for a length);
    ``kinetic_energy``, ``potential_energy`` and ``power`` one value per
    sample; ``shaking_force`` and ``shaking_moment`` (the inertial part,
    −Σ m a_G and its moment) and ``frame_force`` and ``frame_moment`` (the
    total on the frame, weights and point loads included: Norton's
    shaking force where every point load comes from outside the machine)
    samples × 3;
    ``reactions["bearing"]`` a joint's :class:`ReactionColumns`, for the
    joints of the definition's ``joints`` section (empty without).
    """

    def __init__(self, native: "_native.ForceSweep") -> None:
        self._native = native
        c = native.columns()
        self.drivers: Tuple[str, ...] = tuple(native.drivers)
        self.at: np.ndarray = _readonly(c["at"])
        self.effort = _Columns(self.drivers, _readonly(c["effort"]))
        self.kinetic_energy: np.ndarray = _readonly(c["kinetic_energy"])
        self.potential_energy: np.ndarray = _readonly(c["potential_energy"])
        self.power: np.ndarray = _readonly(c["power"])
        self.shaking_force: np.ndarray = _readonly(c["shaking_force"])
        self.shaking_moment: np.ndarray = _readonly(c["shaking_moment"])
        self.frame_force: np.ndarray = _readonly(c["frame_force"])
        self.frame_moment: np.ndarray = _readonly(c["frame_moment"])
        self.reactions: Dict[str, ReactionColumns] = {
            name: ReactionColumns(d) for name, d in c["reactions"].items()
        }

    def __len__(self) -> int:
        return len(self.at)

    def _driver(self, driver: Optional[str]) -> str:
        if driver is None:
            if len(self.drivers) != 1:
                raise TypeError(f"name the driver: this mechanism has {list(self.drivers)}")
            return self.drivers[0]
        if driver not in self.drivers:
            raise KeyError(f"{driver!r} is not a driver: they are {list(self.drivers)}")
        return driver

    def mean_effort(self, driver: Optional[str] = None) -> float:
        """The mean effort of ``driver`` over the swept range,
        (1/(s_n − s_0)) ∫ Q ds by the trapezoidal rule: for a crank turned
        at constant speed, the mean torque. For a whole cycle, sweep with
        the end of the turn included (``to=start + 2π``): ``turn=True``
        leaves out the last interval."""
        return float(self._native.mean_effort(self._driver(driver)))

    def energy_fluctuation(self, driver: Optional[str] = None) -> float:
        """ΔE = max − min of ∫ (Q − Q̄) ds over the samples: the energy a
        flywheel on the driver's shaft must store and give back for the
        driver to supply the mean effort only (J)."""
        return float(self._native.energy_fluctuation(self._driver(driver)))

    def speed_fluctuation(self, inertia: float, speed: float, driver: Optional[str] = None) -> float:
        """The coefficient of speed fluctuation C_s = ΔE / (I ω²) with a
        flywheel of moment of inertia ``inertia`` (kg·m²) at the mean speed
        ``speed`` (rad/s)."""
        return float(self._native.speed_fluctuation(self._driver(driver), float(inertia), float(speed)))

    def flywheel(self, fluctuation: float, speed: float, driver: Optional[str] = None) -> float:
        """The flywheel's moment of inertia I = ΔE / (C_s ω²) (kg·m²) that
        keeps the coefficient of speed fluctuation at ``fluctuation`` at the
        mean speed ``speed`` (rad/s)."""
        if not (fluctuation > 0.0 and speed != 0.0 and math.isfinite(fluctuation * speed * speed)):
            raise ValueError(
                f"the coefficient of speed fluctuation must be positive and the speed nonzero "
                f"(C_s = {fluctuation}, ω = {speed})"
            )
        return self.energy_fluctuation(driver) / (fluctuation * speed * speed)

    def to_csv(self, path: Optional[Union[str, "os.PathLike[str]"]] = None) -> str:
        """The forces as CSV, a column per quantity with its unit in the
        header, written to ``path`` when given."""
        text = self._native.to_csv()
        if path is not None:
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        return text

    def to_pandas(self) -> "pandas.DataFrame":
        """The CSV's columns as a pandas DataFrame (units in the column
        names). Needs pandas."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover
            raise ImportError("to_pandas needs pandas: pip install pandas") from e
        import io

        return pd.read_csv(io.StringIO(self._native.to_csv()))

    def write_svg(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the plot of the driving effort over the sweep beside its
        mean, and the polar diagram of the shaking force, as SVG."""
        self._native.write_svg(os.fspath(path))

    def __repr__(self) -> str:
        return f"<ForceSweep: {len(self)} samples, drivers {list(self.drivers)}>"


class Poses:
    """Positions along a sweep (from :meth:`Mechanism.poses`): ``at`` the
    driver's values, ``poses["th3"]`` a coordinate's values,
    ``poses.point("P")`` a point's :class:`PointColumns` (its positions,
    samples × dim, with no velocity or acceleration), ``stop`` the
    :class:`Stop` that ended it before the end of its range, or ``None``."""

    def __init__(
        self,
        cls: Type["Mechanism"],
        parts: Tuple[np.ndarray, np.ndarray, np.ndarray, Optional[Mapping[str, Any]]],
    ) -> None:
        self._cls = cls
        # Read-only arrays from the native module: the driver's values, the
        # poses (samples × coordinates), the points (samples × points ×
        # dim); then the stop.
        self.at: np.ndarray = parts[0]
        self._q = parts[1]
        self.points: np.ndarray = parts[2]
        self._stop = parts[3]

    @cached_property
    def q(self) -> _Columns:
        """The coordinates' values, by name: ``poses.q["th3"]``."""
        return _Columns(self._cls._coords, self._q)

    @cached_property
    def stop(self) -> Optional[Stop]:
        """``None`` where the poses ran to the end of their range, else why
        they stopped."""
        return None if self._stop is None else Stop(self._stop)

    def __len__(self) -> int:
        return len(self.at)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.q[name]

    def point(self, name: str) -> PointColumns:
        """Point ``name`` over the poses, as :meth:`Sweep.point` gives it:
        its ``position`` (samples × dim), with no velocity or
        acceleration."""
        names = self._cls._points
        if name not in names:
            raise KeyError(f"{name!r} is not a point: they are {list(names)}")
        return PointColumns(self.points[:, names.index(name)])

    def __repr__(self) -> str:
        end = "" if self.stop is None else f", stopped: {self.stop.kind} at {self.stop.at:.6g}"
        return f"<Poses: {len(self)} samples{end}>"


def _outputs(cls: Type["Mechanism"], outputs: Optional[Iterable[str]]) -> List[Tuple[str, Tuple[str, int]]]:
    """The batch outputs asked for, as (name, (kind, index))."""
    coords = list(cls._coords)
    points = list(cls._points)
    if outputs is None:
        outputs = coords + points
    kept = []
    for name in outputs:
        base, _, what = name.partition(".")
        if name == "conditioning":
            kept.append((name, ("conditioning", 0)))
        elif base in coords and what in ("", "rate", "acceleration"):
            kind = {"": "q", "rate": "qd", "acceleration": "qdd"}[what]
            kept.append((name, (kind, coords.index(base))))
        elif base in points and what in ("", "position", "velocity", "acceleration"):
            kept.append((name, (what or "position", points.index(base))))
        else:
            raise KeyError(
                f"{name!r} is not an output: give a coordinate {coords} (with .rate or .acceleration), "
                f"a point {points} (with .velocity or .acceleration) or 'conditioning'"
            )
    return kept


class Batch(Mapping[str, np.ndarray]):
    """The results of :meth:`Mechanism.batch`: ``batch["P"]`` is an output
    with a row per design; ``params`` the designs' parameters (a row each,
    columns in :attr:`parameter_names`); ``samples`` how many samples each
    design has; ``stops`` why a design ended early (``None`` if it did not);
    ``ok`` the designs that ran to their end."""

    def __init__(self, table: np.ndarray, names: Sequence[str], outputs: Sequence[str], d: Mapping[str, Any]) -> None:
        self.params = _readonly(table)
        self.parameter_names = tuple(names)
        self._outputs = {k: _readonly(v) for k, v in zip(outputs, d["outputs"])}
        self.samples = _readonly(np.asarray(d["samples"]).astype(int))
        self.stops: List[Optional[str]] = list(d["stops"])
        self.ok = _readonly(np.array([s is None for s in self.stops], dtype=bool))

    @classmethod
    def concatenate(cls, batches: Sequence["Batch"]) -> "Batch":
        """The batches' designs one after the other, as one batch (they
        must have the same outputs)."""
        if not batches:
            raise ValueError("no batch to concatenate")
        first = batches[0]
        names = list(first._outputs)
        for b in batches:
            if list(b._outputs) != names or b.parameter_names != first.parameter_names:
                raise ValueError("the batches have different outputs or parameters")
        out = cls.__new__(cls)
        out.params = _readonly(np.concatenate([b.params for b in batches]))
        out.parameter_names = first.parameter_names
        out._outputs = {k: _readonly(np.concatenate([b._outputs[k] for b in batches])) for k in names}
        out.samples = _readonly(np.concatenate([b.samples for b in batches]))
        out.stops = [s for b in batches for s in b.stops]
        out.ok = _readonly(np.concatenate([b.ok for b in batches]))
        return out

    def __getitem__(self, name: str) -> np.ndarray:
        return self._outputs[name]

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(self._outputs)

    def __len__(self) -> int:
        return len(self._outputs)

    def __repr__(self) -> str:
        return f"<Batch of {len(self.samples)} designs, {int(self.ok.sum())} complete; outputs {list(self._outputs)}>"
