"""Derived geometry of the RV-80E class and the unit chain of Eq. (1), by hand."""

import pytest

from rvbacklash.factors.catalog import Stage
from rvbacklash.factors.output import output_angle_arcmin_per_um, stage_coefficient_arcmin_per_um
from rvbacklash.geometry import reducer
from rvbacklash.problem import derive_geometry


def test_rv80e_geometry(sun2014):
    # Provenance: anchors.md / Yang et al. 2021 Table 3: i = 1 + 40*38/10 = 153, K1 = 1.5*40/77.5.
    g = derive_geometry(sun2014)
    assert g.ratio == 153
    assert g.K1 == pytest.approx(0.774193548, abs=1e-9)
    assert g.centre_gear_pitch_radius_mm == 8.75         # 1.75 * 10 / 2
    assert g.cycloid_pitch_radius_mm == 58.5             # 1.5 * 39
    assert g.crank_circle_radius_mm == 42.0              # 1.75 * (10 + 38) / 2
    assert g.crank_circle_radius_is_default


def test_ratio_of_commercial_rv_ratios():
    # RV-E catalogue ratios are 1 + z_p z2 / z1 with z_p = 40: 57, 81, 101, 121, 153.
    for z1, z2, i in [(20, 28, 57), (16, 32, 81), (12, 30, 101), (10, 30, 121), (10, 38, 153)]:
        assert reducer.reduction_ratio(z1, z2, 40) == i


def test_unit_chain_by_hand():
    """1 um of backlash at the centre gear pitch circle (r1 = 8.75 mm) turns the centre gear by
    1e-3 / 8.75 = 1.142857e-4 rad; behind i = 153 the output turns 7.469655e-7 rad, i.e.
    7.469655e-7 * 10800 / pi = 2.567878e-3 arcmin (worked by hand, not by the code under test)."""
    assert output_angle_arcmin_per_um(8.75, 153) == pytest.approx(2.567878e-3, rel=1e-6)
    assert output_angle_arcmin_per_um(58.5) == pytest.approx(0.05876490, rel=1e-6)  # 1e-3/58.5 rad


def test_stage_coefficients(sun2014):
    g = derive_geometry(sun2014)
    # cycloid: 1 um at a z_c = 58.5 mm -> 1e-3/58.5 rad = 0.0587649 arcmin
    assert stage_coefficient_arcmin_per_um(Stage.CYCLOID, g) == pytest.approx(0.0587649, rel=1e-5)
    # crank: 1 um at a0 = 42 mm -> 0.0818511 arcmin
    assert stage_coefficient_arcmin_per_um(Stage.CRANK, g) == pytest.approx(0.0818511, rel=1e-5)
    assert stage_coefficient_arcmin_per_um(Stage.INVOLUTE, g) == pytest.approx(2.567878e-3, rel=1e-6)


def test_pin_gap():
    # 40 pins of radius 4 mm on r_p = 77.5 mm: chord 2*77.5*sin(4.5 deg) = 12.16116 mm, minus 8 mm.
    assert reducer.pin_gap_mm(77.5, 4.0, 40) == pytest.approx(4.16116, abs=1e-5)
