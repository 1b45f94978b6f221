"""The rating and life formulas (models/ratings.py) against closed forms and published examples."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rvbacklash.errors import InputError
from rvbacklash.models import compliance as cm
from rvbacklash.models import ratings as rt
from rvbacklash.models.elastic.loads import RollerSet, cycle_equivalent_lamina_loads, roller_loads_n, \
    roller_set_approach_um


def test_fc_table_agrees_with_the_closed_form_it_comes_from():
    # ISO 281 Table 7 (as stored) against ISO/TR 1281-1's closed form with lambda nu = 0.83: two independent readings
    g, f = rt.fc_table("roller")
    for gamma, fc in zip(g, f):
        assert abs(rt.fc_radial_roller_closed_form(gamma) - fc) <= 0.06, gamma
    assert rt.fc_radial_roller(0.115) == pytest.approx(0.5 * (84.2 + 86.4) + 0.25 * (86.4 - 84.2), abs=1e-12)


def test_fc_outside_the_table_is_refused():
    with pytest.raises(InputError, match="ISO 281 f_c table"):
        rt.fc_radial_roller(0.35)
    with pytest.raises(InputError):
        rt.fc_radial_ball(0.005)


def test_tapered_bearing_rating_recomputed_from_its_dimensions():
    # 32005X (25 x 47 x 15 mm), NTN catalogue 2203: C_r = 31.0 kN, e = 0.43 (alpha = atan(e / 1.5) = 16 deg);
    # Z = 17 rollers of 5.5 x 11 mm on a 36 mm pitch circle estimated from its envelope (examples/rv80e.toml)
    c = rt.dynamic_load_rating_radial_roller_n(1, 11.0, 16.0, 17, 5.5, 36.0)
    by_hand = 1.1 * rt.fc_radial_roller(5.5 * math.cos(math.radians(16)) / 36) * (11 * math.cos(math.radians(16))) \
        ** (7 / 9) * 17 ** 0.75 * 5.5 ** (29 / 27)
    assert c == pytest.approx(by_hand, rel=1e-12)
    assert c == pytest.approx(31_000.0, rel=0.03)


def test_ball_rating_follows_iso_281_equation_1():
    # ISO 281 Eq. (1): C_r = b_m f_c (i cos a)^0.7 Z^(2/3) D_w^1.8, f_c at gamma = 0.10 is the table's 55.5
    c = rt.dynamic_load_rating_radial_ball_n(1, 0.0, 10, 10.0, 100.0)
    assert c == pytest.approx(1.3 * 55.5 * 10 ** (2 / 3) * 10.0 ** 1.8, rel=1e-12)
    assert rt.dynamic_load_rating_radial_ball_n(2, 0.0, 10, 10.0, 100.0) == pytest.approx(c * 2 ** 0.7, rel=1e-12)


def test_static_rating_iso_76():
    c0 = rt.static_load_rating_radial_roller_n(1, 10.0, 0.0, 18, 4.0, 34.0)
    assert c0 == pytest.approx(44.0 * (1 - 4 / 34) * 18 * 10 * 4, rel=1e-12)


def test_life_closed_forms():
    assert rt.basic_rating_life_mrev(10_000.0, 10_000.0, 10 / 3) == pytest.approx(1.0)
    assert rt.basic_rating_life_mrev(20_000.0, 10_000.0, 3.0) == pytest.approx(8.0)
    assert math.isinf(rt.basic_rating_life_mrev(1.0, 0.0, 3.0))
    assert rt.life_hours(1.0, 1000.0 / 60.0) == pytest.approx(1000.0)  # 1 Mrev at 1000/60 r/min: 1000 h
    # a load acting for half the revolutions at P and half at 2P: ((1 + 2^p) / 2)^(1/p) P
    p = 10 / 3
    assert rt.equivalent_load_variable_n([1.0, 2.0], [1.0, 1.0], p) == pytest.approx(((1 + 2 ** p) / 2) ** (1 / p))
    assert rt.equivalent_load_variable_n([3.0, 3.0, 3.0], [1, 5, 2], p) == pytest.approx(3.0)


def test_system_life():
    e = rt.ROLLER_WEIBULL_SLOPE
    assert rt.system_life([100.0], [e]) == pytest.approx(100.0)
    assert rt.system_life([100.0] * 6, e) == pytest.approx(100.0 * 6 ** (-1 / e), rel=1e-12)
    assert rt.system_life([100.0, math.inf], e) == pytest.approx(100.0)
    assert math.isinf(rt.system_life([math.inf, math.inf], e))
    lives, slopes = [100.0, 300.0, 50.0], [9 / 8, 10 / 9, 9 / 8]
    system = rt.system_life(lives, slopes)  # mixed slopes: the reliabilities multiply to 0.9 at L
    assert sum((system / li) ** s for li, s in zip(lives, slopes)) == pytest.approx(1.0, abs=1e-12)
    assert system < 50.0


def test_tapered_equivalent_load_and_pair():
    alpha = 16.0
    t = math.tan(math.radians(alpha))
    assert rt.tapered_equivalent_load_n(1000.0, 1.5 * t * 1000.0, alpha) == pytest.approx(1000.0)  # F_a/F_r = e
    assert rt.tapered_equivalent_load_n(1000.0, 3 * t * 1000.0, alpha) == pytest.approx(400.0 + 0.4 / t * 3 * t * 1000)
    fa, fb = rt.tapered_pair_axial_loads_n(1000.0, 1000.0, alpha, 0.0)  # equal loads: the induced forces balance
    assert fa == pytest.approx(fb) and fa == pytest.approx(0.5 * 1000 / (0.4 / t))
    assert rt.tapered_equivalent_load_n(1000.0, fa, alpha) == pytest.approx(1000.0)  # 1.25 tan(a) < e: P = F_r
    fa, fb = rt.tapered_pair_axial_loads_n(1000.0, 3000.0, alpha, 0.0)
    assert fa == pytest.approx(fb) and fb == pytest.approx(0.5 * 3000 / (0.4 / t))


def test_makers_life_formula_at_the_rated_point():
    assert rt.makers_reducer_life_h(6000.0, 15.0, 15.0, 784.0, 784.0) == pytest.approx(6000.0)
    assert rt.makers_reducer_life_h(6000.0, 15.0, 30.0, 784.0, 784.0 * 2) == pytest.approx(6000 / 2 / 2 ** (10 / 3))


def test_hertz_point_contact_sphere_on_flat():
    # Johnson (1985) ch. 4: a = (3 Q R / (4 E*))^(1/3), p0 = 3 Q / (2 pi a^2), delta = a^2 / R
    e_star = cm.contact_modulus_n_per_mm2(206.0, 0.3, 206.0, 0.3)
    q, r = 500.0, 5.0
    a, b, p0, delta = rt.hertz_point_contact(q, 2.0 / r, 0.0, e_star)
    a_exact = (3 * q * r / (4 * e_star)) ** (1 / 3)
    assert a == pytest.approx(a_exact, rel=1e-12) and b == pytest.approx(a_exact, rel=1e-12)
    assert p0 == pytest.approx(3 * q / (2 * math.pi * a_exact ** 2), rel=1e-12)
    assert delta == pytest.approx(a_exact ** 2 / r, rel=1e-12)
    # an ellipse: the semi-axes' product and the load give the peak pressure, delta ~ Q^(2/3)
    a1, b1, p1, d1 = rt.hertz_point_contact(q, 0.5, 0.9, e_star)
    assert a1 > b1 and p1 == pytest.approx(3 * q / (2 * math.pi * a1 * b1), rel=1e-12)
    assert rt.hertz_point_contact(8 * q, 0.5, 0.9, e_star)[3] == pytest.approx(4 * d1, rel=1e-9)


def test_iso_ts_16281_ball_bearing_worked_example():
    # ISO/TS 16281:2008's worked example (../shared/reference/anchors.md): deep-groove ball bearing, Z = 7,
    # D_w = 11.5 mm, D_pw = 43.5 mm, zero clearance, 1000 N radial -> 15.11 um; grooves 0.52 / 0.53 D_w,
    # steel E = 210 GPa, nu = 0.3 (the values with which the example's number is reproduced), a ball on the load line
    d, dpw, z, load = 11.5, 43.5, 7, 1000.0
    gamma = d / dpw
    e_star = cm.contact_modulus_n_per_mm2(210.0, 0.3, 210.0, 0.3)
    inner = rt.ball_raceway_curvatures(d, 0.52, gamma, True)
    outer = rt.ball_raceway_curvatures(d, 0.53, gamma, False)
    k = (rt.hertz_point_contact(load, *inner, e_star)[3] + rt.hertz_point_contact(load, *outer, e_star)[3]) \
        / load ** (2 / 3)
    psi = 2 * math.pi * np.arange(z) / z

    def residual(dr):
        closure = np.maximum(dr * np.cos(psi), 0.0)
        return float(np.sum((closure / k) ** 1.5 * np.cos(psi))) - load

    assert brentq(residual, 1e-6, 1.0, xtol=1e-15) * 1e3 == pytest.approx(15.11, abs=0.005)


def _needles(z=18, slices=30, length=10.0):
    return RollerSet(np.cos(2 * math.pi * np.arange(z) / z), np.zeros(slices), cm.iso_roller_constant_n_per_mm(length))


def test_roller_set_equilibrium_and_stribeck():
    rollers = _needles()
    for clearance in (0.0, 10.0, -4.0):
        dr = roller_set_approach_um(3000.0, clearance, rollers)
        q = np.empty(18)
        roller_loads_n(dr, clearance, rollers, q)
        assert float(np.sum(q * rollers.roller_cos)) == pytest.approx(3000.0, rel=1e-10)
    dr = roller_set_approach_um(3000.0, 0.0, rollers)
    roller_loads_n(dr, 0.0, rollers, q)
    assert q.max() == pytest.approx(4.08 * 3000.0 / 18, rel=0.02)  # Stribeck, line contact, zero clearance


def test_cycle_equivalent_loads_reduce_to_the_standards_two_cases():
    # a constant load: a raceway rotating against it (the load's angle sweeps it) gets ISO/TS 16281's
    # (mean q^4)^(1/4) over the positions, a raceway stationary against it (mean q^4.5)^(1/4.5)
    rollers = _needles(slices=3)
    dr = roller_set_approach_um(3000.0, 0.0, rollers)
    states, points = 360, 360
    rotating, stationary = np.empty(3), np.empty(3)
    cycle_equivalent_lamina_loads(np.full(states, dr), 2 * math.pi * np.arange(states) / states, 0.0, rollers,
                                  points, rotating)
    cycle_equivalent_lamina_loads(np.full(states, dr), np.zeros(states), 0.0, rollers, points, stationary)
    theta = 2 * math.pi * np.arange(points) / points
    q = rollers.stiffness_n_per_mm / 3 * (np.maximum(dr * np.cos(theta), 0) * 1e-3) ** (10 / 9)
    assert rotating[1] == pytest.approx(np.mean(q ** 4) ** 0.25, rel=1e-9)
    assert stationary[1] == pytest.approx(np.mean(q ** 4.5) ** (1 / 4.5), rel=1e-9)


def test_iso_ts_16281_life_of_line_contact_goes_as_the_load_to_the_fourth():
    # zero clearance, straight rollers: the load zone keeps its shape, every lamina load ~ P, L10r ~ P^-4
    rollers = _needles()
    c = rt.dynamic_load_rating_radial_roller_n(1, 10.0, 0.0, 18, 4.0, 34.0)
    qci, qce = rt.iso16281_raceway_ratings_n(c, 18, 4.0 / 34.0)
    lci, lce = rt.iso16281_lamina_rating_n(qci, 30), rt.iso16281_lamina_rating_n(qce, 30)
    lives = []
    for load in (2000.0, 4000.0):
        dr = roller_set_approach_um(load, 0.0, rollers)
        qi, qe = np.empty(30), np.empty(30)
        cycle_equivalent_lamina_loads(np.full(72, dr), 2 * math.pi * np.arange(72) / 72, 0.0, rollers, 72, qi)
        cycle_equivalent_lamina_loads(np.full(72, dr), np.zeros(72), 0.0, rollers, 72, qe)
        lives.append(rt.iso16281_reference_life_mrev(qi, qe, lci, lce))
    assert lives[0] / lives[1] == pytest.approx(16.0, rel=1e-6)


def test_line_contact_peak_pressure_matches_the_half_width_route():
    e_star = cm.contact_modulus_n_per_mm2(206.0, 0.3, 206.0, 0.3)
    a = cm.line_contact_half_width_mm(1200.0, 12.0, 3.0, e_star)
    assert rt.line_contact_peak_pressure_from_load_mpa(1200.0, 12.0, 3.0, e_star) == pytest.approx(
        cm.line_contact_peak_pressure_mpa(1200.0, 12.0, a), rel=1e-12)
