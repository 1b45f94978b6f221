"""Friction, lubrication and heat formulas (models/friction.py): each against a closed form, its
dimensional form or its limits (issue 40)."""

import math

import numpy as np
import pytest

from rvbacklash.models import friction as fr


def test_walther_line_passes_through_both_grade_points_and_falls():
    # ISO VG 100 mineral oil (the [lubrication] default): both points back to 1e-9
    assert fr.kinematic_viscosity_mm2_s(40.0, 100.0, 11.1) == pytest.approx(100.0, rel=1e-9)
    assert fr.kinematic_viscosity_mm2_s(100.0, 100.0, 11.1) == pytest.approx(11.1, rel=1e-9)
    nus = [fr.kinematic_viscosity_mm2_s(t, 100.0, 11.1) for t in (0, 20, 40, 60, 80, 120)]
    assert all(a > b for a, b in zip(nus, nus[1:]))


def test_walther_equation_is_straight_in_its_chart_coordinates():
    # ASTM D341's chart: log log (nu + 0.7) against log T is a straight line; a third point of the line
    # computed by hand (A, B from the two points) is what the function returns
    a, b = fr.walther_constants(100.0, 40.0, 11.1, 100.0)
    t = 70.0 + 273.15
    by_hand = 10 ** 10 ** (a - b * math.log10(t)) - 0.7
    assert fr.kinematic_viscosity_mm2_s(70.0, 100.0, 11.1) == pytest.approx(by_hand, rel=1e-12)
    # an ISO VG 100 oil of VI ~95 has about 30 mm^2/s at 70 degC (ASTM D341 chart reading: 25-35)
    assert 25.0 < by_hand < 35.0


def test_dowson_higginson_matches_its_dimensional_form():
    # h_min = 2.65 alpha^0.54 (eta0 u)^0.7 R^0.43 E'^-0.03 w'^-0.13 (Dowson & Higginson 1977, SI units)
    w, u, r, e, eta, alpha = 100.0, 0.5, 4.0, 2.28e5, 0.09, 2e-8
    h = fr.line_contact_min_film_um(w, u, r, e, eta, alpha)
    si = 2.65 * alpha ** 0.54 * (eta * u) ** 0.7 * (r * 1e-3) ** 0.43 * (e * 1e6) ** -0.03 * (w * 1e3) ** -0.13
    assert h == pytest.approx(si * 1e6, rel=1e-12)
    assert fr.line_contact_min_film_um(w, 0.0, r, e, eta, alpha) == 0.0
    # vectorised: the same numbers element by element
    hv = fr.line_contact_min_film_um(np.array([w, 2 * w]), np.array([u, u]), np.array([r, r]), e, eta, alpha)
    assert hv[0] == pytest.approx(h, rel=1e-14) and hv[1] == pytest.approx(h * 2 ** -0.13, rel=1e-12)


def test_mixed_friction_law_limits():
    assert fr.mixed_friction_coefficient(0.2, 0.1, 0.03) == pytest.approx(0.1)
    assert fr.mixed_friction_coefficient(3.5, 0.1, 0.03) == pytest.approx(0.03)
    assert fr.mixed_friction_coefficient(2.0, 0.1, 0.03) == pytest.approx(0.065)
    assert fr.film_parameter(0.5, 0.3, 0.4) == pytest.approx(1.0)


def test_palmgren_moments_by_hand_and_the_low_speed_limit():
    # dm 50 mm, f0 = 2, nu 20 cSt, n 3000 r/min: nu n = 60 000, M0 = 1e-7 x 2 x 60000^(2/3) x 50^3 = 38.31 N mm
    assert fr.palmgren_viscous_moment_nmm(2.0, 20.0, 3000.0, 50.0) == pytest.approx(38.3135, rel=1e-4)
    # the two branches meet at nu n = 2000 to 1 % (2000^(2/3) = 158.7 against 160)
    hi = fr.palmgren_viscous_moment_nmm(2.0, 20.0, 100.0, 50.0)
    lo = fr.palmgren_viscous_moment_nmm(2.0, 20.0, 99.999, 50.0)
    assert hi == pytest.approx(lo, rel=0.01)
    assert fr.palmgren_viscous_moment_nmm(2.0, 20.0, 0.0, 50.0) == 0.0
    # M1 = f1 P dm: needle bearing, 4000 N on dm 34 mm: 0.0005 x 4000 x 34 = 68 N mm
    assert fr.palmgren_load_moment_nmm(0.0005, 4000.0, 34.0) == pytest.approx(68.0)
    # angular contact ball: f1 = 0.001 (P0/C0)^0.33; at P0 = C0 it is 0.001
    assert fr.angular_ball_f1(1.0, 1.0) == pytest.approx(0.001)
    assert fr.angular_ball_load_n(1000.0, 0.0) == 1000.0 and fr.angular_ball_load_n(100.0, 500.0) == 500.0


def test_gear_loss_factor_by_hand():
    # z1 = 20, u = 2, spur, eps1 = eps2 = 0.8 (eps_a = 1.6): H_V = pi 3 / 40 x (1 - 1.6 + 0.64 + 0.64) = 0.16022
    assert fr.gear_loss_factor(2.0, 20, 0.0, 1.6, 0.8, 0.8) == pytest.approx(math.pi * 3 / 40 * 0.68, rel=1e-12)


def test_mesh_friction_coefficient_scales_as_iso_tr_14179_2():
    base = fr.mesh_friction_coefficient(100.0, 2.0, 5.0, 50.0, 0.5)
    assert base == pytest.approx(0.048 * (100 / 10) ** 0.2 * 50 ** -0.05 * 0.5 ** 0.25, rel=1e-12)
    assert fr.mesh_friction_coefficient(200.0, 2.0, 5.0, 50.0, 0.5) == pytest.approx(base * 2 ** 0.2, rel=1e-12)
    assert fr.mesh_friction_coefficient(100.0, 2.0, 5.0, 50.0, 0.5, 0.0) == 0.0
    assert fr.mesh_power_loss_w(1000.0, 0.05, 0.2) == pytest.approx(10.0)


def test_pin_loss_goes_to_the_contact_that_slips():
    assert fr.pin_contact_loss_w(100.0, 0.1, 0.1, 0.05) == pytest.approx((0.0, 0.5))
    assert fr.pin_contact_loss_w(100.0, 0.1, 0.05, 0.1) == pytest.approx((0.5, 0.0))


def test_pin_sliding_speed_against_the_discs_motion_by_finite_differences():
    # rv80e's stage: the disc's centre at a e^{i chi}, its rotation -chi / z_c (the carrier's); a contact point
    # on the line from pin j's centre through the pitch point, at the pin's radius; its material velocity by a
    # finite difference of the disc's pose, across the normal, equals |omega_d| (|Q P| - r_rp), along it ~0
    a, zc, zp, rp, rr = 1.5, 39, 40, 77.5, 4.0
    chi0, h = 0.3, 1e-7
    omega_out = 1.0  # [rad/s]: d chi / dt = z_c omega_out
    p = a * zp * np.exp(1j * chi0)
    for j in (2, 7, 13):
        q = rp * np.exp(2j * math.pi * j / zp)
        n = (p - q) / abs(p - q)
        c = q + rr * n
        body = (c - a * np.exp(1j * chi0)) * np.exp(1j * chi0 / zc)  # in the disc's frame
        moved = a * np.exp(1j * (chi0 + h)) + body * np.exp(-1j * (chi0 + h) / zc)
        vel = (moved - c) / (h / (zc * omega_out))  # [mm/s]
        normal = (vel * n.conjugate()).real
        tangential = abs((vel * n.conjugate()).imag)
        expect = fr.pin_sliding_speed_m_s(abs(q - p), rr, omega_out) * 1e3
        assert tangential == pytest.approx(expect, rel=1e-5)
        assert abs(normal) < 1e-5 * expect


def test_heat_flow_and_time_constant():
    # 0.1 m^2 at 60 degC in 20 degC air, h = 10, eps = 0: 40 W; radiation alone eps = 1: sigma A (T^4 - Ta^4)
    assert fr.housing_heat_flow_w(60.0, 20.0, 0.1, 10.0, 0.0) == pytest.approx(40.0)
    rad = 5.670374419e-8 * 0.1 * (333.15 ** 4 - 293.15 ** 4)
    assert fr.housing_heat_flow_w(60.0, 20.0, 0.1, 0.0, 1.0) == pytest.approx(rad, rel=1e-12)
    assert fr.housing_heat_flow_w(60.0, 20.0, 0.1, 0.0, 0.0, 2.0) == pytest.approx(80.0)
    assert fr.lumped_time_constant_s(4600.0, 2.0) == pytest.approx(2300.0)
    assert fr.thermal_growth_um(100.0, 12e-6, 40.0) == pytest.approx(48.0)
