"""One way through the code: the import-linter contracts of pyproject.toml hold, and they do
fail on an upward import or a cycle (checked on a copy of the package)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import ROOT

LINT = Path(sys.executable).with_name("lint-imports")


def _lint(src: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(LINT), "--config", str(ROOT / "pyproject.toml"), "--no-cache"], capture_output=True,
                          text=True, cwd=ROOT, env={"PYTHONPATH": str(src), "PATH": "/usr/bin:/bin"}, timeout=120)


def test_the_contracts_hold():
    p = _lint(ROOT / "src")
    assert p.returncode == 0, p.stdout + p.stderr
    assert "2 kept, 0 broken" in p.stdout


@pytest.mark.parametrize("module,line,broken", [
    ("geometry/reducer.py", "import rvbacklash.cli.app\n",  # an upward import
     "rvbacklash.geometry is not allowed to import rvbacklash.cli"),
    ("analysis/exact.py", "import rvbacklash.analysis.simulation\n",  # a cycle between siblings
     "No cycles are allowed in rvbacklash.analysis"),
])
def test_the_contracts_catch_a_violation(tmp_path, module, line, broken):
    copy = tmp_path / "rvbacklash"
    shutil.copytree(ROOT / "src" / "rvbacklash", copy, ignore=shutil.ignore_patterns("__pycache__"))
    f = copy / module
    f.write_text(line + f.read_text())
    p = _lint(tmp_path)
    assert p.returncode != 0 and broken in p.stdout, p.stdout
