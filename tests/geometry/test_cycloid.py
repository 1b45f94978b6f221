"""The exact modified cycloid geometry: the curve, its normals and its undercut limit."""

import math

import numpy as np
import pytest

from rvbacklash.geometry.cycloid import ContactGeometry, PinCentreCurve, profile_points, rotate


@pytest.fixture(scope="module")
def geo():
    return ContactGeometry(39, 40, 1.5, 77.5, 4.0, 2)


def test_curve_closes_after_one_turn_of_the_disc(geo):
    """C(t + 2 pi z_c) = C(t): z_c lobes, and C(t + 2 pi) is C(t) turned by 2 pi / z_c."""
    c = PinCentreCurve(geo.a_mm, geo.rp_mm, geo.zc)
    t = np.linspace(0, 1, 7)
    np.testing.assert_allclose(c.point(t + 2 * math.pi * geo.zc), c.point(t), atol=1e-9)
    np.testing.assert_allclose(c.point(t + 2 * math.pi), rotate(c.point(t), 2 * math.pi / geo.zc), atol=1e-9)


def test_pins_lie_on_the_curve_at_zero_modification(geo):
    """Nominal pins are the generating pins: their centres are on C (signed distance 0)."""
    c = PinCentreCurve(geo.a_mm, geo.rp_mm, geo.zc)
    for chi in (0.0, 0.37, 2.0):
        psi = geo.pin_angles
        centres = geo.rp_mm * np.stack([np.cos(psi), np.sin(psi)], axis=1)
        q = rotate(centres - geo.a_mm * np.array([math.cos(chi), math.sin(chi)]), chi / geo.zc)
        s, _ = c.signed_distance(q, chi - psi + 2 * math.pi * np.arange(geo.zp))
        assert np.max(np.abs(s)) < 1e-10


def test_undercut_limit_of_the_rv80e_class(geo):
    """docs/contact.md: the smallest convex radius of curvature of C is 6.06 mm > r_rp = 4 mm."""
    rho = PinCentreCurve(geo.a_mm, geo.rp_mm, geo.zc).min_convex_radius_of_curvature()
    assert rho == pytest.approx(6.06, abs=0.01)


def test_profile_is_inside_the_pin_circle(geo):
    p = profile_points(geo.a_mm, geo.rp_mm, geo.rrp_mm, geo.zc)
    r = np.linalg.norm(p, axis=1)
    # tips at r_p - r_rp + a... the profile spans [r_p - a - r_rp, r_p + a - r_rp] about the disc centre
    assert r.min() == pytest.approx(77.5 - 1.5 - 4.0, abs=1e-3) and r.max() == pytest.approx(77.5 + 1.5 - 4.0, abs=1e-3)
