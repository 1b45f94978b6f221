"""bench/bench_all.py (`make bench`) runs at a tiny size and prints every row of its table; only
that is checked, never a time."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[1] / "bench" / "bench_all.py"
ROWS = ("contact model production run", "elastic model production run", "`rvbacklash sensitivity",
        "`rvbacklash allocate", "linear engine (sun2014", "linear engine / numpy generation")


def test_bench_all_prints_every_row_of_the_table():
    p = subprocess.run([sys.executable, str(SCRIPT), "--tiny"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    lines = p.stdout.splitlines()
    for row in ROWS:
        line = next((x for x in lines if x.startswith(row)), None)
        assert line is not None, (row, p.stdout)
        assert any(word in line.split() for word in ("pass", "FAIL")), line


def test_no_commands_leaves_those_rows_marked():
    p = subprocess.run([sys.executable, str(SCRIPT), "--tiny", "--no-commands"], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    assert sum("skipped" in x for x in p.stdout.splitlines()) == 2, p.stdout
