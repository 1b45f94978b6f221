"""Selective assembly, continued (issue 39): the one-pass rule and the gaps moved with the pins
against their brute-force oracles, the contact and transmission models' selected runs (one class =
random assembly bit for bit; selection buys yield), explicit class boundaries, the design's
[selection] table, Parquet parts files."""

import math

import numpy as np
import pytest
from scipy import stats

from rvbacklash.analysis.selection.classes import (ClassSet, band_edges_um, class_table, design_selection,
                                                   parse_selection, resolve_selection)
from rvbacklash.analysis.selection.rules import class_plays_arcmin, in_class_um, predicted_play_arcmin
from rvbacklash.analysis.selection.run import simulate_selected
from rvbacklash.analysis.simulation import simulate
from rvbacklash.errors import InputError
from rvbacklash.models.contact import free_interval_bounds, pin_gaps, shift_pin_radius, stage_work, unit_gaps
from rvbacklash.models.unit_errors import empty_unit
from rvbacklash.sampling.contact_source import block_streams, contact_source
from rvbacklash.sampling.unit_draw import draw_scratch, draw_unit


def _drawn_units(problem, n=30, seed=7):
    """n units as the contact model draws them, each with its mesh row (UnitErrors copies)."""
    c = contact_source(problem, "default", seed)
    g = c.geometry.stage_geometry
    streams = block_streams(seed, 0)
    unit = empty_unit(g.zp, g.zc, g.discs, np.int64(0))
    scratch = draw_scratch(g.zp, g.zc)
    out = []
    for _ in range(n):
        drawn = draw_unit(streams, c.laws, c.coef.shape[0], unit, scratch)
        out.append((type(unit)(*(np.array(a, copy=True) if isinstance(a, np.ndarray) else a for a in unit)),
                    c.coef[drawn.crank_step]))
    return c, g, out


def test_one_pass_plays_equal_the_per_class_formula(rv80e_problem):
    """class_plays_arcmin (one division per pin, every class) against predicted_play_arcmin (the
    formula, per class): the same P(s) on real units' gaps, at shifts across and beyond the pins' zone."""
    c, g, units = _drawn_units(rv80e_problem)
    shifts = np.array([-6.0, -2.0, -0.5, 0.0, 0.7, 3.0, 9.0])
    tol = 1e-9 * g.pitch_radius_um
    out = np.empty((2, shifts.size))
    for unit, mesh in units:
        gaps, work = pin_gaps(g.discs, g.zp), stage_work(g.discs, g.zp)
        unit_gaps(mesh, g, unit, gaps, work)
        class_plays_arcmin(gaps.gap_um, gaps.lever_um_per_rad, unit.pin_radius_um, shifts, tol, out)
        ref = [predicted_play_arcmin(gaps.gap_um, gaps.lever_um_per_rad, unit.pin_radius_um, s, tol) for s in shifts]
        assert out[0] == pytest.approx(ref, rel=1e-9, abs=1e-9)
        assert np.all(np.diff(out[0]) < 0)  # P falls as the pins grow


def test_gaps_moved_with_the_pins_equal_the_gaps_found_again(rv80e_problem):
    """shift_pin_radius (the selected run's gaps: moved, not found again) against unit_gaps on the unit
    with its new pins: gaps, levers, the distances at which they close, and the free interval."""
    c, g, units = _drawn_units(rv80e_problem, n=10)
    rng = np.random.default_rng(1)
    for unit, mesh in units:
        gaps, work = pin_gaps(g.discs, g.zp), stage_work(g.discs, g.zp)
        unit_gaps(mesh, g, unit, gaps, work)
        new = unit.pin_radius_um + rng.normal(0.0, 2.0, g.zp)
        for j in range(g.zp):
            shift_pin_radius(mesh, unit, gaps, work, j, new[j])
        moved = free_interval_bounds(gaps, g.pitch_radius_um)
        again, work2 = pin_gaps(g.discs, g.zp), stage_work(g.discs, g.zp)
        assert np.array_equal(unit.pin_radius_um, new)
        found = unit_gaps(mesh, g, unit, again, work2)
        assert gaps.gap_um == pytest.approx(again.gap_um, abs=1e-9)
        assert np.array_equal(gaps.lever_um_per_rad, again.lever_um_per_rad)
        assert work.closing_distance_mm == pytest.approx(work2.closing_distance_mm, abs=1e-12)
        assert moved == pytest.approx(found, rel=1e-9)


def test_in_class_by_division_equals_the_searched_table():
    law = stats.truncnorm(-3, 3, 0.2, 1.1)
    t = class_table(law, ClassSet(5, 2.0), 0.5)
    x = np.concatenate([law.rvs(size=500, random_state=np.random.default_rng(2)), [-10.0, 10.0, t.x_um[0],
                                                                                 t.x_um[-1]]])
    for c in range(5):
        for v in x:
            u = np.interp(v, t.x_um, t.cdf)
            k = t.ppf_um.shape[1]
            tt = u * k - 0.5
            i = min(max(int(math.floor(tt)), 0), k - 2)
            w = min(max(tt - i, 0.0), 1.0)
            ref = t.ppf_um[c, i] + w * (t.ppf_um[c, i + 1] - t.ppf_um[c, i])
            assert in_class_um(v, t, c) == pytest.approx(ref, abs=1e-9)


@pytest.mark.parametrize("model, spec", [("contact", {"backlash": 1.0}), ("transmission", {"backlash": 1.0})])
def test_one_class_is_the_random_run_bit_for_bit(rv80e_problem, model, spec):
    r = simulate_selected(rv80e_problem, parse_selection("pins=1x2um,rollers=1x2um"), samples=300, seed=2,
                          specs=spec, workers=1, model=model)
    plain = simulate(rv80e_problem, samples=300, seed=2, specs=spec, workers=1, model=model).to_dict()
    for d in (r.selected.to_dict(), r.random.to_dict()):
        assert d["outputs"] == plain["outputs"] and d["convergence"] == plain["convergence"]
    assert r.yields[0].random == r.yields[0].selected


@pytest.mark.parametrize("model", ["contact", "transmission"])
def test_selection_closes_the_rigid_play(rv80e_problem, model):
    """The contact and transmission models' backlash (rigid play) with pins and rollers selected: the
    pin rule aims at a closed cycloid stage, the rollers at the crank bearings' mean share, so the
    mean backlash falls and its yield at the random run's median rises; the same units, same seed."""
    random = simulate(rv80e_problem, samples=400, seed=3, model=model, workers=1)
    median = random.outputs["backlash"].quantiles.table
    spec = float(np.median([q.value for q in median])) if median else random.outputs["backlash"].mean
    r = simulate_selected(rv80e_problem, parse_selection("pins=5x2um,rollers=3x2um"), samples=400, seed=3,
                          specs={"backlash": spec}, workers=1, model=model)
    assert r.selected.outputs["backlash"].mean < r.random.outputs["backlash"].mean - 0.1
    y = r.yields[0]
    assert y.selected.fraction > y.random.fraction + 0.1
    assert sum(c.units for c in r.classes if c.part == "pins") == 400
    if model == "transmission":  # the kinematic errors are drawn as the random run draws them
        te = r.selected.outputs["transmission_error"].mean / r.random.outputs["transmission_error"].mean
        assert 0.8 < te < 1.2


def test_selection_refuses_the_linear_model(rv80e_problem):
    with pytest.raises(InputError, match="contact"):
        simulate_selected(rv80e_problem, parse_selection("pins=5x2um"), samples=10, specs={"backlash": 1.0},
                          model="linear")


def test_explicit_boundaries_parse_round_trip_and_cut_the_law():
    s = parse_selection("pins=-4,-2,0,2,4um,rollers=-1,1um,noise=0.5um")
    assert s.pins == ClassSet(6, 0.0, (-4.0, -2.0, 0.0, 2.0, 4.0)) and s.rollers.count == 3
    assert parse_selection(str(s)) == s
    law = stats.norm(0.5, 1.5)
    edges = band_edges_um(law, s.pins, 0.5)  # pins: radius = diameter / 2, from nominal
    assert edges[1:-1] == pytest.approx([-2.0, -1.0, 0.0, 1.0, 2.0]) and edges[0] == -math.inf
    t = class_table(law, s.pins, 0.5)
    assert t.share[3] == pytest.approx(law.cdf(1.0) - law.cdf(0.0), rel=1e-9)
    clear = stats.norm(10.0, 2.0)
    r_edges = band_edges_um(clear, s.rollers, 1.0)  # rollers: the clearance they leave, about its mean
    assert r_edges[1:-1] == pytest.approx([9.0, 11.0])
    for bad, fragment in [("pins=2,1um", "increasing"), ("pins=a,bum", "boundaries"), ("pins=1,nanum", "finite"), ("pins=-1,1", "ending in um")]:
        with pytest.raises(InputError) as e:
            parse_selection(bad)
        assert fragment in str(e.value) and "\n" not in str(e.value)


def test_design_selection_table_and_the_flag_over_it(rv80e):
    from rvbacklash.design.loading import design_from_dict

    d = rv80e.model_dump(mode="json", exclude_none=True)
    d["selection"] = {"pins": "5x2um", "rollers": "-1,0,1um", "noise_um": 0.5, "play_max_arcmin": 0.1,
                      "target_arcmin": 0.3}
    design = design_from_dict(d)
    s = resolve_selection(None, design)
    assert s == parse_selection("pins=5x2um,rollers=-1,0,1um,noise=0.5um,play=0.1,target=0.3")
    assert design_selection(design.selection) == s
    assert resolve_selection("pins=3x1um", design) == parse_selection("pins=3x1um")  # the flag wins
    assert resolve_selection("none", design) is None and resolve_selection(None, rv80e) is None
    d["selection"] = {"pins": "0x2um"}
    with pytest.raises(InputError) as e:
        resolve_selection(None, design_from_dict(d))
    assert "selection.pins" in str(e.value) and "count" in str(e.value)
    d["selection"] = {"pins": "five"}
    with pytest.raises(Exception) as e:
        design_from_dict(d)
    assert "selection.pins" in str(e.value)


def test_parquet_parts_read_as_the_csv(tmp_path):
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    from rvbacklash.analysis.selection.assembly import read_parts

    (tmp_path / "p.csv").write_text("serial,kind,diameter_um\nP1,pin,1.5\nP2,pin,-0.25\nR1,roller,2\n")
    pq.write_table(pa.table({"serial": ["P1", "P2", "R1"], "kind": ["pin", "pin", "roller"],
                             "diameter_um": [1.5, -0.25, 2.0]}), tmp_path / "p.parquet")
    assert read_parts(tmp_path / "p.parquet") == read_parts(tmp_path / "p.csv")
    pq.write_table(pa.table({"serial": ["P1"], "kind": ["bolt"], "diameter_um": [1.0]}), tmp_path / "b.parquet")
    with pytest.raises(InputError, match="record 1 column kind"):
        read_parts(tmp_path / "b.parquet")
