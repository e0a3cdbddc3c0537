"""Python at native speed: each sweep, poses and batch call of the Python
package against the same work done in Rust through the same run-time
model (`cargo run --release -p kinematics-bench --bin parity`, which this
script runs), alternated: a round of the Rust program, then the same calls
from Python, three times. Each side's time is the median of its rounds of
200 calls (thread CPU time; the batch's, one call a round, in process CPU
time, on every core); the ratio Python / Rust is printed per alternation,
with its range.

    pip install ./python
    cargo build --release -p kinematics-bench --bin parity
    python3 bench/python/parity.py

The calls: on the four-bar and the Strider leg of the examples, a sweep of
one turn of 360 steps at a rate of 1 (every column kept), and one turn of
360 poses; on the four-bar, a batch of 10⁴ designs (crank, coupler, rocker
drawn at random), one turn of 360 positions at 10 rad/s keeping C's
position, velocity and acceleration at every sample.
"""

import math
import statistics
import subprocess
import time
from pathlib import Path

import numpy as np

import loopkin as kin

ROOT = Path(__file__).resolve().parents[2]
MECHANISMS = ROOT / "examples" / "mechanisms"
RUST = ROOT / "target" / "release" / "parity"


def median(rounds, clock, f, calls=200):
    """µs a call: the median of `rounds` rounds of `calls` calls."""
    f()
    t = []
    for _ in range(rounds):
        t0 = clock()
        for _ in range(calls):
            f()
        t.append((clock() - t0) / 1000 / calls)
    return statistics.median(t)


def python_round(rounds=9):
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
    out = {}
    for name, m, drv in designs:
        start = m.assemble_all(**{drv: 0.3})[0]
        out[f"{name} sweep 360"] = median(
            rounds, time.thread_time_ns, lambda: m.sweep(drv, start=start, turn=True, steps=360, rate=1.0)
        )
        out[f"{name} poses 360"] = median(rounds, time.thread_time_ns, lambda: m.poses(drv, start=start, turn=True, steps=360))
    m = designs[0][1]
    rng = np.random.default_rng(7)
    n = 10_000
    params = {"a": rng.uniform(0.030, 0.045, n), "b": rng.uniform(0.115, 0.125, n), "c": rng.uniform(0.095, 0.105, n)}
    start = m.assemble(phi=2 * math.pi / 360, th3=0.9, th4=1.6)
    sweep = dict(driver="phi", turn=True, steps=360, rate=10.0)

    def batch():
        res = m.batch(params, start=start, sweep=sweep, outputs=["C", "C.velocity", "C.acceleration"])
        assert bool(res.ok.all())

    out["four-bar batch 10000x360"] = median(min(rounds, 5), time.process_time_ns, batch, calls=1)
    return out


def rust_round():
    text = subprocess.run([str(RUST)], check=True, capture_output=True, text=True).stdout
    return {line.rsplit(" ", 1)[0]: float(line.rsplit(" ", 1)[1]) for line in text.splitlines()}


def main():
    ratios, times = {}, {}
    for _ in range(3):
        rust, py = rust_round(), python_round()
        for k, v in py.items():
            ratios.setdefault(k, []).append(v / rust[k])
            times.setdefault(k, []).append((v, rust[k]))
    print("µs a call, Python and Rust (medians of each side's rounds), and Python / Rust per alternation")
    for k, r in ratios.items():
        py = statistics.median(t for t, _ in times[k])
        rs = statistics.median(t for _, t in times[k])
        print(f"  {k:26s} {py:11.2f} {rs:11.2f}   {statistics.median(r):.3f} ({min(r):.3f}–{max(r):.3f})")


if __name__ == "__main__":
    main()
