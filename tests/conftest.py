"""Shared fixtures for the test suite."""

from __future__ import annotations

import pytest

from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.loading import example_text, load_design
from rvbacklash.problem import prepare


@pytest.fixture(scope="session")
def sun2014():
    return load_design("sun2014")


@pytest.fixture(scope="session")
def rv80e():
    return load_design("rv80e")


@pytest.fixture(scope="session")
def sun2014_problem(sun2014):
    return prepare(sun2014)


@pytest.fixture(scope="session")
def rv80e_problem(rv80e):
    return prepare(rv80e)


@pytest.fixture(scope="session")
def sun2014_result(sun2014_problem):
    return analyze(sun2014_problem)


@pytest.fixture(scope="session")
def sun2014_toml() -> str:
    return example_text("sun2014")


@pytest.fixture(scope="session")
def rv80e_toml() -> str:
    return example_text("rv80e")
