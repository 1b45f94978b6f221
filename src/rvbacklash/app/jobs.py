"""Computations off the event loop, the newest one winning.

Every computation runs in a worker thread: one for the production runs behind the cards, one for
the figures that follow them (loops, TE curves: a next change's run never waits for them), one
for reading and checking designs, one for the on-demand Sobol / allocation / report runs (a long
allocation never delays a card). A request may
name a ``channel`` (the page names one per kind of figure): a newer request on the same channel
supersedes the older one, which is cancelled (if it has not started, it never starts; if it is
running, its progress callback raises at the next block) and answered ``409 superseded``. The
page also checks the request id it gets back: no older input's result is ever shown as the newer
one's. ``POST /api/cancel`` cancels a job by id (the page's cancel button).
"""

from __future__ import annotations

import asyncio
import itertools
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any, Callable


class Cancelled(Exception):
    """A job that was cancelled or superseded (raised by its progress callback)."""

    def __init__(self, job: "Job"):
        super().__init__(job.reason)
        self.job = job


@dataclass(eq=False)
class Job:
    """One computation: its id (the client's request id, or one given here), its channel, how far
    it is (``done`` of ``total``) and whether it was cancelled."""

    id: str
    channel: str | None
    total: int | None = None
    done: int = 0
    state: str = "queued"  # queued | running | finished | cancelled | failed
    reason: str = ""
    cancel_event: threading.Event = field(default_factory=threading.Event)

    def cancel(self, reason: str) -> None:
        if not self.cancel_event.is_set():
            self.reason = reason
            self.cancel_event.set()

    def progress(self, done: int, total: int | None = None) -> None:
        """The progress callback given to the analyses: records how far, stops a cancelled job."""
        self.done = int(done)
        if total is not None:
            self.total = int(total)
        if self.cancel_event.is_set():
            raise Cancelled(self)

    def to_dict(self) -> dict:
        return {"id": self.id, "channel": self.channel, "state": self.state, "done": self.done, "total": self.total,
                "reason": self.reason}


class Jobs:
    """The workbench's computations: two worker threads (live, on demand), newest wins per channel."""

    def __init__(self, keep: int = 64):
        self._pools = {"live": ThreadPoolExecutor(1, thread_name_prefix="rvb-live"),
                       "design": ThreadPoolExecutor(1, thread_name_prefix="rvb-design"),
                       "figures": ThreadPoolExecutor(1, thread_name_prefix="rvb-figures"),
                       "demand": ThreadPoolExecutor(1, thread_name_prefix="rvb-demand")}
        self._lock = threading.Lock()
        self._latest: dict[str, Job] = {}
        self._jobs: dict[str, Job] = {}  # the last `keep` jobs, for progress and cancel
        self._keep = keep
        self._ids = itertools.count(1)
        self.stopping = threading.Event()  # set when the server stops (the warm-up checks it)

    def _register(self, job_id: Any, channel: Any, total: int | None) -> Job:
        job = Job(str(job_id) if job_id is not None else f"job-{next(self._ids)}",
                  str(channel) if channel is not None else None, total)
        with self._lock:
            if job.channel is not None:
                old = self._latest.get(job.channel)
                if old is not None:
                    old.cancel(f"superseded by request {job.id}")
                self._latest[job.channel] = job
            self._jobs[job.id] = job
            while len(self._jobs) > self._keep:
                oldest = next(iter(self._jobs))
                if self._jobs[oldest].state in ("queued", "running"):
                    break
                del self._jobs[oldest]
        return job

    async def run(self, fn: Callable[[Job], Any], *, job_id: Any = None, channel: Any = None, pool: str = "live",
                  total: int | None = None) -> tuple[Job, Any]:
        """Run ``fn(job)`` in the pool's thread; (job, its result). Raises ``Cancelled``."""
        job = self._register(job_id, channel, total)
        loop = asyncio.get_running_loop()
        return job, await loop.run_in_executor(self._pools[pool], self._call, job, fn)

    def _call(self, job: Job, fn: Callable[[Job], Any]) -> Any:
        if job.cancel_event.is_set():  # superseded while it waited: never started
            job.state = "cancelled"
            raise Cancelled(job)
        job.state = "running"
        try:
            result = fn(job)
        except Cancelled:
            job.state = "cancelled"
            raise
        except BaseException:
            job.state = "failed"
            raise
        if job.cancel_event.is_set():  # finished as it was superseded: its result is not the newest input's
            job.state = "cancelled"
            raise Cancelled(job)
        job.state = "finished"
        return result

    def background(self, fn: Callable[[], Any]) -> None:
        """Run ``fn()`` in the live thread, ahead of any request (the warm-up)."""
        self._pools["live"].submit(fn)

    def get(self, job_id: str) -> Job | None:
        with self._lock:
            return self._jobs.get(str(job_id))

    def cancel(self, job_id: str) -> Job | None:
        job = self.get(job_id)
        if job is not None:
            job.cancel("cancelled")
        return job

    def active(self) -> int:
        """Jobs queued or running (a burst of changes leaves none behind)."""
        with self._lock:
            return sum(j.state in ("queued", "running") for j in self._jobs.values())

    def shutdown(self) -> None:
        self.stopping.set()
        with self._lock:
            for job in self._jobs.values():
                job.cancel("server stopping")
        for pool in self._pools.values():
            pool.shutdown(wait=True, cancel_futures=True)
