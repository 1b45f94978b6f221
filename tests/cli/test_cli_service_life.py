"""``rvbacklash service-life``: the datasheet over time printed, its JSON (valid against its schema),
CSV and SVG, the example duty cycle, one-line errors, Ctrl-C keeping the steps done."""

import json
import threading
from pathlib import Path

import jsonschema

import rvbacklash.examples as examples

from helpers import interrupt_on_progress, one_line_error, run_cli


def test_service_life_table_json_csv_plot(tmp_path):
    out, csv_out, svg = tmp_path / "s.json", tmp_path / "s.csv", tmp_path / "s.svg"
    p = run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,1000,6000", "-n", "200",
                "--spec-lost-motion-arcmin", "1.5", "--json", out, "--csv", csv_out, "--plot", svg)
    assert p.returncode == 0, p.stderr
    for text in ("Nominal unit", "lost motion [arcmin]", "cycloid flanks", "pin seats", "crank needle bearings",
                 "Production run: 200 units", "accuracy life", "6,000", "transmission error",
                 "its own wear"):
        assert text in p.stdout, text
    data = json.loads(out.read_text())
    assert [pt["hours"] for pt in data["points"]] == [0.0, 1000.0, 6000.0]
    lm = [pt["lost_motion_arcmin"] for pt in data["points"]]
    assert lm[0] < lm[1] < lm[2]  # the lost motion grows with wear
    prod = data["production"]
    assert prod["units"] == 200 and prod["yield_at_hours"][0]["fraction"] >= prod["yield_at_hours"][2]["fraction"]
    assert prod["unit_wear"] == "own"
    assert [t["hours"] for t in data["transmission_error"]] == [0.0, 1000.0, 6000.0]
    s = run_cli("schema", "--output", "service-life")
    assert s.returncode == 0, s.stderr
    schema = json.loads(s.stdout)
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
    rows = csv_out.read_text().splitlines()
    assert rows[0].startswith("hours,lost_motion_arcmin") and "yield" in rows[0] and len(rows) == 4
    assert "te_peak_to_peak_ccw_arcsec" in rows[0]
    assert "<svg" in svg.read_text()[:2000]


def test_service_life_errors_name_the_flag(tmp_path):
    one_line_error(run_cli("service-life", "rv80e", "--duty-cycle", tmp_path / "none.csv"), "error: --duty-cycle")
    one_line_error(run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,x"),
                   "error: --hours")
    one_line_error(run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "-1"),
                   "error: --hours")
    one_line_error(run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "--step-fraction", "0"),
                   "error: --step-fraction")
    one_line_error(run_cli("service-life", "sun2014", "--duty-cycle", "robot-joint"), "error: elastic")
    design = tmp_path / "d.toml"
    design.write_text(Path(examples.__file__).with_name("rv80e.toml").read_text()
                      + "\n[wear]\npin_rolling_fraction = 1.5\n")
    line = one_line_error(run_cli("service-life", design, "--duty-cycle", "robot-joint"), "wear.pin_rolling_fraction")
    assert "1.5" in line


def test_a_stop_keeps_the_steps_done_marked_partial():
    """A stop request (Ctrl-C's, or the workbench's) ends the stepping after the step under way; the
    result is marked partial."""
    import rvbacklash.api as api
    from rvbacklash.interrupt import stop_on

    event = threading.Event()
    event.set()
    box = {}

    def run():
        with stop_on(event):
            box["r"] = api.service_life("rv80e", duty_cycle="robot-joint", hours=[0, 6000], samples=0)

    t = threading.Thread(target=run)
    t.start()
    t.join()
    r = box["r"]
    assert r.partial and r.steps == 0 and r.trajectory[0].hours == 0.0
    assert r.to_dict()["partial"] is True


def test_ctrl_c_in_service_life_exits_130_with_the_steps_done(tmp_path):
    """Ctrl-C once the stepping has finished steps: exit 130, the JSON written and marked partial."""
    out = tmp_path / "s.json"
    code, tty = interrupt_on_progress(["service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,20000",
                                       "-n", "0", "--step-fraction", "0.02", "--json", out], tmp_path,
                                      progress=rb"service life\S*\s.*?\b[1-9][0-9]*/1000")
    assert code == 130 and "Traceback" not in tty, tty[-2000:]
    data = json.loads(out.read_text())
    assert data["partial"] is True and 0 < data["steps"] and data["trajectory"][-1]["hours"] < 20000


def test_calibrate_reads_a_units_loops_over_its_service_and_recovers_k(tmp_path):
    """Done-when (issue 38 item 4, through the CLI): one unit's loops at 0 h and 1000 h of the robot-joint
    cycle, made by the model with the wear coefficients 1.7 times the design's and reading noise
    (0.01 arcmin a sample, seeded), are read by the bench reader; `calibrate --duty-cycle --hours` fits
    the scale, its 95 % interval holds 1.7, and --write-design writes the design with the scaled
    coefficients."""
    import numpy as np

    import rvbacklash.api as api
    from rvbacklash.analysis.bench_synthetic import model_loop_samples, write_loop_csv
    from rvbacklash.analysis.service_life import nominal_trajectory, wear_geometry
    from rvbacklash.analysis.service_life.calibration import scaled_inputs
    from rvbacklash.analysis.service_life.worn import worn_model, worn_unit
    from rvbacklash.design.duty_cycle import read_duty_cycle
    from rvbacklash.models.elastic import PreparedUnit, elastic_model, nominal_realization, other_stages_nominal

    problem = api.prepare("rv80e")
    model = elastic_model(problem)
    cycle = read_duty_cycle(api.example_duty_cycle("robot-joint"))
    tr = nominal_trajectory(problem, cycle, [0, 1000], model=model,
                            wear=scaled_inputs(problem.design.wear, 1.7))
    geo = wear_geometry(problem, model)
    inv, clr = other_stages_nominal(problem)
    files = []
    for hours, state in zip((0, 1000), (tr.wear[0], tr.wear[-1])):
        pu = PreparedUnit(worn_model(problem, model, state),
                          worn_unit(problem, nominal_realization(problem), inv, clr, state, geo))
        t, q, a = model_loop_samples(problem, cycles=1, samples_per_branch=150, noise_arcmin=0.01, seed=hours + 1,
                                     prepared=pu)
        files.append(write_loop_csv(tmp_path / f"unit 7 at {hours} h.csv", t, q, a))
    js, toml = tmp_path / "w.json", tmp_path / "calibrated.toml"
    p = run_cli("calibrate", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,1000", "--bench", files[0],
                "--bench", files[1], "--json", js, "--write-design", toml)
    assert p.returncode == 0, p.stderr
    assert "wear coefficients x" in p.stdout
    data = json.loads(js.read_text())
    assert data["scale_ci95_low"] < 1.7 < data["scale_ci95_high"], data
    assert data["scale_ci95_high"] / data["scale_ci95_low"] < 1.6
    assert data["sources"] == [str(f) for f in files]
    assert data["measured_hours"] == [1000.0]
    s = run_cli("schema", "--output", "calibrate")
    jsonschema.validate(data, json.loads(s.stdout), cls=jsonschema.Draft202012Validator)
    calibrated = api.load_design(toml) if hasattr(api, "load_design") else None
    text = toml.read_text()
    assert "calibrate --duty-cycle robot-joint" in text and str(files[0]) in text
    if calibrated is not None:
        assert calibrated.wear.flank_wear_coefficient == np.float64(problem.design.wear.flank_wear_coefficient
                                                                     * data["scale"])
    # one line, nothing written: hours that do not match the loops, or --hours without --duty-cycle
    one_line_error(run_cli("calibrate", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0", "--bench", files[0],
                           "--bench", files[1], "--write-design", tmp_path / "x.toml"), "error: --hours")
    one_line_error(run_cli("calibrate", "rv80e", "--hours", "0,1000", "--bench", files[0], "--bench", files[1]),
                   "error: --duty-cycle")
    assert not (tmp_path / "x.toml").exists()
