"""The disc bodies' load state (models/elastic/bodies.py; issue 36, item 1): the FE is loaded by the
nominal unit the loop solves, with the change of its pins' forces over the rigidity interval, so
that the figures depend on the unit's gaps, not on how the design writes them, and a preload's
self-balanced pin forces do not read as the body's compliance."""

from __future__ import annotations

import numpy as np
import pytest

from rvbacklash.design.loading import design_from_toml, example_text
from rvbacklash.models.elastic import PreparedUnit, elastic_model, nominal_unit
from rvbacklash.models.elastic.bodies import disc_load_n
from rvbacklash.models.elastic.chain import LOST_MOTION, BACKLASH, RIGIDITY
from rvbacklash.problem import prepare
from rvbacklash.units import ARCMIN_PER_RAD

from helpers import with_factor


def _design(equidistance_um: float, hole_clearance_um: tuple[float, float] | None = None):
    text = example_text("rv80e").replace("equidistance_modification_um = 5.0",
                                         f"equidistance_modification_um = {equidistance_um}")
    if hole_clearance_um is not None:
        text = with_factor(text, "pin_hole_clearance",
                           f"lower_um = {hole_clearance_um[0]}\nupper_um = {hole_clearance_um[1]}")
    return prepare(design_from_toml(text))


def _nominal(problem):
    """(the nominal unit's figures: lost motion, backlash, rigidity; the disc bodies' element
    stiffness at the output [N m/arcmin]; the gaps of its pins [um])."""
    model = elastic_model(problem)
    unit = nominal_unit(problem)
    figures = PreparedUnit(model, unit).figures()
    disc = 1.0 / (model.chain.disc_body_compliance_rad_per_nm * ARCMIN_PER_RAD)
    return figures[[LOST_MOTION, BACKLASH, RIGIDITY]], disc, unit.gap_um


def test_the_same_gaps_written_two_ways_give_the_same_figures():
    """Issue 36's pair: the equidistance modification 0 um with a pin/hole clearance of [5, 20] um
    (mean 12.5) against 5 um with [0, 5] um (mean 2.5) give the nominal unit the same pins (each gap
    moves by the modification plus half the hole clearance). Before the fix the disc FE was loaded
    by a unit without hole clearance, preloaded in the first writing: rigidity 266.5 against 312.5
    N m/arcmin, disc bodies 868 against 1666."""
    a_figures, a_disc, a_gaps = _nominal(_design(0.0, (5.0, 20.0)))
    b_figures, b_disc, b_gaps = _nominal(_design(5.0, (0.0, 5.0)))
    assert np.max(np.abs(a_gaps - b_gaps)) < 1e-6  # the same unit
    assert a_figures == pytest.approx(b_figures, rel=1e-3)
    assert a_disc == pytest.approx(b_disc, rel=1e-3)


def test_a_preload_does_not_read_as_the_disc_bodies_compliance():
    """A nominal unit whose every pin interferes (equidistance -10 um: all 40 + 40 pins closed at zero
    torque, up to 2 kN each) against a free one (0 um): the disc bodies are one linear body, their
    stiffness set by how the torque's increment spreads over the pins, not by the preload's
    self-balanced forces. Measured: 1765 against 1671 N m/arcmin with the increment over the rigidity
    interval; 161 for the preloaded unit loaded with its forces at the rated torque (the preload
    included); before issue 36 (a unit without hole clearance at the rated torque) 35 against 868."""
    preloaded = _design(-10.0)
    load = disc_load_n(elastic_model(preloaded), nominal_unit(preloaded))
    assert np.count_nonzero(load < 0) > 10  # the opposite flanks unload: the preload is in the picture
    _, disc_preloaded, _ = _nominal(preloaded)
    _, disc_free, _ = _nominal(_design(0.0))
    assert 0.9 < disc_preloaded / disc_free < 1.15


def test_a_free_unit_loads_every_pin_more():
    """The increment of a free unit (rv80e's nominal, 11 + 11 pins at the rated torque): no pin
    unloads, the pins closed at the top of the interval carry it."""
    problem = prepare(design_from_toml(example_text("rv80e")))
    load = disc_load_n(elastic_model(problem), nominal_unit(problem))
    assert np.all(load >= 0.0)
    assert list(np.count_nonzero(load, axis=1)) == [11, 11]
