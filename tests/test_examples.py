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


def test_rv80e_elastic_comment_says_where_the_structure_comes_from():
    """Regression: the [elastic] comment still said that the crankshafts, support bearings and
    carrier must come from FE or supplier data (the rigidity an upper bound) although the example's
    [structure] table derives them."""
    from rvbacklash.design.loading import example_text, load_design

    text = example_text("rv80e")
    elastic = text[text.index("\n[elastic]"):text.index("\n[structure]")]
    comments = " ".join(line.partition("#")[2].strip() for line in elastic.splitlines() if "#" in line)
    assert load_design("rv80e").structure is not None
    assert "must come from FE" not in comments and "upper bound" not in comments
    assert "from [structure] below" in comments
