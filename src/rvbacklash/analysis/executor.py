"""Where independent tasks run: in this process, on a local cluster of processes, or on an
existing Dask cluster — one small interface for the sweeps and the allocation search.

    with executor("local", workers=2) as ex:
        for i, value in ex.map_unordered(fn, tasks, stop=event):
            ...

Schedulers: ``inline`` runs the tasks one after the other in this process; ``local`` starts a
``dask.distributed.LocalCluster`` of ``workers`` processes (default: one per core) with one thread
each; an address (``tcp://host:8786``) connects to a running cluster (docs/sweeps.md). ``fn`` and
the tasks must be picklable: a module-level function and plain data. Dask is an optional extra
(``pip install 'rvbacklash[sweep]'``), imported only here, only for a cluster.

Nothing of a task's result may depend on where it runs: a task carries its own seed (stream).
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import signal
import threading
import uuid
import warnings
from contextlib import contextmanager
from typing import Any, Callable, Iterator, Sequence

from rvbacklash.errors import InputError

SCHEDULERS = ("inline", "local")
RETRIES = 2  # extra attempts of a failed task (a worker that dies is re-run by the scheduler as well)
CONNECT_TIMEOUT_S = 10
# Worker processes of a local cluster: without dask's MALLOC_TRIM_THRESHOLD_ (65536), which makes
# glibc return every freed large array to the system, so that each new histogram of a point's run
# is page-faulted in again: numpy's cumsum/histogram on them ran 5x slower and a point ~25 % slower
# than in a plain process (measured, bench/bench_sweep.py). No profiling thread either.
LOCAL_WORKER_CONFIG = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                       "distributed.worker.profile.enabled": False}
_ADDRESS = re.compile(r"^[a-z][a-z0-9+]*://\S+$")
_SCHEDULER_HELP = "allowed: inline, local, or the address of a Dask scheduler such as tcp://host:8786"


def cores() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


def check_scheduler(scheduler: Any) -> str:
    if not isinstance(scheduler, str) or not (scheduler in SCHEDULERS or _ADDRESS.match(scheduler)):
        raise InputError("scheduler", scheduler, _SCHEDULER_HELP)
    return scheduler


def check_workers(workers: Any) -> int | None:
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InputError("workers", workers, "allowed: a number of workers >= 1, or None for one per core")
    return workers


def dask_available() -> bool:
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


class _Failed:
    """An InputError raised by a task, carried back as data (its pickled form loses the field)."""

    def __init__(self, e: InputError):
        self.field, self.has_value, self.value, self.allowed = e.field, e.has_value, e.value, e.allowed

    def error(self) -> InputError:
        return InputError(self.field, self.value, self.allowed) if self.has_value else \
            InputError(self.field, allowed=self.allowed)


def _call(fn: Callable, task: Any) -> Any:
    try:
        return fn(task)
    except InputError as e:
        return _Failed(e)


def _unwrap(value: Any) -> Any:
    if isinstance(value, _Failed):
        raise value.error()
    return value


class Executor:
    """Runs picklable tasks (see the module docstring). ``scheduler`` is "inline", "local" or
    the address of the cluster; ``workers`` the number of tasks that run at once."""

    def __init__(self, scheduler: str, client: Any = None, workers: int = 1):
        self.scheduler = scheduler
        self.workers = workers
        self._client = client

    def __repr__(self) -> str:
        return f"<Executor {self.scheduler}, {self.workers} worker{'s' if self.workers != 1 else ''}>"

    @property
    def client(self) -> Any:
        """The dask.distributed Client (None inline)."""
        return self._client

    def slots(self) -> int:
        """Tasks that run at once: the cluster's threads right now (it may have grown)."""
        if self._client is None:
            return 1
        return max(1, sum(self._client.nthreads().values()))

    def map_unordered(self, fn: Callable[[Any], Any], tasks: Sequence, *,
                      stop: threading.Event | None = None) -> Iterator[tuple[int, Any]]:
        """Yield (task index, fn(task)) as tasks finish; retries a task whose worker died; stops
        submitting when ``stop`` is set (the tasks under way still finish and are yielded).

        One task per worker thread is in flight, plus one (counted again as tasks finish, so
        that workers joining a running cluster are used); a stop is therefore quick, and the
        tasks no worker has started are cancelled. An InputError raised by ``fn`` is raised here
        as it was; another exception after ``RETRIES`` more attempts."""
        if self._client is None:
            for i, task in enumerate(tasks):
                if stop is not None and stop.is_set():
                    return
                yield i, fn(task)
            return
        yield from self._map_dask(fn, tasks, stop)

    def _map_dask(self, fn, tasks, stop) -> Iterator[tuple[int, Any]]:
        from distributed import as_completed

        client = self._client
        order = iter(enumerate(tasks))
        pending: dict[str, tuple[int, Any]] = {}  # key -> (task index, future)
        finished = as_completed(loop=client.loop)
        run, name = uuid.uuid4().hex[:8], getattr(fn, "__name__", "task")
        stopped = False

        def submit() -> bool:
            if stop is not None and stop.is_set():
                return False
            nxt = next(order, None)
            if nxt is None:
                return False
            i, task = nxt
            f = client.submit(_call, fn, task, key=f"{name}-{run}-{i}", pure=False, retries=RETRIES)
            pending[f.key] = (i, f)
            finished.add(f)
            return True

        def fill() -> None:  # one task per worker thread in flight, plus one (a cluster may grow)
            while len(pending) < self.slots() + 1 and submit():
                pass

        try:
            fill()
            for f in finished:
                if f.key not in pending:  # cancelled after a stop
                    continue
                i, _ = pending.pop(f.key)
                value = _unwrap(f.result())  # raises the task's exception (after its retries)
                f.release()
                fill()
                if stop is not None and stop.is_set() and not stopped:
                    stopped = True
                    self._cancel_queued(pending)
                yield i, value
        finally:
            if pending:  # the caller stopped early, or a task failed
                with contextlib.suppress(Exception):
                    client.cancel([f for _, f in pending.values()])

    def _cancel_queued(self, pending: dict[str, tuple[int, Any]]) -> None:
        """On a stop: cancel the submitted tasks that no worker has started yet."""
        try:
            busy = {str(k) for keys in self._client.processing().values() for k in keys}
        except Exception:  # pragma: no cover - a scheduler that does not tell
            return
        queued = [key for key in pending if key not in busy]
        if queued:
            futures = [pending.pop(key)[1] for key in queued]
            with contextlib.suppress(Exception):
                self._client.cancel(futures)


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """Worker processes inherit an ignored SIGINT: a Ctrl-C at the terminal (sent to the whole
    process group) then reaches the sweep only, which stops cleanly instead of the workers dying."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _need_dask(scheduler: str) -> None:
    if not dask_available():
        raise InputError("scheduler", scheduler, "needs dask.distributed, an optional extra: "
                                                 "pip install 'rvbacklash[sweep]'; allowed without it: inline")


@contextmanager
def executor(scheduler: str = "inline", workers: int | None = None) -> Iterator[Executor]:
    """An Executor on ``scheduler`` ("inline", "local" or an address such as tcp://host:8786).

    ``workers``: for "local", the worker processes (default: one per core), each with one
    thread; not allowed with an address (the cluster has its own workers); inline runs one task
    at a time. The cluster started for "local" is closed on exit."""
    scheduler = check_scheduler(scheduler)
    workers = check_workers(workers)
    if scheduler == "inline":
        yield Executor("inline", None, 1)
        return
    _need_dask(scheduler)
    import dask
    from distributed import Client, LocalCluster

    quiet = logging.ERROR
    if scheduler == "local":
        n = workers or cores()
        environ = dict(os.environ)
        with _sigint_ignored(), warnings.catch_warnings(), dask.config.set(LOCAL_WORKER_CONFIG):
            # the scheduler's HTTP (health) server moves off a busy port 8787 with a warning: harmless here
            warnings.filterwarnings("ignore", message=r"Port \d+ is already in use")
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                   silence_logs=quiet)
        os.environ.clear()  # the nannies set their workers' variables in this process too: undo that here
        os.environ.update(environ)
        try:
            with Client(cluster, set_as_default=False) as client:
                yield Executor("local", client, n)
        finally:
            cluster.close()
        return
    if workers is not None:
        raise InputError("workers", workers, f"allowed only with scheduler inline or local; the cluster at "
                                             f"{scheduler} has its own workers")
    try:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT_S, set_as_default=False)
    except (OSError, TimeoutError) as e:
        raise InputError("scheduler", scheduler, f"cannot connect ({type(e).__name__}: {e}); {_SCHEDULER_HELP} "
                                                 f"that is running") from None
    try:
        yield Executor(scheduler, client, max(1, sum(client.nthreads().values())))
    finally:
        client.close()
