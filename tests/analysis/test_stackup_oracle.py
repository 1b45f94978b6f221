"""Independent oracle: first-order propagation with the `uncertainties` package of Table 1
written out again by hand (not through rvbacklash's transfers) and Eq. (2)."""

import math

import pytest
from uncertainties import ufloat, umath

from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.loading import load_design
from rvbacklash.problem import prepare


@pytest.mark.parametrize("name", ["sun2014", "rv80e"])
def test_propagation_matches_uncertainties(name):
    design = load_design(name)
    s1, s2, s3 = design.first_stage, design.second_stage, design.crank_stage
    x = [(z.lower_um + z.upper_um) / 2 if z.distribution == "fixed"
         else ufloat((z.lower_um + z.upper_um) / 2, (z.upper_um - z.lower_um) / 6)
         for z in prepare(design).zones]
    al = math.radians(s1.pressure_angle_deg)
    k1 = s2.eccentricity_mm * s2.pins / s2.pin_circle_radius_mm
    q = umath.sqrt(1 - k1 ** 2)
    kn = s3.eccentricity_transfer_coefficient
    j1 = [-x[0] / umath.cos(al), 2 * x[1] * umath.tan(al), x[2] * umath.tan(al), x[3] * umath.tan(al),
          x[4], 2 * x[5] / umath.cos(al), x[6], x[7], 2 * x[8] * umath.tan(al)]
    j2 = [k1 * x[9], 2 * x[10], -2 * x[11] * q, x[12] / 4, 2 * x[13] * q, -2 * x[14], x[15],
          k1 * x[16], 2 * x[17], -2 * x[18] * q]
    j3 = [x[19], 2 * kn * x[20]]
    i = 1 + s2.pins * s1.planet_teeth / s1.centre_gear_teeth
    r1 = s1.module_mm * s1.centre_gear_teeth / 2
    a0 = s3.crank_circle_radius_mm or s1.module_mm * (s1.centre_gear_teeth + s1.planet_teeth) / 2
    k = 180 * 60 / math.pi * 1e-3
    phi = k / (i * r1) * sum(j1) + k / (s2.eccentricity_mm * s2.cycloid_teeth) * sum(j2) + k / a0 * sum(j3)

    t = analyze(prepare(design)).total
    assert t.mean_arcmin == pytest.approx(phi.nominal_value, rel=1e-12)
    assert t.sigma_arcmin == pytest.approx(phi.std_dev, rel=1e-12)
