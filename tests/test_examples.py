"""The shipped notebook-style example runs top to bottom."""

import subprocess
import sys

from helpers import ROOT


def test_quickstart_example_runs_top_to_bottom(tmp_path):
    script = ROOT / "examples" / "quickstart.py"
    p = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "yield" in p.stdout and "Traceback" not in p.stderr
    assert (tmp_path / "quickstart-report.html").read_text().startswith("<!DOCTYPE html>")
    assert (tmp_path / "quickstart-factors.csv").read_text().startswith("id,")
