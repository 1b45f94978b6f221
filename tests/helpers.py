"""Helpers shared by the tests (importable: pytest puts tests/ on sys.path)."""

from __future__ import annotations

import os
import pty
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from rvbacklash.design.loading import design_from_toml, example_text

ROOT = Path(__file__).resolve().parents[1]


def run_cli_process(*args, cwd: Path | None = None, timeout: float = 180) -> subprocess.CompletedProcess:
    """Run the installed command line exactly as a user would (a fresh interpreter)."""
    return subprocess.run([sys.executable, "-m", "rvbacklash", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, timeout=timeout)


def run_cli(*args) -> subprocess.CompletedProcess:
    """Run the command line's entry point in this process (same code path as the ``rvbacklash``
    script, without paying the interpreter start-up for every case): exit code, stdout, stderr."""
    import contextlib
    import io

    from rvbacklash.cli import main

    out, err = io.StringIO(), io.StringIO()
    code = 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            main([str(a) for a in args])
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    return subprocess.CompletedProcess(["rvbacklash", *map(str, args)], code, out.getvalue(), err.getvalue())


def one_line_error(p: subprocess.CompletedProcess, fragment: str = "") -> str:
    """The single stderr line of a refused command (exit 2, no traceback); checks ``fragment``."""
    assert p.returncode == 2, (p.returncode, p.stdout[-500:], p.stderr[-2000:])
    assert "Traceback" not in p.stderr, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), p.stderr
    assert fragment in lines[0], lines[0]
    return lines[0]


def with_factor(toml: str, key: str, body: str) -> str:
    """Replace (or add) the table [factors.key] of an example's TOML by ``body``."""
    head = f"[factors.{key}]"
    if head not in toml:
        return toml + "\n" + head + "\n" + body + "\n"
    start = toml.index(head)
    end = toml.find("\n[", start + 1)
    return toml[:start] + head + "\n" + body + "\n" + (toml[end:] if end != -1 else "")


def example_with(name: str, *replacements: tuple[str, str]):
    """A built-in example with text replacements, as a validated Design."""
    text = example_text(name)
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new, 1)
    return design_from_toml(text)


# rv80e with other numbers of cranks and pillars (issue 36): the lines changed so that the holes fit
CRANK_LAYOUTS = {
    (3, 3): (),
    (2, 2): (("rated_torque_nm = 784.0", "rated_torque_nm = 520.0"),),
    (2, 4): (("rated_torque_nm = 784.0", "rated_torque_nm = 520.0"),
             ("pillar_radius_mm = 42.0", "pillar_radius_mm = 48.0"),
             ("pillar_width_mm = 20.0", "pillar_width_mm = 12.0"), ("pillar_depth_mm = 20.0", "pillar_depth_mm = 12.0"),
             ("disc_pillar_hole_diameter_mm = 34.0", "disc_pillar_hole_diameter_mm = 22.0")),
    (3, 6): (("pillar_radius_mm = 42.0", "pillar_radius_mm = 57.0"),
             ("pillar_width_mm = 20.0", "pillar_width_mm = 8.0"), ("pillar_depth_mm = 20.0", "pillar_depth_mm = 8.0"),
             ("disc_pillar_hole_diameter_mm = 34.0", "disc_pillar_hole_diameter_mm = 16.0"),
             ("support_bearing_seat_diameter_mm = 47.0", "support_bearing_seat_diameter_mm = 44.0")),
}


def crank_layout_text(cranks: int, pillars: int) -> str:
    """rv80e's TOML with ``cranks`` planets (cranks) and ``pillars`` carrier pillars (CRANK_LAYOUTS:
    two cranks rated 520 N m; pillars and holes small enough to stand between the cranks)."""
    text = example_text("rv80e").replace("planets = 3", f"planets = {cranks}", 1).replace(
        "carrier_pillars = 3", f"carrier_pillars = {pillars}", 1)
    for old, new in CRANK_LAYOUTS[(cranks, pillars)]:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


def call_beside_fifo(fifo: Path, fn, timeout: float = 60.0) -> dict:
    """{"value": fn()} or {"error": what it raised}, fn run in a thread; if it still blocks after
    ``timeout`` (reading the FIFO ``fifo``, which has no writer), the FIFO's write end is opened and
    closed (the reader gets EOF and returns: nothing is left blocked) and the test fails. The
    timeout only bounds a hang: a reader that refuses the FIFO returns at once."""
    out = {}

    def run():
        try:
            out["value"] = fn()
        except BaseException as e:  # noqa: BLE001 - handed to the test
            out["error"] = e

    t = threading.Thread(target=run, daemon=True)
    t.start()
    t.join(timeout)
    if t.is_alive():
        try:
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))  # the blocked reader gets EOF
        except OSError:
            pass
        t.join(10)
        pytest.fail(f"reading {fifo} blocked for {timeout} s")
    return out


def interrupt_on_progress(args: list, cwd, again_after: float | None = None,
                          progress: bytes = rb"sampling\S*\s.*?\b[1-9][0-9]*/[0-9]+") -> tuple[int, str]:
    """Run a command on a pseudo-terminal (so that it draws its progress bar), send SIGINT once
    the bar shows finished work (``progress``, a regex of the tty's bytes: by default finished
    samples), and a second one ``again_after`` seconds later; return (exit code, what it printed on
    the tty)."""
    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "rvbacklash", *map(str, args)], stdin=slave, stdout=slave,
                            stderr=slave, cwd=cwd, env={**os.environ, "COLUMNS": "120"})
    os.close(slave)
    seen = b""
    deadline = time.monotonic() + 900  # a guard: an empty numba cache on a loaded machine compiles for minutes
    sent = False
    while time.monotonic() < deadline:
        try:
            chunk = os.read(master, 4096)
        except OSError:
            break
        if not chunk:
            break
        seen += chunk
        if not sent and re.search(progress, seen):
            proc.send_signal(signal.SIGINT)
            sent = True
            if again_after is not None:
                time.sleep(again_after)
                proc.send_signal(signal.SIGINT)
    proc.wait(timeout=120)  # a guard: writing the partial results on a loaded machine
    os.close(master)
    assert sent, seen.decode(errors="replace")[-2000:]
    return proc.returncode, seen.decode(errors="replace")
