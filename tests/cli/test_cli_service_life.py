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
                 "Production run: 200 units", "accuracy life", "6,000"):
        assert text in p.stdout, text
    data = json.loads(out.read_text())
    assert [pt["hours"] for pt in data["points"]] == [0.0, 1000.0, 6000.0]
    lm = [pt["lost_motion_arcmin"] for pt in data["points"]]
    assert lm[0] < lm[1] < lm[2]  # the lost motion grows with wear
    prod = data["production"]
    assert prod["units"] == 200 and prod["yield_at_hours"][0]["fraction"] >= prod["yield_at_hours"][2]["fraction"]
    s = run_cli("schema", "--output", "service-life")
    assert s.returncode == 0, s.stderr
    schema = json.loads(s.stdout)
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
    rows = csv_out.read_text().splitlines()
    assert rows[0].startswith("hours,lost_motion_arcmin") and "yield" in rows[0] and len(rows) == 4
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
