"""Design studies larger than one machine, on Ray.

A design pickles as its definition's text and its parameters, so that
every worker process compiles the definition once and runs its share of
the designs in native code. :func:`batch` splits a study into chunks, runs
:meth:`Mechanism.batch <loopkin.Mechanism.batch>` on each chunk as a Ray
task (each task on all the cores of its node) and joins the results in the
designs' order, equal to what one in-process batch gives. A chunk whose
worker dies (killed, out of memory, its node lost) is run again, up to
``retries`` times, so that a failure costs only that chunk; ``progress``
hears of every chunk as it finishes.

Start or join a cluster first (``ray.init()`` on a laptop,
``ray.init(address="auto")`` on a cluster's node); Ray is an optional
dependency: ``pip install loopkin[ray]``.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping, Optional

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
    retries: int = 3,
    progress: Optional[Callable[[int, int], None]] = None,
    **kwargs: Any,
) -> Batch:
    """:meth:`Mechanism.batch <loopkin.Mechanism.batch>` over Ray: the
    designs in chunks of ``chunk_size``, each chunk a task; ``kwargs`` as
    for ``Mechanism.batch`` (``start``, ``sweep``, ``outputs``,
    ``reduce``, …).

    A chunk whose worker process dies is run again, up to ``retries``
    times (an error of the study itself, such as a bad keyword, is not
    retried). ``progress(done, total)`` is called with the designs done
    so far each time a chunk finishes.

    Raises:
        ImportError: Ray is not installed.
        RuntimeError: no Ray cluster is running (call ``ray.init()``).
        ValueError: ``chunk_size`` below 1 or ``retries`` below 0.
    """
    try:
        import ray
    except ImportError as e:  # pragma: no cover
        raise ImportError("loopkin.cluster needs Ray: pip install loopkin[ray]") from e
    if not ray.is_initialized():
        raise RuntimeError("no Ray cluster: call ray.init() (or ray.init(address='auto')) first")
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be at least 1, not {chunk_size}")
    if retries < 0:
        raise ValueError(f"retries must be 0 or more, not {retries}")
    arrays = {k: np.asarray(v, dtype=float).reshape(-1) for k, v in params.items()}
    n = max((a.size for a in arrays.values()), default=1)
    task = ray.remote(_run_chunk).options(max_retries=retries, retry_exceptions=False)
    ref = ray.put(design)
    starts = list(range(0, n, chunk_size))
    futures = [task.remote(ref, {k: a[i : i + chunk_size] for k, a in arrays.items()}, kwargs) for i in starts]
    sizes = {f: min(chunk_size, n - i) for f, i in zip(futures, starts)}
    waiting, done = list(futures), 0
    while waiting:
        ready, waiting = ray.wait(waiting, num_returns=1)
        done += sum(sizes[f] for f in ready)
        if progress is not None:
            progress(done, n)
    return Batch.concatenate(ray.get(futures))
