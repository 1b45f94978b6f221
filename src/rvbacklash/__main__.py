"""``python -m rvbacklash``: the command line (``rvbacklash.cli.main``).

Ctrl-C is handled from this module's first lines: importing ``rvbacklash.cli`` takes a while on a
loaded machine, and a press then used to end in a KeyboardInterrupt traceback (exit -2). Until
``rvbacklash.cli.main`` installs the command line's own handling, a press ends the process as
that handling would before anything is written: one line, exit 130. ``_signal`` and ``os`` are
loaded by Python's start-up (no import to wait for).
"""
import _signal
import os


def _exit_130(signum, frame) -> None:
    try:
        os.write(2, b"interrupted: nothing was written\n")
    finally:
        os._exit(130)


_signal.signal(_signal.SIGINT, _exit_130)

from rvbacklash.cli import main  # noqa: E402 - after the handler, on purpose

main()
