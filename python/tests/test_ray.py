"""A design study on a local Ray cluster (on the loopback interface) gives
exactly what the in-process batch gives.

Skipped where Ray is not installed, unless LOOPKIN_REQUIRE_RAY is set (as
the project's CI sets it), where its absence fails."""

import os

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
