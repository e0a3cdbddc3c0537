"""The fixed cost of a call from Python, for `python/README.md`: each call
of the Python API against the native method it wraps (the same work in
the native module, with the arrays it hands over), interleaved in one
process, in thread CPU time; the median and range of nine rounds. A
sweep of one step shows the fixed cost alone, which the noise of a
360-sample sweep (a few µs) hides. Run
with loopkin installed in release (`pip install ./python`):

    python3 bench/python/per_call.py

The library's own time for the same calls is printed by
`cargo run --release -p kinematics-bench --bin per_call`.
"""

import math
import time
from pathlib import Path

import loopkin as kin

MECHANISMS = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


def rounds(pairs, n):
    """Median and range (µs a call) of each of `pairs`' two functions,
    alternated round by round."""
    times = [([], []) for _ in pairs]
    for _ in range(9):
        for (f, g), (tf, tg) in zip(pairs, times):
            for fn, out in ((f, tf), (g, tg)):
                fn()
                t0 = time.thread_time_ns()
                for _ in range(n):
                    fn()
                out.append((time.thread_time_ns() - t0) / n / 1000)
    return [tuple(sorted(t)[4] for t in pair) + tuple((min(t), max(t)) for t in pair) for pair in times]


def main():
    FourBar = kin.load(MECHANISMS / "four_bar.mech")
    Strider = kin.load(MECHANISMS / "strider.mech")
    designs = [
        ("four-bar", FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5), "phi"),
        (
            "Strider",
            Strider(tri=2.0, ape=math.pi / 4, femur=1.8, rocker_l=2.6, rocker_s=1.4, phi=math.pi + 0.2, tibia=2.5, foot=1.8),
            "th",
        ),
    ]
    print("µs a call: Python API, native method, Python's share (median of 9 rounds; range)")
    for name, m, drv in designs:
        start = m.assemble_all(**{drv: 0.3})[0]
        q = start.array.tolist()
        calls = [
            ("pose", lambda: m.pose(start), lambda: None, 20000),
            ("assemble", lambda: m.assemble(start), lambda: m._m.assemble(start.array.tolist(), None), 20000),
            (
                "analyze",
                lambda: m.analyze(start, rate=10.0),
                lambda: m._m.analyze(start.array.tolist(), [10.0], [0.0], None),
                20000,
            ),
            (
                "sweep 1",
                lambda: m.sweep(drv, start=start, to=0.31, steps=1),
                lambda: m._m.sweep(drv, q, (None, 0.31, None, 1, 1.0, 0.0, "stop"), None),
                2000,
            ),
            (
                "poses 1",
                lambda: m.poses(drv, start=start, to=0.31, steps=1),
                lambda: m._m.poses(drv, q, (None, 0.31, None, 1), None),
                2000,
            ),
            (
                "sweep 360",
                lambda: m.sweep(drv, start=start, turn=True, steps=360),
                lambda: m._m.sweep(drv, q, (None, None, 1.0, 360, 1.0, 0.0, "stop"), None),
                300,
            ),
            (
                "poses 360",
                lambda: m.poses(drv, start=start, turn=True, steps=360),
                lambda: m._m.poses(drv, q, (None, None, 1.0, 360), None),
                300,
            ),
        ]
        results = []
        for what, f, g, n in calls:
            (py, native, rpy, rnative), = rounds([(f, g)], n)
            results.append((what, py, native, rpy, rnative))
        for what, py, native, rpy, rnative in results:
            print(
                f"{name:9} {what:10} {py:9.2f} ({rpy[0]:.2f}–{rpy[1]:.2f})  {native:9.2f} "
                f"({rnative[0]:.2f}–{rnative[1]:.2f})  {py - native:7.2f}"
            )


if __name__ == "__main__":
    main()
