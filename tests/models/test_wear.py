"""Wear formulas (models/wear.py): Archard's closed forms, the single-pass form against the
integral of a Hertzian pressure, the running-in integral, and the sliding kinematics against finite
differences of the disc's rigid motion."""

import math

import numpy as np
import pytest

from rvbacklash.api import prepare
from rvbacklash.models import wear as wr


def test_dimensional_coefficient_is_k_over_hardness():
    # K = 1e-8 on 700 HV (6865 N/mm^2): k = 1e-8 / 6864.655 mm^2/N = 1.4567e-12 mm^3/(N mm) = 1.4567e-9 /(N m)
    assert wr.dimensional_wear_coefficient(1e-8, 700.0) == pytest.approx(1e-8 / (700 * 9.80665) * 1e3, rel=1e-15)
    assert wr.dimensional_wear_coefficient(1e-8, 700.0) == pytest.approx(1.4567e-9, rel=1e-4)


def test_flat_contact_closed_form_w_equals_k_p_s():
    # a flat pad of 20 mm^2 under 2000 N (p = 100 MPa) sliding 1000 m with k = 1e-8 mm^3/(N m):
    # V = k F s = 0.02 mm^3, w = V / A = 1 um = k p s
    k, area, force, s_m = 1e-8, 20.0, 2000.0, 1000.0
    v = wr.archard_volume_mm3(k, force, s_m)
    assert v == pytest.approx(0.02, rel=1e-15)
    w = wr.archard_depth_um(k, force / area, s_m * 1e3)
    assert w == pytest.approx(v / area * 1e3, rel=1e-14)
    assert w == pytest.approx(1.0, rel=1e-14)
    # proportional to k, to p and to s; zero without load or without sliding
    assert wr.archard_depth_um(2 * k, 100.0, 1e6) == pytest.approx(2 * w, rel=1e-15)
    assert wr.archard_depth_um(k, 100.0, 2e6) == pytest.approx(2 * w, rel=1e-15)
    assert wr.archard_depth_um(k, 0.0, 1e6) == 0.0 and wr.archard_depth_um(k, 100.0, 0.0) == 0.0


def test_single_pass_depth_is_the_integral_of_k_p_ds_over_a_hertzian_contact():
    # a point crossed by a line contact of half-width b and peak p0 while sliding at v_s / v_t = 0.3:
    # h = k int p(x) (v_s / v_t) dx = k (F / L) (v_s / v_t), with F / L = pi b p0 / 2 (Hertz)
    k, b, p0, ratio = 2e-9, 0.12, 1500.0, 0.3
    x = np.linspace(-b, b, 200_001)
    p = p0 * np.sqrt(np.clip(1.0 - (x / b) ** 2, 0.0, None))
    integral = np.trapezoid(wr.archard_depth_um(k, p, ratio * np.gradient(x)) / np.gradient(x), x)
    q = math.pi * b * p0 / 2.0
    assert wr.pass_depth_um(k, q, ratio) == pytest.approx(integral, rel=1e-5)


def test_running_in_integral():
    # no running-in: the hours themselves; m = 5, tau = 100 h: exact integral of 1 + 4 exp(-t/100)
    assert wr.running_in_hours(10.0, 30.0, 1.0, 100.0) == 20.0
    t0, t1 = 50.0, 400.0
    t = np.linspace(t0, t1, 400_001)
    assert wr.running_in_hours(t0, t1, 5.0, 100.0) == pytest.approx(np.trapezoid(1 + 4 * np.exp(-t / 100.0), t),
                                                                    rel=1e-9)
    # additive over consecutive steps (the stepping relies on it)
    assert wr.running_in_hours(0, 70, 5, 100) + wr.running_in_hours(70, 500, 5, 100) == pytest.approx(
        wr.running_in_hours(0, 500, 5, 100), rel=1e-14)


@pytest.fixture(scope="module")
def stage():
    g = prepare("rv80e").cycloid
    return g.a_mm, g.rp_mm, g.rrp_mm, g.zp, g.zc, g.K1


def _contact_point(chi, a, rp, rrp, zp):
    """Pin 0 (at Q = r_p) meets disc 0 at crank angle chi: the contact point on QP, r_rp from Q."""
    p = a * zp * np.exp(1j * chi)
    q = rp + 0j
    return q + rrp * (p - q) / abs(p - q), p, q


@pytest.mark.parametrize("phi", [0.3, 1.0, 1.7, 2.5, 3.0, 4.0, 5.5])
def test_flank_sliding_is_the_disc_turning_about_the_pitch_point(stage, phi):
    # the disc's rigid motion: x = a e^{i chi} + e^{-i chi / z_c} X; its material at the contact point,
    # differentiated in chi, slides along the contact's tangent at |P P_c| / z_c per radian of phase
    a, rp, rrp, zp, zc, k1 = stage
    chi, h = -phi, 1e-6
    c, p, q = _contact_point(chi, a, rp, rrp, zp)
    x_disc = np.exp(1j * chi / zc) * (c - a * np.exp(1j * chi))

    def material(ch):
        return a * np.exp(1j * ch) + np.exp(-1j * ch / zc) * x_disc

    v = (material(chi + h) - material(chi - h)) / (2 * h)
    n = (p - q) / abs(p - q)
    tangential = abs((v * np.conj(n)).imag)
    normal = (v * np.conj(n)).real
    assert abs(normal) < 1e-6 * abs(v)  # the contact's normal passes through the instantaneous centre
    assert tangential == pytest.approx(wr.flank_sliding_per_phase_mm(phi, rp, k1, rrp, zc), rel=1e-7)


def test_flank_arc_per_phase_against_the_contact_points_on_the_disc(stage):
    a, rp, rrp, zp, zc, k1 = stage
    phi = np.linspace(0.2, 6.0, 30)
    h = 1e-6

    def on_disc(ph):
        chi = -ph
        c, _, _ = _contact_point(chi, a, rp, rrp, zp)
        return np.exp(1j * chi / zc) * (c - a * np.exp(1j * chi))

    numeric = np.abs((on_disc(phi + h) - on_disc(phi - h)) / (2 * h))
    closed = wr.flank_arc_per_phase_mm(phi, rp, k1, float(zp), float(zc), rrp)
    assert np.allclose(closed, numeric, rtol=1e-6)


def test_contact_direction_and_clearance_growth():
    k1 = 0.7
    phi = np.linspace(0, 2 * math.pi, 1001)
    theta = wr.contact_direction_rad(phi, k1)
    assert np.abs(theta).max() == pytest.approx(math.asin(k1), rel=1e-5)
    assert wr.clearance_growth_um(1.0, 2.0, 0.5) == 8.0
    # needles: the raceway's rolling per revolution, pi d_i (1 + gamma) / 2
    d_i, big_d = 30.0, 4.0
    gamma = big_d / (d_i + big_d)
    assert wr.needle_rolling_per_revolution_mm(d_i, big_d) == pytest.approx(math.pi * d_i * (1 + gamma) / 2,
                                                                            rel=1e-14)
