"""Shared fixtures: the definitions shipped with the project."""

from pathlib import Path

import pytest

import loopkin as kin

MECHANISMS = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


def mechanism(name: str):
    """The class of the shipped definition ``name.mech``."""
    return kin.load(MECHANISMS / f"{name}.mech")


@pytest.fixture(scope="session")
def FourBar():
    return mechanism("four_bar")


@pytest.fixture(scope="session")
def four_bar(FourBar):
    return FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)


def close(got, want, tol, scale=None):
    """|got − want| ≤ tol · max(1, |want|) (elementwise, or by the scale)."""
    import numpy as np

    got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    s = np.maximum(1.0, np.abs(want) if scale is None else scale)
    return bool(np.all(np.abs(got - want) <= tol * s))
