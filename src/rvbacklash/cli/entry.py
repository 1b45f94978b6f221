"""The entry point of the ``rvbacklash`` command: every error as one line, Ctrl-C as exit 130."""

from __future__ import annotations

import re
import sys

try:  # typer >= 0.2x vendors click
    from typer._click import exceptions as click_exceptions
except ImportError:  # pragma: no cover - older typer with click as a dependency
    from click import exceptions as click_exceptions

import typer

import rvbacklash.cli.commands  # noqa: F401  (registers the commands on the app)
import rvbacklash.cli.allocation  # noqa: F401  (sensitivity, allocate)
import rvbacklash.cli.hysteresis  # noqa: F401  (hysteresis)
import rvbacklash.cli.capacity  # noqa: F401  (capacity)
import rvbacklash.cli.efficiency  # noqa: F401  (efficiency)
import rvbacklash.cli.service_life  # noqa: F401  (service-life)
import rvbacklash.cli.bench  # noqa: F401  (bench, calibrate)
import rvbacklash.cli.sweep  # noqa: F401  (sweep, sweep-plot)
import rvbacklash.cli.transmission  # noqa: F401  (transmission-error)
import rvbacklash.cli.workbench  # noqa: F401  (app: the workbench in the browser)
import rvbacklash.cli.selection  # noqa: F401  (assemble)
from rvbacklash.cli.app import app
from rvbacklash.interrupt import EXIT_CODE, stop_was_requested


def _argv_value(flags: list[str], argv: list[str]) -> str | None:
    """The value given to one of ``flags`` on the command line (for error messages)."""
    for i, a in enumerate(argv):
        for f in flags:
            if a == f and i + 1 < len(argv):
                return argv[i + 1]
            if a.startswith(f + "="):
                return a[len(f) + 1:]
    return None


def click_error_line(e: Exception, argv: list[str]) -> str:
    """One line naming the flag, the value and what is allowed, for a usage error of click."""
    msg = re.sub(r"\s+", " ", e.format_message()).strip()
    param = getattr(e, "param", None)
    if isinstance(e, click_exceptions.MissingParameter):
        return f"error: {msg}"
    if isinstance(e, click_exceptions.BadParameter) and param is not None:
        flags = list(getattr(param, "opts", [])) or [getattr(param, "name", None) or "argument"]
        flag = max(flags, key=len)
        value = _argv_value(flags, argv)
        raw = re.sub(r"\s+", " ", str(getattr(e, "message", msg))).strip()
        if raw.startswith("Value error, "):  # e.g. "Value error, 'xml' is not one of 'table', 'json', 'csv'."
            allowed = "one of" + raw.partition("is not one of")[2].rstrip(".") if "is not one of" in raw else raw[13:]
        else:  # "Input should be a valid integer, unable to parse ..."
            allowed = raw.removeprefix("Input should be ").split(",")[0].rstrip(".")
        shown = f" = {value!r}" if value is not None else ""
        return f"error: {flag}{shown}: allowed: {allowed}"
    return f"error: {msg}"


def main(argv: list[str] | None = None) -> None:
    """Run the ``rvbacklash`` command (``rvbacklash.cli.main`` calls it with the command line's
    Ctrl-C handling installed: a Ctrl-C never lands here as an exception but one a loop raises)."""
    args = sys.argv[1:] if argv is None else argv
    try:
        code = app(args=args, prog_name="rvbacklash", standalone_mode=False)
    except click_exceptions.NoArgsIsHelpError as e:  # a bare command or group: its help
        if e.ctx is not None:
            sys.stdout.write(e.ctx.get_help() + "\n")
        code = 0
    except click_exceptions.ClickException as e:
        sys.stderr.write(click_error_line(e, args) + "\n")
        code = 2
    except (typer.Abort, KeyboardInterrupt):  # e.g. a loop that stopped before anything could be kept
        sys.stderr.write("interrupted\n")
        code = EXIT_CODE
    except BrokenPipeError:  # e.g. `rvbacklash ... | head`
        code = 0
    code = code if isinstance(code, int) else 0
    if code == 0 and stop_was_requested():  # a Ctrl-C after work had finished: written, then 130
        sys.stderr.write("interrupted: what was finished is written\n")
        code = EXIT_CODE
    sys.exit(code)
