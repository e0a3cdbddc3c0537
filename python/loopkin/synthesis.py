"""Dimensional synthesis with exact derivatives.

:func:`synthesize` runs the library's global search (the one behind
``kinematics synthesize``): seeded feasible starting designs inside the
bounds, each refined by Levenberg–Marquardt with the exact Jacobian on
every core, the constraints checked over the whole motion, the distinct
optima ranked. Its keywords are the fields of the command's problem file.

:func:`path` (needs SciPy: ``pip install loopkin[synthesis]``) finds the parameters for which a point passes through target
positions at prescribed values of the driver, minimising

    E = Σ_i |r(d_i; p) − t_i|²

by SciPy's trust-region least squares, with the Jacobian ∂r/∂p taken from
the design sensitivities (exact, from Φ_u ∂u/∂p = −Φ_p), not from finite
differences. The parameters varied must be listed in the definition's
``sensitivities`` section. Every pose is assembled in the same assembly
modes, so that the design found runs on one branch through all targets.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._model import ArrayLike, Mechanism, Pose
from .errors import KinematicsError

__all__ = ["synthesize", "synthesize_file", "Found", "Optimum", "path", "Synthesized"]


class Synthesized:
    """The result of a synthesis.

    Attributes:
        design: the best design found.
        error: E = Σ_i |r(d_i) − t_i|² of that design.
        residuals: r(d_i) − t_i, an array of shape (targets, dim).
        poses: the design's pose at each target.
        evaluations: how many times the targets were evaluated.
        result: SciPy's ``OptimizeResult``.
    """

    def __init__(self, design: Mechanism, error: float, residuals: np.ndarray, poses: Sequence[Pose], evaluations: int, result: Any) -> None:
        self.design = design
        self.error = error
        self.residuals = residuals
        self.poses = list(poses)
        self.evaluations = evaluations
        self.result = result

    def __repr__(self) -> str:
        return f"Synthesized({self.design!r}, error={self.error:.3e})"


Amount = Union[float, str]


class Optimum:
    """One local optimum the search found.

    Attributes:
        design: the design (a :class:`~loopkin.Mechanism` of the class
            searched).
        error: E = Σ_j w_j |output_j − target_j|².
        target_errors: |output_j − target_j| at each target (an array).
        max_error: the largest of them.
        driver_values: the driver's value at each target (an array).
        poses: the design's pose at each target, in its assembly modes.
        full_turn: whether an angle driver turns fully (None for a length).
        min_transmission: the smallest transmission angle over the motion,
            folded into [0, π/2] (rad), of the dyads constrained; None with
            none.
        feasible: whether every constraint holds over the motion.
        one_branch: whether the motion passes from target to target
            without a stop (no branch or circuit defect).
        reached_by: how many refined starts ended here.
    """

    def __init__(self, design: Mechanism, d: Mapping[str, Any]) -> None:
        cls = type(design)
        self.design = cls(**dict(zip(cls.parameter_names(), d["values"])))
        self.error: float = d["error"]
        self.target_errors = np.asarray(d["target_errors"], dtype=float)
        self.max_error: float = d["max_error"]
        self.driver_values = np.asarray(d["driver_values"], dtype=float)
        names = cls.coordinate_names()
        self.poses = [self.design.pose(dict(zip(names, q))) for q in d["poses"]]
        self.full_turn: Optional[bool] = d["full_turn"]
        self.min_transmission: Optional[float] = d["min_transmission"]
        self.feasible: bool = d["feasible"]
        self.one_branch: bool = d["one_branch"]
        self.reached_by: int = d["reached_by"]

    def __repr__(self) -> str:
        return f"Optimum(error={self.error:.4e}, feasible={self.feasible}, reached_by={self.reached_by})"


class Found:
    """What a search found: :attr:`optima`, feasible first, each group by
    E ascending; :attr:`best`, the first feasible one (None without one);
    the evaluations, the starts drawn, those for which no feasible design
    was drawn, and what stopped the search early (``"evaluations"``,
    ``"time"`` or None)."""

    def __init__(self, design: Mechanism, problem: Dict[str, Any], d: Mapping[str, Any]) -> None:
        self.optima: List[Optimum] = [Optimum(design, o) for o in d["optima"]]
        self.evaluations: int = d["evaluations"]
        self.starts: int = d["starts"]
        self.undrawn: int = d["undrawn"]
        self.stopped_by: Optional[str] = d["stopped_by"]
        self.problem = problem

    @property
    def best(self) -> Optional[Optimum]:
        """The best feasible optimum, or None."""
        return self.optima[0] if self.optima and self.optima[0].feasible else None

    def figure(self, ax: Any = None, steps: int = 360) -> Any:
        """The best design at its targets over the path of its point
        (path and motion generation), the targets marked; on ``ax`` or a
        new figure's axes (matplotlib), which are returned."""
        from .plot import _pyplot

        best = self.best or (self.optima[0] if self.optima else None)
        if best is None:
            raise ValueError("the search found no design to draw")
        plt = _pyplot()
        if ax is None:
            _, ax = plt.subplots(figsize=(7, 7))
        task = self.problem["task"]
        m = best.design
        driver = self.problem["driver"]
        if task["kind"] in ("path", "motion"):
            point = task["point"]
            first = best.poses[0]
            if best.full_turn:
                sweeps = [m.sweep(driver, start=first, turn=True, steps=steps)]
            else:
                lo, hi = float(best.driver_values.min()), float(best.driver_values.max())
                sweeps = [m.sweep(driver, start=first, to=to, steps=steps, rate=(1.0 if to > first[driver] else -1.0)) for to in (lo, hi) if to != first[driver]]
            for k, sw in enumerate(sweeps):
                r = sw.point(point).position
                ax.plot(r[:, 0], r[:, 1], color="0.4", lw=1.2, label=f"path of {point}" if k == 0 else None)
            t = np.array([[float(_native.read_quantity(v, 3, True)) if isinstance(v, str) else float(v) for v in row[:2]] for row in self.problem["targets"]])
            ax.plot(t[:, 0], t[:, 1], "o", mfc="none", mec="tab:red", ms=9, label="targets")
        links = [(a, b) for a, b in _links(m, best.poses[0], driver)]
        for j, pose in enumerate(best.poses):
            motion = m.analyze(pose)
            colour = plt.cm.viridis(j / max(len(best.poses) - 1, 1))
            for a, b in links:
                pa, pb = motion.points[a].position, motion.points[b].position
                ax.plot([pa[0], pb[0]], [pa[1], pb[1]], color=colour, lw=1.5, label=f"target {j + 1}" if (a, b) == links[0] else None)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"{type(m).__name__}: E = {best.error:.3e}")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
        ax.figure.tight_layout()
        return ax

    def __repr__(self) -> str:
        return f"Found({len(self.optima)} optima, best={self.best!r}, evaluations={self.evaluations})"


def _links(m: Mechanism, pose: Pose, driver: str) -> List[Tuple[str, str]]:
    """The links found from a short sweep of the design (the pairs drawn)."""
    sw = m.sweep(driver, start=pose, to=pose[driver] + 0.3, steps=8)
    pairs: List[Tuple[str, str]] = []
    for link in sw.links():
        pts = list(link.points)
        if len(pts) == 2:
            pairs.append((pts[0], pts[1]))
        elif not link.frame:
            pairs.extend((pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts)))
    return pairs


def _amount(v: Amount) -> Union[float, str]:
    """A value for the problem's JSON: a string as written, a number as a
    float (one that is not finite as its text, which the problem refuses
    by name)."""
    if isinstance(v, str):
        return v
    x = float(v)
    return x if math.isfinite(x) else repr(x)


def synthesize(
    design: Mechanism,
    *,
    targets: Union[Sequence[Sequence[Amount]], np.ndarray],
    vary: Mapping[str, Tuple[Amount, Amount]],
    point: Optional[str] = None,
    motion: Optional[Tuple[str, str, float]] = None,
    output: Optional[str] = None,
    driver: Optional[str] = None,
    prescribed: Optional[Sequence[Amount]] = None,
    relative: Optional[Sequence[Amount]] = None,
    in_order: bool = False,
    order_span: Optional[Amount] = None,
    modes: Optional[Sequence[str]] = None,
    values: Optional[Mapping[str, Amount]] = None,
    sampling: Optional[Mapping[str, Tuple[Amount, Amount]]] = None,
    start: Optional[Mapping[str, Amount]] = None,
    weights: Optional[Sequence[float]] = None,
    at_most: Optional[Sequence[Tuple[Mapping[str, float], float]]] = None,
    grashof_crank: Optional[Tuple[str, str, str, str, float]] = None,
    transmission: Optional[Sequence[Tuple[Tuple[str, str, str], Amount]]] = None,
    inside: Optional[Sequence[Tuple[str, Sequence[float], Sequence[float]]]] = None,
    full_turn: bool = False,
    starts: int = 16,
    keep: int = 8,
    seed: int = 0,
    evaluations: Optional[int] = None,
    seconds: Optional[float] = None,
    tries: Optional[int] = None,
    patience: Optional[int] = None,
    progress: Optional[Callable[[int, int, int, int, float, int], None]] = None,
) -> Found:
    """The library's global search for a synthesis problem of ``design``'s
    class, from its parameters not varied; the keywords are the fields of
    ``kinematics synthesize``'s problem file (``kinematics_core::synthesis::Spec``).

    The task: ``point="C"`` (path generation: ``targets`` its positions),
    ``motion=("C", "th3", length)`` (motion generation: each target
    ``[x, y, θ]``, an angle's error weighed by ``length``) or
    ``output="th4"`` (function generation: each target ``[input,
    output]``). ``vary`` maps each varied parameter to its bounds; the
    timing is free unless ``prescribed`` (a driver value per target) or
    ``relative`` (increments from a free first value) is given;
    ``in_order`` keeps free driver values increasing, less than a turn (or
    ``order_span``). Constraints: ``grashof_crank=(crank, coupler, rocker,
    ground, margin)``, ``at_most=[({name: c}, bound)]``,
    ``transmission=[(("B", "C", "D"), "40deg")]``, ``inside=[(point, lo,
    hi)]``, ``full_turn``. The search: ``starts``, ``keep``, ``seed``, a
    budget of ``evaluations`` or ``seconds``; ``progress`` is called with
    (screened, starts, refined, keep, best E, evaluations). Values may be
    strings with an angle's unit (``"30deg"``).

    Raises:
        KinematicsError: a name that is not the mechanism's, bounds that
            are not finite, targets of the wrong size (the message says
            which).
        ValueError: no task or more than one.
    """
    cls = type(design)
    tasks = [t for t in (point, motion, output) if t is not None]
    if len(tasks) != 1:
        raise ValueError("give exactly one task: point= (path), motion= (motion) or output= (function generation)")
    if point is not None:
        task: Dict[str, Any] = {"kind": "path", "point": point}
    elif motion is not None:
        task = {"kind": "motion", "point": motion[0], "angle": motion[1], "length": float(motion[2])}
    else:
        task = {"kind": "function", "output": output}
    if driver is None:
        if len(cls.driver_names()) != 1:
            raise ValueError(f"name the driver: {cls.__name__} has drivers {list(cls.driver_names())}")
        driver = cls.driver_names()[0]
    rows = [[_amount(v) for v in row] for row in (targets.tolist() if isinstance(targets, np.ndarray) else targets)]
    problem: Dict[str, Any] = {"driver": driver, "task": task, "targets": rows}
    if prescribed is not None and relative is not None:
        raise ValueError("give prescribed= or relative=, not both")
    if prescribed is not None:
        problem["timing"] = {"prescribed": [_amount(v) for v in prescribed]}
    elif relative is not None:
        problem["timing"] = {"relative": [_amount(v) for v in relative]}
    problem["in_order"] = bool(in_order)
    if order_span is not None:
        problem["order_span"] = _amount(order_span)
    if modes is not None:
        problem["modes"] = list(modes)
    problem["vary"] = {k: [_amount(lo), _amount(hi)] for k, (lo, hi) in vary.items()}
    problem["sampling"] = {k: [_amount(lo), _amount(hi)] for k, (lo, hi) in (sampling or {}).items()}
    problem["values"] = {k: _amount(v) for k, v in (values or {}).items()}
    problem["start"] = {k: _amount(v) for k, v in (start or {}).items()}
    if weights is not None:
        problem["weights"] = [float(w) for w in weights]
    problem["at_most"] = [{"terms": {k: float(c) for k, c in terms.items()}, "bound": float(b)} for terms, b in (at_most or [])]
    if grashof_crank is not None:
        crank, coupler, rocker, ground, *margin = grashof_crank
        problem["grashof_crank"] = {"crank": crank, "coupler": coupler, "rocker": rocker, "ground": ground, "margin": float(margin[0]) if margin else 0.0}
    problem["transmission"] = [{"points": list(pts), "min": _amount(mu)} for pts, mu in (transmission or [])]
    problem["inside"] = [{"point": p, "lo": [float(x) for x in lo], "hi": [float(x) for x in hi]} for p, lo, hi in (inside or [])]
    problem["full_turn"] = bool(full_turn)
    problem["search"] = {"starts": int(starts), "keep": int(keep), "seed": int(seed), "evaluations": evaluations, "seconds": seconds, "tries": tries, "patience": patience}
    fixed = {k: v for k, v in problem["values"].items() if k not in cls.sensitivity_parameters()}
    if fixed:
        design = design.replace(**{k: (_native.read_quantity(v, 3, True) if isinstance(v, str) else v) for k, v in fixed.items()})
        problem["values"] = {k: v for k, v in problem["values"].items() if k not in fixed}
    q = np.zeros(len(cls.coordinate_names()))
    raw = _native.synthesize(design._m, json.dumps(problem), list(q), progress)
    return Found(design, problem, raw)


def synthesize_file(
    path: Union[str, "os.PathLike[str]"],
    *,
    seed: Optional[int] = None,
    starts: Optional[int] = None,
    progress: Optional[Callable[[int, int, int, int, float, int], None]] = None,
) -> Found:
    """Solves the problem file of ``kinematics synthesize`` (TOML: the
    definition's file ``mechanism``, beside it, and the fields of
    :func:`synthesize`), as the command does: the definition loaded, its
    parameters set from ``values`` and the varied ones to mid-range, then
    the library's search (``seed`` and ``starts`` replace the file's).
    Reading TOML needs Python 3.11 (``tomllib``) or the ``tomli`` package.

    Raises:
        KinematicsError: as :func:`synthesize`; ValueError: the file names
            no definition.
    """
    try:
        import tomllib  # type: ignore[import-not-found]
    except ImportError:  # pragma: no cover
        import tomli as tomllib  # type: ignore[no-redef]
    from ._model import load

    file = Path(path)
    problem: Dict[str, Any] = tomllib.loads(file.read_text(encoding="utf-8"))
    if "mechanism" not in problem:
        raise ValueError(f"{file}: the problem names no definition; add mechanism = \"file.mech\"")
    cls = load(file.parent / problem["mechanism"])
    params: Dict[str, Any] = {}
    for k, v in problem.get("values", {}).items():
        params[k] = v
    for k, (lo, hi) in problem.get("vary", {}).items():
        lo, hi = (_native.read_quantity(x, 3, True) if isinstance(x, str) else float(x) for x in (lo, hi))
        params.setdefault(k, 0.5 * (lo + hi))
    design = cls(**params)
    search = dict(problem.get("search", {}))
    if seed is not None:
        search["seed"] = int(seed)
    if starts is not None:
        search["starts"] = int(starts)
    problem["search"] = search
    problem["values"] = {k: v for k, v in problem.get("values", {}).items() if k in cls.sensitivity_parameters()}
    q = np.zeros(len(cls.coordinate_names()))
    raw = _native.synthesize(design._m, json.dumps(problem), list(q), progress)
    return Found(design, problem, raw)


def path(
    design: Mechanism,
    point: str,
    targets: Union[Sequence[Sequence[float]], np.ndarray],
    driver_values: ArrayLike,
    *,
    vary: Sequence[str],
    start: Optional[Mapping[str, float]] = None,
    modes: Optional[Sequence[str]] = None,
    bounds: Optional[Mapping[str, Tuple[float, float]]] = None,
    **least_squares: Any,
) -> Synthesized:
    """Path generation with prescribed timing: the parameters ``vary`` of
    ``design`` (its other parameters fixed) for which ``point`` is at
    ``targets[i]`` when the driver is at ``driver_values[i]``.

    ``start`` is a pose whose unknowns guess the first target's (and whose
    modes are kept, unless ``modes`` is given); ``bounds`` maps a parameter
    to (low, high). Further keywords go to ``scipy.optimize.least_squares``.

    Raises:
        ValueError: a parameter of ``vary`` is not in the definition's
            ``sensitivities`` section, or the targets do not match the
            driver values.
    """
    try:
        from scipy.optimize import least_squares as solve
    except ImportError as e:  # pragma: no cover
        raise ImportError("loopkin.synthesis needs SciPy: pip install loopkin[synthesis]") from e
    cls = type(design)
    missing = [p for p in vary if p not in cls.sensitivity_parameters()]
    if missing:
        raise ValueError(
            f"{missing} must be listed in the definition's `sensitivities` section to be varied "
            f"(it lists {list(cls.sensitivity_parameters())})"
        )
    if len(cls.driver_names()) != 1:
        raise ValueError("path synthesis needs a mechanism with one driver")
    driver = cls.driver_names()[0]
    t = np.asarray(targets, dtype=float)
    d = np.asarray(driver_values, dtype=float).reshape(-1)
    if t.ndim != 2 or t.shape[0] != d.size:
        raise ValueError(f"targets must be an array of shape ({d.size}, dim), one per driver value; got {t.shape}")
    guess = design.pose(start or {}, **{driver: float(d[0])})
    if modes is None:
        modes = _modes_near(design, guess)
    modes = list(modes)
    x0 = np.array([design.params[p] for p in vary])
    scale = max(float(np.ptp(t, axis=0).max()), 1e-300)
    cache: Dict[bytes, Tuple[np.ndarray, np.ndarray, list]] = {}
    count = [0]

    def evaluate(x: np.ndarray) -> Tuple[np.ndarray, np.ndarray, list]:
        key = x.tobytes()
        if key in cache:
            return cache[key]
        count[0] += 1
        r = np.empty_like(t)
        jac = np.zeros((t.size, len(vary)))
        poses: list = []
        try:
            m = design.replace(**dict(zip(vary, x)))
            q: Mapping[str, float] = guess
            for i, value in enumerate(d):
                pose = m.assemble(m.pose(q, **{driver: float(value)}), modes=modes)
                motion = m.analyze(pose)
                sens = m.sensitivities(motion)
                r[i] = motion.points[point].position - t[i]
                for k, p in enumerate(vary):
                    jac[i * t.shape[1] : (i + 1) * t.shape[1], k] = sens[p].points[point].position
                poses.append(pose)
                q = pose
        except KinematicsError:
            # Outside the designs that assemble at every target: a flat,
            # high plateau, which the trust region steps back from.
            r[:] = 10.0 * scale
            jac[:] = 0.0
            poses = []
        out = (r.reshape(-1), jac, poses)
        cache.clear()
        cache[key] = out
        return out

    lo = np.array([(bounds or {}).get(p, (-np.inf, np.inf))[0] for p in vary])
    hi = np.array([(bounds or {}).get(p, (-np.inf, np.inf))[1] for p in vary])
    least_squares.setdefault("x_scale", "jac")
    result = solve(lambda x: evaluate(x)[0], x0, jac=lambda x: evaluate(x)[1], bounds=(lo, hi), **least_squares)
    best = design.replace(**dict(zip(vary, result.x)))
    r, _, poses = evaluate(result.x)
    return Synthesized(best, float(r @ r), r.reshape(t.shape), poses, count[0], result)


def _modes_near(design: Mechanism, guess: Pose) -> Sequence[str]:
    """The modes of the assembly nearest the guess (by its unknowns)."""
    best: Optional[Tuple[float, Sequence[str]]] = None
    for modes, pose in design.assemblies(guess):
        if isinstance(pose, BaseException):
            continue
        diff = np.asarray(pose.array) - np.asarray(guess.array)
        angles = np.array([design.kinds()[n] == "angle" for n in pose])
        diff[angles] = np.remainder(diff[angles] + np.pi, 2 * np.pi) - np.pi
        gap = float(np.abs(diff).sum())
        if best is None or gap < best[0]:
            best = (gap, modes)
    if best is None:
        return ["+"] * design._native.mode_count
    return best[1]
