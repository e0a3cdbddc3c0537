"""Figures of merit a linkage designer checks first: the Grashof class of a
four-bar, and over a sweep the transmission angle between two links, the
dead centres of an output, its stroke, its mechanical advantage and a
quick-return's time ratio.

The sweep's figures are methods of :class:`loopkin.Sweep`
(:meth:`~loopkin.Sweep.dead_centres`, :meth:`~loopkin.Sweep.stroke`,
:meth:`~loopkin.Sweep.time_ratio`, :meth:`~loopkin.Sweep.transmission`,
:meth:`~loopkin.Sweep.mechanical_advantage`);
they are computed in native code by the library's ``merit`` module, the
same code that serves the Rust crate and the ``kinematics`` command::

    import loopkin as kin
    kin.grashof(ground=0.11, input=0.04, coupler=0.12, output=0.10).kind  # "crank-rocker"
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Tuple

import numpy as np

from . import _native

__all__ = ["Grashof", "grashof", "DeadCentre", "Stroke", "TimeRatio", "Transmission", "MechanicalAdvantage"]


@dataclass(frozen=True)
class Grashof:
    """A four-bar's Grashof class: ``kind`` is "crank-rocker" (S + L < P + Q,
    the input the shortest: it turns fully), "double-crank" (the ground the
    shortest), "rocker-crank" (the output the shortest), "double-rocker"
    (the coupler the shortest), "triple-rocker" (S + L > P + Q: no link
    turns fully) or "change-point" (S + L = P + Q); with the two sums."""

    kind: str
    s_plus_l: float
    p_plus_q: float


def grashof(ground: float, input: float, coupler: float, output: float) -> Grashof:  # noqa: A002
    """The Grashof class of the four-bar with these link lengths (the
    ground between the fixed pivots, the input link, the coupler, the
    output link).

    Raises:
        InvalidGeometryError: a length that is not positive and finite, or
            a longest link at least the sum of the others.
    """
    kind, sl, pq = _native.grashof(float(ground), float(input), float(coupler), float(output))
    return Grashof(kind, sl, pq)


@dataclass(frozen=True)
class DeadCentre:
    """Where an output's rate changes sign: the swept value ``at``, the
    output's ``value`` there, and whether it is a ``maximum``."""

    at: float
    value: float
    maximum: bool


@dataclass(frozen=True)
class Stroke:
    """An output's least and largest values over a sweep."""

    min: float
    max: float

    @property
    def length(self) -> float:
        """max − min."""
        return self.max - self.min


@dataclass(frozen=True)
class TimeRatio:
    """A quick-return's input angles (rad) from the output's minimum to its
    maximum (``rising``) and back (``falling``), at constant input speed."""

    rising: float
    falling: float

    @property
    def ratio(self) -> float:
        """The slower stroke's angle over the faster one's (≥ 1)."""
        return max(self.rising, self.falling) / min(self.rising, self.falling)


@dataclass(frozen=True)
class Transmission:
    """The transmission angle μ ∈ [0, π] at every sample (``values``, rad),
    its least and largest values and the swept values where they occur."""

    values: np.ndarray
    min: float
    at_min: float
    max: float
    at_max: float

    @property
    def worst_departure(self) -> float:
        """The largest departure of μ from 90° over the sweep (rad)."""
        return max(math.pi / 2 - self.min, self.max - math.pi / 2)


def _transmission(raw: Tuple[np.ndarray, Tuple[float, float], Tuple[float, float]]) -> Transmission:
    values, (at_min, lo), (at_max, hi) = raw
    values.flags.writeable = False
    return Transmission(values, lo, at_min, hi, at_max)


@dataclass(frozen=True)
class MechanicalAdvantage:
    """An output's mechanical advantage at every sample (``values``): the
    ratio of its effort to the input's with no losses and no inertia,
    MA = φ'/q' by the conservation of power (the swept driver's rate over
    the output's; signed, ±inf at the output's dead centres), and the
    least ``|MA|`` with the swept value where it occurs."""

    values: np.ndarray
    least: float
    at_least: float
