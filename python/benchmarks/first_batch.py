"""The first batch of a class compiled afresh: what a small study pays.

    pip install ./python numpy
    python python/benchmarks/first_batch.py [rounds]

For 10, 100 and 1000 four-bar designs × 360 positions (with velocities
and accelerations, then positions only), each round compiles the
definition afresh (a class of its own name, so that nothing compiled by
an earlier round is reused), takes a batch of two designs at four
positions a turn (which compiles the plain step and pose, and no code in
vector lanes: its steps are too long for them), then times the batch of
the given size: wall and process CPU time, the medians over the rounds
(seven by default). A batch compiles its code in vector lanes only once
the model's batches have run enough positions to pay for it
(`Batch::LANES_FROM_STEPS`, `Batch::LANES_FROM_POSES`); before, every
batch in pairs compiled it,
about 2.4 ms for the four-bar's step and 1.3 ms for its pose.
"""

import statistics
import sys
import time

import numpy as np

import loopkin as kin

TEXT = """struct FourBar{k} {{
    params   {{ a, b, c, d, p, beta }}
    drivers  {{ phi }}
    unknowns {{ th3, th4 }}
    points   {{ B = polar(a, phi); C = vec2(d, 0.0) + polar(c, th4); P = B + polar(p, th3 + beta); }}
    loops    {{ B + polar(b, th3) == C; }}
}}"""

COUNT = [0]


def once(n, positions_only):
    """Wall and CPU ms of the first batch of `n` designs of a class
    compiled afresh."""
    COUNT[0] += 1
    four_bar = kin.compile(TEXT.format(k=COUNT[0]))
    m = four_bar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = m.assemble_all(phi=0.5)[0]
    a = np.linspace(0.03, 0.05, n)
    m.batch({"a": a[:2]}, start=start, sweep=dict(driver="phi", turn=True, steps=4),
            outputs=["P"], positions_only=positions_only)
    t0, c0 = time.perf_counter(), time.process_time()
    m.batch({"a": a}, start=start, sweep=dict(driver="phi", turn=True, steps=360),
            outputs=["P"], positions_only=positions_only)
    return (time.perf_counter() - t0) * 1e3, (time.process_time() - c0) * 1e3


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    print(f"first batch of a class compiled afresh, 360 positions a design: ms, "
          f"median of {rounds} rounds")
    for positions_only in (False, True):
        for n in (10, 100, 1000):
            r = [once(n, positions_only) for _ in range(rounds)]
            wall = statistics.median(x[0] for x in r)
            cpu = statistics.median(x[1] for x in r)
            what = "positions only" if positions_only else "v and a"
            print(f"  {what:14} {n:5d} designs: {wall:7.2f} wall, {cpu:7.2f} CPU")


if __name__ == "__main__":
    main()
