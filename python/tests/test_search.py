"""The library's global search from Python, as a notebook would use it:
Problem B of the published path-generation benchmarks (five points,
prescribed crank angles) posed with keywords, its best design re-scored
by the sources' closed form of the coupler point written here, its
figure drawn; mistakes are errors that name them."""

import math
from pathlib import Path

import numpy as np
import pytest

import loopkin as kin
from loopkin.synthesis import synthesize

DEFINITION = Path(__file__).resolve().parents[2] / "examples" / "synthesis" / "benchmark_four_bar.mech"
TARGETS = [[3.0, 3.0], [2.759, 3.363], [2.372, 3.663], [1.890, 3.862], [1.355, 3.943]]
ANGLES = ["30deg", "45deg", "60deg", "75deg", "90deg"]


def coupler(r1, r2, r3, r4, rcx, rcy, th2):
    """C on the sources' branch ((A − O4) × (B − O4) < 0), the crank pivot
    at the origin and the ground link along x: B from the circles about A
    and O4, C = A + rcx u + rcy n (written here, not the library's)."""
    a = np.array([r2 * math.cos(th2), r2 * math.sin(th2)])
    d = np.array([r1, 0.0]) - a
    l = math.hypot(*d)
    along = (r3 * r3 - r4 * r4 + l * l) / (2 * l)
    h = math.sqrt(r3 * r3 - along * along)
    u = d / l
    n = np.array([-u[1], u[0]])
    for s in (1.0, -1.0):
        b = a + along * u + s * h * n
        if (a[0] - r1) * b[1] - a[1] * (b[0] - r1) < 0:
            e = (b - a) / r3
            return a + rcx * e + rcy * np.array([-e[1], e[0]])
    raise AssertionError("no intersection on the branch")


def problem_b(Bench, **extra):
    start = Bench(r1=10, r2=2, r3=10, r4=10, rcx=1, rcy=1, x0=0, y0=0, t0=0)
    lengths = {k: (0.0, 50.0) for k in ("r1", "r2", "r3", "r4")}
    return synthesize(
        start,
        point="C",
        targets=TARGETS,
        prescribed=ANGLES,
        modes=["-"],
        grashof_crank=("r2", "r3", "r4", "r1", 0.0),
        vary={**lengths, "rcx": (-50, 50), "rcy": (-50, 50)},
        sampling={k: (5.0, 50.0) for k in lengths},
        **extra,
    )


def test_problem_b_beats_the_published_error_from_python(tmp_path):
    Bench = kin.load(DEFINITION)
    calls = []
    found = problem_b(Bench, progress=lambda *p: calls.append(p))
    best = found.best
    assert best is not None and best.feasible, found
    p = best.design.params
    e = sum(
        float(np.sum((coupler(p["r1"], p["r2"], p["r3"], p["r4"], p["rcx"], p["rcy"], math.radians(deg)) - np.array(t)) ** 2))
        for deg, t in zip((30, 45, 60, 75, 90), TARGETS)
    )
    assert e <= 1.284e-6, e
    assert abs(e - best.error) <= 1e-9 * e
    assert np.allclose(best.driver_values, np.radians([30, 45, 60, 75, 90]), atol=1e-15)
    assert len(best.poses) == 5 and best.target_errors.shape == (5,)
    assert p["x0"] == 0.0 and p["t0"] == 0.0
    # The progress was reported, ending with every start screened.
    assert calls and calls[-1][0] == 16, calls[-3:]
    assert found.evaluations > 0 and found.starts == 16
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    ax = found.figure()
    png = tmp_path / "synthesis.png"
    ax.figure.savefig(png, dpi=80)
    assert png.stat().st_size > 10_000


def test_search_mistakes_are_errors():
    Bench = kin.load(DEFINITION)
    start = Bench(r1=10, r2=2, r3=10, r4=10, rcx=1, rcy=1, x0=0, y0=0, t0=0)
    with pytest.raises(kin.InvalidGeometryError, match="`q` is not a parameter"):
        synthesize(start, point="C", targets=TARGETS, vary={"q": (0, 1)})
    with pytest.raises(kin.InvalidGeometryError, match="no point `Z`"):
        synthesize(start, point="Z", targets=TARGETS, vary={"r1": (0, 1)})
    with pytest.raises(kin.InvalidGeometryError, match="vary.r1: `inf` is not a finite number"):
        synthesize(start, point="C", targets=TARGETS, vary={"r1": (0, float("inf"))})
    with pytest.raises(ValueError, match="exactly one task"):
        synthesize(start, targets=TARGETS, vary={"r1": (0, 1)})


def test_the_command_s_problem_files_are_solved_as_the_command_solves_them():
    """The data files of ``kinematics synthesize`` from Python: Problem B
    (the same design as the keywords give), and the slider-crank's
    function generation, re-scored by x = a cos φ + √(b² − (a sin φ − e)²)."""
    from loopkin.synthesis import synthesize_file

    try:
        import tomllib  # noqa: F401
    except ImportError:
        pytest.importorskip("tomli")
    folder = DEFINITION.parent
    b = synthesize_file(folder / "problem_b.toml").best
    again = problem_b(kin.load(DEFINITION)).best
    assert b.error == again.error and b.design.params == again.design.params
    found = synthesize_file(folder / "slider_crank_function.toml", seed=1)
    best = found.best
    p = best.design.params
    for phi, deg in zip(best.driver_values, (20, 70, 130, 190, 250, 310)):
        assert abs(phi - math.radians(deg)) < 1e-15
    want = [0.05 * math.cos(f) + math.sqrt(0.04 - (0.05 * math.sin(f) - 0.01) ** 2) for f in best.driver_values]
    got = [p["a"] * math.cos(f) + math.sqrt(p["b"] ** 2 - (p["a"] * math.sin(f) - p["e"]) ** 2) for f in best.driver_values]
    assert max(abs(g - w) for g, w in zip(got, want)) < 1e-11
    assert best.full_turn is True
