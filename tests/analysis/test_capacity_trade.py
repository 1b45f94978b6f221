"""The trade made visible (analysis/capacity/trade.py): lost motion against life of a design and its
what-ifs, computed through the API: the design's point is the hysteresis loop's lost motion and the
capacity datasheet's life and rated torque; a what-if equal to the design gives the design's point;
a crank-bearing clearance moves lost motion and life together, a modification moves lost motion and
the pins' stress, hardly the bearings' life (docs/capacity.md)."""

import math

import pytest

import rvbacklash as rb
from rvbacklash.analysis.capacity import (WhatIf, capacity_trade, clearance_what_if, default_what_ifs,
                                          modification_what_if)
from rvbacklash.errors import InputError


@pytest.fixture(scope="module")
def problem():
    return rb.prepare("rv80e")


@pytest.fixture(scope="module")
def trade(problem):
    return capacity_trade(problem)  # the design and the default what-ifs (docs/capacity.md's table)


def test_the_designs_point_is_the_loop_and_the_datasheet(problem, trade):
    d = trade.points[0]
    assert d.family == "design" and d.edits == {}
    cap = rb.capacity(problem)
    assert d.reducer_life_h == pytest.approx(cap.reducer_life_h, rel=1e-12)
    assert d.derived_rated_torque_nm == pytest.approx(cap.derived_rated_torque_nm, rel=1e-9)
    assert d.max_pin_stress_mpa == pytest.approx(cap.max_pin_stress_mpa, rel=1e-12)
    assert d.weakest_bearing == cap.weakest_bearing
    loop = rb.hysteresis(problem)
    assert d.lost_motion_arcmin == loop.lost_motion_arcmin
    assert d.torsional_rigidity_nm_per_arcmin == loop.torsional_rigidity_nm_per_arcmin
    assert d.crank_clearance_um == pytest.approx(4.5) and d.equidistance_modification_um == 5.0
    assert trade.stated_rated_torque_nm == 784.0 and trade.rated_life_h == 6000.0 and not trade.partial


def test_default_what_ifs_leave_out_the_designs_own_values(problem, trade):
    names = [w.name for w in default_what_ifs(problem)]
    assert "equidistance modification 5 um" not in names  # rv80e's own
    assert [p.name for p in trade.points[1:]] == names
    assert len(trade.points) == 1 + 4 + 3


def test_a_what_if_equal_to_the_design_gives_the_designs_point(problem, trade):
    """Metamorphic: the clearance fixed at the zone mean, the modification set to its own value."""
    same = capacity_trade(problem, [clearance_what_if(trade.points[0].crank_clearance_um),
                                    modification_what_if(5.0)], angles=trade.crank_angles)
    d = trade.points[0]
    for p in same.points[1:]:
        assert p.lost_motion_arcmin == pytest.approx(d.lost_motion_arcmin, rel=1e-12)
        assert p.reducer_life_h == pytest.approx(d.reducer_life_h, rel=1e-12)
        assert p.derived_rated_torque_nm == pytest.approx(d.derived_rated_torque_nm, rel=1e-9)


def test_clearance_moves_lost_motion_and_life_together(trade):
    pts = sorted([p for p in trade.points if p.family in ("design", "clearance")], key=lambda p: p.crank_clearance_um)
    assert [p.crank_clearance_um for p in pts] == pytest.approx([-4.0, 0.0, 4.5, 10.0, 20.0])
    for a, b in zip(pts, pts[1:]):  # opening the clearance: more lost motion, a shorter life, a lower rating
        assert b.lost_motion_arcmin > a.lost_motion_arcmin
        assert b.reducer_life_h < a.reducer_life_h
        assert b.derived_rated_torque_nm < a.derived_rated_torque_nm
        assert b.max_pin_force_n == pytest.approx(a.max_pin_force_n, rel=1e-9)  # the pins do not see it
    # docs/capacity.md: 20 um costs ~28 % of life, ~10 % of rated torque against the zone mean
    d = trade.points[0]
    assert pts[-1].reducer_life_h / d.reducer_life_h == pytest.approx(0.72, abs=0.03)
    assert pts[-1].derived_rated_torque_nm / d.derived_rated_torque_nm == pytest.approx(0.90, abs=0.02)


def test_modification_moves_lost_motion_and_pin_stress_not_life(trade):
    pts = sorted([p for p in trade.points if p.family in ("design", "modification")],
                 key=lambda p: p.equidistance_modification_um)
    assert [p.equidistance_modification_um for p in pts] == [0.0, 2.0, 5.0, 10.0]
    for a, b in zip(pts, pts[1:]):
        assert b.lost_motion_arcmin > a.lost_motion_arcmin
        assert b.max_pin_stress_mpa > a.max_pin_stress_mpa  # fewer pins share the load
    lives = [p.reducer_life_h for p in pts]
    assert max(lives) / min(lives) < 1.03  # the bearings carry the discs' resultant, which the torque sets


def test_the_design_alone_and_the_rows(problem, trade):
    alone = capacity_trade(problem, ())
    assert len(alone.points) == 1 and alone.points[0] == trade.points[0]
    rows = trade.rows()
    assert len(rows) == len(trade.points) and rows[1]["edits"].startswith("factors.crank_bearing_clearance.")
    assert math.isfinite(trade.to_dict()["points"][0]["reducer_life_h"])


def test_bad_what_ifs_are_one_line(problem):
    with pytest.raises(InputError) as e:
        capacity_trade(problem, [WhatIf("too much", {"second_stage.equidistance_modification_um": -1e6})])
    assert e.value.field == "what_if 'too much'" and "equidistance_modification_um" in str(e.value)
    with pytest.raises(InputError) as e:
        capacity_trade(problem, [WhatIf("nothing", {})])
    assert e.value.field == "what_ifs"
    with pytest.raises(InputError) as e:
        capacity_trade(problem, [modification_what_if(float(m)) for m in range(40)])
    assert e.value.field == "what_ifs" and "at most 32" in str(e.value)
    with pytest.raises(InputError) as e:
        capacity_trade(rb.prepare("sun2014"), ())
    assert e.value.field in ("elastic", "structure")
