"""The nominal design through the exact contact geometry: one unit (arcmin) and one disc
numbering (from 1) in every output."""

import math

import pytest

from rvbacklash.analysis.contact import nominal_contact
from rvbacklash.units import ARCMIN_PER_RAD


def test_rv80e_nominal_contact(rv80e_problem):
    """rv80e: designed 5 um equidistance and 3 um moving distance, the H6/g5 pin/hole clearance
    at its mean; disc 1 and 2 are symmetric at crank angle 0 (180 deg apart)."""
    r = nominal_contact(rv80e_problem, 0.0)
    assert [d.disc for d in r.discs] == [1, 2]
    assert not r.cycloid_stage_preloaded
    # the equidistance and moving-distance part alone: (2*5 - 2*3 sqrt(1 - K1^2)) / (a z_c) rad
    k1 = rv80e_problem.geometry.K1
    mods = (2 * 5 - 2 * 3 * math.sqrt(1 - k1 ** 2)) / 58500 * ARCMIN_PER_RAD
    cl = rv80e_problem.means_um[15] / 58500 * ARCMIN_PER_RAD  # half the clearance each way
    assert r.cycloid_stage_arcmin == pytest.approx(mods + cl, rel=0.01)
    assert r.discs[0].play_ccw_arcmin == pytest.approx(r.discs[1].play_ccw_arcmin, rel=1e-9)
    assert r.lost_motion_arcmin == pytest.approx(r.cycloid_stage_arcmin + sum(r.other_stages_mean_arcmin.values()))
    d = r.to_dict()
    assert "profile_xy_mm" not in d and "play_ccw_arcmin" in d["discs"][0] and "rad" not in str(list(d))
    assert len(r.rows()) == 2 and r.rows()[0]["disc"] == 1
