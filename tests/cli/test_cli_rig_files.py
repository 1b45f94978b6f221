"""Rig files as they come, end to end (issue 35): `bench` reads the public rig's two-run TE file as
one unit (table, JSON valid against its schema, CSV, plot with the model's lost motion), the same
format flags on `bench` and `calibrate` (--columns, --format-profile, --decimal), and a two-run
file is refused by `calibrate` in one line."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest

import rvbacklash as rb
from helpers import one_line_error, run_cli
from rvbacklash.analysis.bench_synthetic import model_loop_samples, two_run_te, write_loop_csv, write_rig_te_csv
from rvbacklash.report.files import render_json
from rvbacklash.report.schemas import output_schema

RIG_FILE = Path(__file__).parent.parent / "data" / "rig_two_runs.csv"  # tests/design/test_rig_files.py: its truth


def test_bench_reads_the_public_rig_file_as_one_unit(tmp_path):
    js, csv_out, svg = tmp_path / "r.json", tmp_path / "r.csv", tmp_path / "r.svg"
    p = run_cli("bench", RIG_FILE, "--json", js, "--csv", csv_out, "--plot", svg)
    assert p.returncode == 0, p.stderr
    for text in ("forward and backward runs", "1.1999 (0.98", "backward run above", "public RV test rig"):
        assert text in p.stdout, p.stdout
    d = json.loads(js.read_text())
    jsonschema.validate(d, output_schema("bench"))
    (u,) = d["units"]
    assert u["kind"] == "transmission_error_two_runs" and u["ccw_run"] == "backward"
    assert u["lost_motion_mean_arcmin"] == pytest.approx(1.2, abs=0.005)
    assert len(u["lost_motion_arcmin"]) == len(u["output_angle_deg"]) == 1024
    assert [s["order"] for s in u["forward"]["leading_orders"]][:3] == [1, 2, 39]
    assert u["te_peak_to_peak_arcsec"] == u["forward"]["te_peak_to_peak_arcsec"]
    header = csv_out.read_text().splitlines()[0]
    assert header == ("source,kind,te_peak_to_peak_arcsec,te_peak_to_peak_backward_arcsec,lost_motion_mean_arcmin")
    assert svg.read_text().lstrip().startswith(("<?xml", "<svg"))


def test_placed_in_the_design_run_and_drawn_beside_the_model(rv80e_problem, tmp_path):
    """With a design: both runs' TE and the mean lost motion placed among the transmission model's
    units (the run read as ccw against the ccw flank); the plot draws the model's curve."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rvbacklash.report.bench_plots import draw_lost_motion

    f = write_rig_te_csv(tmp_path / "inside.csv", *two_run_te({1: 25.0, 2: 8.0, 39: 1.5}, 0.5, samples=720,
                                                               noise_arcsec=0.2, seed=1))
    b = rb.read_bench([f], design=rv80e_problem, samples=100, seed=0)
    jsonschema.validate(json.loads(render_json(b.to_dict())), output_schema("bench"))
    (u,) = b.units
    placed = {p.figure: p for p in u.placement}
    assert list(placed) == ["te_peak_to_peak_arcsec", "te_peak_to_peak_backward_arcsec", "lost_motion_mean_arcmin"]
    for p in placed.values():
        assert 0 < p.percentile < 100 and not p.outside
    lm = placed["lost_motion_mean_arcmin"]
    assert lm.measured == pytest.approx(0.5, abs=0.005) and lm.predicted_q05 <= lm.predicted_median <= lm.predicted_q95
    model = rb.transmission_error(rv80e_problem, shares=False)
    fig, ax = plt.subplots()
    draw_lost_motion(ax, [u], model)
    labels = [line.get_label() for line in ax.get_lines()]
    # the output's lost motion: the cycloid stage (1.09) + the other stages' linear means (issue 36 item 11)
    assert any(label.startswith("model, rv80e nominal unit (rigid, no load): mean 1.53") for label in labels), labels
    drawn = next(line for line in ax.get_lines() if line.get_label().startswith("model"))
    np.testing.assert_array_equal(drawn.get_ydata(), model.lost_motion_arcmin)
    plt.close(fig)


def _german_loop(problem, folder: Path) -> tuple[Path, Path]:
    """A loop as a rig might write it (metadata lines, its own headers without units, ';' and
    decimal commas) and the same loop as the project writes it."""
    t, q, a = model_loop_samples(problem, cycles=1, samples_per_branch=80, noise_arcmin=0.01, seed=3)
    plain = write_loop_csv(folder / "plain.csv", t, q, a)
    body = [line.replace(",", ";").replace(".", ",") for line in plain.read_text().splitlines()[1:]]
    german = folder / "pruefstand.csv"
    german.write_text("\n".join(["Pruefstand 2;Prüfling 4711", "Temperatur;23,5", "Zeit;Moment;Verdrehung", *body])
                      + "\n")
    return german, plain


def test_the_same_format_flags_on_bench_and_calibrate(rv80e_problem, tmp_path):
    german, plain = _german_loop(rv80e_problem, tmp_path)
    flags = ("--columns", "time=Zeit,torque=Moment,angle=Verdrehung", "--time-unit", "s", "--torque-unit", "N m",
             "--angle-unit", "arcmin")
    line = one_line_error(run_cli("bench", german, "--format", "json"), f"error: {german}: no column of a known "
                                                                         f"quantity (columns found: 'Zeit'")
    assert "--columns" in line
    b = run_cli("bench", german, *flags, "--format", "json")
    assert b.returncode == 0, b.stderr
    d = json.loads(b.stdout)
    jsonschema.validate(d, output_schema("bench"))
    ref = json.loads(run_cli("bench", plain, "--format", "json").stdout)["units"][0]
    (u,) = d["units"]
    assert u["metadata"] == ["Pruefstand 2;Prüfling 4711", "Temperatur;23,5"]
    for k in ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin"):
        assert u[k] == ref[k]
    profile = tmp_path / "pruefstand.toml"
    profile.write_text('name = "Pruefstand 2"\ndecimal = ","\n[columns]\ntime = "Zeit"\ntorque = "Moment"\n'
                       'angle = "Verdrehung"\n[units]\ntime = "s"\ntorque = "N m"\nangle = "arcmin"\n')
    c = run_cli("calibrate", "rv80e", "--bench", german, "--format-profile", profile, "--bootstrap", "0",
                "--format", "json")
    assert c.returncode == 0, c.stderr
    jsonschema.validate(json.loads(c.stdout), output_schema("calibrate"))
    one_line_error(run_cli("calibrate", "rv80e", "--bench", german, *flags, "--decimal", ";"),
                   "error: --decimal = ';': allowed: '.' or ','")
    one_line_error(run_cli("calibrate", "rv80e", "--bench", german, "--columns", "torque"),
                   "error: --columns = 'torque': allowed: ROLE=COLUMN pairs")
    one_line_error(run_cli("bench", german, "--format-profile", tmp_path / "none.toml"),
                   f"error: {tmp_path / 'none.toml'}: no such file; allowed: a TOML format profile")
    one_line_error(run_cli("calibrate", "rv80e", "--bench", german, *flags, "--seed", "-1"),
                   "error: --seed = -1: allowed: an integer >= 0")


def test_calibrate_refuses_a_two_run_te_file_in_one_line(tmp_path):
    one_line_error(run_cli("calibrate", "rv80e", "--bench", RIG_FILE),
                   f"error: {RIG_FILE}: a transmission-error curve; allowed: hysteresis loops (torque and angle)")
