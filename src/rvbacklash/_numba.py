"""numba for the compiled kernels, with its on-disk cache keyed by the package's source.

numba reuses a cached kernel as long as the kernel's own file is unchanged; it does not see a
change in another module's kernel that it calls (the Monte-Carlo kernel of sampling/ calls the
contact geometry of models/). The cache therefore lives in a directory named after a hash of
every source file of the package: any change starts a fresh cache, a user never runs stale
machine code. ``NUMBA_CACHE_DIR``, when set, is the base of that directory; else the user's
cache directory (``$XDG_CACHE_HOME`` or ``~/.cache``). Compile kernels with ``njit`` from here.

``njit`` is numba's with ``error_model="numpy"``: a float division by zero gives inf or NaN as
IEEE 754 says instead of raising ZeroDivisionError; every other division gives the same bits. The
kernels never divide by zero on purpose. The point is speed. numba keeps two atomic operations
(a reference count up, then down) for every array a function binds: its arguments, the arrays of
a tuple it unpacks, every view. It removes them only where it can prove them redundant, which it
cannot in a function that may raise, and under numba's default every division may raise. Those
counts cost ~5 ns each; the elastic model paid ~6 us per unit for them (docs/elastic.md,
performance). ``njit_borrowing`` goes further for the per-unit kernels that allocate nothing.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import threading
import time
from pathlib import Path

import numba as nb
from numba.core import sigutils
from numba.core.caching import FunctionCache
from numba.core.compiler_lock import global_compiler_lock
from numba.core.cpu import CPUTargetOptions
from numba.core.runtime import rtsys

_PACKAGE = Path(__file__).resolve().parent


@functools.cache
def source_hash() -> str:
    """First 16 hex digits of the sha256 of every .py file of the package (paths and contents)."""
    h = hashlib.sha256()
    for path in sorted(_PACKAGE.rglob("*.py")):
        h.update(str(path.relative_to(_PACKAGE)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _cache_dir() -> str:
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "rvbacklash")
    return os.path.join(base, f"numba-{source_hash()}")


nb.config.CACHE_DIR = _cache_dir()


class _LoadingCache(FunctionCache):
    """numba's on-disk cache of one function, without the half second its first load costs.

    numba's ``FunctionCache.load_overload`` first refreshes the CPU target: it imports and
    registers every implementation numba can lower (numba.cpython.*, numba.np.*, typed
    containers, ...; ~0.5 s of CPU), which only compiling needs, since a cached kernel is machine
    code already linked with everything it calls. Loading needs two things of the target: the
    symbols of numba's C helpers (installed when the context is created) and of its runtime (NRT:
    ``rtsys.initialize``, which the refresh would have done). A function that is not in the cache
    is compiled as before: numba's compiler refreshes the target itself (``compile_extra``)."""

    def load_overload(self, sig, target_context):
        rtsys.initialize(target_context)
        with self._guard_against_spurious_io_errors():
            return self._load_overload(sig, target_context)


# the numba internals _LoadingCache relies on (numba >= 0.59); without them, numba's own cache
_FAST_LOAD = all(hasattr(FunctionCache, a) for a in ("_load_overload", "_guard_against_spurious_io_errors")) \
    and hasattr(rtsys, "initialize")


try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: no lock, each process compiles what it misses
    fcntl = None

_LOCK_WAIT_S = 900.0  # longest wait for another process's compile (then compile here): no deadlock can hang
_held: set[str] = set()  # the compile locks this process holds (a kernel compiles the kernels it calls inside)
_held_fds: dict[str, int] = {}
_held_guard = threading.Lock()


def _forget_locks_in_child() -> None:
    """A process forked while another thread compiles shares that thread's lock (one open file): the
    child closes its copy, else the lock would last as long as the child."""
    for fd in _held_fds.values():
        with contextlib.suppress(OSError):
            os.close(fd)
    _held.clear()
    _held_fds.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_locks_in_child)


@contextlib.contextmanager
def _compile_lock(path: str):
    """An exclusive lock on ``path`` between processes (``flock``; released by the OS when a process
    ends, however it ends), while this process compiles the kernel whose cache index is beside it."""
    with _held_guard:
        mine = path in _held
    if mine or fcntl is None:
        yield
        return
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError:  # a cache directory without write access: numba skips its cache too
        yield
        return
    try:
        deadline = time.monotonic() + _LOCK_WAIT_S
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if time.monotonic() > deadline:
                    break  # pragma: no cover - compile here as well
                time.sleep(0.05)  # polled, not blocking: a signal handler (Ctrl-C) runs at once
            except OSError:  # pragma: no cover - a file system without flock
                break
        with _held_guard:
            _held.add(path)
            _held_fds[path] = fd
        try:
            yield
        finally:
            with _held_guard:
                _held.discard(path)
                _held_fds.pop(path, None)
    finally:
        os.close(fd)  # releases the flock


def _compiled_once(dispatcher):
    """``dispatcher.compile`` that a kernel missing from the on-disk cache compiles in one process at
    a time: two processes that miss the same kernel at once (pytest's workers, a sweep's, a command
    and a bench) used to both compile it (a large kernel: ~50 s of CPU each); the second now waits
    for the first, then loads its machine code from the cache (numba's compile looks there first).
    One lock per kernel, beside its cache index; a kernel holds its lock while it compiles the
    kernels it calls, whose locks come after: the call graph has no cycles, so neither can the
    waits (and a wait ends after _LOCK_WAIT_S anyway)."""
    compile_ = dispatcher.compile
    index = getattr(getattr(dispatcher._cache, "_cache_file", None), "_index_path", None)
    if index is None or not hasattr(dispatcher, "overloads"):  # pragma: no cover - other numba internals
        return compile_
    path = index + ".lock"

    def compile(sig):
        with global_compiler_lock:  # this process's compiles, one at a time, as numba's own compile
            args, _ = sigutils.normalize_signature(sig)
            if tuple(args) in dispatcher.overloads:
                return compile_(sig)
            with _compile_lock(path):
                return compile_(sig)

    return compile


def njit(**options):
    """``numba.njit(**options)`` with ``error_model="numpy"`` (module docstring); ``cache=True``
    keeps the kernel in the on-disk cache that loads without refreshing numba's target
    (``_LoadingCache``) and that a kernel enters once from every process compiling it at the same
    time (``_compiled_once``)."""
    if not (options.get("cache") and _FAST_LOAD):
        return nb.njit(error_model="numpy", **options)
    decorate = nb.njit(error_model="numpy", **{**options, "cache": False})

    def cached_kernel(fn):
        dispatcher = decorate(fn)
        dispatcher._cache = _LoadingCache(dispatcher.py_func)  # what Dispatcher.enable_caching does
        dispatcher.compile = _compiled_once(dispatcher)
        return dispatcher

    return cached_kernel


def njit_borrowing(**options):
    """``njit`` for a per-unit kernel that allocates nothing and only reads and writes arrays its
    caller holds (``unit_draw.draw_unit``, ``contact.stage_play``, ``elastic.chain.loop_figures``),
    compiled without numba's runtime (its ``_nrt=False`` option): its own code keeps no reference
    counts. Each call of such a kernel binds a few dozen arrays (its scratch records, its
    arguments), two atomic operations each that numba could not prune in a function this size:
    ~1 us of the contact model's ~4.9 us per unit (draw_unit alone went from 1.75 to 1.0 us),
    ~2 us of the elastic model's ~23 us of evaluation.

    A function it calls is compiled without the runtime too when this kernel compiles it first;
    one that another caller compiled first (same argument types) is linked as it is, with its own
    counts. Either way is safe as long as no function under such a kernel returns an array or
    keeps one beyond the call (none does: they return scalars; a callee that allocated would make
    numba refuse to compile when compiled from here). ``_nrt`` is a private option of numba (there
    since 0.40, checked here): without it, this is plain ``njit``."""
    if hasattr(CPUTargetOptions, "_nrt"):
        options["_nrt"] = False
    return njit(**options)


__all__ = ["nb", "njit", "njit_borrowing", "source_hash"]
