"""Design studies larger than one machine, on Ray.

A design pickles as its definition's text and its parameters, so that
every worker process compiles the definition once and runs its share of
the designs in native code. :func:`batch` splits a study into chunks, runs
:meth:`Mechanism.batch <loopkin.Mechanism.batch>` on each chunk as a Ray
task (each task on all the cores of its node) and joins the results in the
designs' order, equal to what one in-process batch gives.

Start or join a cluster first (``ray.init()`` on a laptop,
``ray.init(address="auto")`` on a cluster's node); Ray is an optional
dependency: ``pip install loopkin[ray]``.
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ._model import ArrayLike, Mechanism
from ._sweep import Batch

__all__ = ["batch"]


def _run_chunk(design: Mechanism, params: Mapping[str, np.ndarray], kwargs: Mapping[str, Any]) -> Batch:
    return design.batch(params, **kwargs)


def batch(
    design: Mechanism,
    params: Mapping[str, ArrayLike],
    *,
    chunk_size: int = 10_000,
    **kwargs: Any,
) -> Batch:
    """:meth:`Mechanism.batch <loopkin.Mechanism.batch>` over Ray: the
    designs in chunks of ``chunk_size``, each chunk a task; ``kwargs`` as
    for ``Mechanism.batch`` (``start``, ``sweep``, ``outputs``, …).

    Raises:
        ImportError: Ray is not installed.
        RuntimeError: no Ray cluster is running (call ``ray.init()``).
    """
    try:
        import ray
    except ImportError as e:  # pragma: no cover
        raise ImportError("loopkin.cluster needs Ray: pip install loopkin[ray]") from e
    if not ray.is_initialized():
        raise RuntimeError("no Ray cluster: call ray.init() (or ray.init(address='auto')) first")
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be at least 1, not {chunk_size}")
    arrays = {k: np.asarray(v, dtype=float).reshape(-1) for k, v in params.items()}
    n = max((a.size for a in arrays.values()), default=1)
    task = ray.remote(_run_chunk)
    ref = ray.put(design)
    futures = [
        task.remote(ref, {k: a[i : i + chunk_size] for k, a in arrays.items()}, kwargs) for i in range(0, n, chunk_size)
    ]
    return Batch.concatenate(ray.get(futures))
