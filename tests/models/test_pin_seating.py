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
    """The seats' part of the pins' angle to first order, sum_j k_j L_j delta_seat,j / sum_j k_j L_j^2,
    from every pin's force at the converged angle: the seat's approach by Johnson's formula
    (``johnson_line_approach_um``) or Palmgren's, k_j by a central difference of the pin's whole law."""
    c = model.chain
    a = pu.branch(torque_nm, el.RISE)
    x = a[ch.PINS] + a[ch.PIN_SEATING]
    f = pu.pin_forces_n(x).ravel()
    lev = (pu.unit.lever_um_per_rad / c.lever_factor).ravel()
    law = pu.law_a.ravel()
    e = model.inputs
    pin = cm.Body(c.pin_radius_mm, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio)
    housing = cm.Body(c.pin_radius_mm, e.housing_youngs_modulus_gpa, e.housing_poisson_ratio)
    moved = stiffness = 0.0
    for fj, lj, aj in zip(f, lev, law):
        if fj <= 0.0:
            continue
        seat = (cm.johnson_line_approach_um(fj, c.contact_length_mm, pin, housing,
                                            cm.RELATIVE_RADIUS_CAP * c.pin_radius_mm) if c.johnson
                else cm.palmgren_line_approach_um(fj, c.contact_length_mm))
        h = 1e-4 * fj
        k = 2 * h / (cm.law_approach_um(fj + h, aj, c.law_b, c.law_n) - cm.law_approach_um(fj - h, aj, c.law_b, c.law_n))
        moved += k * lj * seat
        stiffness += k * lj * lj
    return moved / stiffness, a[ch.PIN_SEATING], x


@pytest.mark.parametrize("law", ["johnson", "palmgren"])
def test_seats_part_of_the_pins_angle_is_their_first_order_effect(problem, law):
    p = with_elastic(problem, contact_law=law, housing_youngs_modulus_gpa=170.0)
    model = el.elastic_model(p)
    rigid_seats = el.elastic_model(with_elastic(problem, contact_law=law, pin_seating="none"))
    assert model.chain.seat_a > 0.0
    for unit in (el.nominal_unit(p), el.nominal_unit(p, 0.03)):
        pu = el.PreparedUnit(model, unit)
        for t in (23.52, 392.0, 784.0):
            independent, kernel, x = seat_angle_independent(pu, t, model)
            assert kernel > 0.0
            assert kernel == pytest.approx(independent, rel=1e-6), (law, t)
            # and it is what the seats do to the pins' angle: the same unit with rigid seats turns less by about
            # that much once the load is shared (first order: within 3.4 % with Johnson's law at 50 and 100 % T_R,
            # 5.2 % with Palmgren's; at +-3 % T_R, where 4 of 40 pins carry, removing the seats moves the load
            # sharing and the first order is 15-25 % off: the seats' part of the lost motion is read to that)
            if t > 100.0:
                b = el.PreparedUnit(rigid_seats, unit).branch(t, el.RISE)
                assert x - (b[ch.PINS] + b[ch.PIN_SEATING]) == pytest.approx(kernel, rel=0.06), (law, t)


def test_preloaded_pins_seats_take_a_share_not_the_pins_angle(problem):
    # a preloaded stage: opposing pins pressed at zero torque. Their seats' first-order effects cancel in
    # pairs, so the seats' part stays a fraction of the pins' wind-up (a force-weighted reading gave -700 %)
    from rvbacklash.models.unit_errors import Realization

    model = el.elastic_model(problem)
    r = Realization.nominal(problem.cycloid, -8.0, -4.0, 0.0)
    unit = el.unit_from_realization(problem, r, 0.0, 0.0)
    assert unit.gap_um.min() < 0.0  # preloaded
    fig = el.PreparedUnit(model, unit).figures()
    seat_lm = fig[el.ELEMENT_LOST_MOTION + ch.PIN_SEATING]
    pins_lm = fig[el.ELEMENT_LOST_MOTION + ch.PINS]
    assert 0.0 < seat_lm < pins_lm
    span = fig[el.SHARES:]
    assert 0.0 < span[ch.PIN_SEATING] < span[ch.PINS]


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
