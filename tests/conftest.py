"""Shared fixtures and helpers for the test suite."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from rvbacklash import analyze, load_design
from rvbacklash.design.loading import example_text


@pytest.fixture(scope="session")
def sun2014():
    return load_design("sun2014")


@pytest.fixture(scope="session")
def sun2014_result(sun2014):
    return analyze(sun2014)


@pytest.fixture(scope="session")
def sun2014_toml() -> str:
    return example_text("sun2014")


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    """Run the installed command line exactly as a user would (a fresh interpreter)."""
    return subprocess.run([sys.executable, "-m", "rvbacklash", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, timeout=120)
