"""Ctrl-C (SIGINT): a request to stop a long loop, or, in the command line, the end of the process.

**Stop windows.** Long loops (the Monte-Carlo engine, scenario comparisons, Sobol runs,
allocations, sweeps) run inside ``stop_requested()``: while it is active, SIGINT sets an event
that the loop checks between units of work; the loop finishes the units under way and returns
partial results, which its caller reports marked partial. Outside the main thread (signal
handlers cannot be installed there) a window yields the event of the window or ``stop_on`` it
runs under (a loop's worker threads run a copy of its context): the workbench stops a job's loops
by setting that event, and a Ctrl-C reaches the loops a loop runs in its threads (an allocation's
candidates); KeyboardInterrupt keeps its usual meaning.

**Library use** (a script, Jupyter): ``stop_requested`` installs its handler for the window
only; a second Ctrl-C in the window raises KeyboardInterrupt at once, and outside a window Python's
own KeyboardInterrupt applies.

**The command line** installs one handler for the whole command (``exit_on_sigint``, when a
command starts) and every SIGINT goes through it:

1. While no loop has finished any work (``mark_progress`` not yet called: the modules import,
   numba compiles its kernels or loads them from its cache, the design is read, or a first block
   is under way, perhaps compiling in a worker thread), the process ends at once: one line on
   stderr, the standard streams flushed, ``os._exit(130)``.
   Raising KeyboardInterrupt instead is not safe there: it lands wherever the main thread is,
   e.g. inside numba's compiler or a half-done lazy import (``from scipy import stats``), which
   then fails later with an unrelated error (``no compiled object yet``, a ``NameError``, exit
   1 with a traceback) or swallows it and runs on; and waiting for a first block that compiles
   its kernel in a worker can take a minute. Ending the process is clean because nothing is
   half-written at those moments: result files are written only after the run (the next point),
   atomically, and numba writes its cache files atomically too.
2. Once work has finished: the stop request above (every open window, and every window that opens
   later, stops its loop), and the process is committed to writing what it has, marked partial
   where a loop stopped early; the command then exits 130 (``stop_was_requested``) — also when the
   press came between loops or after the last one (the report's later sections, the statistics,
   the rendering), where ending the process would throw finished work away. Further Ctrl-C are
   ignored, with a note: a second press must not break the writing of what the first one asked
   to keep (it used to land in the finishing code's lazy imports and lose everything).
3. While files are written (``writing``, which ``atomic.atomic_write`` and the report layer's
   ``write_files`` use): the writing completes, every file whole, then the process exits 130.

Sweeps call ``mark_progress(on_disk=True)`` before they start: their results directory and
worker processes must always be closed in order, so a Ctrl-C in a sweep's window is always a stop
request; and since every finished point is already on disk, a second Ctrl-C stops at once
(KeyboardInterrupt, which the sweep command reports) instead of waiting for the points under way.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import signal
import sys
import threading
from collections.abc import Iterator

EXIT_CODE = 130  # 128 + SIGINT, what a shell reports for a process ended by Ctrl-C

_windows: list[threading.Event] = []  # the main thread's open stop windows, innermost last
_FRESH = {"cli": False, "progress": False, "on_disk": False, "stopping": False, "writing": 0, "deferred": False,
          "told": False}
_state = dict(_FRESH)
# the stop event a window outside the main thread yields: the innermost window's or stop_on's
_enclosing: contextvars.ContextVar[threading.Event | None] = contextvars.ContextVar("rvbacklash_stop", default=None)
_dropped: contextvars.ContextVar[threading.Event | None] = contextvars.ContextVar("rvbacklash_drop", default=None)


def _exit_now(message: str) -> None:
    """End the process: the terminal restored (a progress bar's line cleared, the cursor rich hid
    shown again), the standard streams flushed, the message on stderr, exit code 130."""
    for action in (lambda: sys.stderr.isatty() and sys.stderr.write("\r\x1b[2K\x1b[?25h"), sys.stdout.flush,
                   lambda: sys.stderr.write(message + "\n"), sys.stderr.flush):
        try:  # a stream may be closed, a broken pipe, or busy in the interrupted code: exit anyway
            action()
        except Exception:  # noqa: BLE001 - nothing may keep the process from ending
            pass
    os._exit(EXIT_CODE)


def _on_sigint(signum, frame) -> None:
    s = _state
    if not s["cli"]:  # library use: only installed inside a window
        if any(ev.is_set() for ev in _windows):
            raise KeyboardInterrupt  # second Ctrl-C: stop now
        if _windows:
            _windows[-1].set()
        return
    if s["stopping"]:
        if s["on_disk"] and not s["writing"]:
            raise KeyboardInterrupt  # the finished work is on disk (and no file is half-written): stop now
        if not s["told"]:
            s["told"] = True
            with contextlib.suppress(Exception):
                sys.stderr.write("\nstopping: the finished part is being written, marked partial (Ctrl-C again is "
                                 "ignored until then)\n")
        return
    if s["progress"]:
        s["stopping"] = True
        for ev in _windows:  # every loop under way stops (an outer loop would not start its next item)
            ev.set()
        return
    if s["writing"]:
        s["deferred"] = True
        return
    _exit_now("interrupted: nothing was written")


@contextlib.contextmanager
def stop_requested() -> Iterator[threading.Event]:
    """A stop window (module docstring): yields the event that a Ctrl-C sets. Outside the main
    thread it yields the event of the enclosing window or ``stop_on`` of this thread's context
    (a loop's worker threads run a copy of it: ``contextvars.copy_context``), so a stop reaches
    the loops nested in them too."""
    if threading.current_thread() is not threading.main_thread():
        yield _enclosing.get() or threading.Event()
        return
    event = threading.Event()
    own = signal.getsignal(signal.SIGINT) is not _on_sigint  # library use: install for this window
    previous = None
    if own:
        try:
            previous = signal.signal(signal.SIGINT, _on_sigint)
        except ValueError:  # pragma: no cover - e.g. an embedding interpreter without signals
            yield event
            return
    if _state["stopping"]:  # a Ctrl-C already asked every loop to stop: this one does not start its work
        event.set()
    _windows.append(event)
    token = _enclosing.set(event)
    try:
        yield event
    finally:
        _enclosing.reset(token)
        _windows.remove(event)
        if own:
            signal.signal(signal.SIGINT, previous)


class Abandoned(Exception):
    """Work under way dropped at a ``stop_on`` stop (``check_abandoned``)."""


@contextlib.contextmanager
def stop_on(event: threading.Event) -> Iterator[None]:
    """Stop requests from elsewhere than Ctrl-C (the workbench's cancel, a client gone): every stop
    window opened inside, outside the main thread, yields ``event``; its loop stops when it is set,
    as on Ctrl-C. Unlike a Ctrl-C's stop, whose loops finish the blocks under way and keep them,
    a costly block may be dropped half-way (``check_abandoned``): whoever set the event does not
    want the result."""
    tokens = _enclosing.set(event), _dropped.set(event)
    try:
        yield
    finally:
        _dropped.reset(tokens[1])
        _enclosing.reset(tokens[0])


def check_abandoned() -> None:
    """Raise ``Abandoned`` if the event of the enclosing ``stop_on`` is set: polled between the
    chunks of a costly block (in a loop's worker thread: it runs a copy of the loop's context)."""
    event = _dropped.get()
    if event is not None and event.is_set():
        raise Abandoned


def mark_progress(on_disk: bool = False) -> None:
    """Finished work exists that a stop should keep: from now on a Ctrl-C inside a stop window is
    a request to stop (and write it marked partial), no longer the end of the process. The
    command line calls it when a loop reports progress. ``on_disk``: the work is kept on disk as
    it finishes (a sweep's points), so a second Ctrl-C may stop at once."""
    _state["progress"] = True
    _state["on_disk"] = _state["on_disk"] or on_disk


def stop_was_requested() -> bool:
    """A Ctrl-C asked the command to stop once work had finished (point 2): it exits 130."""
    return bool(_state["stopping"])


@contextlib.contextmanager
def writing() -> Iterator[None]:
    """Files are being written: a Ctrl-C waits until the outermost such section is done (with the
    command line's handler; otherwise nothing changes). The deferred exit happens only after a
    section that completed: one that fails lets its error (the command's one-line message) through."""
    s = _state
    s["writing"] += 1
    completed = False
    try:
        yield
        completed = True
    finally:
        s["writing"] -= 1
        if completed and s["writing"] == 0 and s["deferred"] and s["cli"]:
            _exit_now("interrupted after the files were written")


@contextlib.contextmanager
def exit_on_sigint(process: bool = False) -> Iterator[None]:
    """The command line's handling of Ctrl-C for one command (module docstring), from its start to
    its end. After it, the previous handler is restored (a test calling the entry point in process
    keeps its own); with ``process`` (the command is the whole process) Ctrl-C is ignored instead:
    the command has returned and only the interpreter's shutdown is left (joining worker threads,
    flushing), where Python's own handling would turn a press into a KeyboardInterrupt traceback or
    a death by SIGINT after the partial results were written. Main thread only; elsewhere nothing is
    installed."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = dict(_state)
    _state.update(_FRESH, cli=True)  # before the handler: a Ctrl-C right after it finds the state set
    previous = signal.signal(signal.SIGINT, _on_sigint)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.SIG_IGN if process else previous)
        _state.update(saved)
