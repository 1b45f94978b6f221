"""Transfers of Table 1: linearity, values against the formulas written out by hand."""

import math

import numpy as np
import pytest

from rvbacklash.problem import derive_geometry
import rvbacklash.factors.transfers as t
from rvbacklash.factors.catalog import CATALOG, FACTOR_KEYS, factor_by_key

ALPHA = 20.0
TAN, COS = math.tan(math.radians(ALPHA)), math.cos(math.radians(ALPHA))
K1 = 1.5 * 40 / 77.5


def test_catalog_is_the_21_factors_in_table2_order():
    assert [f.id for f in CATALOG] == list(range(1, 22))
    assert len(set(FACTOR_KEYS)) == 21
    assert [int(f.stage) for f in CATALOG] == [1] * 9 + [2] * 10 + [3] * 2
    with pytest.raises(KeyError, match="allowed"):
        factor_by_key("nope")


@pytest.mark.parametrize("factor", CATALOG, ids=FACTOR_KEYS)
def test_every_transfer_is_linear_through_zero(factor, sun2014):
    g = derive_geometry(sun2014)
    x = np.array([-7.0, 0.0, 1.0, 3.5])
    y = factor.transfer(x, g)
    assert y[1] == 0
    np.testing.assert_allclose(y, factor.gain(g) * x, rtol=1e-12, atol=0)


def test_formulas_by_hand():
    # Eq. (3): 30 um of thinning over cos 20 deg
    assert t.base_tangent_length_backlash_um(-30.0, ALPHA) == pytest.approx(30 / COS)
    # 10 um apart -> normal 2*10*sin(a), transverse 2*10*tan(a)
    assert t.radial_shift_backlash_um(10.0, ALPHA) == pytest.approx(20 * TAN)
    # run-out 18 um = eccentricity 9 um -> 2*9*tan(a)
    assert t.gear_runout_backlash_um(18.0, ALPHA) == pytest.approx(18 * TAN)
    assert t.axis_parallelism_in_plane_backlash_um(10.0, ALPHA) == pytest.approx(10 * TAN)
    assert t.axis_parallelism_out_of_plane_backlash_um(3.0) == pytest.approx(3.0)
    assert t.profile_backlash_um(9.0, ALPHA) == pytest.approx(18 / COS)
    assert t.equidistance_modification_backlash_um(5.0) == pytest.approx(10.0)
    assert t.moving_distance_modification_backlash_um(-10.0, K1) == pytest.approx(20 * math.sqrt(1 - K1**2))
    assert t.pitch_circle_tangential_backlash_um(46.5, K1) == pytest.approx(36.0)  # 46.5*60/77.5
    assert t.disc_runout_backlash_um(24.0) == pytest.approx(6.0)
    assert t.clearance_backlash_um(17.5) == pytest.approx(17.5)
    assert t.crank_eccentricity_backlash_um(5.0, 0.01) == pytest.approx(0.1)


def test_pin_errors_are_modifications_with_the_opposite_sign(sun2014):
    """A pin circle larger by d acts as a moving distance -d; a pin larger by d as an
    equidistance modification -d (docs/model.md)."""
    g = derive_geometry(sun2014)
    f = factor_by_key
    assert f("pin_circle_radius").gain(g) == pytest.approx(-f("moving_distance_modification").gain(g))
    assert f("pin_radius").gain(g) == pytest.approx(-f("equidistance_modification").gain(g))
    assert f("equidistance_modification_error").gain(g) == f("equidistance_modification").gain(g)
    assert f("moving_distance_modification_error").gain(g) == f("moving_distance_modification").gain(g)
