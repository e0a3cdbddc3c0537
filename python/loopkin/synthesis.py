"""Dimensional synthesis with exact derivatives (needs SciPy:
``pip install loopkin[synthesis]``).

:func:`path` finds the parameters for which a point passes through target
positions at prescribed values of the driver, minimising

    E = Σ_i |r(d_i; p) − t_i|²

by SciPy's trust-region least squares, with the Jacobian ∂r/∂p taken from
the design sensitivities (exact, from Φ_u ∂u/∂p = −Φ_p), not from finite
differences. The parameters varied must be listed in the definition's
``sensitivities`` section. Every pose is assembled in the same assembly
modes, so that the design found runs on one branch through all targets.
"""

from __future__ import annotations

from typing import Any, Dict, Mapping, Optional, Sequence, Tuple

import numpy as np

from ._model import ArrayLike, Mechanism, Pose
from .errors import KinematicsError

__all__ = ["path", "Synthesized"]


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


def path(
    design: Mechanism,
    point: str,
    targets: ArrayLike,
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
                pose = m.assemble(q, modes=modes, **{driver: float(value)})
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
