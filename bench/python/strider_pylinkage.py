"""Positions of the Strider leg over turns of its crank, by pylinkage's
numba-compiled solver, for the comparison in the README (`cargo run
--release -p kinematics-bench --bin strider`).

    pip install pylinkage numba
    python3 bench/python/strider_pylinkage.py [turns]

Drives `pylinkage.solver.simulation.simulate` directly with the Strider's
joints (two fixed frame points, the crank, four circle-circle joints and
two points fixed to the rocker arms), with the dimensions of pylinkage's
Strider example. Prints the foot positions (H, I) at the first samples,
for the cross-check against the Rust side, then the time per step over
five repetitions of `turns` turns of 3600 steps (thread CPU time, after a
warm-up that compiles the solver).
"""

import math
import sys
import time

import numpy as np
from pylinkage.solver.simulation import simulate
from pylinkage.solver.types import (
    JOINT_CRANK,
    JOINT_FIXED,
    JOINT_REVOLUTE,
    JOINT_STATIC,
)

STEPS = 3600
# Frame triangle, its aperture, femur, long rocker, short rocker, the
# short rocker's angle to the long one, tibia, foot link.
TRI, APE, FEMUR, ROCKER_L, ROCKER_S, PHI, TIBIA, FOOT = (
    2.0, math.pi / 4, 1.8, 2.6, 1.4, math.pi + 0.2, 2.5, 1.8,
)

# Joints: A, Y, B, B', C, D, E, F, G, H, I.
TYPES = [JOINT_STATIC, JOINT_STATIC, JOINT_FIXED, JOINT_FIXED, JOINT_CRANK,
         JOINT_REVOLUTE, JOINT_REVOLUTE, JOINT_FIXED, JOINT_FIXED,
         JOINT_REVOLUTE, JOINT_REVOLUTE]
PARENTS = [(-1, -1), (-1, -1), (0, 1), (0, 1), (0, -1), (3, 4), (2, 4),
           (4, 6), (4, 5), (5, 7), (6, 8)]
CONSTRAINTS = [(), (), (TRI, -APE), (TRI, APE), (1.0, 2 * math.pi / STEPS),
               (FEMUR, ROCKER_L), (FEMUR, ROCKER_L), (ROCKER_S, -PHI),
               (ROCKER_S, PHI), (TIBIA, FOOT), (TIBIA, FOOT)]
# The starting positions of the example: the crank pin below A, the knees
# outside, the feet below.
START = [(0, 0), (0, 1), (1.41, 1.41), (-1.41, 1.41), (0, -1), (-2.25, 0),
         (2.25, 0), (-1.4, -1.2), (1.4, -1.2), (-2.7, -2.7), (2.7, -2.7)]


def arrays():
    flat, offsets = [], []
    for c in CONSTRAINTS:
        offsets.append(len(flat))
        flat.extend(c)
    parents = np.full((len(TYPES), 3), -1, dtype=np.int32)
    for j, p in enumerate(PARENTS):
        parents[j, :2] = p
    return (
        np.array(START, dtype=np.float64),
        np.array(flat, dtype=np.float64),
        np.array(TYPES, dtype=np.int32),
        parents,
        np.array(offsets, dtype=np.int32),
        np.arange(len(TYPES), dtype=np.int32),
    )


def run(iterations):
    positions, constraints, types, parents, offsets, order = arrays()
    return simulate(positions, constraints, types, parents, offsets, order,
                    iterations, 1.0)


def main():
    turns = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    trajectory = run(STEPS)
    for k in (0, 1, 900, 1800, 2700):
        h, i = trajectory[k, 9], trajectory[k, 10]
        print(f"step {k}: H = ({h[0]:.15f}, {h[1]:.15f}), I = ({i[0]:.15f}, {i[1]:.15f})")
    times = []
    for _ in range(5):
        t0 = time.thread_time_ns()
        run(STEPS * turns)
        times.append((time.thread_time_ns() - t0) / (STEPS * turns))
    print("ns per step:", " ".join(f"{t:.1f}" for t in times))


if __name__ == "__main__":
    main()
