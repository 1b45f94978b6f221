"""The terminal tables of report/tables.py: what a user reads."""

from __future__ import annotations

import dataclasses
import io

import pytest
from rich.console import Console

import rvbacklash as rb
from rvbacklash.report.tables import print_simulation, rate_text


@pytest.mark.parametrize("per_s, text", [
    (212.3, "212 samples/s"), (4.71, "4.71 samples/s"), (0.5, "0.5 samples/s"), (999.4, "999 samples/s"),
    (1000.0, "1 k samples/s"), (21_230.0, "21.2 k samples/s"), (3.4e6, "3.4 M samples/s"),
])
def test_rate_in_the_unit_that_fits(per_s, text):
    assert rate_text(per_s, "samples") == text


def test_a_slow_run_prints_its_rate_not_zero_millions():
    """Regression: `simulate --model transmission` printed '4.71 s, 0.00 M samples/s'."""
    sim = rb.simulate("rv80e", samples=1000, seed=1)
    slow = dataclasses.replace(sim, elapsed_s=4.71)  # the transmission model's pace: ~212 units/s
    out = io.StringIO()
    print_simulation(slow, Console(file=out, width=160))
    last = out.getvalue().strip().splitlines()[-1]
    assert last == "4.71 s, 212 samples/s"
