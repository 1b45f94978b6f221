"""Selective assembly (issue 39): the class sets and their tables, the rules, the selected run's
limits (one class = random assembly bit for bit; no noise and fine classes = the closed-form
prediction), same seed same numbers."""

import math

import numpy as np
import pytest
from scipy import stats

from rvbacklash.analysis.selection.classes import ClassSet, class_table, make_selection, parse_selection
from rvbacklash.analysis.selection.rules import in_class_um, predicted_play_arcmin
from rvbacklash.analysis.selection.run import simulate_selected, surplus
from rvbacklash.analysis.selection.source import (draw_selected_kernel, empty_record, measurement_errors,
                                                  selection_tables)
from rvbacklash.analysis.simulation import simulate
from rvbacklash.errors import InputError
from rvbacklash.sampling.contact_source import block_streams, saved_units
from rvbacklash.sampling.elastic_source import draw_units, elastic_source, empty_batch

SPEC = {"lost_motion": 1.0}


def test_parse_selection_and_its_errors():
    s = parse_selection("pins=5x2um, rollers=3x2um,noise=0.5um,play=-0.5:0,target=0.3")
    assert (s.pins, s.rollers, s.noise_um) == (ClassSet(5, 2.0), ClassSet(3, 2.0), 0.5)
    assert (s.play_min_arcmin, s.play_max_arcmin, s.target_arcmin) == (-0.5, 0.0, 0.3)
    d = parse_selection("rollers=4x1.5um")
    assert d.pins.count == 1 and d.play_min_arcmin == -math.inf and d.play_max_arcmin == 0.0 and d.target_arcmin is None
    assert parse_selection("pins=1x1um").random
    for bad, fragment in [("pins=5", "COUNTxWIDTHum"), ("pins=0x2um", "count"), ("pins=5x0um", "width"),
                          ("pins=5x2um,pins=3x1um", "twice"), ("bolts=3x1um", "unknown key"),
                          ("noise=1um", "no part"), ("pins=5x2um,noise=-1um", ">= 0"),
                          ("pins=5x2um,play=1:0", "MIN <= MAX"), ("", "allowed")]:
        with pytest.raises(InputError) as e:
            parse_selection(bad)
        assert fragment in str(e.value) and "\n" not in str(e.value)


def test_class_table_shares_bands_and_conditional_parts():
    law = stats.truncnorm(-3, 3, 0.0, 1.0)
    t = class_table(law, ClassSet(5, 2.0), 0.5)  # radius bands 1 um wide centred on 0
    assert t.share.sum() == pytest.approx(1.0)
    assert t.share[2] == pytest.approx(law.cdf(0.5) - law.cdf(-0.5), rel=1e-9)
    x = law.rvs(size=4000, random_state=np.random.default_rng(3))
    edges = [-3.0, -1.5, -0.5, 0.5, 1.5, 3.0]
    for c in range(5):
        y = np.array([in_class_um(v, t, c) for v in x])
        assert edges[c] - 1e-6 <= y.min() and y.max() <= edges[c + 1] + 1e-6
        # the parts of a class follow the law conditioned on its band: their mean is the band's
        assert y.mean() == pytest.approx(t.mean_um[c], abs=0.03)
    one = class_table(law, ClassSet(1, 2.0), 0.5)
    assert one.share == pytest.approx([1.0]) and one.mean_um[0] == pytest.approx(0.0, abs=1e-3)


def test_surplus_closed_form():
    r, left = surplus(np.array([0.25, 0.5, 0.25]), np.array([0.5, 0.5, 0.0]))
    assert r == pytest.approx(2.0) and left == pytest.approx([0.0, 0.5, 0.5])
    assert surplus(np.array([0.3, 0.7]), np.array([0.3, 0.7]))[0] == pytest.approx(1.0)


def _draw(problem, selection, seed=5, n=400):
    src = elastic_source(problem, "default", seed)
    c, g = src.contact, src.contact.geometry
    tables = selection_tables(src, selection)
    record = empty_record(measurement_errors(seed, (), 0, n, selection.noise_um))
    batch = empty_batch(n, g.discs, g.zp)
    draw_selected_kernel(block_streams(c.seed, 0, c.stream), c.laws, g.stage_geometry, c.coef, batch, saved_units(0, g),
                         tables, record)
    return src, batch, record, tables


def test_one_class_draws_the_random_units_bit_for_bit(rv80e_problem):
    src, batch, record, _ = _draw(rv80e_problem, parse_selection("pins=1x2um,rollers=1x3um"))
    c = src.contact
    ref = draw_units(c, block_streams(c.seed, 0, c.stream), 400)
    for a, b in zip(ref, batch):
        assert np.array_equal(a, b, equal_nan=True)
    assert not record.pin_class.any() and not record.roller_class.any()


def test_one_class_run_is_the_random_run(rv80e_problem):
    r = simulate_selected(rv80e_problem, parse_selection("pins=1x2um,rollers=1x2um"), samples=300, seed=2, specs=SPEC,
                          workers=1)
    plain = simulate(rv80e_problem, samples=300, seed=2, specs=SPEC, workers=1, model="elastic").to_dict()
    for d in (r.selected.to_dict(), r.random.to_dict()):
        assert d["outputs"] == plain["outputs"] and d["convergence"] == plain["convergence"]
    assert r.yields[0].random == r.yields[0].selected and r.pin_surplus_fraction == 0.0


def test_no_noise_fine_classes_reach_the_closed_form_play(rv80e_problem):
    """With no measurement error and classes 0.03 um wide, every unit the pins can close lands at
    min(P(law mean), 0) within a class's step (P: the predicted play, rules module): the closed form
    of the exact selection's play; a unit the pins cannot close takes the largest class."""
    _, _, random, _ = _draw(rv80e_problem, parse_selection("pins=1x1um"))
    p0 = random.predicted_play_arcmin  # P at the law's mean: the pins of random assembly
    _, _, fine, tables = _draw(rv80e_problem, parse_selection("pins=400x0.03um"))
    k, p = tables.pins.mean_um.size, fine.predicted_play_arcmin
    closed = p0 <= 0
    assert closed.sum() > 100 and np.all(np.abs(2 * fine.pin_class[closed] - (k - 1)) <= 1)  # the middle class
    reached = (p0 > 0) & (p <= 1e-12)
    assert reached.sum() > 50
    ok = closed | reached
    assert np.all(p[ok] <= 1e-12)  # in the window
    # a unit the pins close lands at 0 = min(P0, 0) within a class's step (0.015 um of radius: ~0.002
    # arcmin at P's slope of 0.12 arcmin/um; a few pins' flat levers are steeper)
    miss = np.abs(p[reached])
    assert np.median(miss) < 0.003 and np.quantile(miss, 0.9) < 0.01
    still_open = p > 1e-12  # the largest pins could not close these
    assert still_open.any() and np.all(fine.pin_class[still_open] == k - 1) and np.all(p0[still_open] > 0)


def test_rules_compensate_and_noise_blurs(rv80e_problem):
    """Metamorphic: without noise every unit the rule closes is predicted closed; with a measurement
    error the prediction it acted on is off, and some units it meant to close stay open."""
    _, _, exact, _ = _draw(rv80e_problem, parse_selection("pins=5x2um"))
    _, b0, _, _ = _draw(rv80e_problem, parse_selection("pins=5x2um"))
    _, b1, noisy, _ = _draw(rv80e_problem, parse_selection("pins=5x2um,noise=1um"))
    assert not np.array_equal(exact.pin_class, noisy.pin_class)
    free0 = np.isnan(b0.preload_um).mean()
    free1 = np.isnan(b1.preload_um).mean()
    assert free1 > free0


def test_selection_buys_yield_same_seed_same_numbers(rv80e_problem):
    sel = parse_selection("pins=5x2um,rollers=3x2um,noise=0.5um")
    a = simulate_selected(rv80e_problem, sel, samples=600, seed=4, specs=SPEC, workers=1)
    b = simulate_selected(rv80e_problem, sel, samples=600, seed=4, specs=SPEC, workers=2)
    da, db = a.to_dict(), b.to_dict()
    for d in (da, db):
        for k in ("elapsed_random_s", "elapsed_selected_s"):
            d.pop(k)
        for run in ("random_run", "selected_run"):
            d[run].pop("elapsed_s")
    assert da == db
    y = a.yields[0]
    assert y.output == "lost_motion" and y.selected.fraction > y.random.fraction + 0.05
    used = sum(c.units for c in a.classes if c.part == "pins")
    assert used == 600 and a.pin_sets_per_unit >= 1.0
    assert a.to_frame is not None and any(r["table"] == "classes" for r in a.rows())


def test_selection_needs_a_spec_and_the_elastic_model(rv80e_problem):
    sel = make_selection(pins=ClassSet(5, 2.0))
    with pytest.raises(InputError, match="spec"):
        simulate_selected(rv80e_problem, sel, samples=10)
    with pytest.raises(InputError, match="elastic"):
        simulate_selected(rv80e_problem, sel, samples=10, specs=SPEC, model="contact")


def test_selection_json_validates_against_the_simulate_schema(rv80e_problem):
    import json

    import jsonschema

    from rvbacklash.report.files import render_json
    from rvbacklash.report.schemas import output_schema

    r = simulate_selected(rv80e_problem, parse_selection("pins=3x2um,rollers=2x2um"), samples=200, seed=1,
                          specs={"lost_motion": 1.0, "rigidity": 280.0}, workers=1)
    data = json.loads(render_json(r.to_dict()))
    assert data["selected_run"]["outputs"]["lost_motion"]["yield"]["total"] == 200
    assert [y["output"] for y in data["yields"]] == ["lost_motion", "rigidity", "joint"]
    schema = output_schema("simulate")
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
    data["yields"][0]["moved"] = 1
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)


def test_class_sweep_one_class_is_random_and_the_plot_draws(rv80e_problem):
    from rvbacklash.analysis.selection.run import class_sweep
    from rvbacklash.report.selection import class_sweep_svg

    s = class_sweep(rv80e_problem, counts=(1, 5), widths=(2.0,), rollers=ClassSet(1, 2.0), samples=300, seed=3,
                    workers=1)
    one = next(p for p in s.points if p.pin_classes == 1)
    assert one.yield_ == s.random_yield and one.pin_surplus_fraction == 0.0
    assert len(s.rows()) == 2 and s.to_dict()["points"][0]["yield"]["total"] == 300
    svg = class_sweep_svg(s)
    assert svg.lstrip().startswith("<?xml") and "pin diameter classes" in svg
