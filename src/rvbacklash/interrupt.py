"""Ctrl-C as a request to stop, not an exception in the middle of bookkeeping.

Long loops (the Monte-Carlo engine, scenario comparisons, sweeps) run inside
``stop_requested()``: while it is active, SIGINT sets a flag that the loop checks between
units of work, so partial results stay consistent; a second Ctrl-C raises KeyboardInterrupt
at once. Outside the main thread (signal handlers cannot be installed there) the flag is
still returned and KeyboardInterrupt keeps its usual meaning.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from typing import Iterator


@contextlib.contextmanager
def stop_requested() -> Iterator[threading.Event]:
    event = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield event
        return
    previous = signal.getsignal(signal.SIGINT)

    def on_sigint(signum, frame):
        if event.is_set():  # second Ctrl-C: stop now
            raise KeyboardInterrupt
        event.set()

    try:
        signal.signal(signal.SIGINT, on_sigint)
    except ValueError:  # pragma: no cover - e.g. an embedding interpreter without signals
        yield event
        return
    try:
        yield event
    finally:
        signal.signal(signal.SIGINT, previous)
