"""Design sweeps: the SWEEP.toml schema (errors name the field), the points (grid, Latin
hypercube, Sobol), one row per point from the point's own stream, bit-identical rows inline, on a
LocalCluster of 1 and 2 workers and after a resume, and a worker that dies mid-sweep."""

from __future__ import annotations

import functools
import json
import os
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from rvbacklash.analysis.executor import Executor, executor
from rvbacklash.analysis.simulation import simulate
from rvbacklash.analysis.sweep import (evaluate_point, load_sweep, plan_sweep, quantile_tag, read_points,
                                       render_rows_csv, run_sweep)
from rvbacklash.design.loading import design_from_dict, example_text
from rvbacklash.design.sweep_spec import resolve_path, sweep_from_toml, sweep_points, with_values
from rvbacklash.errors import InputError
from rvbacklash.problem import prepare

LINEAR = """
design = "rv80e"
model = "linear"
samples = {samples}
seed = 5
spec_arcmin = 2.0

[[parameters]]
path = "second_stage.equidistance_modification_um"
values = [0, 4, 8]

[[parameters]]
path = "grades.cycloid"
values = [4, 5]
"""


def write(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.fixture(scope="module")
def plan(tmp_path_factory):
    return plan_sweep(write(tmp_path_factory.mktemp("sweep"), LINEAR.format(samples=3000)))


@pytest.fixture(scope="module")
def inline_rows(plan):
    return run_sweep(plan, scheduler="inline").rows()


@pytest.fixture(scope="module")
def cluster():
    with executor("local", workers=2) as ex:
        yield ex


# --- the input ---------------------------------------------------------------------------------

def error_of(text: str, tmp_path: Path) -> InputError:
    with pytest.raises(InputError) as e:
        plan_sweep(write(tmp_path, text))
    return e.value


@pytest.mark.parametrize("change,field,fragment", [
    (("second_stage.equidistance_modification_um", "second_stage.equidistance_um"), "parameters[0].path",
     "unknown field 'equidistance_um' in second_stage; allowed: cycloid_teeth"),
    (("second_stage.equidistance_modification_um", "second_stage"), "parameters[0].path", "is a table"),
    (("second_stage.equidistance_modification_um", "correlation.matrix"), "parameters[0].path",
     "not a single value"),
    (("values = [4, 5]", "values = [4, 5.5]"), "parameters[1].values[1]",
     "whole numbers for the integer field grades.cycloid"),
    (("values = [4, 5]", "values = [4, 4]"), "parameters[1].values", "listed twice"),
    (("values = [4, 5]", "values = [4, 5]\nlow = 1"), "parameters[1]", "exactly one of"),
    (("values = [4, 5]", "low = 3\nhigh = 6"), "parameters[1].low", "low/high are for sampling"),
    (("values = [4, 5]", "start = 4\nstop = 6"), "parameters[1]", "a range needs start, stop and count"),
    (("values = [4, 5]", "start = 4\nstop = 6\ncount = 1"), "parameters[1].count", ">= 2"),
    (("values = [4, 5]", "start = 4\nstop = 6\ncount = 4"), "parameters[1].count", "between whole numbers"),
    (("samples = 3000", "samples = 0"), "samples", ">= 1"),
    (("samples = 3000", "sample = 3000"), "sample", "unknown field; allowed fields here: name"),
    (("seed = 5", "seed = 5\nsampling = \"sobol\"\npoints = 10"), "points", "a power of 2"),
    (("seed = 5", "seed = 5\nquantiles = [0.9, 1.5]"), "quantiles", "0 < p < 1"),
    (("model = \"linear\"", "model = \"elastik\""), "model", "allowed: linear, contact"),
    (("spec_arcmin = 2.0", "spec_arcmin = 2.0\n[specs]\npreload = 5.0"), "specs.preload",
     "not an output of the linear model"),
    (("design = \"rv80e\"", "design = \"nope.toml\""), "design", "a built-in example (rv80e, sun2014)"),
])
def test_sweep_errors_name_the_field(tmp_path, change, field, fragment):
    text = LINEAR.format(samples=3000).replace(*change)
    e = error_of(text, tmp_path)
    assert e.field == field, str(e)
    assert fragment in str(e), str(e)


def test_an_out_of_range_point_is_named_before_anything_runs(tmp_path):
    text = LINEAR.format(samples=3000).replace("values = [0, 4, 8]", "values = [0, 4, 1500]")
    e = error_of(text, tmp_path)
    # point 4 = (1500, 4): the grid runs the first parameter slowest
    assert e.field == ("point 4 (second_stage.equidistance_modification_um = 1500.0, grades.cycloid = 4): "
                       "parameters[0] second_stage.equidistance_modification_um")
    assert e.value == 1500.0 and "<= 1000" in e.allowed
    assert not list(tmp_path.glob("*/points"))


def test_paths_reach_every_kind_of_field():
    assert resolve_path("grades.cycloid").kind == "int"
    assert resolve_path("factors.pin_hole_clearance.upper_um").kind == "float"
    assert resolve_path("grades.factors.pin_radius").kind == "int"
    edition = resolve_path("grades.edition")
    assert edition.kind == "str" and edition.choices == ("1995", "2013")
    with pytest.raises(ValueError, match="needs one factor key after it"):
        resolve_path("grades.factors.nope")


def test_a_factor_zone_field_is_set_in_the_design_data():
    base = {"factors": {"bearing_eccentricity": {"plus_minus_um": 2.0}}}
    out = with_values(base, ("factors.pin_hole_clearance.upper_um", "factors.bearing_eccentricity.plus_minus_um"),
                      (9.0, 3.0))
    assert out == {"factors": {"bearing_eccentricity": {"plus_minus_um": 3.0},
                               "pin_hole_clearance": {"upper_um": 9.0}}}
    assert base["factors"]["bearing_eccentricity"]["plus_minus_um"] == 2.0  # a copy


# --- points ------------------------------------------------------------------------------------

def spec_of(body: str, sampling: str = "grid", points: int | None = None):
    head = f'design = "rv80e"\nsamples = 100\nseed = 3\nsampling = "{sampling}"\n'
    return sweep_from_toml(head + (f"points = {points}\n" if points else "") + body)


def test_grid_runs_the_first_parameter_slowest_and_ranges_are_clean():
    spec = spec_of('[[parameters]]\npath = "second_stage.equidistance_modification_um"\nstart = 0\nstop = 0.3\n'
                   'count = 4\n[[parameters]]\npath = "grades.edition"\nvalues = ["1995", "2013"]\n')
    assert sweep_points(spec) == [(0.0, "1995"), (0.0, "2013"), (0.1, "1995"), (0.1, "2013"), (0.2, "1995"),
                                  (0.2, "2013"), (0.3, "1995"), (0.3, "2013")]


def test_latin_hypercube_puts_one_point_in_every_stratum_of_every_parameter():
    body = ('[[parameters]]\npath = "second_stage.equidistance_modification_um"\nlow = -10\nhigh = 10\n'
            '[[parameters]]\npath = "grades.cycloid"\nlow = 3\nhigh = 6\n'
            '[[parameters]]\npath = "grades.edition"\nvalues = ["1995", "2013"]\n')
    pts = sweep_points(spec_of(body, "latin-hypercube", 20))
    eq = np.array([p[0] for p in pts])
    assert sorted(np.floor((eq + 10) / 20 * 20).astype(int)) == list(range(20))  # one per stratum of width 1
    assert sorted(p[1] for p in pts) == sorted([3, 4, 5, 6] * 5)  # 20 strata over 4 integers: 5 each
    assert sorted(p[2] for p in pts) == ["1995"] * 10 + ["2013"] * 10
    assert sweep_points(spec_of(body, "latin-hypercube", 20)) == pts  # seeded
    assert sweep_points(spec_of(body.replace("low = -10", "low = -10.0"), "latin-hypercube", 20)) == pts
    other = sweep_points(sweep_from_toml('design = "rv80e"\nsamples = 100\nseed = 4\nsampling = "latin-hypercube"\n'
                                         'points = 20\n' + body))
    assert other != pts


def test_sobol_points_are_balanced():
    body = '[[parameters]]\npath = "second_stage.equidistance_modification_um"\nlow = 0\nhigh = 8\n'
    pts = [p[0] for p in sweep_points(spec_of(body, "sobol", 16))]
    # a scrambled Sobol' sequence of 2^4 points has one point in each of 16 equal intervals
    assert sorted(np.floor(np.array(pts) / 8 * 16).astype(int)) == list(range(16))


# --- rows ----------------------------------------------------------------------------------------

def test_quantile_tags():
    assert [quantile_tag(p) for p in (0.99865, 0.5, 0.00135, 0.9, 0.999)] == ["q99865", "q50", "q00135", "q90",
                                                                              "q999"]


def test_a_row_is_the_points_own_run(plan, inline_rows):
    """Oracle: point 3 = (4 um, grade 5) simulated directly with stream (3,) of the sweep's seed."""
    data = with_values(__import__("tomllib").loads(example_text("rv80e")), plan.parameters, (4.0, 5))
    direct = simulate(prepare(design_from_dict(data)), samples=3000, seed=5, spec_arcmin=2.0, model="linear",
                      stream=(3,))
    row = inline_rows[3]
    assert (row["point"], row["second_stage.equidistance_modification_um"], row["grades.cycloid"]) == (3, 4.0, 5)
    o = direct.output
    assert row["backlash_mean"] == o.mean and row["backlash_sigma"] == o.sigma
    q = o.quantiles.at(0.99865)
    assert (row["backlash_q99865"], row["backlash_q99865_ci95_low"], row["backlash_q99865_ci95_high"]) == \
        (q.value, q.ci95_low, q.ci95_high)
    assert (row["backlash_yield"], row["backlash_yield_ci95_low"]) == (o.yield_.fraction, o.yield_.ci95_low)
    assert row["samples"] == 3000 and row["linear_mean_arcmin"] == direct.linear_reference.mean_arcmin
    # a different stream, a different (independent) sample of the same design
    assert simulate(prepare(design_from_dict(data)), samples=3000, seed=5, model="linear",
                    stream=(4,)).output.mean != o.mean


def test_more_equidistance_modification_more_backlash(inline_rows):
    """The linear model: the mean grows by S * 2 * 4 um per step (Eq. (1)); checked as monotone."""
    means = {(r["second_stage.equidistance_modification_um"], r["grades.cycloid"]): r["backlash_mean"]
             for r in inline_rows}
    for g in (4, 5):
        assert means[(0.0, g)] < means[(4.0, g)] < means[(8.0, g)]
        steps = np.diff([r["linear_mean_arcmin"] for r in inline_rows if r["grades.cycloid"] == g])
        assert steps == pytest.approx([steps[0]] * 2, rel=1e-9)  # exact: linear in the modification


def test_same_rows_inline_local_and_a_rerun(plan, inline_rows, cluster):
    assert run_sweep(plan, scheduler="inline", workers=1).rows() == inline_rows  # threads per point do not matter
    assert run_sweep(plan, scheduler=cluster).rows() == inline_rows  # 2 worker processes
    one = run_sweep(plan, scheduler="local", workers=1)
    assert one.scheduler == "local" and one.rows() == inline_rows


def die_on_point_1(marker: str, task):
    if task.index == 1 and not os.path.exists(marker):
        Path(marker).touch()
        os._exit(1)
    return evaluate_point(task)


class Dying(Executor):
    """The cluster, but the worker running point 1 dies the first time."""

    def __init__(self, inner: Executor, marker: str):
        super().__init__(inner.scheduler, inner.client, inner.workers)
        self.marker = marker

    def map_unordered(self, fn, tasks, *, stop=None):
        return super().map_unordered(functools.partial(die_on_point_1, self.marker), tasks, stop=stop)


def test_a_worker_that_dies_loses_no_point(plan, inline_rows, cluster, tmp_path):
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    marker = tmp_path / "died"
    result = run_sweep(plan, scheduler=Dying(cluster, str(marker)), out=tmp_path / "out")
    assert marker.exists() and not result.partial
    assert result.rows() == inline_rows
    assert sorted(p.name for p in (tmp_path / "out" / "points").iterdir()) == [f"{i:06d}.json" for i in range(6)]


# --- results and resume --------------------------------------------------------------------------

def stop_after(n: int):
    stop = threading.Event()

    def progress(done, total):
        if done >= n:
            stop.set()
    return stop, progress


def stop_while_running(point: int, stop: threading.Event, partial: bool = False):
    """evaluate_point, with a Ctrl-C (``stop`` set) while ``point`` runs: inline, the point's own run
    stops after its blocks under way; ``partial`` says whether samples were left (else they were
    all under way, and the point finishes)."""
    import dataclasses

    def evaluate(task):
        if task.index != point:
            return evaluate_point(task)
        stop.set()
        outcome = evaluate_point(task)
        return dataclasses.replace(outcome, partial=True) if partial else outcome
    return evaluate


@pytest.mark.parametrize("partial", [False, True])
def test_a_ctrl_c_inline_keeps_the_point_under_way_only_if_its_run_finished(plan, inline_rows, tmp_path,
                                                                             monkeypatch, partial):
    """docs/sweeps.md (issue 36 item 14): inline, the point being computed when Ctrl-C comes is kept
    if its run still finished, dropped if its run stopped short; either way the sweep is partial,
    "interrupted", and stops submitting."""
    import rvbacklash.analysis.sweep as sweep_module

    stop = threading.Event()
    monkeypatch.setattr(sweep_module, "evaluate_point", stop_while_running(2, stop, partial))
    out = tmp_path / "out"
    r = run_sweep(plan, out=out, scheduler="inline", workers=1, stop=stop)
    kept = [0, 1] if partial else [0, 1, 2]
    assert r.partial and [row["point"] for row in r.rows()] == kept
    assert r.rows() == inline_rows[:len(kept)]
    state = json.loads((out / "sweep.json").read_text())
    assert state["status"] == "partial" and state["interrupted"] is True and state["points_done"] == len(kept)


def test_a_ctrl_c_in_the_last_point_that_finishes_it_leaves_a_complete_sweep(plan, inline_rows, tmp_path,
                                                                            monkeypatch):
    """Issue 36 item 14: the state said "complete" and "interrupted": true at once. Every point is
    finished: complete, not interrupted (nothing to resume), and the rows are the sweep's."""
    import rvbacklash.analysis.sweep as sweep_module

    stop = threading.Event()
    monkeypatch.setattr(sweep_module, "evaluate_point", stop_while_running(len(plan) - 1, stop))
    out = tmp_path / "out"
    r = run_sweep(plan, out=out, scheduler="inline", workers=1, stop=stop)
    assert stop.is_set() and not r.partial and r.rows() == inline_rows
    state = json.loads((out / "sweep.json").read_text())
    assert state["status"] == "complete" and state["interrupted"] is False and state["points_done"] == len(plan)
    assert not load_sweep(out).partial


@pytest.mark.parametrize("where", ["inline", "cluster"])
def test_an_interrupted_sweep_resumes_without_losing_or_repeating_a_point(plan, inline_rows, cluster, tmp_path, where):
    out = tmp_path / "out"
    stop, progress = stop_after(2)
    first = run_sweep(plan, out=out, scheduler="inline" if where == "inline" else cluster, progress=progress,
                      stop=stop)
    assert first.partial and 2 <= first.points_done < 6
    state = json.loads((out / "sweep.json").read_text())
    assert state["status"] == "partial" and state["points_done"] == first.points_done
    assert load_sweep(out).rows() == first.rows() and load_sweep(out).partial
    seen = []
    second = run_sweep(plan, out=out, scheduler="inline", progress=lambda d, t: seen.append((d, t)))
    assert seen[0] == (first.points_done, 6) and seen[-1] == (6, 6)
    assert second.skipped == first.points_done and not second.partial
    assert second.rows() == inline_rows
    assert len(list((out / "points").glob("*.json"))) == 6
    assert json.loads((out / "sweep.json").read_text())["status"] == "complete"
    import pyarrow.parquet as pq

    assert pq.read_table(out / "results.parquet").to_pylist() == inline_rows
    assert (out / "results.csv").read_bytes() == render_rows_csv(inline_rows)
    third = run_sweep(plan, out=out, scheduler="inline")
    assert third.skipped == 6 and third.rows() == inline_rows


def test_csv_holds_the_exact_numbers(inline_rows):
    import csv
    import io

    rows = list(csv.DictReader(io.StringIO(render_rows_csv(inline_rows).decode())))
    column = "backlash_q99865_ci95_high"
    assert [float(r[column]) for r in rows] == [r[column] for r in inline_rows]


def test_another_sweep_into_the_same_directory_is_refused_unless_forced(plan, tmp_path):
    out = tmp_path / "out"
    run_sweep(plan, out=out, scheduler="inline")
    other = plan_sweep(write(tmp_path, LINEAR.format(samples=2000), "other.toml"))
    assert other.fingerprint != plan.fingerprint
    with pytest.raises(InputError) as e:
        run_sweep(other, out=out, scheduler="inline")
    assert e.value.field == "out" and "different sweep" in e.value.allowed and "--force" in e.value.allowed
    forced = run_sweep(other, out=out, scheduler="inline", force=True)
    assert forced.skipped == 0 and forced.rows()[0]["samples"] == 2000
    assert all(r["samples"] == 2000 for r in read_points(out / "points").values())


def test_the_name_and_the_comments_do_not_change_the_fingerprint(plan, tmp_path):
    text = "# a comment\nname = \"renamed\"\ndescription = \"same numbers\"\n" + LINEAR.format(samples=3000)
    assert plan_sweep(write(tmp_path, text)).fingerprint == plan.fingerprint


def test_out_must_be_a_sweep_directory(plan, tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="is not a directory"):
        run_sweep(plan, out=tmp_path / "file")
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("keep me")
    with pytest.raises(InputError, match="holds no sweep"):
        run_sweep(plan, out=tmp_path / "mine")
    run_sweep(plan, out=tmp_path / "mine", scheduler="inline", force=True)
    assert (tmp_path / "mine" / "notes.txt").read_text() == "keep me"  # --force removes only the sweep's files


def test_the_shipped_example_sweep_is_valid():
    p = plan_sweep("modifications-sweep")
    assert len(p) == 63 and p.spec.model == "contact" and p.base_name == "rv80e"
    assert p.limits == {"backlash": 1.0, "preload": 5.0}
    assert p.points[0] == (-10.0, -20.0) and p.points[-1] == (10.0, 10.0)


def test_one_sweep_at_a_time_in_a_directory(plan, tmp_path):
    out = tmp_path / "out"
    refused = []

    def progress(done, total):
        if done == 1 and not refused:
            with pytest.raises(InputError) as e:
                run_sweep(plan, out=out, scheduler="inline")
            refused.append(e.value)
    run_sweep(plan, out=out, scheduler="inline", progress=progress)
    assert refused and refused[0].field == "out" and "in use by another running sweep" in refused[0].allowed
    assert run_sweep(plan, out=out, scheduler="inline").skipped == 6  # the lock went with the first run


def test_a_sweep_that_cannot_start_leaves_nothing_behind(plan, tmp_path, monkeypatch):
    """Issue 18: an unreachable scheduler left DIR/.lock and DIR/sweep.json behind. A directory the
    sweep created (or found empty) is removed again; a sweep's directory stays as a resume finds it."""
    import rvbacklash.analysis.executor as ex

    monkeypatch.setattr(ex, "CONNECT_TIMEOUT_S", 0.5)
    for out in (tmp_path / "new", tmp_path / "empty"):
        if out.name == "empty":
            out.mkdir()
        with pytest.raises(InputError) as e:
            run_sweep(plan, out=out, scheduler="tcp://127.0.0.1:1")
        assert e.value.field == "scheduler" and "cannot connect" in str(e.value)
        assert not out.exists()
    done = tmp_path / "done"
    first = run_sweep(plan, out=done, scheduler="inline")
    (done / "points" / sorted(os.listdir(done / "points"))[0]).unlink()  # one point to run again
    with pytest.raises(InputError):
        run_sweep(plan, out=done, scheduler="tcp://127.0.0.1:1")
    assert len(read_points(done / "points", plan)) == len(plan) - 1
    assert run_sweep(plan, out=done, scheduler="inline").rows() == first.rows()  # the resume uses what stayed


def test_a_transmission_sweep_gives_the_te_figures_of_each_point(tmp_path):
    """model = "transmission": every point's row carries the TE peak-to-peak figures and yield
    against its spec, the same numbers as simulate on the point's stream."""
    text = """
design = "rv80e"
model = "transmission"
samples = 400
seed = 3

[specs]
backlash = 3.0
transmission_error = 60.0

[[parameters]]
path = "second_stage.equidistance_modification_um"
values = [0, 8]
"""
    plan = plan_sweep(write(tmp_path, text))
    rows = run_sweep(plan, scheduler="inline").rows()
    assert len(rows) == 2
    for i, row in enumerate(rows):
        for key in ("transmission_error_mean", "transmission_error_q99865", "transmission_error_yield",
                    "lost_motion_max_mean", "joint_yield"):
            assert key in row, key
        run = simulate(prepare(plan.designs[i]), model="transmission", samples=400, seed=3, stream=(i,),
                       specs={"backlash": 3.0, "transmission_error": 60.0}, workers=1)
        te = run.outputs["transmission_error"]
        assert row["transmission_error_mean"] == te.mean and row["transmission_error_yield"] == te.yield_.fraction


def test_an_elastic_sweep_with_a_life_spec_gives_the_life_columns(tmp_path):
    """A life spec (specs.life, the output's name, as simulate's --spec-life-h sets it) gives every
    point the elastic model's life columns and the joint yield with them, the numbers simulate gives
    on the point's stream; ``life = true`` gives the columns without a spec; the linear model refuses."""
    text = """
design = "rv80e"
model = "elastic"
samples = 300
seed = 3

[specs]
lost_motion = 2.5
life = 2500.0

[[parameters]]
path = "second_stage.equidistance_modification_um"
values = [0, 8]
"""
    plan = plan_sweep(write(tmp_path, text))
    assert {"life", "rated_torque", "weakest_bearing_life", "max_pin_stress"} <= {o.name for o in plan.outputs}
    rows = run_sweep(plan, scheduler="inline").rows()
    for i, row in enumerate(rows):
        run = simulate(prepare(plan.designs[i]), model="elastic", samples=300, seed=3, stream=(i,),
                       specs={"lost_motion": 2.5, "life": 2500.0}, workers=1)
        assert row["life_mean"] == run.outputs["life"].mean and row["life_yield"] == run.outputs["life"].yield_.fraction
        assert row["rated_torque_q50"] == next(q.value for q in run.outputs["rated_torque"].quantiles
                                               if q.probability == 0.5)
        assert row["joint_yield"] == run.joint_yield.fraction
    no_spec = plan_sweep(write(tmp_path, text.replace("life = 2500.0", "").replace("seed = 3", "seed = 3\nlife = true"),
                               "t.toml"))
    assert "life" in {o.name for o in no_spec.outputs} and no_spec.fingerprint != plan.fingerprint
    # a sweep without the field keeps its fingerprint (life false is left out of it)
    plain_text = text.replace("life = 2500.0", "")
    assert plan_sweep(write(tmp_path, plain_text, "u.toml")).fingerprint == \
        plan_sweep(write(tmp_path, plain_text.replace("seed = 3", "seed = 3\nlife = false"), "v.toml")).fingerprint
    e = error_of(LINEAR.format(samples=100).replace("spec_arcmin = 2.0", "spec_arcmin = 2.0\n[specs]\nlife = 6000.0"),
                 tmp_path)
    assert e.field == "specs.life" and "elastic" in str(e)
