"""loopkin against pylinkage 1.3's numba-compiled solver, in one process:
time per position of a whole sweep, positions only and with velocities and
accelerations, on a four-bar and on pylinkage's Strider leg, through each
library's fastest public Python path.

    pip install ./python "pylinkage==1.3.*" numba
    python python/benchmarks/pylinkage_compare.py [turns] [rounds] [designs]

pylinkage: ``pylinkage.solver.simulation.simulate`` (positions) and
``simulate_with_kinematics`` (positions, velocities, accelerations), the
numba-compiled loops under ``Mechanism.step_fast``, given the joint arrays
directly. loopkin: ``Mechanism.poses`` (positions) and ``Mechanism.sweep``
(every coordinate, point, velocity and acceleration, with the limit and
change-point checks). Each round times one sweep of each variant in turn
(A B C D, thread CPU time, after a warm-up that compiles pylinkage's
solver), over ``turns`` turns of 3600 steps; the medians and the ranges
over the rounds are printed, and the ratios per round.

Before timing, the feet (Strider) and the coupler joint (four-bar) of the
two libraries are checked to agree to 1e-12 at every step of a turn.
"""

import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from pylinkage.solver.simulation import simulate, simulate_with_kinematics
from pylinkage.solver.types import JOINT_CRANK, JOINT_REVOLUTE, JOINT_STATIC

import loopkin as kin

STEPS = 3600
MECH = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


class Pylinkage:
    """A linkage as pylinkage's solver takes it: joint types, parents,
    constraints and starting positions."""

    def __init__(self, types, parents, constraints, start, crank):
        flat, offsets = [], []
        for c in constraints:
            offsets.append(len(flat))
            flat.extend(c)
        par = np.full((len(types), 3), -1, dtype=np.int32)
        for j, p in enumerate(parents):
            par[j, :2] = p
        self.args = (
            np.array(flat, dtype=np.float64),
            np.array(types, dtype=np.int32),
            par,
            np.array(offsets, dtype=np.int32),
            np.arange(len(types), dtype=np.int32),
        )
        self.start = np.array(start, dtype=np.float64)
        self.crank = crank

    def positions(self, n):
        return simulate(self.start.copy(), *self.args, n, 1.0)

    def kinematics(self, n, omega):
        z = np.zeros_like(self.start)
        return simulate_with_kinematics(
            self.start.copy(), z.copy(), z.copy(), *self.args,
            np.array([omega]), np.array([0.0]), np.array([self.crank], dtype=np.int32), n, 1.0,
        )


# The four-bar: A = (0, 0), D = (d, 0), crank AB = a, coupler BC = b,
# rocker DC = c; the crank starts at 0 and turns 2π/3600 a step.
A4, B4, C4, D4 = 0.04, 0.12, 0.10, 0.11
FOUR_BAR = Pylinkage(
    [JOINT_STATIC, JOINT_STATIC, JOINT_CRANK, JOINT_REVOLUTE],
    [(-1, -1), (-1, -1), (0, -1), (2, 1)],
    [(), (), (A4, 2 * math.pi / STEPS), (B4, C4)],
    [(0, 0), (D4, 0), (A4, 0), (0.10, 0.11)],
    crank=2,
)

# pylinkage's Strider example, as bench/python/strider_pylinkage.py
# defines it (its joints, parents, constraints and start).
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench" / "python"))
import strider_pylinkage as sp  # noqa: E402

TRI, APE, FEMUR, ROCKER_L, ROCKER_S, PHI, TIBIA, FOOT = sp.TRI, sp.APE, sp.FEMUR, sp.ROCKER_L, sp.ROCKER_S, sp.PHI, sp.TIBIA, sp.FOOT
STRIDER = Pylinkage(sp.TYPES, sp.PARENTS, sp.CONSTRAINTS, sp.START, crank=4)
# The same leg, its crank turning 2π/360 a step.
CRANK = (1.0, 2 * math.pi / STEPS)
assert sp.CONSTRAINTS.count(CRANK) == 1, "the Strider's crank constraint is not where it was"
STRIDER_TURN = Pylinkage(
    sp.TYPES, sp.PARENTS, [(1.0, 2 * math.pi / 360) if c == CRANK else c for c in sp.CONSTRAINTS],
    sp.START, crank=4,
)


def angle(p, q):
    return math.atan2(q[1] - p[1], q[0] - p[0])


def loopkin_four_bar():
    FourBar = kin.load(MECH / "four_bar.mech")
    m = FourBar(a=A4, b=B4, c=C4, d=D4, p=0.06, beta=0.5)
    th0 = 2 * math.pi / STEPS
    start = m.assemble(phi=th0, th3=angle((A4, 0), (0.10, 0.11)), th4=angle((D4, 0), (0.10, 0.11)))
    return m, "phi", start, th0, [("C", 3)]


def loopkin_strider():
    Strider = kin.load(MECH / "strider.mech")
    m = Strider(tri=TRI, ape=APE, femur=FEMUR, rocker_l=ROCKER_L, rocker_s=ROCKER_S, phi=PHI, tibia=TIBIA, foot=FOOT)
    th0 = -math.pi / 2 + 2 * math.pi / STEPS
    c, d, e = (0.0, -1.0), (-2.25, 0.0), (2.25, 0.0)
    f, g, h, i = (-1.4, -1.2), (1.4, -1.2), (-2.7, -2.7), (2.7, -2.7)
    b, bp = (1.41, 1.41), (-1.41, 1.41)
    guess = dict(th=th0, d1=angle(bp, d), d2=angle(c, d), e1=angle(b, e), e2=angle(c, e), h1=angle(d, h),
                 h2=angle(f, h), i1=angle(e, i), i2=angle(g, i))
    return m, "th", m.assemble(**guess), th0, [("H", 9), ("I", 10)]


def check(name, pyl, ours):
    m, driver, start, th0, pairs = ours
    trajectory = pyl.positions(STEPS)
    poses = m.poses(driver, start=start, from_=th0, turn=True, steps=STEPS)
    assert poses.stop is None and len(poses) == STEPS
    worst = max(float(np.abs(poses.point(p) - trajectory[:, j]).max()) for p, j in pairs)
    assert worst < 1e-12, (name, worst)
    print(f"{name}: {', '.join(p for p, _ in pairs)} agree with pylinkage's to {worst:.1e} over a turn")


def measure(name, pyl, ours, turns, rounds, omega=10.0):
    m, driver, start, th0, _ = ours
    n = STEPS * turns
    pyl.positions(STEPS)
    pyl.kinematics(STEPS, omega)  # numba compiles on first use
    variants = {
        "pylinkage positions": lambda: pyl.positions(n),
        "loopkin poses": lambda: m.poses(driver, start=start, from_=th0, turns=turns, steps=n),
        "pylinkage kinematics": lambda: pyl.kinematics(n, omega),
        "loopkin sweep": lambda: m.sweep(driver, start=start, from_=th0, turns=turns, steps=n, rate=omega),
    }
    report(f"{name}, {turns} turns of {STEPS} positions a call", variants, rounds, n)


def measure_turn(name, pyl_turn, ours, rounds, omega=10.0):
    """One turn of 360 positions per call: the calls' fixed costs count.
    The two libraries' points are checked equal first, at every position."""
    m, driver, start, _, pairs = ours
    th0 = start.array[0] + 2 * math.pi / 360 - 2 * math.pi / STEPS
    trajectory = pyl_turn.positions(360)
    poses = m.poses(driver, start=start, from_=th0, turn=True, steps=360)
    assert poses.stop is None and len(poses) == 360
    worst = max(float(np.abs(poses.point(p) - trajectory[:, j]).max()) for p, j in pairs)
    assert worst < 1e-12, (name, worst)
    pyl_turn.kinematics(360, omega)
    variants = {
        "pylinkage positions": lambda: pyl_turn.positions(360),
        "loopkin poses": lambda: m.poses(driver, start=start, from_=th0, turn=True, steps=360),
        "pylinkage kinematics": lambda: pyl_turn.kinematics(360, omega),
        "loopkin sweep": lambda: m.sweep(driver, start=start, from_=th0, turn=True, steps=360, rate=omega),
    }
    report(f"{name}, one turn of 360 positions a call", variants, rounds * 20, 360)


def report(title, variants, rounds, n):
    times = {k: [] for k in variants}
    for _ in range(rounds):
        for k, f in variants.items():
            t0 = time.thread_time_ns()
            f()
            times[k].append((time.thread_time_ns() - t0) / n)
    print(f"\n{title}: ns per position, median (range) over {rounds} rounds")
    for k, v in times.items():
        print(f"  {k:22s} {statistics.median(v):8.1f}  ({min(v):.1f}–{max(v):.1f})")
    for ours_k, theirs_k in (("loopkin poses", "pylinkage positions"), ("loopkin sweep", "pylinkage kinematics")):
        r = [t / u for u, t in zip(times[ours_k], times[theirs_k])]
        print(f"  pylinkage / loopkin, {ours_k.split()[1]:6s}: {statistics.median(r):.2f}× ({min(r):.2f}–{max(r):.2f})")


def four_bar_of(a, b, c, steps):
    """pylinkage's four-bar of crank a, coupler b, rocker c (ground D4), its
    crank turning 2π/steps a step, C started above the ground line."""
    return Pylinkage(
        [JOINT_STATIC, JOINT_STATIC, JOINT_CRANK, JOINT_REVOLUTE],
        [(-1, -1), (-1, -1), (0, -1), (2, 1)],
        [(), (), (a, 2 * math.pi / steps), (b, c)],
        [(0, 0), (D4, 0), (a, 0), (0.10, 0.11)],
        crank=2,
    )


def measure_batch(designs, rounds, omega=10.0):
    """10⁴ four-bar designs (crank, coupler, rocker drawn at random, all
    crank-rockers), 360 positions each with velocities and accelerations:
    pylinkage's solver called once per design (its arrays built before the
    clock starts) against one loopkin batch keeping C's position, velocity
    and acceleration at every sample; process CPU time (the batch runs on
    every core)."""
    rng = np.random.default_rng(7)
    a = rng.uniform(0.030, 0.045, designs)
    b = rng.uniform(0.115, 0.125, designs)
    c = rng.uniform(0.095, 0.105, designs)
    pyl = [four_bar_of(*abc, 360) for abc in zip(a, b, c)]
    m, driver, start, _, _ = loopkin_four_bar()
    th0 = 2 * math.pi / 360
    sweep = dict(driver=driver, from_=th0, turn=True, steps=360, rate=omega)
    outputs = ["C", "C.velocity", "C.acceleration"]

    def ours():
        return m.batch({"a": a, "b": b, "c": c}, start=start, sweep=sweep, outputs=outputs)

    def theirs():
        return [p.kinematics(360, omega) for p in pyl]

    # The same answers first: C's position, velocity and acceleration of
    # every design at every position.
    res, out = ours(), theirs()
    assert bool(res.ok.all())
    worst = 0.0
    for k, (pos, vel, acc) in enumerate(out):
        for got, want in zip((res["C"][k], res["C.velocity"][k], res["C.acceleration"][k]), (pos, vel, acc)):
            scale = max(1.0, float(np.abs(want[:, 3]).max()))
            worst = max(worst, float(np.abs(got - want[:, 3]).max()) / scale)
    print(f"\nbatch: C, its velocity and acceleration agree with pylinkage's to {worst:.1e} (relative) "
          f"over {designs} designs × 360 positions")
    assert worst < 1e-12, worst
    times = {"pylinkage, one call per design": [], "loopkin batch": []}
    for _ in range(rounds):
        for k, f in (("pylinkage, one call per design", theirs), ("loopkin batch", ours)):
            t0 = time.process_time_ns()
            f()
            times[k].append((time.process_time_ns() - t0) / (designs * 360))
    print(f"batch of {designs} designs × 360 positions (v and a): ns of CPU per position, median (range) "
          f"over {rounds} rounds")
    for k, v in times.items():
        print(f"  {k:32s} {statistics.median(v):8.1f}  ({min(v):.1f}–{max(v):.1f})")
    r = [t / u for t, u in zip(times["pylinkage, one call per design"], times["loopkin batch"])]
    print(f"  pylinkage / loopkin, batch : {statistics.median(r):.2f}× ({min(r):.2f}–{max(r):.2f})")


def main():
    turns = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    designs = int(sys.argv[3]) if len(sys.argv) > 3 else 10_000
    four, strider = loopkin_four_bar(), loopkin_strider()
    check("four-bar", FOUR_BAR, four)
    check("Strider", STRIDER, strider)
    measure("four-bar", FOUR_BAR, four, turns, rounds)
    measure("Strider", STRIDER, strider, turns, rounds)
    measure_turn("four-bar", four_bar_of(A4, B4, C4, 360), four, rounds)
    measure_turn("Strider", STRIDER_TURN, strider, rounds)
    measure_batch(designs, rounds)


if __name__ == "__main__":
    main()
