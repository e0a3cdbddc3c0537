"""A design study on a local Ray cluster (on the loopback interface) gives
exactly what the in-process batch gives.

Skipped where Ray is not installed, unless LOOPKIN_REQUIRE_RAY is set (as
the project's CI sets it), where its absence fails."""

import os
import signal
from pathlib import Path

import numpy as np
import pytest

from conftest import mechanism

if os.environ.get("LOOPKIN_REQUIRE_RAY"):
    import ray
else:
    ray = pytest.importorskip("ray")


@pytest.fixture(scope="module")
def cluster():
    ray.init(
        address="local",
        num_cpus=2,
        include_dashboard=False,
        _node_ip_address="127.0.0.1",
        log_to_driver=False,
        configure_logging=False,
    )
    yield
    ray.shutdown()


def test_a_study_of_100000_designs_on_ray_equals_the_in_process_batch(cluster):
    from loopkin import cluster as kin_cluster

    FourBar = mechanism("four_bar")
    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = m.assemble_all(phi=0.0)[0]
    rng = np.random.default_rng(5)
    n = 100_000
    params = {"a": rng.uniform(0.03, 0.11, n), "c": rng.uniform(0.08, 0.12, n), "beta": rng.uniform(-1, 1, n)}
    kw = dict(start=start, sweep=dict(driver="phi", turn=True, steps=12, rpm=300), outputs=["th3", "P", "P.velocity"])
    there = kin_cluster.batch(m, params, chunk_size=12_500, **kw)
    here = m.batch(params, **kw)
    assert there.params.shape == (n, 6)
    assert np.array_equal(there.params, here.params)
    for k in ("th3", "P", "P.velocity"):
        assert np.array_equal(there[k], here[k], equal_nan=True)
    assert np.array_equal(there.samples, here.samples)
    assert there.stops == here.stops
    # Some designs cannot turn (a + d > b + c); the study says which.
    assert 0 < (~here.ok).sum() < n and here.ok.sum() > n // 2


def _running_chunks():
    """The process ids of the Ray workers running a chunk now (Ray names
    a worker's process after the task it runs)."""
    pids = []
    for proc in Path("/proc").iterdir():
        if proc.name.isdigit():
            try:
                cmd = (proc / "cmdline").read_bytes()
            except OSError:
                continue
            if cmd.startswith(b"ray::_run_chunk"):
                pids.append(int(proc.name))
    return pids


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="finds the workers through /proc")
def test_a_worker_killed_mid_study_costs_only_its_chunk(cluster):
    from loopkin import cluster as kin_cluster

    FourBar = mechanism("four_bar")
    m = FourBar(a=0.04, b=0.12, c=0.10, d=0.11, p=0.06, beta=0.5)
    start = m.assemble_all(phi=0.0)[0]
    rng = np.random.default_rng(11)
    n = 120_000
    params = {"a": rng.uniform(0.02, 0.06, n), "b": rng.uniform(0.10, 0.14, n)}
    kw = dict(start=start, sweep=dict(driver="phi", turn=True, steps=360, rpm=600), outputs=["P.acceleration"], reduce="peak")
    killed, reports = [], []

    def progress(done, total):
        reports.append((done, total))
        # At the first chunk done, kill a worker in the middle of another.
        if not killed:
            for pid in _running_chunks():
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
                break

    there = kin_cluster.batch(m, params, chunk_size=15_000, progress=progress, **kw)
    assert killed, "no worker was running a chunk when the first one finished"
    here = m.batch(params, **kw)
    assert np.array_equal(there["P.acceleration"], here["P.acceleration"], equal_nan=True)
    assert np.array_equal(there.samples, here.samples) and there.stops == here.stops
    # A report per chunk, the designs done growing to all of them.
    assert len(reports) == 8 and reports[-1] == (n, n)
    assert all(a[0] < b[0] for a, b in zip(reports, reports[1:]))
    with pytest.raises(ValueError, match="retries"):
        kin_cluster.batch(m, params, retries=-1, **kw)
