"""A batch of 10⁶ four-bar designs, 360 positions each (velocities and
accelerations included), on every core of this machine: the peak
acceleration of the coupler point per design.

    python python/benchmarks/batch_million.py [designs] [chunk] [--ray]

The designs (crank, coupler, rocker and coupler-point offset drawn at
random, seed 1) run in chunks through ``Mechanism.batch``, which releases
the interpreter and runs each chunk on all cores; the coupler point's
acceleration is reduced to its peak per design as the batch runs
(``reduce="peak"``), so that no sample is kept. Prints the wall time, the
time per position, and how many designs turn fully.

With ``--ray`` the same study runs, in alternation with the in-process
batch (two rounds each), through ``loopkin.cluster.batch`` on a local Ray
cluster of one worker per core (started before the clock, each worker
compiling the definition on its first chunk; each task runs its chunk's
batch on the node's threads), and the two are printed
side by side as wall time per position times the cores: the CPU a
position costs each way, the in-process batch's from its threads and
Ray's from its worker processes, with the driver's scheduling and the
transfer of the chunks' results included.
"""

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

import loopkin as kin

MECH = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


def ray_study(designs, chunk):
    """In-process batch against loopkin.cluster.batch, alternated: the
    wall time per position times the cores, each way."""
    import ray

    from loopkin import cluster

    cores = os.cpu_count() or 1
    ray.init(num_cpus=cores, include_dashboard=False, log_to_driver=False)
    FourBar = kin.load(MECH / "four_bar.mech")
    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = m.assemble_all(phi=0.0)[1]
    rng = np.random.default_rng(1)
    params = {k: rng.uniform(lo, hi, designs) for k, (lo, hi) in
              {"a": (0.02, 0.06), "b": (0.10, 0.14), "c": (0.08, 0.12), "p": (0.03, 0.09)}.items()}
    kw = dict(start=start, sweep=dict(driver="phi", turn=True, steps=360, rpm=600),
              outputs=["P.acceleration"], reduce="peak")
    # Warm the workers (each compiles the definition once).
    cluster.batch(m, {k: v[: 2 * cores] for k, v in params.items()}, chunk_size=2, **kw)
    times = {"in-process batch": [], "Ray, one worker per core": []}
    results = {}
    for _ in range(2):
        for name, run in (("in-process batch", lambda: m.batch(params, **kw)),
                          ("Ray, one worker per core", lambda: cluster.batch(m, params, chunk_size=chunk, **kw))):
            t0 = time.perf_counter()
            res = run()
            times[name].append(time.perf_counter() - t0)
            results[name] = np.asarray(res["P.acceleration"])
    a, b = results.values()
    assert np.array_equal(a, b, equal_nan=True), "Ray's results differ from the in-process batch's"
    positions = designs * 360
    print(f"{designs} designs × 360 positions, {cores} cores: wall time × cores per position (two rounds)")
    for name, t in times.items():
        per = [w * cores / positions * 1e9 for w in t]
        print(f"  {name:26s} {min(per):6.1f}–{max(per):6.1f} ns per position per core "
              f"({min(t):.2f}–{max(t):.2f} s wall)")
    ray.shutdown()


def main():
    if "--ray" in sys.argv:
        sys.argv.remove("--ray")
        designs = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
        chunk = int(sys.argv[2]) if len(sys.argv) > 2 else 20_000
        ray_study(designs, chunk)
        return
    designs = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    chunk = int(sys.argv[2]) if len(sys.argv) > 2 else 50_000
    FourBar = kin.load(MECH / "four_bar.mech")
    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = m.assemble_all(phi=0.0)[1]
    rng = np.random.default_rng(1)
    params = {
        "a": rng.uniform(0.02, 0.06, designs),
        "b": rng.uniform(0.10, 0.14, designs),
        "c": rng.uniform(0.08, 0.12, designs),
        "p": rng.uniform(0.03, 0.09, designs),
    }
    sweep = dict(driver="phi", turn=True, steps=360, rpm=600)
    peak = np.empty(designs)
    full = 0
    t0 = time.perf_counter()
    c0 = time.process_time()
    for i in range(0, designs, chunk):
        part = {k: v[i : i + chunk] for k, v in params.items()}
        res = m.batch(part, start=start, sweep=sweep, outputs=["P.acceleration"], reduce="peak")
        peak[i : i + chunk] = res["P.acceleration"]
        full += int(res.ok.sum())
    wall = time.perf_counter() - t0
    cpu = time.process_time() - c0
    positions = designs * 360
    print(f"{designs} designs × 360 positions on {os.cpu_count()} cores: {wall:.1f} s wall, {cpu:.1f} s CPU")
    print(f"{wall / positions * 1e9:.0f} ns wall per position, {cpu / positions * 1e9:.0f} ns CPU per position")
    print(f"{full} designs turn fully; peak |a_P| median {np.median(peak[np.isfinite(peak)]):.1f} m/s²")
    assert math.isfinite(wall)


if __name__ == "__main__":
    main()
