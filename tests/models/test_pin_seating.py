"""The pins' seats in the housing grooves (issue 28; models/compliance.py ``pin_seat_law_a_um_per_n``,
models/elastic/chain.py ``seat_angle_rad``): the seat's law against Johnson's formula, the seats'
part of the pins' angle against an independent reader of the converged forces, and what the
element does to rv80e."""

from __future__ import annotations

import numpy as np
import pytest

from rvbacklash.models import compliance as cm
from rvbacklash.models import elastic as el
from rvbacklash.models.elastic import chain as ch
from rvbacklash.problem import prepare


@pytest.fixture(scope="module")
def problem(rv80e):
    return prepare(rv80e)


def with_elastic(problem, **update):
    d = problem.design
    return prepare(d.model_copy(update={"elastic": d.elastic.model_copy(update=update)}))


def test_seat_law_is_johnsons_approach_at_the_conforming_cap():
    # delta = F (a - b ln F) with the seat's a and b equals Johnson's two-cylinder approach with the relative
    # radius at its cap (10 pin radii), the pin and the groove both of the pin's radius
    pin, housing = cm.Body(4.0, 208.0, 0.3), cm.Body(4.0, 170.0, 0.28)
    a = cm.pin_seat_law_a_um_per_n(12.0, pin, housing)
    b = cm.johnson_law_b_um_per_n(12.0, 208.0, 0.3, 170.0, 0.28)
    for f in (50.0, 500.0, 2000.0, 8000.0):
        assert f * (a - b * np.log(f)) == pytest.approx(
            cm.johnson_line_approach_um(f, 12.0, pin, housing, cm.RELATIVE_RADIUS_CAP * 4.0), rel=1e-12)


def test_seat_approaches_no_more_than_any_flank(problem):
    # a conforming contact (the groove fits the pin) is wider than the flank's at the same load, and its bodies'
    # radii (the pin's) are smaller than the flank's: its approach is the smaller of the two, except at the few
    # pins where the flank is near-conformal too (capped alike: equal within 1 %)
    c = el.elastic_model(problem).chain
    e = problem.design.elastic
    b_seat = cm.johnson_law_b_um_per_n(c.contact_length_mm, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio,
                                       e.housing_youngs_modulus_gpa, e.housing_poisson_ratio)
    assert c.seat_b_fraction * c.law_b == pytest.approx(b_seat, rel=1e-12)  # the seat's part of the shared b
    g = problem.cycloid
    laws = np.empty((g.discs, g.zp))
    ch.fill_pin_law(0.0, c, laws)
    flank = laws - c.seat_a
    assert np.all(flank > 0.99 * c.seat_a) and np.median(flank) > 1.15 * c.seat_a


def seat_angle_independent(pu, torque_nm, model):
    """1e-6 sum_j F_j delta_seat(F_j) / T from every pin's force at the converged angle, the seat's
    approach by Johnson's formula (``johnson_line_approach_um``) or Palmgren's."""
    c = model.chain
    a = pu.branch(torque_nm, el.RISE)
    x = a[ch.PINS] + a[ch.PIN_SEATING]
    f = pu.pin_forces_n(x).ravel()
    e = model.inputs
    pin = cm.Body(c.pin_radius_mm, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio)
    housing = cm.Body(c.pin_radius_mm, e.housing_youngs_modulus_gpa, e.housing_poisson_ratio)
    seat = np.array([(cm.johnson_line_approach_um(fj, c.contact_length_mm, pin, housing,
                                                  cm.RELATIVE_RADIUS_CAP * c.pin_radius_mm) if c.johnson
                      else cm.palmgren_line_approach_um(fj, c.contact_length_mm)) if fj > 0 else 0.0 for fj in f])
    t_el = ch.branch_point(torque_nm, ch.RISE, c)[0]
    return 1e-6 * float(f @ seat) / t_el, a[ch.PIN_SEATING]


@pytest.mark.parametrize("law", ["johnson", "palmgren"])
def test_seats_part_of_the_pins_angle_is_the_forces_work_on_the_seats(problem, law):
    p = with_elastic(problem, contact_law=law, housing_youngs_modulus_gpa=170.0)
    model = el.elastic_model(p)
    assert model.chain.seat_a > 0.0
    for unit in (el.nominal_unit(p), el.nominal_unit(p, 0.03)):
        pu = el.PreparedUnit(model, unit)
        for t in (23.52, 392.0, 784.0):
            independent, kernel = seat_angle_independent(pu, t, model)
            assert kernel > 0.0
            assert kernel == pytest.approx(independent, rel=1e-8), (law, t)


def test_seat_is_an_element_in_series_and_none_removes_it(problem):
    from rvbacklash.analysis.hysteresis import hysteresis

    with_seats = hysteresis(problem)
    without = hysteresis(with_elastic(problem, pin_seating="none"))
    assert without.compliance_share["pin_seating"] == 0.0 and without.element_stiffness_nm_per_arcmin["pin_seating"] is None
    share = with_seats.compliance_share["pin_seating"]
    assert 0.0 < share < with_seats.compliance_share["cycloid_pins"]  # conforming: stiffer than the flanks
    assert with_seats.torsional_rigidity_nm_per_arcmin < without.torsional_rigidity_nm_per_arcmin
    # the seats carry no dead band: the pins' free play is unchanged
    assert with_seats.dead_band_arcmin["pin_seating"] == 0.0
    assert with_seats.dead_band_arcmin["cycloid_pins"] == pytest.approx(without.dead_band_arcmin["cycloid_pins"],
                                                                        rel=1e-12)
