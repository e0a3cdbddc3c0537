"""The values a mechanism hands back: options, poses, motions of points and
frames, forces, reactions and sensitivities, each a read-only view of the
native results with its names."""

from __future__ import annotations

from typing import (
    TYPE_CHECKING,
    Any,
    Dict,
    Iterator,
    Mapping,
    Optional,
    Sequence,
    Tuple,
    Type,
    TypeVar,
)

import numpy as np

from . import _native

if TYPE_CHECKING:
    from ._model import Mechanism

class Options:
    """Solver options, shared by assembly, analysis, sweeps and batches.

    Attributes:
        tolerance: Newton–Raphson has converged when every |Φ_i| is at most
            ``tolerance`` times its equation's term scale S_i (relative), or
            at most ``tolerance`` in the equation's units when ``absolute``.
        max_iterations: the largest number of Newton iterations.
        singularity_threshold: Φ_u is singular when its conditioning (the
            distance of the scaled Jacobian to the nearest singular matrix)
            is at or below this.
        branch: "any" (the branch nearest the guess), "positive" or
            "negative" (by the sign of det Φ_u).
        absolute: whether ``tolerance`` is absolute.
    """

    __slots__ = ("tolerance", "max_iterations", "singularity_threshold", "branch", "absolute")

    def __init__(
        self,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
        singularity_threshold: Optional[float] = None,
        branch: str = "any",
        absolute: bool = False,
    ) -> None:
        t, n, s, _, _ = _native.default_options()
        self.tolerance = float(t if tolerance is None else tolerance)
        self.max_iterations = int(n if max_iterations is None else max_iterations)
        self.singularity_threshold = float(s if singularity_threshold is None else singularity_threshold)
        self.branch = branch
        self.absolute = bool(absolute)

    def _tuple(self) -> Tuple[float, int, float, str, bool]:
        return (self.tolerance, self.max_iterations, self.singularity_threshold, self.branch, self.absolute)

    def __repr__(self) -> str:
        return (
            f"Options(tolerance={self.tolerance!r}, max_iterations={self.max_iterations!r}, "
            f"singularity_threshold={self.singularity_threshold!r}, branch={self.branch!r}, "
            f"absolute={self.absolute!r})"
        )


def _opts(options: Optional[Options]) -> Optional[Tuple[float, int, float, str, bool]]:
    """The options as the native calls take them: ``None`` for the
    defaults, which it then reads as they are."""
    return None if options is None else options._tuple()


def _readonly(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


V = TypeVar("V", bound="Values")


class Values(Mapping[str, float]):
    """Values by name (coordinates, or their rates or accelerations); the
    array, in the mechanism's order, is :attr:`array`."""

    __slots__ = ("_names", "array")

    def __init__(self, names: Sequence[str], array: np.ndarray) -> None:
        self._names = tuple(names)
        if type(array) is not np.ndarray or array.dtype != np.float64:
            array = np.asarray(array, dtype=float)
        array.flags.writeable = False
        self.array = array

    @classmethod
    def _view(cls: Type[V], names: Tuple[str, ...], array: np.ndarray) -> V:
        """Values over ``array``, a read-only float array, as it is."""
        v = object.__new__(cls)
        v._names = names
        v.array = array
        if isinstance(v, Pose):
            v.modes = None
        return v

    def __getitem__(self, name: str) -> float:
        try:
            return float(self.array[self._names.index(name)])
        except ValueError:
            raise KeyError(f"{name!r} is not one of {list(self._names)}") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return np.asarray(self.array, dtype=dtype)

    def __repr__(self) -> str:
        inner = ", ".join(f"{n}={v:.12g}" for n, v in zip(self._names, self.array))
        return f"{{{inner}}}"


class Pose(Values):
    """A pose of a mechanism: every coordinate (drivers first) by name, and
    the assembly modes it was assembled in (``None`` when unknown).

    ``pose["th3"]`` is a coordinate; ``pose.array`` all of them in order;
    ``pose.modes`` a tuple of "+"/"-", one per block with two modes.
    """

    __slots__ = ("modes",)

    def __init__(self, names: Sequence[str], array: np.ndarray, modes: Optional[Sequence[str]] = None) -> None:
        super().__init__(names, array)
        self.modes = None if modes is None else tuple(modes)

    def __repr__(self) -> str:
        m = "" if self.modes is None else f" modes={''.join(self.modes)}"
        return f"Pose({super().__repr__()}{m})"


class PointMotion:
    """A point's position r, velocity v and acceleration a (numpy arrays of
    2 or 3 components), with the speed |v| and |a|."""

    __slots__ = ("position", "velocity", "acceleration")

    def __init__(self, values: np.ndarray) -> None:
        # Views of a read-only array: read-only themselves.
        if values.flags.writeable:
            values = _readonly(values.copy())
        self.position = values[0]
        self.velocity = values[1]
        self.acceleration = values[2]

    @property
    def speed(self) -> float:
        """|v|."""
        return float(np.linalg.norm(self.velocity))

    def __repr__(self) -> str:
        return f"PointMotion(position={self.position}, velocity={self.velocity}, acceleration={self.acceleration})"


class FrameMotion:
    """A body frame's motion: rotation matrix R (its axes in fixed
    coordinates), origin o, the origin's velocity and acceleration, angular
    velocity ω and angular acceleration α."""

    __slots__ = ("rotation", "origin", "velocity", "acceleration", "angular_velocity", "angular_acceleration")

    def __init__(self, values: np.ndarray) -> None:
        v = np.asarray(values, dtype=float)
        self.rotation = _readonly(v[..., 0:9].reshape(v.shape[:-1] + (3, 3)).copy())
        self.origin = _readonly(v[..., 9:12].copy())
        self.velocity = _readonly(v[..., 12:15].copy())
        self.acceleration = _readonly(v[..., 15:18].copy())
        self.angular_velocity = _readonly(v[..., 18:21].copy())
        self.angular_acceleration = _readonly(v[..., 21:24].copy())

    def __repr__(self) -> str:
        return f"FrameMotion(origin={self.origin}, angular_velocity={self.angular_velocity})"


class _ByName(Mapping[str, Any]):
    """Points or frames by name, each made on first access from its row of
    one read-only array (``make(row)``): what a motion holds, built only
    for the names read."""

    __slots__ = ("_names", "_where", "_rows", "_make", "_made")

    def __init__(
        self, names: Tuple[str, ...], where: Optional[Dict[str, int]], rows: np.ndarray, make: Any
    ) -> None:
        self._names = names
        self._where = where
        self._rows = rows
        self._make = make
        self._made: Dict[str, Any] = {}

    def __getitem__(self, name: str) -> Any:
        got = self._made.get(name)
        if got is None:
            try:
                k = self._where[name] if self._where is not None else self._names.index(name)
            except (KeyError, ValueError):
                raise KeyError(f"{name!r} is not one of {list(self._names)}") from None
            got = self._made[name] = self._make(self._rows[k])
        return got

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def __repr__(self) -> str:
        return "{" + ", ".join(f"{n!r}: {self[n]!r}" for n in self._names) + "}"


class Motion:
    """The motion at one pose: ``q``, ``qd`` (q') and ``qdd`` (q'') by
    name, every point and frame by name, and the diagnostics.

    Attributes:
        q, qd, qdd: :class:`Values` of every coordinate, drivers first.
        points: :class:`PointMotion` by name (a read-only mapping).
        frames: :class:`FrameMotion` by name (a read-only mapping).
        conditioning: 1/‖Φ̃_u⁻¹‖∞ of the scaled Jacobian, 0 at a singular
            pose.
        det_sign: the sign of det Φ_u (the assembly branch).
        residual: max |Φ_i| / S_i at q.
    """

    __slots__ = ("_cls", "_raw", "_q", "_qd", "_qdd", "_points", "_frames", "conditioning", "det_sign", "residual")

    def __init__(self, cls: Type["Mechanism"], native: Tuple[Any, ...]) -> None:
        # The native arrays, shaped into values by name where first read.
        self._cls = cls
        self._raw = native[:3]
        self.conditioning: float = native[3]
        self.det_sign: float = native[4]
        self.residual: float = native[5]
        self._q: Optional[Pose] = None
        self._qd: Optional[Values] = None
        self._qdd: Optional[Values] = None
        self._points: Optional[_ByName] = None
        self._frames: Optional[_ByName] = None

    def _coordinates(self) -> None:
        qs = self._raw[0]
        qs.flags.writeable = False
        names = self._cls._coords
        n = len(names)
        self._q = Pose._view(names, qs[:n])
        self._qd = Values._view(names, qs[n : 2 * n])
        self._qdd = Values._view(names, qs[2 * n :])

    @property
    def q(self) -> Pose:
        """Every coordinate, drivers first (a :class:`Pose`)."""
        if self._q is None:
            self._coordinates()
        return self._q  # type: ignore[return-value]

    @property
    def qd(self) -> Values:
        """Every coordinate's rate q'."""
        if self._qd is None:
            self._coordinates()
        return self._qd  # type: ignore[return-value]

    @property
    def qdd(self) -> Values:
        """Every coordinate's acceleration q''."""
        if self._qdd is None:
            self._coordinates()
        return self._qdd  # type: ignore[return-value]

    @property
    def points(self) -> Mapping[str, PointMotion]:
        """:class:`PointMotion` by point name."""
        if self._points is None:
            cls = self._cls
            rows = self._raw[1].reshape(len(cls._points), 3, -1) if cls._points else self._raw[1].reshape(0, 3, 2)
            rows.flags.writeable = False
            self._points = _ByName(cls._points, cls._point_where, rows, PointMotion)
        return self._points

    @property
    def frames(self) -> Mapping[str, FrameMotion]:
        """:class:`FrameMotion` by frame name."""
        if self._frames is None:
            cls = self._cls
            rows = self._raw[2].reshape(len(cls._frames), 24)
            rows.flags.writeable = False
            self._frames = _ByName(cls._frames, None, rows, FrameMotion)
        return self._frames

    @property
    def pose(self) -> Pose:
        """The pose, as :class:`Pose`."""
        return self.q

    def __repr__(self) -> str:
        return f"Motion(q={self.q!r}, qd={self.qd!r}, qdd={self.qdd!r})"


class Forces:
    """The forces at one motion (:meth:`Mechanism.forces`).

    Attributes:
        effort: :class:`Values` of each driver's effort, the torque (N·m,
            angle drivers) or force (N, length drivers) it must supply,
            positive when it drives the coordinate's growth.
        kinetic_energy: T = Σ ½ m |v_G|² + ½ ω · J ω (J).
        potential_energy: V = −Σ m g · r_G + Σ ½ k (L − L₀)² (J).
        power: Σ Q_k ḋ_k, the power the drivers supply (W).
        shaking_force: −Σ m a_G, the force the links' inertia exerts on the
            frame (N; 3 components).
        shaking_moment: its moment about the origin (N·m; 3 components).
        frame_force: the total force of the mechanism on the frame, what
            Norton calls the shaking force: −Σ m a_G + Σ m g + Σ F_P, the
            weights and point loads included (N; 3 components). Each
            point load counts as coming from outside the machine; one that
            also bears on the frame (a gas force, on the cylinder head too)
            cancels there: declare it on its joint's coordinate instead.
        frame_moment: its moment about the origin, the drivers' reactions
            and the torques on bodies included (N·m; 3 components).
    """

    __slots__ = (
        "effort",
        "kinetic_energy",
        "potential_energy",
        "power",
        "shaking_force",
        "shaking_moment",
        "frame_force",
        "frame_moment",
    )

    def __init__(self, drivers: Sequence[str], d: Dict[str, Any]) -> None:
        self.effort = Values(drivers, _readonly(np.asarray(d["effort"])))
        self.kinetic_energy = float(d["kinetic_energy"])
        self.potential_energy = float(d["potential_energy"])
        self.power = float(d["power"])
        self.shaking_force: np.ndarray = _readonly(np.asarray(d["shaking_force"]))
        self.shaking_moment: np.ndarray = _readonly(np.asarray(d["shaking_moment"]))
        self.frame_force: np.ndarray = _readonly(np.asarray(d["frame_force"]))
        self.frame_moment: np.ndarray = _readonly(np.asarray(d["frame_moment"]))

    def __repr__(self) -> str:
        return f"Forces(effort={self.effort!r}, power={self.power:.6g})"


class MassSensitivity:
    """How the drivers' efforts change with one body's mass and moment of
    inertia (:meth:`Mechanism.mass_sensitivities`).

    Attributes:
        mass: :class:`Values` of ∂Q_k/∂m for each driver (N·m/kg for an
            angle driver, N/kg for a length).
        inertia: :class:`Values` of ∂Q_k/∂J for each driver, for a body
            turning by an angle in a planar mechanism; ``None`` otherwise.
    """

    __slots__ = ("mass", "inertia")

    def __init__(self, drivers: Sequence[str], d: Dict[str, Any]) -> None:
        self.mass = Values(drivers, _readonly(np.asarray(d["mass"])))
        self.inertia: Optional[Values] = (
            None if d["inertia"] is None else Values(drivers, _readonly(np.asarray(d["inertia"])))
        )

    def __repr__(self) -> str:
        return f"MassSensitivity(mass={self.mass!r}, inertia={self.inertia!r})"


class JointReaction:
    """The reaction at one joint (:meth:`Mechanism.reactions`).

    Attributes:
        force: the force the joint's first body exerts on its second, in
            the fixed axes (N; 3 components, z = 0 in a planar mechanism).
        force_in_body: the same force in the second body's axes.
        moment: the moment the first body exerts on the second (N·m), other
            than a driver's torque.
        effort: the driver's effort in this joint, or ``None``.
    """

    __slots__ = ("force", "force_in_body", "moment", "effort")

    def __init__(self, d: Dict[str, Any]) -> None:
        self.force: np.ndarray = _readonly(np.asarray(d["force"]))
        self.force_in_body: np.ndarray = _readonly(np.asarray(d["force_in_body"]))
        self.moment: np.ndarray = _readonly(np.asarray(d["moment"]))
        self.effort: Optional[float] = None if d["effort"] is None else float(d["effort"])

    def __repr__(self) -> str:
        return f"JointReaction(force={self.force!r}, effort={self.effort!r})"


class Sensitivity:
    """The derivatives of a motion with respect to one parameter p:
    ∂q/∂p, ∂q'/∂p, ∂q''/∂p (:class:`Values`) and each point's ∂r/∂p,
    ∂v/∂p, ∂a/∂p (:class:`PointMotion`, in the point's units per unit of
    p)."""

    __slots__ = ("parameter", "q", "qd", "qdd", "points")

    def __init__(self, cls: Type["Mechanism"], parameter: str, d: Dict[str, Any]) -> None:
        names = cls._coords
        self.parameter = parameter
        self.q = Values(names, d["q"])
        self.qd = Values(names, d["qd"])
        self.qdd = Values(names, d["qdd"])
        self.points = _ByName(cls._points, cls._point_where, _readonly(d["points"]), PointMotion)

    def __repr__(self) -> str:
        return f"Sensitivity({self.parameter}: q={self.q!r})"


def _hint(name: str, names: "Sequence[str]") -> str:
    """" (did you mean 'x'?)" for the name of ``names`` nearest ``name``, as the
    compiler suggests one: within a third of the longer name's length in
    edit distance, a transposition of neighbours counting one edit; "" for
    none, or a name over 64 characters."""
    if len(name) > 64:
        return ""
    best, best_d = None, None
    for cand in names:
        a, b = name, cand
        d = [[0] * (len(b) + 1) for _ in range(len(a) + 1)]
        for i in range(len(a) + 1):
            d[i][0] = i
        for j in range(len(b) + 1):
            d[0][j] = j
        for i in range(1, len(a) + 1):
            for j in range(1, len(b) + 1):
                cost = 0 if a[i - 1] == b[j - 1] else 1
                d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost)
                if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                    d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
        dist = d[len(a)][len(b)]
        if dist * 3 <= max(len(a), len(b)) and (best_d is None or dist < best_d):
            best, best_d = cand, dist
    return f" (did you mean {best!r}?)" if best is not None and best != name else ""
