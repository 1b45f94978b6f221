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
import contextlib
import contextvars
import itertools
import threading
from concurrent.futures import Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from typing import Any, Callable

from starlette.requests import Request

from rvbacklash.interrupt import stop_on


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
        self.check()

    def check(self) -> None:
        """Raise ``Cancelled`` if the job was cancelled (between the steps of a job)."""
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
                       # the capacity card: root searches of seconds, apart from the loops and TE curves
                       "capacity": ThreadPoolExecutor(1, thread_name_prefix="rvb-capacity"),
                       "demand": ThreadPoolExecutor(1, thread_name_prefix="rvb-demand")}
        self._lock = threading.Lock()
        self._latest: dict[str, Job] = {}
        self._jobs: dict[str, Job] = {}  # the last `keep` jobs, for progress and cancel
        self._keep = keep
        self._ids = itertools.count(1)
        self._futures: set[Future] = set()  # submitted, not done (the shutdown waits for them, bounded)
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
        """Run ``fn(job)`` in the pool's thread; (job, its result). Raises ``Cancelled``, also when
        the client of the request (``client_watched``) goes away meanwhile."""
        job = self._register(job_id, channel, total)
        future = asyncio.wrap_future(self._submit(pool, self._call, job, fn))
        gone = _client_gone.get()
        try:
            if gone is not None:
                waiter = asyncio.ensure_future(gone.wait())
                try:
                    await asyncio.wait({future, waiter}, return_when=asyncio.FIRST_COMPLETED)
                finally:
                    waiter.cancel()
                if gone.is_set():
                    job.cancel("the client went away")
            return job, await future
        except asyncio.CancelledError:  # the request itself was cancelled (the server stops): so is its job
            job.cancel("server stopping")
            raise

    def _call(self, job: Job, fn: Callable[[Job], Any]) -> Any:
        if job.cancel_event.is_set():  # superseded while it waited: never started
            job.state = "cancelled"
            raise Cancelled(job)
        job.state = "running"
        stopped = False
        try:
            with stop_on(job.cancel_event):  # the job's loops stop when it is cancelled, as on Ctrl-C
                result = fn(job)
        except Cancelled:
            stopped = True
        except BaseException:
            if not job.cancel_event.is_set():
                job.state = "failed"
                raise
            stopped = True  # what a stopped loop raised (too little done to keep, ...)
        # A cancelled job's exception is raised afresh, outside the handler: the one caught carries
        # the computation's frames (its arrays) in its traceback, and a future keeping it in a
        # reference cycle would hold them until the next garbage collection.
        if stopped or job.cancel_event.is_set():  # or finished as it was superseded: not the newest input's
            job.state = "cancelled"
            raise Cancelled(job)
        job.state = "finished"
        return result

    def _submit(self, pool: str, fn: Callable, *args) -> Future:
        future = self._pools[pool].submit(fn, *args)
        with self._lock:
            self._futures.add(future)
        future.add_done_callback(self._futures.discard)
        return future

    def background(self, fn: Callable[[], Any]) -> None:
        """Run ``fn()`` in the live thread, ahead of any request (the warm-up)."""
        self._submit("live", fn)

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

    def cancel_all(self, reason: str) -> None:
        """Every job cancelled (the server stops): the running ones stop at their next check. No
        lock: a signal handler calls it, maybe while this thread holds the lock."""
        self.stopping.set()
        for job in list(self._jobs.values()):  # one C-level copy: no other code runs meanwhile
            job.cancel(reason)

    def shutdown(self, timeout_s: float = 10.0) -> bool:
        """Every job cancelled, the threads stopped: whether they all stopped within ``timeout_s``
        (a step no job can interrupt, e.g. numba compiling a kernel in the warm-up, may take longer:
        the process then ends without waiting for it)."""
        self.cancel_all("server stopping")
        for pool in self._pools.values():
            pool.shutdown(wait=False, cancel_futures=True)
        with self._lock:
            running = set(self._futures)
        return not wait(running, timeout=timeout_s).not_done


_client_gone: contextvars.ContextVar[asyncio.Event | None] = contextvars.ContextVar("rvb_client_gone", default=None)


@contextlib.asynccontextmanager
async def client_watched(request: Request):
    """Inside it, the jobs a request runs are cancelled if its client goes away (ASGI's
    ``http.disconnect``: a closed tab, a script stopped): nobody would read their answer. Enter it
    once the body is read (the messages that follow it are the disconnect)."""
    gone = asyncio.Event()

    async def watch() -> None:
        while (await request.receive())["type"] != "http.disconnect":
            pass
        gone.set()

    watcher = asyncio.create_task(watch())
    token = _client_gone.set(gone)
    try:
        yield
    finally:
        _client_gone.reset(token)
        watcher.cancel()
