"""Serial draws, parallel evaluation: the pattern of the per-unit block sources (the elastic and
transmission-error models)."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable

from rvbacklash.interrupt import check_abandoned


def draw_then_evaluate(n: int, chunk: int, threads: int, draw: Callable[[int, int], Any],
                       evaluate: Callable[[int, Any], None]) -> None:
    """Units [0, n) in chunks: ``draw(start, m)`` in order on this thread (one stream per factor,
    so the numbers do not depend on the pool), ``evaluate(start, units)`` by a pool of ``threads``
    (nogil kernels, each chunk filling its own slice); at most threads + 1 chunks in flight. A
    workbench job's stop drops the block between two chunks (``interrupt.check_abandoned``)."""
    with ThreadPoolExecutor(max_workers=threads) as pool:
        jobs = []
        try:
            for start in range(0, n, chunk):
                check_abandoned()
                m = min(chunk, n - start)
                if len(jobs) > threads:  # bounded memory
                    jobs.pop(0).result()
                jobs.append(pool.submit(evaluate, start, draw(start, m)))
            for job in jobs:
                job.result()
        except BaseException:  # the chunks not yet evaluating are not evaluated
            for job in jobs:
                job.cancel()
            raise
