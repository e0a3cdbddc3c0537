"""Mechanisms compiled from text: the class a definition becomes, its poses,
motions, sweeps and batches."""

from __future__ import annotations

import copyreg
import math
import os
import sys
import threading
import warnings
from typing import (
    Any,
    ClassVar,
    Dict,
    Iterable,
    List,
    Mapping,
    Optional,
    Sequence,
    Tuple,
    Type,
    TypeVar,
    Union,
    cast,
)

import numpy as np

from . import _native
from .errors import CannotAssembleError, RadiansWarning

__all__ = [
    "compile",
    "load",
    "Mechanism",
    "Pose",
    "Motion",
    "PointMotion",
    "FrameMotion",
    "Sensitivity",
    "Options",
]

ArrayLike = Union[Sequence[float], np.ndarray]
M = TypeVar("M", bound="Mechanism")

_classes: Dict[str, Type["Mechanism"]] = {}

# An angle written as a plain number above two turns (4π) was likely meant
# in degrees: `90` is 14.3 turns.
_TWO_TURNS = 4.0 * math.pi
_PACKAGE = os.path.dirname(os.path.abspath(__file__))


def _caller_level() -> int:
    """The ``stacklevel`` of a warning that names the first frame outside
    this package: the user's line that gave the value."""
    frame = sys._getframe(1)
    level = 1
    while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) == _PACKAGE:
        frame = frame.f_back  # type: ignore[assignment]
        level += 1
    return level
_lock = threading.Lock()


def compile(text: str) -> Type["Mechanism"]:  # noqa: A001 (the language's word)
    """Compiles a mechanism definition into a class.

    ``text`` is a definition exactly as written inside ``mechanism! { … }``
    in Rust: a ``struct Name { params {…} drivers {…} unknowns {…} points
    {…} loops {…} … }``. The definition is checked, differentiated exactly
    (the velocity Jacobian and the convective terms of the accelerations),
    split into blocks solved in closed form where a form is known, and
    compiled to machine code, all in this process.

    The result is a subclass of :class:`Mechanism` named after the struct;
    an instance holds one design (the parameter values, as keywords). The
    same text compiles once per process: compiling it again returns the same
    class.

    Raises:
        DefinitionError: with every error of the definition, the line and
            column of the first, and the message the Rust macro gives.
    """
    with _lock:
        cached = _classes.get(text)
    if cached is not None:
        return cached
    native = _native.compile(text)
    keywords = ", ".join(native.parameters)
    doc = (
        f"The mechanism {native.name}, compiled from its definition.\n\n"
        f"Construct a design with its parameters as keywords: "
        f"{native.name}({keywords}).\n"
    )
    coordinates = native.coordinates
    names = tuple(c[0] for c in coordinates)
    cls = MechanismType(
        native.name,
        (Mechanism,),
        {
            "__doc__": doc,
            "_native": native,
            "__module__": __name__.rsplit(".", 1)[0],
            # What every call reads, read from the native object once.
            "_coords": names,
            "_where": {n: i for i, n in enumerate(names)},
            "_kinds": {c[0]: c[2] for c in coordinates},
            "_points": tuple(native.points),
            "_point_where": {n: i for i, n in enumerate(native.points)},
            "_frames": tuple(native.frames),
            "_nd": int(native.drivers),
        },
    )
    with _lock:
        # The metaclass made a subclass of Mechanism.
        return _classes.setdefault(text, cast("Type[Mechanism]", cls))


def load(path: Union[str, "os.PathLike[str]"]) -> Type["Mechanism"]:
    """Compiles the definition in the file ``path`` (a ``.mech`` file)."""
    with open(path, encoding="utf-8") as f:
        return compile(f.read())


def _native_model(text: str, values: List[float]) -> "_native.Model":
    """Rebuilds a native model from its text and values (for pickle)."""
    return compile(text)._native.with_values(values)


def _rebuild(text: str, params: Dict[str, float]) -> "Mechanism":
    """Rebuilds a design from its text and parameters (for pickle)."""
    return compile(text)(**params)


class MechanismType(type):
    """The metaclass of compiled mechanisms: a class pickles as its text."""

    _native: "_native.Model"
    _coords: Tuple[str, ...]
    _where: Dict[str, int]
    _kinds: Dict[str, str]
    _points: Tuple[str, ...]
    _point_where: Dict[str, int]
    _frames: Tuple[str, ...]
    _nd: int

    @property
    def text(cls) -> str:
        """The definition the class was compiled from."""
        return cls._native.text

    def __repr__(cls) -> str:
        return f"<mechanism class {cls.__name__}>"


copyreg.pickle(MechanismType, lambda cls: (compile, (cls._native.text,)))


from ._forces import _Forces
from ._forward import Trajectory, _Forward  # noqa: F401 (Trajectory re-exported)
from ._values import (  # noqa: F401 (re-exported: `loopkin._model` names them too)
    FrameMotion,
    Forces,
    JointReaction,
    MassSensitivity,
    Motion,
    Options,
    PointMotion,
    Pose,
    Sensitivity,
    Values,
    _hint,
    _opts,
    _readonly,
)

# After the values: `_batch` reads `_sweep`, which reads them from here.
from ._batch import _Batch  # noqa: E402

class Mechanism(_Forces, _Forward, _Batch, metaclass=MechanismType):
    """A design of a compiled mechanism: the class :func:`compile` returns,
    with one value per parameter.

    ``FourBar(a=0.04, b=0.12, …)`` checks every value (finite; lengths
    positive; a string with an angle's unit, ``beta="30deg"``, is read in
    radians) and raises :class:`~loopkin.errors.InvalidParameterError` or
    :class:`~loopkin.errors.NonFiniteError` otherwise; a missing or unknown
    keyword is a ``TypeError``. A design is immutable: :meth:`replace` makes
    another. A design pickles as its definition and parameters, so that a
    worker process recompiles it (once per process).
    """

    # Set on each compiled class by compile(), read from the native model
    # once: the model, the coordinates (drivers first) with their index and
    # kind, the points with their index, the frames and the number of
    # drivers.
    _native: ClassVar["_native.Model"]
    _coords: ClassVar[Tuple[str, ...]]
    _where: ClassVar[Dict[str, int]]
    _kinds: ClassVar[Dict[str, str]]
    _points: ClassVar[Tuple[str, ...]]
    _point_where: ClassVar[Dict[str, int]]
    _frames: ClassVar[Tuple[str, ...]]
    _nd: ClassVar[int]
    __slots__ = ("_m",)

    def __init__(self, **params: Union[float, str]) -> None:
        cls = type(self)
        if cls is Mechanism:
            raise TypeError("Mechanism is abstract: make a class with loopkin.compile(text)")
        names = cls._native.parameters
        unknown = [k for k in params if k not in names]
        if unknown:
            hint = _hint(unknown[0], names)
            raise TypeError(f"{cls.__name__} has no parameter {unknown[0]!r}{hint}; its parameters are {list(names)}")
        missing = [n for n in names if n not in params]
        if missing:
            raise TypeError(f"{cls.__name__}() missing parameter(s): {', '.join(missing)}")
        values = [
            _native.read_quantity(v, 3, True) if isinstance(v, str) else float(v)
            for v in (params[n] for n in names)
        ]
        m = cls._native.with_values(values)
        m.validate()
        object.__setattr__(self, "_m", m)

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"a design is immutable: use .replace({name}=…)")

    # -- the definition ---------------------------------------------------

    @classmethod
    def definition(cls) -> str:
        """The text the class was compiled from."""
        return cls._native.text

    @classmethod
    def parameter_names(cls) -> Tuple[str, ...]:
        """The parameters, in declaration order."""
        return tuple(cls._native.parameters)

    @classmethod
    def coordinate_names(cls) -> Tuple[str, ...]:
        """Every coordinate, drivers first."""
        return cls._coords

    @classmethod
    def driver_names(cls) -> Tuple[str, ...]:
        """The drivers."""
        return cls._coords[: cls._nd]

    @classmethod
    def unknown_names(cls) -> Tuple[str, ...]:
        """The unknowns."""
        return cls._coords[cls._nd :]

    @classmethod
    def kinds(cls) -> Dict[str, str]:
        """Each coordinate's kind: "angle" (radians) or "length"."""
        return dict(cls._kinds)

    @classmethod
    def point_names(cls) -> Tuple[str, ...]:
        """The points of interest."""
        return cls._points

    @classmethod
    def frame_names(cls) -> Tuple[str, ...]:
        """The body frames."""
        return cls._frames

    @classmethod
    def blocks(cls) -> List[Dict[str, Any]]:
        """How the loop equations are solved, block by block in solve order:
        ``{"unknowns": […], "method": "closed form: …" or "Newton–Raphson",
        "modes": bool}``."""
        return [{"unknowns": list(u), "method": m, "modes": k} for u, m, k in cls._native.blocks]

    @classmethod
    def describe(cls) -> str:
        """The mechanism described as ``kinematics check`` prints it: its
        coordinates (each an angle or a length), its scalar equations,
        numbered, its blocks in solve order with the equations each is
        solved from and how (a closed form, which dyad, two assembly
        modes or one, or Newton–Raphson), its mobility, its bodies, loads
        and joints, and its number of assemblies."""
        return cls._native.description

    @classmethod
    def sensitivity_parameters(cls) -> Tuple[str, ...]:
        """The parameters of the definition's ``sensitivities`` section."""
        return tuple(cls._native.sensitivity_parameters)

    # -- the design -------------------------------------------------------

    @property
    def params(self) -> Dict[str, float]:
        """The parameter values by name."""
        return dict(zip(self._native.parameters, self._m.values))

    def replace(self: M, **changes: Union[float, str]) -> M:
        """A copy of the design with some parameters changed (a value may be
        a string with a unit, as for the constructor)."""
        p: Dict[str, Union[float, str]] = {**self.params, **changes}
        return type(self)(**p)

    def __reduce__(self) -> Tuple[Any, Tuple[str, Dict[str, float]]]:
        return (_rebuild, (self._native.text, self.params))

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other.params == self.params  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self).__name__, tuple(self._m.values)))

    def __repr__(self) -> str:
        inner = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
        return f"{type(self).__name__}({inner})"

    # -- poses ------------------------------------------------------------

    def pose(self, pose: Optional[Mapping[str, Union[float, str]]] = None, **values: Union[float, str]) -> Pose:
        """A pose from values by name: drivers and guesses of the unknowns
        (a coordinate not given is 0, or its value in ``pose``); a value
        may be a string with a unit, ``phi="30deg"`` (angles in radians
        otherwise).

        Raises:
            KeyError: for a name that is not a coordinate.
        """
        names = self._coords
        # A pose of this class, as it is: its array is read-only.
        if not values and type(pose) is Pose and pose._names is names:
            return pose
        q = np.zeros(len(names))
        if pose is not None:
            for k, v in pose.items():
                q[self._index(k)] = self._quantity(k, v, 0)
        for k, v in values.items():
            q[self._index(k)] = self._quantity(k, v, 0)
        return Pose(names, q, getattr(pose, "modes", None))

    def _quantity(self, name: str, value: Union[float, str], order: int) -> float:
        """``value`` as a number: a string with a unit (``"30deg"``,
        ``"120rpm"``, ``"10deg/s2"``) read for coordinate ``name``'s kind
        at ``order`` (0 value, 1 rate, 2 acceleration), in radians for an
        angle."""
        if isinstance(value, str):
            angle = self._kinds.get(name) == "angle"
            return _native.read_quantity(value, order, angle)
        if (
            order == 0
            and abs(value) > _TWO_TURNS
            and round(value, 1) == value
            and self._kinds.get(name) == "angle"
        ):
            # A number as a person writes degrees (90, 22.5), not one
            # computed in radians (6π, a sample of a sweep of turns).
            v = float(value)
            warnings.warn(
                f"{name}={v:g} is read as {v:g} rad ({v / (2 * math.pi):.1f} turns); "
                f'write {name}="{v:g}deg" for degrees',
                RadiansWarning,
                stacklevel=_caller_level(),
            )
        return value  # type: ignore[return-value]

    def _index(self, name: str) -> int:
        try:
            return self._where[name]
        except KeyError:
            names = self._coords
            hint = _hint(name, names)
            raise KeyError(f"{name!r} is not a coordinate of {type(self).__name__}{hint}: they are {list(names)}") from None

    def residual(self, pose: Mapping[str, Union[float, str]]) -> np.ndarray:
        """Φ(q), one value per loop equation (0 where the loops close)."""
        return self._m.residual(self.pose(pose).array.tolist())

    def assemble(
        self,
        pose: Optional[Mapping[str, Union[float, str]]] = None,
        *,
        modes: Optional[Sequence[str]] = None,
        options: Optional[Options] = None,
        **values: Union[float, str],
    ) -> Pose:
        """Assembles the mechanism at the drivers given (by keyword, or in
        ``pose``), from the guesses of the unknowns there.

        With ``modes`` ("+" or "-" per block with two modes, see
        :meth:`blocks`), the closed-form blocks are solved in those modes
        with no guess; without, each closed-form block takes the mode
        nearest the guess.

        Raises:
            CannotAssembleError: the links cannot close a loop there.
            NotConvergedError: Newton–Raphson found no pose near the guess.
            SingularError: the pose found is singular.
            NonFiniteError, WrongLengthError: bad input.
        """
        q = self.pose(pose, **values)
        if modes is not None:
            out = self._m.assemble_in(q.array.tolist(), list(modes))
            return Pose(q._names, out, modes)
        out = self._m.assemble(q.array.tolist(), _opts(options))
        return Pose(q._names, out)

    def assemble_all(
        self, pose: Optional[Mapping[str, Union[float, str]]] = None, **values: Union[float, str]
    ) -> List[Pose]:
        """Every assembly at the drivers given, one per combination of
        modes that closes (in the order of :meth:`assemblies`), each with
        its ``modes``.

        Raises:
            CannotAssembleError (or the error of the first combination): when
                no combination closes.
        """
        found = []
        first_error: Optional[BaseException] = None
        for modes, result in self.assemblies(pose, **values):
            if isinstance(result, BaseException):
                first_error = first_error or result
            else:
                found.append(result)
        if not found:
            raise first_error or CannotAssembleError("the mechanism does not assemble there")
        return found

    def assemblies(
        self, pose: Optional[Mapping[str, Union[float, str]]] = None, **values: Union[float, str]
    ) -> List[Tuple[Tuple[str, ...], Union[Pose, BaseException]]]:
        """Every combination of modes with its pose, or the exception that
        says why it does not close: combination i has block j in mode "-"
        where bit j of i is set."""
        q = self.pose(pose, **values)
        out: List[Tuple[Tuple[str, ...], Union[Pose, BaseException]]] = []
        for modes, result in self._m.assemble_all(q.array.tolist()):
            if isinstance(result, BaseException):
                out.append((tuple(modes), result))
            else:
                out.append((tuple(modes), Pose(q._names, result, modes)))
        return out

    # -- motion -----------------------------------------------------------

    def _driver_values(
        self,
        what: str,
        one: Optional[Union[float, str]],
        many: Optional[Mapping[str, Union[float, str]]],
        default: float,
    ) -> List[float]:
        if many is None and (one is None or type(one) is float) and self._nd == 1:
            return [default if one is None else one]
        if one is None and many is None:
            return [default] * self._nd
        drivers = self.driver_names()
        if one is not None and many is not None:
            raise TypeError(f"give {what} or {what}s, not both")
        order = 1 if what == "rate" else 2
        if one is not None:
            if len(drivers) != 1:
                raise TypeError(
                    f"{type(self).__name__} has {len(drivers)} drivers: give {what}s={{name: value}} for {list(drivers)}"
                )
            return [float(self._quantity(drivers[0], one, order))]
        out = [default] * len(drivers)
        for k, v in (many or {}).items():
            if k not in drivers:
                raise KeyError(f"{k!r} is not a driver of {type(self).__name__}: they are {list(drivers)}")
            out[drivers.index(k)] = float(self._quantity(k, v, order))
        return out

    def analyze(
        self,
        pose: Mapping[str, Union[float, str]],
        *,
        rate: Optional[Union[float, str]] = None,
        acceleration: Optional[Union[float, str]] = None,
        rates: Optional[Mapping[str, Union[float, str]]] = None,
        accelerations: Optional[Mapping[str, Union[float, str]]] = None,
        options: Optional[Options] = None,
    ) -> Motion:
        """The motion at the closed pose ``pose`` (from :meth:`assemble`):
        the unknowns' rates q' from Φ_u u' = −Φ_d d' and accelerations q''
        from Φ_u u'' = −Φ_d d'' − (Φ_q q')_q q', every point's and frame's
        position, velocity and acceleration, with exact derivatives.

        ``rate``/``acceleration`` for a mechanism with one driver, or
        ``rates``/``accelerations`` by driver name (a driver not given is at
        rest).

        Raises:
            SingularError: at a singular pose.
            NonFiniteError, WrongLengthError: bad input.
        """
        q = self.pose(pose)
        d = self._m.analyze(
            q.array.tolist(),
            self._driver_values("rate", rate, rates, 0.0),
            self._driver_values("acceleration", acceleration, accelerations, 0.0),
            _opts(options),
        )
        return Motion(type(self), d)

    def step(
        self,
        pose: Mapping[str, Union[float, str]],
        *,
        rate: Optional[Union[float, str]] = None,
        acceleration: Optional[Union[float, str]] = None,
        rates: Optional[Mapping[str, Union[float, str]]] = None,
        accelerations: Optional[Mapping[str, Union[float, str]]] = None,
    ) -> Motion:
        """Assembles at the drivers of ``pose`` from its unknowns (as
        :meth:`assemble`) and analyses the motion there (as :meth:`analyze`)
        in one call."""
        q = self.pose(pose)
        d = self._m.step(
            q.array.tolist(),
            self._driver_values("rate", rate, rates, 0.0),
            self._driver_values("acceleration", acceleration, accelerations, 0.0),
        )
        return Motion(type(self), d)

    def _range(
        self, driver: str, to: Optional[Union[float, str]], turn: bool, turns: Optional[float]
    ) -> Optional[float]:
        """The whole turns of a sweep's range (``None`` with an end
        ``to``), once ``driver`` is checked to be a driver."""
        if self._where.get(driver, self._nd) >= self._nd:
            raise KeyError(f"{driver!r} is not a driver of {type(self).__name__}: they are {list(self.driver_names())}")
        if turn and turns is None:
            turns = 1.0
        if to is not None and turns is not None:
            raise TypeError("give either to= or turn/turns=, not both")
        return turns

    def sweep(
        self,
        driver: str,
        *,
        start: Mapping[str, Union[float, str]],
        from_: Optional[Union[float, str]] = None,
        to: Optional[Union[float, str]] = None,
        turn: bool = False,
        turns: Optional[float] = None,
        steps: int = 360,
        rate: Union[float, str] = 1.0,
        rpm: Optional[float] = None,
        acceleration: Union[float, str] = 0.0,
        change_points: str = "stop",
        options: Optional[Options] = None,
    ) -> "Sweep":
        """Sweeps the driver ``driver`` from the pose ``start`` (the other
        drivers stay at their values there, at rest), assembling and
        analysing every sample; runs in native code with the interpreter
        released.

        The range: ``from_`` (default: the start's value) to ``to``
        (included, ``steps + 1`` samples), or ``turn=True`` / ``turns=n``
        (whole turns, the end left out, ``steps`` samples); an angle driver
        makes one turn by default. ``rate`` (or ``rpm`` for an angle) and
        ``acceleration`` are the driver's rate and acceleration. A value may
        be a string with a unit: ``from_="30deg"``, ``rate="120rpm"``,
        ``acceleration="10deg/s2"``.

        The sweep stops early, with :attr:`Sweep.stop` saying why, at a
        limit position, a singular pose or a change point (two branches
        meeting); ``change_points="smooth"`` or ``"switch"`` passes a change
        point on the branch where the motion is smooth, or on the other.

        A sweep backwards (``turns`` < 0, or ``to`` below ``from_``) needs
        a negative rate: its samples follow the motion, and a positive rate
        would be the opposite motion's.

        Raises:
            KeyError: ``driver`` is not a driver.
            ValueError: bad range or options; a sweep backwards with a
                positive rate.
        """
        turns = self._range(driver, to, turn, turns)
        if rpm is not None:
            rate = rpm * 2.0 * math.pi / 60.0
        # (A float needs no reading: the common case, checked first.)
        if type(rate) is not float:
            rate = float(self._quantity(driver, rate, 1))
        if type(acceleration) is not float:
            acceleration = float(self._quantity(driver, acceleration, 2))
        if from_ is not None:
            from_ = self._quantity(driver, from_, 0)
        if to is not None:
            to = self._quantity(driver, to, 0)
        q = self.pose(start)
        # The samples follow the motion: a sweep backwards (turns < 0, or
        # to below from_) with a positive rate would give the velocities
        # of the opposite motion.
        if rate > 0 and ((turns is not None and turns < 0) or to is not None):
            first = from_ if from_ is not None else float(q.array[self._where[driver]])
            if turns is not None or (to is not None and to < first):
                raise ValueError(
                    f"the sweep runs {driver} backwards, from {first:g} "
                    f"{'by ' + format(turns, 'g') + ' turns' if turns is not None else 'to ' + format(to, 'g')}, "
                    f"but its rate {rate:g} is positive: give a negative rate (rate={-rate:g}) "
                    f"for the motion the samples follow"
                )
        native = self._m.sweep(
            driver,
            q.array.tolist(),
            (from_, to, turns, int(steps), rate, acceleration, change_points),
            None if options is None else options._tuple(),
        )
        return Sweep(type(self), self, native)

    def simulate(
        self,
        *,
        start: Mapping[str, Union[float, str]],
        duration: float,
        steps: int,
        values: Optional[Mapping[str, ArrayLike]] = None,
        rates: Optional[Mapping[str, ArrayLike]] = None,
        accelerations: Optional[Mapping[str, ArrayLike]] = None,
        options: Optional[Options] = None,
    ) -> "Sweep":
        """A simulation in time: ``steps + 1`` samples at t = duration·k/steps,
        where each driver follows the arrays given for it (``steps + 1``
        values each: its value, rate and acceleration at each sample); a
        driver with no values stays at its value in ``start``, and a rate
        or acceleration not given is zero. Every sample is assembled and
        analysed as a sweep's (stopping at a singular pose or a change of
        branch); the result is a :class:`Sweep` whose variable is ``t``.

        Raises:
            KeyError: a name that is not a driver.
            ValueError: an array without ``steps + 1`` values.
        """
        drivers = self.driver_names()
        n = int(steps) + 1
        q = self.pose(start)
        table = {}
        for what, given in (("values", values), ("rates", rates), ("accelerations", accelerations)):
            a = np.empty((n, len(drivers)))
            for j, name in enumerate(drivers):
                a[:, j] = q[name] if what == "values" else 0.0
            for name, column in (given or {}).items():
                if name not in drivers:
                    raise KeyError(f"{name!r} is not a driver of {type(self).__name__}: they are {list(drivers)}")
                column = np.asarray(column, dtype=float).reshape(-1)
                if column.size != n:
                    raise ValueError(f"{what}[{name!r}] has {column.size} values; steps={steps} needs {n}")
                a[:, drivers.index(name)] = column
            table[what] = list(a.reshape(-1))
        native = self._m.simulate(
            q.array.tolist(), float(duration), int(steps), table["values"], table["rates"], table["accelerations"], _opts(options)
        )
        return Sweep(type(self), self, native)

    def poses(
        self,
        driver: str,
        *,
        start: Mapping[str, Union[float, str]],
        from_: Optional[Union[float, str]] = None,
        to: Optional[Union[float, str]] = None,
        turn: bool = False,
        turns: Optional[float] = None,
        steps: int = 360,
        options: Optional[Options] = None,
    ) -> "Poses":
        """Positions only, along the same grid as :meth:`sweep`: each pose
        assembled from the previous one (the closed-form blocks in the
        start's modes), then every point's position; no rates, no
        accelerations, no judgement of the conditioning, and no search for
        change points; it stops where the mechanism does not assemble (at a
        limit position, found by bisection as :meth:`sweep` finds it), and
        :attr:`Poses.stop` says why. The fastest way to trace paths.
        ``from_`` and ``to`` may be strings with a unit, as for
        :meth:`sweep`."""
        turns = self._range(driver, to, turn, turns)
        if from_ is not None:
            from_ = self._quantity(driver, from_, 0)
        if to is not None:
            to = self._quantity(driver, to, 0)
        q = self.pose(start)
        parts = self._m.poses(
            driver, q.array.tolist(), (from_, to, turns, int(steps)), None if options is None else options._tuple()
        )
        return Poses(type(self), parts)


# The result classes, imported once the classes they name are defined
# (`_sweep` reads `_model`'s values), not at every call.
from ._sweep import Poses, Sweep  # noqa: E402
