"""Plots of sweeps with matplotlib (an optional dependency:
``pip install loopkin[plot]``).

Each function draws on the axes given, or on a new figure's, and returns
the axes; angles are drawn in degrees.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Iterable, Optional, Sequence, Tuple

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from ._sweep import Deviations, Sweep

__all__ = ["motion", "path", "point", "band"]


def _pyplot() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover
        raise ImportError("loopkin.plot needs matplotlib: pip install loopkin[plot]") from e
    return plt


def _x(sweep: "Sweep") -> Tuple[np.ndarray, str]:
    kinds = sweep.design.kinds()
    if kinds.get(sweep.variable) == "angle":
        return np.degrees(sweep.at), f"{sweep.variable} (deg)"
    if sweep.variable == "t":
        return sweep.at, "t (s)"
    return sweep.at, f"{sweep.variable} (m)"


def motion(sweep: "Sweep", coordinates: Optional[Sequence[str]] = None, axes: Optional[Sequence[Any]] = None) -> Any:
    """The unknowns (or ``coordinates``), their rates and accelerations
    against the swept driver, on three stacked axes."""
    plt = _pyplot()
    if axes is None:
        _, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 8))
    names = list(coordinates) if coordinates is not None else list(sweep.design.unknown_names())
    x, label = _x(sweep)
    kinds = sweep.design.kinds()
    for name in names:
        scale = (180 / math.pi) if kinds[name] == "angle" else 1.0
        axes[0].plot(x, sweep.q[name] * scale, label=name)
        axes[1].plot(x, sweep.qd[name] * scale, label=name)
        axes[2].plot(x, sweep.qdd[name] * scale, label=name)
    axes[0].set_ylabel("value (deg or m)")
    axes[1].set_ylabel("rate (deg/s or m/s)")
    axes[2].set_ylabel("acceleration (deg/s² or m/s²)")
    axes[2].set_xlabel(label)
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best")
    axes[0].figure.tight_layout()
    return axes


def path(sweep: "Sweep", points: Iterable[str], ax: Any = None, projection: Tuple[int, int] = (0, 1)) -> Any:
    """The paths of ``points`` (their positions over the sweep), with equal
    scales on both axes."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 6))
    i, j = projection
    for name in points:
        r = sweep.point(name).position
        ax.plot(r[:, i], r[:, j], label=name)
        ax.plot(r[:1, i], r[:1, j], "o", color=ax.lines[-1].get_color())
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("xyz"[i] + " (m)")
    ax.set_ylabel("xyz"[j] + " (m)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    ax.figure.tight_layout()
    return ax


def point(sweep: "Sweep", name: str, axes: Optional[Sequence[Any]] = None) -> Any:
    """The speed |v| and the acceleration |a| of point ``name`` against the
    swept driver."""
    plt = _pyplot()
    if axes is None:
        _, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    x, label = _x(sweep)
    p = sweep.point(name)
    axes[0].plot(x, p.speed)
    axes[0].set_ylabel(f"|v_{name}| (m/s)")
    axes[1].plot(x, p.acceleration_magnitude)
    axes[1].set_ylabel(f"|a_{name}| (m/s²)")
    axes[1].set_xlabel(label)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    axes[0].figure.tight_layout()
    return axes


def band(sweep: "Sweep", name: str, deviations: "Deviations", magnify: float = 1.0, ax: Any = None) -> Any:
    """The path of point ``name`` with its worst-case tolerance band,
    magnified ``magnify`` times: at each sample, the path offset both ways
    along its normal n by |n_x| w_x + |n_y| w_y, the largest normal
    deviation allowed by the worst-case components (w_x, w_y)."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 6))
    r = sweep.point(name).position[:, :2]
    w = deviations.position_components[:, :2] * magnify
    t = np.gradient(r, axis=0)
    t /= np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-300)
    n = np.column_stack([-t[:, 1], t[:, 0]])
    h = (np.abs(n) * w).sum(axis=1, keepdims=True)
    outer, inner = r + h * n, r - h * n
    ring = np.vstack([outer, outer[:1], inner[:1], inner[::-1]])
    ax.fill(ring[:, 0], ring[:, 1], color="tab:orange", alpha=0.25, lw=0, label=f"worst case ×{magnify:g}")
    ax.plot(outer[:, 0], outer[:, 1], color="tab:orange", lw=0.7)
    ax.plot(inner[:, 0], inner[:, 1], color="tab:orange", lw=0.7)
    ax.plot(r[:, 0], r[:, 1], color="tab:blue", label=f"{name}, nominal")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"tolerance band of {name}, magnified {magnify:g}×")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    ax.figure.tight_layout()
    return ax
