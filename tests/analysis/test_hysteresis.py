"""The hysteresis loop as a result (analysis/hysteresis.py), its JSON, the report's elastic section,
and the elastic model through the Monte-Carlo engine."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import rvbacklash as rb
from rvbacklash.analysis.hysteresis import elastic_section, hysteresis, loop_figures_from_branches
from rvbacklash.analysis.simulation import MODELS, simulate
from rvbacklash.errors import InputError


@pytest.fixture(scope="module")
def problem(rv80e_problem):
    return rv80e_problem


@pytest.fixture(scope="module")
def nominal(problem):
    return hysteresis(problem)


def read(branch: dict, torque: float) -> float:
    """The angle of a JSON branch at a torque: the first node there (an independent reader)."""
    for t, a in zip(branch["torque_nm"], branch["angle_arcmin"]):
        if abs(t - torque) <= 1e-9:
            return a
    raise AssertionError(f"no node at {torque} N m in {branch['branch']}")


def test_the_definitions_recomputed_from_the_json_loop(nominal):
    d = json.loads(json.dumps(nominal.to_dict()))
    assert [b["branch"] for b in d["loop"]] == ["load+", "unload+", "load-", "unload-"]
    tr, x = d["rated_torque_nm"], d["measuring_torque_fraction"]
    lo, hi = d["rigidity_interval_fraction"]
    b = {br["branch"]: br for br in d["loop"]}
    lm = 0.5 * (read(b["load+"], x * tr) + read(b["unload+"], x * tr)) \
        - 0.5 * (read(b["load-"], -x * tr) + read(b["unload-"], -x * tr))
    bl = read(b["unload+"], 0.0) - read(b["unload-"], 0.0)
    k = 2 * (hi - lo) * tr / ((read(b["load+"], hi * tr) - read(b["load+"], lo * tr))
                              + (read(b["load-"], -lo * tr) - read(b["load-"], -hi * tr)))
    assert lm == pytest.approx(d["lost_motion_arcmin"], rel=1e-9)
    assert bl == pytest.approx(d["backlash_arcmin"], rel=1e-9)
    assert k == pytest.approx(d["torsional_rigidity_nm_per_arcmin"], rel=1e-9)
    again = loop_figures_from_branches(d["loop"], tr, x, (lo, hi))
    assert again["lost_motion_arcmin"] == pytest.approx(lm, rel=1e-12)


def test_the_loop_is_closed_and_runs_the_cycle(nominal):
    b = {br.branch: br for br in nominal.loop}
    tr = nominal.rated_torque_nm
    assert (b["load+"].torque_nm[0], b["load+"].torque_nm[-1]) == (0.0, tr)
    assert (b["unload+"].torque_nm[0], b["unload+"].torque_nm[-1]) == (tr, 0.0)
    assert (b["load-"].torque_nm[0], b["load-"].torque_nm[-1]) == (0.0, -tr)
    assert (b["unload-"].torque_nm[0], b["unload-"].torque_nm[-1]) == (-tr, 0.0)
    for a, c in (("load+", "unload+"), ("unload+", "load-"), ("load-", "unload-"), ("unload-", "load+")):
        assert b[a].angle_arcmin[-1] == pytest.approx(b[c].angle_arcmin[0], abs=1e-12)
    # centred: the middle of the zero-torque width is 0
    assert b["unload+"].angle_arcmin[-1] + b["unload-"].angle_arcmin[-1] == pytest.approx(0.0, abs=1e-12)
    # with friction the output sticks at the turning point: the first nodes of unload+ hold the angle
    # (to round-off: a kernel compiled in another variant may order a sum differently, 1 ulp seen)
    assert b["unload+"].angle_arcmin[1] == pytest.approx(b["unload+"].angle_arcmin[0], rel=0, abs=1e-12)


def test_nominal_rv80e_figures_hang_together(nominal, problem):
    r = nominal
    assert sum(r.lost_motion_share_arcmin.values()) == pytest.approx(r.lost_motion_arcmin, rel=1e-12)
    dead = sum(r.dead_band_arcmin.values())
    # lost motion adds the elastic deflection at +-x T_R to the dead bands; backlash adds friction's width
    assert r.lost_motion_arcmin > dead and r.backlash_arcmin > dead
    # the involute stage's dead band is its linear mean (Eq. (1)), the crank bearings' k G_r / a0
    from rvbacklash.factors.catalog import Stage

    m = problem.stage_mask(Stage.INVOLUTE)
    assert r.dead_band_arcmin["involute_stage"] == pytest.approx(
        float(problem.sensitivities_arcmin_per_um[m] @ problem.means_um[m]), rel=1e-12)
    assert r.dead_band_arcmin["crank_bearings"] == pytest.approx(
        r.lever_factor * 4.5e-3 / 42.0 * 10800 / math.pi, rel=1e-9)
    assert len(r.pins_in_contact_at_rated) == 2 and min(r.pins_in_contact_at_rated) >= 3
    assert r.pins_in_contact_at_measuring[0] <= r.pins_in_contact_at_rated[0]
    assert r.pin_forces_at_rated_n.max() == pytest.approx(r.max_pin_force_at_rated_n)
    assert "loop" in r.to_dict() and "pin_forces_at_rated_n" not in r.to_dict()
    assert len(r.rows()) == sum(len(b.torque_nm) for b in r.loop)


def test_more_points_same_figures(problem, nominal):
    finer = hysteresis(problem, points=7)
    assert finer.lost_motion_arcmin == nominal.lost_motion_arcmin
    assert len(finer.loop[0].torque_nm) < len(nominal.loop[0].torque_nm)
    with pytest.raises(InputError) as e:
        hysteresis(problem, points=1)
    assert e.value.field == "points"


def test_a_measured_unit_with_the_nominal_values_is_the_nominal_unit(tmp_path, problem, nominal):
    f = tmp_path / "unit.toml"
    f.write_text("[pins]\nhole_clearance_um = [" + ", ".join(["12.5"] * 40) + "]\n")
    r = hysteresis(problem, measured=f)
    assert r.unit.startswith("measured")
    assert r.lost_motion_arcmin == pytest.approx(nominal.lost_motion_arcmin, rel=1e-9)
    with pytest.raises(InputError) as e:
        hysteresis(problem, unit=0)
    assert e.value.field == "unit"


def test_the_api_takes_any_design_form(rv80e):
    r = rb.hysteresis(rv80e, points=5)
    assert isinstance(r, rb.HysteresisResult) and r.design_name == "rv80e"
    with pytest.raises(InputError) as e:
        rb.hysteresis("sun2014")
    assert e.value.field == "elastic"


def test_elastic_section_picks_the_quantile_units(problem):
    s = elastic_section(problem, samples=200, seed=3, points=5)
    low, high = s.quantile_units["5 %"], s.quantile_units["95 %"]
    assert low.lost_motion_arcmin < high.lost_motion_arcmin
    assert s.to_dict()["quantile_units"]["5 %"]["unit"].startswith("unit at the 5 %")
    again = elastic_section(problem, samples=200, seed=3, points=5)
    assert again.quantile_units["95 %"].lost_motion_arcmin == high.lost_motion_arcmin


# --- through the engine ------------------------------------------------------------------------

def test_elastic_is_a_model_of_the_engine(problem):
    assert "elastic" in MODELS
    r = simulate(problem, samples=3000, seed=1, model="elastic", specs={"lost_motion": 1.0, "rigidity": 1200.0})
    assert list(r.outputs) == ["lost_motion", "backlash", "rigidity", "preload"]
    lm, rig = r.outputs["lost_motion"], r.outputs["rigidity"]
    assert lm.unit == "arcmin" and rig.unit == "nm_per_arcmin" and not rig.spec_is_upper
    assert 0 < lm.mean < 2 and rig.mean > 0
    assert r.joint_yield is not None and r.joint_yield.count <= min(lm.yield_.count, rig.yield_.count)
    # the block source's numbers are the evaluation of the drawn units
    from rvbacklash.models.elastic import elastic_model, loop_design
    from rvbacklash.sampling.contact_source import block_streams, contact_source
    from rvbacklash.sampling.elastic_source import BLOCK_UNITS, draw_units, evaluate_batch

    c = contact_source(problem, "default", 1)
    design = loop_design(elastic_model(problem))  # block b holds units [b BLOCK_UNITS, (b + 1) BLOCK_UNITS)
    out = np.hstack([evaluate_batch(design, draw_units(c, block_streams(1, b), min(BLOCK_UNITS, 3000 - s)))
                     for b, s in enumerate(range(0, 3000, BLOCK_UNITS))])
    assert lm.mean == pytest.approx(float(np.mean(out[0])), rel=1e-12)
    assert rig.yield_.count == int(np.sum(out[2] >= 1200.0))


def test_elastic_units_are_the_contact_models_units(problem):
    """Same seed, same units: the elastic run's preload output (the contact model's stage_play of
    each drawn unit) is the contact run's, unit for unit, so its statistics are identical."""
    el = simulate(problem, samples=3000, seed=3, model="elastic", specs={"preload": 5.0})
    ct = simulate(problem, samples=3000, seed=3, model="contact", specs={"preload": 5.0})
    assert el.preload_fraction == ct.preload_fraction and 0 < el.preload_fraction < 1
    assert el.outputs["preload"].to_dict() == ct.outputs["preload"].to_dict()
    assert el.outputs["preload"].yield_.count == ct.outputs["preload"].yield_.count


def test_elastic_runs_are_reproducible_for_any_worker_count(problem):
    # three blocks of 4096 units and a partial one: threads finish them out of order
    a = simulate(problem, samples=3 * 4096 + 50, seed=7, model="elastic", workers=1)
    b = simulate(problem, samples=3 * 4096 + 50, seed=7, model="elastic", workers=2, chunk_blocks=1)
    assert a.to_dict()["outputs"] == b.to_dict()["outputs"]


def test_elastic_method_and_correlation_are_checked(problem):
    with pytest.raises(InputError) as e:
        simulate(problem, samples=100, model="elastic", method="sobol")
    assert e.value.field == "method"


def test_saved_units_have_the_contact_models_format(problem):
    r = simulate(problem, samples=200, seed=2, model="elastic", save_units=3)
    assert len(r.units) == 3
    real, linear, stage = r.units[0]
    assert linear > 0 and math.isfinite(stage) and real.pin_radial_um.shape == (40,)


def test_assumptions_say_what_the_model_has(rv80e):
    # the text follows the model: FE bodies and seats for rv80e; rigid discs and pillars without their fields
    from rvbacklash.analysis.hysteresis import hysteresis
    from rvbacklash.problem import prepare

    full = hysteresis(prepare(rv80e)).assumptions
    assert "disc bodies by plane-stress finite elements" in full and "3-D finite-element body" in full
    assert "pins' seats" in full and "disc bodies rigid" not in full
    st = rv80e.structure.model_copy(update={name: None for name in (
        "disc_pillar_hole_diameter_mm", "disc_pillar_hole_radius_mm", "disc_centre_hole_diameter_mm",
        "carrier_flange_thickness_mm", "carrier_end_plate_thickness_mm", "carrier_outer_diameter_mm",
        "carrier_bore_diameter_mm", "support_bearing_seat_diameter_mm")})
    bare = hysteresis(prepare(rv80e.model_copy(update={"structure": st, "elastic": rv80e.elastic.model_copy(
        update={"pin_seating": "none"})}))).assumptions
    assert "disc bodies rigid" in bare and "clamped beams in rigid plates" in bare and "seats" not in bare


# --- friction at or above the measuring torque (issue 36 item 2) ---------------------------------

def with_elastic(rv80e, **changes):
    return rb.prepare(rv80e.model_copy(update={"elastic": rv80e.elastic.model_copy(update=changes)}))


# the stated constant 2 N m (the example's friction before the contacts' became the default, heat40)
@pytest.mark.parametrize("changes, stuck", [
    ({"rated_torque_nm": 66.0, "friction_torque_nm": 2.0}, True),  # x T_R = 1.98 N m < T_f = 2 N m
    ({"rated_torque_nm": 67.0, "friction_torque_nm": 2.0}, False),  # x T_R = 2.01 N m > T_f
    ({"friction_torque_nm": 23.50}, False),  # x T_R = 23.52 N m (T_R = 784)
    ({"friction_torque_nm": 23.52}, True),  # T_f = x T_R: the rising branch arrives at 0 from below
])
def test_friction_at_the_measuring_torque_is_said_wherever_lost_motion_is(rv80e, changes, stuck):
    """Metamorphic: a 1.5 % change of T_R (or 0.02 N m of friction) across T_f = x T_R takes the
    lost motion from about the backlash to a fraction of it (66 N m: 0.071 against a backlash of
    1.589; 67 N m: 1.567; friction 23.50 -> 23.52 N m at 784 N m: 1.853 -> 0.359 arcmin), with no
    word before issue 36. The figure is the definition's (a bench reads the same), so it stays; the
    loop says it reads the stick band, naming the friction and x T_R, and says nothing otherwise."""
    h = hysteresis(with_elastic(rv80e, **changes))
    xt = h.measuring_torque_fraction * h.rated_torque_nm
    assert h.lost_motion_in_stick_band is stuck
    if stuck:
        assert h.lost_motion_arcmin < 0.25 * h.backlash_arcmin  # the stick band's width, not the play
        (w,) = h.warnings
        assert f"friction {h.friction_torque_nm:.4g} N m" in w and f"x T_R = {xt:.4g} N m" in w and "stick band" in w
        assert "(stick band)" in h.summary()[0]
    else:
        assert h.lost_motion_arcmin > 0.9 * h.backlash_arcmin and h.warnings == ()
    d = json.loads(json.dumps(h.to_dict()))
    assert d["lost_motion_in_stick_band"] is stuck and len(d["warnings"]) == stuck


def test_a_production_run_in_the_stick_band_flags_its_lost_motion_and_yield(rv80e, tmp_path):
    """simulate --model elastic: the lost motion output carries the warning (JSON, the yield row of
    the table, the CSV's note) and the run lists it; the report puts it among its warnings, on the
    yield card and on the elastic section's card; bench --design and calibrate carry it too. At
    T_R = 67 N m none of them says anything."""
    from helpers import run_cli
    from rvbacklash.report.files import render_csv

    stuck = with_elastic(rv80e, rated_torque_nm=66.0, friction_torque_nm=2.0)  # the stated constant
    free = with_elastic(rv80e, rated_torque_nm=67.0, friction_torque_nm=2.0)
    run = simulate(stuck, samples=300, seed=1, model="elastic", specs={"lost_motion": 1.0})
    lm = run.outputs["lost_motion"]
    assert lm.yield_.fraction == 1.0  # every unit "meets" 1 arcmin: the stick band, not the play
    assert lm.warning and "stick band" in lm.warning and run.warnings == (lm.warning,)
    assert run.outputs["backlash"].warning is None and run.outputs["rigidity"].warning is None
    d = json.loads(json.dumps(run.to_dict()))
    assert d["outputs"]["lost_motion"]["warning"] == lm.warning and d["warnings"] == [lm.warning]
    assert any(r["statistic"].startswith("yield") and r["note"].startswith("warning: friction")
               for r in run.rows() if r["output"] == "lost_motion")
    assert "stick band" in render_csv(run.rows())
    other = simulate(free, samples=300, seed=1, model="elastic", specs={"lost_motion": 1.0})
    assert other.warnings == () and all(o.warning is None for o in other.outputs.values())

    design = tmp_path / "t66.toml"
    from rvbacklash.report.design_toml import design_toml

    design.write_text(design_toml(stuck.design, "T_R 66 N m"))
    p = run_cli("simulate", design, "--model", "elastic", "-n", "300", "--spec-lost-motion-arcmin", "1")
    assert p.returncode == 0, p.stderr
    text = " ".join(p.stdout.split())
    assert "(see warning)" in text and "warning (lost_motion): friction 2 N m >= the measuring torque" in text

    data = rb.make_report(stuck, samples=300, seed=1, model="elastic", specs={"lost_motion": 1.0})
    assert any("stick band" in w for w in data.warnings)
    html = rb.render_html(data)
    cards = html[html.index('id="headline"'):html.index('id="headline-model"')]
    assert "stick band" in cards and 'id="stick-band"' in html

    from rvbacklash.analysis.bench_synthetic import model_loop_samples, write_loop_csv

    t, q, a = model_loop_samples(stuck, cycles=1, samples_per_branch=150, noise_arcmin=0.002, seed=2)
    loop = write_loop_csv(tmp_path / "loop.csv", t, q, a)
    b = rb.read_bench([loop], design=stuck, samples=100, seed=1)
    assert len(b.warnings) == 1 and "stick band" in b.warnings[0]
    assert json.loads(json.dumps(b.to_dict()))["warnings"] == list(b.warnings)
    c = rb.calibrate(stuck, bench=[loop], bootstrap=0)
    assert any(w.startswith("before") and "stick band" in w for w in c.warnings)
    s = rb.sensitivity(stuck, model="elastic", output="lost_motion", samples=64, resamples=100)
    assert any("stick band" in n for n in s.notes)
    assert not any("stick band" in n for n in rb.sensitivity(stuck, model="elastic", output="backlash", samples=64,
                                                              resamples=100).notes)
