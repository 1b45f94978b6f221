"""Every benchmark runs at a tiny size so that none can rot (they print figures; nothing is timed)."""

from __future__ import annotations

import subprocess
import sys

from helpers import ROOT


def test_bench_te_runs_and_prints_its_figures():
    p = subprocess.run([sys.executable, str(ROOT / "bench" / "bench_te.py"), "--samples", "64"], capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    assert "units/s" in p.stdout and "ms/unit" in p.stdout and "one unit's curve" in p.stdout
