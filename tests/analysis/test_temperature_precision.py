"""Precision at a temperature (issue 40 item 5, heat40): the parts' differential expansion as a change of
the unit's geometry (analysis/losses/thermal.py) feeding the contact, elastic and transmission-error
models: the crank circle against the discs' bores, the cranks' throw against the profile's eccentricity,
the involute stage's centre distance; metamorphic checks (equal coefficients: nothing moves; a hotter
housing opens the pins as the linear model says) and the `--temperature` flag of transmission-error."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import rvbacklash.api as api
from rvbacklash.analysis.losses.thermal import (clearance_change, crank_clearance_at_temperature,
                                                precision_at_temperature, transmission_at_temperature,
                                                unit_at_temperature, with_equal_expansion)
from rvbacklash.analysis.transmission import transmission_error
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.models import friction as fr
from rvbacklash.models.elastic import elastic_model
from rvbacklash.models.kinematics import perfect_unit

POSITIONS = 320  # rv80e's production-run grid (8 z_p)


@pytest.fixture(scope="module")
def problem():
    return api.prepare("rv80e")


@pytest.fixture(scope="module")
def model(problem):
    return elastic_model(problem)


@pytest.fixture(scope="module")
def unit(problem):
    """A unit with errors (seeded): pins off their circle and pitch, tooth spaces, the discs' run-out and
    crank eccentricity, the gears' and crank holes' kinematic errors."""
    rng = np.random.default_rng(40)
    p = perfect_unit(problem)
    z, d = problem.cycloid.zp, problem.cycloid.discs
    return p.with_(pin_radial_um=rng.normal(0, 2.0, z), pin_tangential_um=rng.normal(0, 2.0, z),
                   pin_radius_um=rng.normal(0, 1.0, z), tooth_pitch_um=rng.normal(0, 2.0, (d, problem.cycloid.zc)),
                   runout_um=rng.normal(0, 2.0, (d, 2)), eccentricity_error_um=rng.normal(0, 1.0, d),
                   centre_gear_eccentricity_um=rng.normal(0, 3.0, 2), planet_eccentricity_um=rng.normal(0, 3.0, (3, 2)))


def test_the_offset_clearance_in_closed_form():
    # a journal offset by d across its travel in a clearance circle of diameter G: the chord sqrt(G^2 - 4 d^2)
    assert fr.offset_clearance_um(4.5, 0.0) == 4.5
    assert fr.offset_clearance_um(4.5, 1.26) == pytest.approx(math.sqrt(4.5 ** 2 - 4 * 1.26 ** 2), rel=1e-15)
    assert fr.offset_clearance_um(4.5, -1.26) == fr.offset_clearance_um(4.5, 1.26)
    assert fr.offset_clearance_um(4.5, 2.25) == 0.0 and fr.offset_clearance_um(4.5, 3.0) == 0.0
    assert fr.offset_clearance_um(-2.0, 1.0) == -2.0  # a preload stays a preload


def test_the_iron_carrier_against_the_steel_discs_closes_the_crank_bearings(problem, model):
    # rv80e's defaults: carrier 11.0e-6, discs 12.5e-6 /K on a 42 mm crank circle: each eccentric sits
    # 42 x 1.5e-6 x dT inward in its bore (1.26 um at 40 degC, 2.52 um at 60); the needle bearings' 4.5 um
    # (zone mean) leave a tangential chord of sqrt(4.5^2 - 4 x 1.26^2) = 3.728 um at 40 degC, none at 60
    th = problem.design.thermal
    c40, c60 = clearance_change(problem, th, 40.0), clearance_change(problem, th, 60.0)
    assert c40.crank_circle_um == pytest.approx(-42.0 * 1.5e-6 * 20 * 1e3, rel=1e-12)
    assert c60.crank_circle_um == pytest.approx(-2.52, rel=1e-12)
    assert crank_clearance_at_temperature(4.5, c40) == pytest.approx(math.sqrt(4.5 ** 2 - 4 * 1.26 ** 2), rel=1e-12)
    assert crank_clearance_at_temperature(4.5, c60) == 0.0
    # the steel gears outgrow the iron carrier's crank circle: the centre distance closes (less backlash)
    assert c60.centre_distance_um == pytest.approx(
        -problem.geometry.centre_distance_mm * 1.5e-6 * 40 * 1e3, rel=1e-12) and c60.centre_distance_um < 0
    assert c60.crank_eccentricity_um == 0.0  # cranks and discs both bearing steel
    # the loop reads the chord: at 60 degC the needle bearings' dead band is gone
    ref = precision_at_temperature(problem, model, th, 20.0)
    warm = precision_at_temperature(problem, model, th, 60.0)
    assert ref.crank_bearing_clearance_um == pytest.approx(4.5) and warm.crank_bearing_clearance_um == 0.0
    assert warm.lost_motion_arcmin < ref.lost_motion_arcmin - 0.3  # the crank stage's ~0.36 arcmin dead band


def test_equal_coefficients_leave_te_lost_motion_and_clearances(problem, model, unit):
    """Metamorphic (issue 40 item 7): a uniform temperature change with every part's coefficient equal
    scales the whole reducer, which leaves every angle as it is: no clearance, TE or lost motion changes
    (read in the disc's frame: exactly)."""
    th = with_equal_expansion(problem.design.thermal, 12e-6)
    c = clearance_change(problem, th, 80.0)
    for v in (c.moving_distance_modification_um, c.equidistance_modification_um, c.pin_hole_clearance_um,
              c.crank_bearing_clearance_um, c.support_bearing_clearance_um, c.crank_eccentricity_um,
              c.crank_circle_um, c.centre_distance_um):
        assert abs(v) < 1e-12  # sums of growths: rounding
    cold = transmission_error(problem, unit, "unit", POSITIONS, shares=False)
    hot = transmission_at_temperature(problem, unit, c, POSITIONS, shares=False, label="unit")
    assert cold.te_peak_to_peak_arcsec > 5.0  # a unit with errors: a real TE to compare
    assert hot.te_peak_to_peak_arcsec == pytest.approx(cold.te_peak_to_peak_arcsec, abs=1e-6)
    np.testing.assert_allclose(hot.te_ccw_arcsec, cold.te_ccw_arcsec, rtol=0, atol=1e-6)
    np.testing.assert_allclose(hot.lost_motion_arcmin, cold.lost_motion_arcmin, rtol=1e-12)
    assert hot.other_stages_arcmin == pytest.approx(cold.other_stages_arcmin, rel=1e-12)
    assert hot.temperature_c == 80.0 and cold.temperature_c is None
    ref, warm = (precision_at_temperature(problem, model, th, t, POSITIONS) for t in (20.0, 80.0))
    assert warm.lost_motion_arcmin == pytest.approx(ref.lost_motion_arcmin, rel=1e-9)
    assert warm.backlash_arcmin == pytest.approx(ref.backlash_arcmin, rel=1e-9)
    assert warm.torsional_rigidity_nm_per_arcmin == pytest.approx(ref.torsional_rigidity_nm_per_arcmin, rel=1e-9)
    assert ref.te_peak_to_peak_arcsec == 0.0 and abs(warm.te_peak_to_peak_arcsec) < 1e-6


@pytest.mark.parametrize("housing, sign", [(14.5e-6, 1.0), (10.5e-6, -1.0)])
def test_a_hotter_housing_opens_the_pins(problem, model, unit, housing, sign):
    """Metamorphic: the housing's expansion coefficient above the pins' and discs' (every other part as
    the discs) moves the pin circle out from the discs as it warms: the moving-distance change
    r_p (alpha_d - alpha_h) dT < 0 opens the cycloid stage, so backlash, lost motion (elastic and rigid)
    grow by the linear model's transfer of that change (Eq. (1), factor 19's sqrt(1 - K1^2)); a housing
    below them closes it. The error-free unit's TE barely moves (a uniform radial change: < 1 arcsec); a
    unit with errors changes its TE with its play (which pins carry), not checked here."""
    alpha = 12.5e-6
    th = with_equal_expansion(problem.design.thermal, alpha).model_copy(update={"housing_expansion_per_k": housing})
    c = clearance_change(problem, th, 60.0)
    assert c.moving_distance_modification_um == pytest.approx(77.5 * (alpha - housing) * 40 * 1e3, rel=1e-9)
    sens = problem.sensitivities_arcmin_per_um[FACTOR_KEYS.index("moving_distance_modification_error")]
    expected = sens * c.moving_distance_modification_um  # the linear model's change of the lost motion [arcmin]
    assert sign * expected > 0.1
    ref, warm = (precision_at_temperature(problem, model, th, t) for t in (20.0, 60.0))
    assert sign * (warm.backlash_arcmin - ref.backlash_arcmin) > 0.0
    assert warm.backlash_arcmin - ref.backlash_arcmin == pytest.approx(expected, rel=0.25)
    assert warm.lost_motion_arcmin - ref.lost_motion_arcmin == pytest.approx(expected, rel=0.25)
    cold = transmission_error(problem, unit, "unit", POSITIONS, shares=False)
    hot = transmission_at_temperature(problem, unit, c, POSITIONS, shares=False, label="unit")
    assert hot.lost_motion_reference_arcmin - cold.lost_motion_reference_arcmin == pytest.approx(expected, rel=0.25)
    nominal = transmission_at_temperature(problem, perfect_unit(problem), c, POSITIONS, shares=False)
    assert 0.0 < nominal.te_peak_to_peak_arcsec < 1.0


def test_the_unit_at_temperature_is_the_unit_plus_the_change(problem, unit):
    c = clearance_change(problem, problem.design.thermal, 70.0)
    hot = unit_at_temperature(unit, c)
    assert hot.moving_distance_um == pytest.approx(unit.moving_distance_um + c.moving_distance_modification_um)
    assert hot.pin_clearance_um == pytest.approx(unit.pin_clearance_um + c.pin_hole_clearance_um)
    assert hot.eccentricity_error_um == pytest.approx(unit.eccentricity_error_um + c.crank_eccentricity_um)
    np.testing.assert_array_equal(hot.pin_radial_um, unit.pin_radial_um)  # the unit's own errors kept


def test_transmission_error_takes_a_temperature(tmp_path):
    from helpers import one_line_error, run_cli

    js = tmp_path / "te.json"
    p = run_cli("transmission-error", "rv80e", "--positions", str(POSITIONS), "--temperature", "60", "--json", js)
    assert p.returncode == 0, p.stderr
    d = json.loads(js.read_text())
    assert d["temperature_c"] == 60.0 and d["unit"] == "nominal at 60 degC"
    assert d["other_stages_from"] == "linear means, at 60 degC"
    # the steel gears closer, the crank bearings closed: only the involute stage's reduced backlash is left
    assert 0.0 < d["other_stages_arcmin"] < 0.069
    bad = run_cli("transmission-error", "rv80e", "--temperature", "400")
    assert bad.returncode == 2
    line = one_line_error(bad)
    assert "--temperature" in line and "400" in line and "-40 to 150" in line
