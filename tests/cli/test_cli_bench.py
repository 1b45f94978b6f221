"""`rvbacklash bench` and `rvbacklash calibrate` end to end (issue 29), and every bad-data case
as one line naming the file, the column and the problem, exit 2, nothing written."""

from __future__ import annotations

import json

import jsonschema
import numpy as np
import pytest

import rvbacklash as rb
from helpers import call_beside_fifo, example_text, one_line_error, run_cli
from rvbacklash.analysis.bench_synthetic import model_loop_samples, te_curve, write_loop_csv, write_te_csv
from rvbacklash.report.schemas import output_schema


@pytest.fixture(scope="module")
def truth(rv80e):
    e = rv80e.elastic.model_copy(update={"structure_stiffness_nm_per_arcmin": 400.0, "friction_torque_nm": 3.0})
    return rb.prepare(rv80e.model_copy(update={"elastic": e}))


@pytest.fixture(scope="module")
def loop_file(truth, tmp_path_factory):
    t, q, a = model_loop_samples(truth, cycles=2, samples_per_branch=300, noise_arcmin=0.01, offset_arcmin=1.5,
                                 seed=7, crank_clearance_um=6.0)
    return write_loop_csv(tmp_path_factory.mktemp("bench") / "unit 1.csv", t, q, a, angle_unit="deg")


def test_bench_reads_a_loop_and_a_te_curve(loop_file, tmp_path):
    te = write_te_csv(tmp_path / "te.tsv", *te_curve({1: 8.0, 39: 2.0}, samples=1500, noise_arcsec=0.2))
    js, csv_out, svg = tmp_path / "b.json", tmp_path / "b.csv", tmp_path / "b.svg"
    p = run_cli("bench", loop_file, te, "--json", js, "--csv", csv_out, "--plot", svg)
    assert p.returncode == 0, p.stderr
    for text in ("Measured loops", "2 cycles", "Measured transmission error", "39: 2.0"):
        assert text in p.stdout
    d = json.loads(js.read_text())
    jsonschema.validate(d, output_schema("bench"))
    loop, curve = d["units"]
    for key in ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin", "rigidity_secants",
                "hysteresis_loss_j", "uncertainty_k2", "cycles", "noise_arcmin", "loop"):
        assert key in loop
    assert loop["rated_torque_from"] == "loop peaks" and loop["rated_torque_nm"] == pytest.approx(784.0, rel=1e-3)
    assert curve["te_peak_to_peak_arcsec"] > 0 and [s["order"] for s in curve["leading_orders"]][:2] == [1, 39]
    assert csv_out.read_text().splitlines()[0].startswith("source,kind,")
    assert svg.read_text().lstrip().startswith(("<?xml", "<svg"))


def test_bench_places_a_unit_in_the_design_run(rv80e_problem, tmp_path):
    """The design's own nominal unit: inside the band, no factor named; percentiles in 0..100."""
    t, q, a = model_loop_samples(rv80e_problem, cycles=1, samples_per_branch=150, noise_arcmin=0.005, seed=2)
    f = write_loop_csv(tmp_path / "nominal.csv", t, q, a)
    js = tmp_path / "p.json"
    p = run_cli("bench", f, "--design", "rv80e", "-n", "300", "--seed", "1", "--json", js)
    assert p.returncode == 0, p.stderr
    assert "In the predicted production run of rv80e" in p.stdout
    placed = json.loads(js.read_text())["units"][0]["placement"]
    assert [x["figure"] for x in placed] == ["lost_motion_arcmin", "backlash_arcmin",
                                             "torsional_rigidity_nm_per_arcmin", "hysteresis_loss_j"][:len(placed)]
    for x in placed:
        assert 0 <= x["percentile"] <= 100 and not x["outside"] and x["explaining_factors"] == []
        assert x["predicted_q05"] <= x["predicted_median"] <= x["predicted_q95"]


def test_calibrate_writes_a_design_that_reproduces_the_loop(loop_file, tmp_path):
    """Done-when check: `calibrate` recovers the stiffness and the friction within their intervals
    and `hysteresis calibrated.toml` gives the measured figures."""
    out, js, svg = tmp_path / "calibrated.toml", tmp_path / "c.json", tmp_path / "c.svg"
    stated = tmp_path / "stated.toml"  # the loop's friction the stated constant: the fit's parameter is the torque
    stated.write_text(example_text("rv80e").replace("[elastic]\n", '[elastic]\nfriction_model = "stated"\n', 1))
    p = run_cli("calibrate", stated, "--bench", loop_file, "--write-design", out, "--json", js, "--plot", svg)
    assert p.returncode == 0, p.stderr
    d = json.loads(js.read_text())
    jsonschema.validate(d, output_schema("calibrate"))
    fitted = {x["name"]: x for x in d["parameters"]}
    for name, true in (("structure_stiffness_nm_per_arcmin", 400.0), ("friction_torque_nm", 3.0)):
        assert fitted[name]["ci95_low"] <= true <= fitted[name]["ci95_high"], fitted[name]
    text = out.read_text()
    assert text.startswith("# Calibrated with `rvbacklash calibrate` on ") and str(loop_file) in text
    assert "structure_stiffness_nm_per_arcmin = " in text and "[factors.crank_bearing_clearance]" in text
    h = run_cli("hysteresis", out, "--format", "json")
    assert h.returncode == 0, h.stderr
    b = run_cli("bench", loop_file, "--design", out, "-n", "200", "--format", "json")
    assert b.returncode == 0, b.stderr
    model, measured = json.loads(h.stdout), json.loads(b.stdout)["units"][0]
    for k in ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin"):
        assert abs(model[k] - measured[k]) <= measured["uncertainty_k2"][k], k
    assert svg.read_text().lstrip().startswith(("<?xml", "<svg"))
    assert "lack of fit" not in p.stdout and "BOUND" not in p.stdout and "WARNING" not in text
    assert d["lack_of_fit"] is False and d["flags"] == []


def test_calibrate_flags_a_loop_the_model_did_not_make(truth, tmp_path, monkeypatch):
    """Issue 36 item 6 end to end: a stiffness falling with load (500 -> 250 N m/arcmin) - the
    table flags the misfit and the clearance at its bound and shows where the misfit sits, the
    JSON says so (schema-valid), the written design's comments carry both warnings."""
    t, q, a = model_loop_samples(truth, cycles=1, samples_per_branch=200, noise_arcmin=0.003, seed=3)
    f = write_loop_csv(tmp_path / "held out.csv", t, q, a + q / (500.0 - 250.0 * np.abs(q) / 784.0) - q / 400.0)
    out, js = tmp_path / "calibrated.toml", tmp_path / "c.json"
    monkeypatch.setenv("COLUMNS", "250")  # the table's cells unwrapped
    p = run_cli("calibrate", "rv80e", "--bench", f, "--write-design", out, "--json", js)
    assert p.returncode == 0, p.stderr
    for text in ("AT LOWER BOUND: no estimate", "LACK OF FIT: interval too narrow", "Where the misfit sits",
                 "warning: lack of fit", "warning: crank_clearance_offset_um at its lower bound"):
        assert text in p.stdout, text
    d = json.loads(js.read_text())
    jsonschema.validate(d, output_schema("calibrate"))
    assert d["lack_of_fit"] is True and d["residual_over_expected"] > 10 and len(d["flags"]) == 2
    assert [x["at_bound"] for x in d["parameters"]] == [None, None, "lower"]
    comments = [line for line in out.read_text().splitlines() if line.startswith("# WARNING, ")]
    bound = f"# WARNING, crank_clearance_offset_um at its lower bound -4.5 um (zero clearance) for {f}"
    assert [c.split(":")[0] for c in comments] == ["# WARNING, lack of fit", bound]


# --- bad data: one line naming the file and the column, exit 2, nothing written ----------------------

GOOD = "time [s],torque [N m],angle [arcmin]\n"


def loop_rows(n=200, top=784.0):
    """A plain loop 0 -> +top -> 0 -> -top -> 0 (rows of time, torque, angle)."""
    u = np.linspace(0, 4, n)
    t = top * np.where(u < 1, u, np.where(u < 2, 2 - u, np.where(u < 3, -(u - 2), u - 4)))
    return [(k * 0.01, float(x), float(x / 300.0 + np.sign(x))) for k, x in enumerate(t)]


def as_text(rows, header=GOOD):
    return header + "".join(",".join("" if v is None else str(v) for v in r) + "\n" for r in rows)


@pytest.mark.parametrize("case, text, fragment", [
    ("empty", "", "the file is empty"),
    ("only a header", GOOD, "a header and no data rows"),
    ("no unit", "torque,angle [arcmin]\n1,2\n", "column 'torque': no unit; allowed: a unit in the header"),
    ("unknown unit", "torque [N m],angle [grad]\n1,2\n", "column 'angle [grad]' = 'grad': unknown unit"),
    ("non-numeric", as_text(loop_rows()[:5] + [(0.5, "12,5x", 1.0)]), "column 'torque [N m]' = '12"),
    ("NaN run", as_text(loop_rows()[:20] + [(0.2 + k, 5.0, None) for k in range(5)] + loop_rows()[20:]),
     "column 'angle [arcmin]': rows 22-26: 5 missing or NaN cells"),
    ("single branch", as_text([r for r in loop_rows() if r[0] < 0.5]), "found load+ only (missing unload+, load-"),
    ("torque short of T_R", as_text(loop_rows(top=500.0)), "column 'torque [N m]': load+ reaches 49"),
    ("no torque, no te", "time [s],angle [deg]\n0,1\n", "column 'torque' or 'te': missing"),
    ("no angle", "torque [N m],time [s]\n0,1\n", "column 'angle': missing"),
    ("TE with a gap", "output angle [deg],te [arcsec]\n" + "".join(f"{k * 0.5},{k % 7}\n" for k in range(600)),
     "column 'output angle [deg]': the samples span 299.5 deg"),
    # issue 35: exit 0 with wrong figures before (inf arcmin from a finite cell), a shuffled time accepted
    ("overflow on conversion", "output angle [deg],te [arcsec]\n" + "".join(f"{k * 0.5},{k % 7}\n" for k in range(720))
     + "1e308,1\n", "column 'output angle [deg]' = 1e+308: row 722: inf arcmin once converted"),
    ("time goes back", as_text(loop_rows()[:50] + loop_rows()[60:70] + loop_rows()[50:60] + loop_rows()[70:]),
     "column 'time [s]': row 62: the time goes back (0.69 s, then 0.5 s; 1 such step)"),
    ("unrecognised columns", "phi,M,zeit\n1,2,3\n", "no column of a known quantity (columns found: 'phi', 'M', "
                                                     "'zeit'); allowed: headers such as 'torque [N m]'"),
])
def test_bad_bench_data_is_one_line_naming_file_and_column(tmp_path, case, text, fragment):
    f = tmp_path / "bad.csv"
    f.write_text(text.replace("12,5x", '"12,5x"'))
    js = tmp_path / "out.json"
    args = ("--rated-torque-nm", "784") if case == "torque short of T_R" else ()
    line = one_line_error(run_cli("bench", f, *args, "--json", js), f"error: {f}")
    assert fragment in line, line
    assert not js.exists()


def test_units_from_flags_and_a_missing_file(tmp_path):
    f = tmp_path / "flags.csv"
    f.write_text(as_text(loop_rows(400), header="time,torque,angle\n"))
    p = run_cli("bench", f, "--torque-unit", "N m", "--angle-unit", "arcmin", "--time-unit", "s", "--format", "json")
    assert p.returncode == 0, p.stderr
    assert json.loads(p.stdout)["units"][0]["drift_per"] == "s"
    one_line_error(run_cli("bench", tmp_path / "none.csv"), "no such file")
    one_line_error(run_cli("bench", f, "--torque-unit", "N m", "--angle-unit", "arcmin", "--time-unit", "s",
                           "--rated-torque-nm", "-5"), "error: --rated-torque-nm = -5.0")


def test_calibrate_errors_write_nothing(rv80e, tmp_path):
    rigid = rb.prepare(rv80e.model_copy(update={"elastic": rv80e.elastic.model_copy(
        update={"structure_stiffness_nm_per_arcmin": 1e8})}))
    t, q, a = model_loop_samples(rigid, cycles=1, samples_per_branch=80, noise_arcmin=0.005, seed=1)
    f = write_loop_csv(tmp_path / "rigid.csv", t, q, a)
    out = tmp_path / "cal.toml"
    line = one_line_error(run_cli("calibrate", "rv80e", "--bench", f, "--write-design", out),
                          f"error: {f}: calibration = 'structure_stiffness_nm_per_arcmin': not identifiable")
    assert "stiffer than these loops resolve" in line and not out.exists()
    one_line_error(run_cli("calibrate", "sun2014", "--bench", f, "--write-design", out), "error: elastic")
    assert not out.exists()


# --- issue 35: defects of the tryout, each one line and exit 2 (they hung, or printed a traceback) -------

def test_a_negative_seed_is_refused_as_everywhere(tmp_path):
    """`--seed -1` with --design was a numpy traceback, without it silently accepted."""
    te = write_te_csv(tmp_path / "te.tsv", *te_curve({1: 8.0}, samples=800))
    for args in ((), ("--design", "rv80e", "-n", "100")):
        one_line_error(run_cli("bench", te, *args, "--seed", "-1"), "error: --seed = -1: allowed: an integer >= 0")


@pytest.mark.skipif(not hasattr(__import__("os"), "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize("command", ["bench", "calibrate"])
def test_a_fifo_as_a_bench_file_is_refused_not_waited_on(tmp_path, command):
    import os

    fifo = tmp_path / "loop.csv"
    os.mkfifo(fifo)
    args = ("bench", fifo) if command == "bench" else ("calibrate", "rv80e", "--bench", fifo)
    out = call_beside_fifo(fifo, lambda: run_cli(*args))
    one_line_error(out["value"], f"error: {fifo}: a FIFO (named pipe), not a regular file")


def test_a_bench_file_name_too_long_says_so(tmp_path):
    f = tmp_path / ("unit" * 75 + ".csv")
    one_line_error(run_cli("bench", f), "file name too long (304 bytes); allowed: names of at most")
