"""Synthesis from Python, as in a notebook: the command's problem files
solved as ``kinematics synthesize`` solves them, and a problem posed with
keywords, each best design drawn at its targets over its path.

    python python/examples/synthesis.py [output folder]

writes the figures (PNG) into the folder (default ``target/loopkin``).
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import loopkin as kin  # noqa: E402
from loopkin.synthesis import synthesize, synthesize_file  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else "target/loopkin")
out.mkdir(parents=True, exist_ok=True)
examples = Path(__file__).resolve().parents[2] / "examples" / "synthesis"

# 1. Problem B of the published benchmarks, from its file: five points at
#    prescribed crank angles.
found = synthesize_file(examples / "problem_b.toml")
best = found.best
print(f"Problem B: E = {best.error:.4e} (best published 1.284e-6), {found.evaluations} evaluations")
print("  design:", {k: round(v, 6) for k, v in best.design.params.items()})
found.figure().figure.savefig(out / "synthesis-problem-b.png", dpi=90)

# 2. The same four-bar posed with keywords: the coupler point through four
#    points of an arc, the crank turning fully, the transmission angle at
#    the rocker pin B kept within [35°, 145°] over the whole turn.
Bench = kin.load(examples / "benchmark_four_bar.mech")
start = Bench(r1=4, r2=1, r3=4, r4=3, rcx=1, rcy=1, x0=0, y0=0, t0=0)
found = synthesize(
    start,
    point="C",
    targets=[[3.0, 3.0], [2.0, 3.6], [1.0, 3.6], [0.0, 3.0]],
    in_order=True,
    values={"x0": 0, "y0": 0, "t0": 0},
    vary={"r1": (1, 6), "r2": (0.5, 3), "r3": (1, 6), "r4": (1, 6), "rcx": (-4, 4), "rcy": (-4, 4)},
    grashof_crank=("r2", "r3", "r4", "r1", 0.1),
    transmission=[(("A", "B", "O4"), "35deg")],
    full_turn=True,
    starts=32,
    seed=1,
)
best = found.best
print(
    f"arc: E = {best.error:.3e}, smallest transmission angle {best.min_transmission * 57.29577951308232:.1f}°,"
    f" {len(found.optima)} distinct optima"
)
found.figure().figure.savefig(out / "synthesis-arc.png", dpi=90)
