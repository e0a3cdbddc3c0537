"""What a call from Python adds to the same work in Rust, through the same
model: ``Mechanism.sweep`` and ``Mechanism.poses`` against the native work
they run, done by the extension module with nothing handed back to Python
(``_repeat_in_rust``: the same sweep builder, the same columns filled,
then dropped).

    pip install ./python
    python python/benchmarks/python_overhead.py [rounds]

For the four-bar and the Strider leg of ``examples/mechanisms`` and three
sizes (36, 360 and 3600 positions a call), each round times one call of
each variant in turn (thread CPU time, interleaved: Python sweep, Rust
sweep, Python poses, Rust poses), enough calls a round for about 10⁴
positions. Printed: ns per position, the median and range over the
rounds, and the ratio Python ÷ Rust of each round (median and range). The
aim is at most 1.15.
"""

import math
import statistics
import sys
import time
from pathlib import Path

import loopkin as kin

MECH = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


def angle(p, q):
    return math.atan2(q[1] - p[1], q[0] - p[0])


def four_bar():
    m = kin.load(MECH / "four_bar.mech")(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = m.assemble(phi=0.0, th3=angle((0.04, 0), (0.10, 0.11)), th4=angle((0.11, 0), (0.10, 0.11)))
    return m, "phi", start


def strider():
    m = kin.load(MECH / "strider.mech")(
        tri=2.0, ape=math.pi / 4, femur=1.8, rocker_l=2.6, rocker_s=1.4, phi=math.pi + 0.2, tibia=2.5, foot=1.8
    )
    c, d, e = (0.0, -1.0), (-2.25, 0.0), (2.25, 0.0)
    f, g, h, i = (-1.4, -1.2), (1.4, -1.2), (-2.7, -2.7), (2.7, -2.7)
    b, bp = (1.41, 1.41), (-1.41, 1.41)
    start = m.assemble(
        th=-math.pi / 2, d1=angle(bp, d), d2=angle(c, d), e1=angle(b, e), e2=angle(c, e),
        h1=angle(d, h), h2=angle(f, h), i1=angle(e, i), i2=angle(g, i),
    )
    return m, "th", start


def variants(m, driver, start, steps, omega=10.0):
    """The four calls of one size: each sweeps one turn in ``steps``
    steps from the start. The native ones take the arguments the Python
    methods hand to the extension module."""
    q = start.array.tolist()
    spec = (None, None, 1.0, steps, omega, 0.0, "stop")
    native = m._m
    return {
        "Python sweep": lambda: m.sweep(driver, start=start, turns=1.0, steps=steps, rate=omega),
        "Rust sweep": lambda: native._repeat_in_rust("sweep", driver, q, spec, None, 1),
        "Python poses": lambda: m.poses(driver, start=start, turns=1.0, steps=steps),
        "Rust poses": lambda: native._repeat_in_rust("poses", driver, q, spec, None, 1),
    }


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 15
    for name, make in (("four-bar", four_bar), ("Strider", strider)):
        m, driver, start = make()
        # Both do the same work: the same samples.
        s = m.sweep(driver, start=start, turns=1.0, steps=360, rate=10.0)
        p = m.poses(driver, start=start, turns=1.0, steps=360)
        assert s.stop is None and p.stop is None and len(s) == len(p) == 360, (s.stop, p.stop)
        for steps in (36, 360, 3600):
            calls = max(1, 10_000 // steps)
            vs = variants(m, driver, start, steps)
            for f in vs.values():
                f()
            times = {k: [] for k in vs}
            for _ in range(rounds):
                for k, f in vs.items():
                    t0 = time.thread_time_ns()
                    for _ in range(calls):
                        f()
                    times[k].append((time.thread_time_ns() - t0) / (calls * steps))
            print(f"\n{name}, {steps} positions a call ({calls} calls a round): ns per position, median (range) over {rounds} rounds")
            for k, v in times.items():
                print(f"  {k:13s} {statistics.median(v):8.1f}  ({min(v):.1f}–{max(v):.1f})")
            for what in ("sweep", "poses"):
                r = [a / b for a, b in zip(times[f"Python {what}"], times[f"Rust {what}"])]
                print(f"  Python / Rust, {what}: {statistics.median(r):.3f} ({min(r):.3f}–{max(r):.3f})")


if __name__ == "__main__":
    main()
