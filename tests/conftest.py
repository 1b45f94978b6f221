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
def rv80e_elastic():
    """(problem, elastic model, other stages' nominal involute, crank clearance) of rv80e, shared by
    the capacity and service-life tests (one per xdist worker)."""
    import rvbacklash.api as api
    from rvbacklash.models.elastic import elastic_model, other_stages_nominal

    problem = api.prepare("rv80e")
    inv, clr = other_stages_nominal(problem)
    return problem, elastic_model(problem), inv, clr


@pytest.fixture(scope="session")
def sun2014_result(sun2014_problem):
    return analyze(sun2014_problem)


@pytest.fixture(scope="session")
def sun2014_toml() -> str:
    return example_text("sun2014")


@pytest.fixture(scope="session")
def rv80e_toml() -> str:
    return example_text("rv80e")


# The test files that take longest, started first. pytest-xdist hands whole files to the two
# workers (pyproject: --dist loadfile --no-loadscope-reorder), in the order they are collected;
# its default order (most tests first) started files of one or two long tests (a browser, a burst,
# a bench) last, one worker then ran them alone while the other idled. Longest first (--durations
# of a warm run); files not listed follow in their usual order. Only the order changes, never what
# runs; a stale list costs time, not coverage.
SLOW_FIRST = (
    "tests/cli/test_cli_interrupt.py",
    "tests/test_benches.py",
    "tests/report/test_html.py",
    "tests/analysis/test_allocation.py",
    "tests/cli/test_cli_sweep.py",
    "tests/models/test_contact_kernel.py",
    "tests/mechanics/test_carrier_body.py",
    "tests/analysis/test_bench_calibration.py",
    "tests/report/test_schemas.py",
    "tests/analysis/test_bench_roundtrip.py",
    "tests/cli/test_cli_json_stdout.py",
    "tests/analysis/test_service_life.py",
    "tests/mechanics/test_carrier_layout.py",
    "tests/analysis/test_sweep.py",
    "tests/app/test_app_browser.py",
    "tests/analysis/test_selection_inventory.py",
    "tests/cli/test_cli_hysteresis.py",
    "tests/analysis/test_hysteresis.py",
    "tests/report/test_capacity_report.py",
    "tests/cli/test_cli_allocation.py",
    "tests/app/test_app_burst.py",
    "tests/mechanics/test_disc_body.py",
    "tests/analysis/test_sensitivity_global.py",
    "tests/analysis/test_statistics.py",
    "tests/cli/test_cli_bench.py",
    "tests/cli/test_cli.py",
    "tests/cli/test_cli_two_cranks.py",
    "tests/app/test_app_cli.py",
    "tests/test_examples.py",
    "tests/cli/test_cli_service_life.py",
)


def pytest_collection_modifyitems(config, items):
    rank = {name: i for i, name in enumerate(SLOW_FIRST)}

    def key(item) -> int:
        try:
            return rank.get(item.path.relative_to(config.rootpath).as_posix(), len(rank))
        except ValueError:  # a file outside the project
            return len(rank)

    items.sort(key=key)  # stable: the tests of a file keep their order
