"""``service-life --sensitivity`` (issue 38): the Sobol indices of the accuracy life on the command line,
the same numbers as ``api.accuracy_life_sensitivity`` for the same hours, spec and seed (table, JSON valid
against the schema); bad input one line naming the flag."""

import json

import jsonschema
import pytest

import rvbacklash.api as api
from helpers import one_line_error, run_cli
from rvbacklash.report.files import render_json


def test_service_life_sensitivity_is_the_apis_accuracy_life_sobol(tmp_path):
    out = tmp_path / "s.json"
    p = run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,300", "-n", "0", "--seed", "3",
                "--spec-lost-motion-arcmin", "1.4", "--sensitivity", "--sensitivity-samples", "64", "--json", out)
    assert p.returncode == 0, p.stderr
    assert "Which tolerance buys hours" in p.stdout and "censored at 300 h" in p.stdout
    assert "equidistance_modification_error" in p.stdout
    data = json.loads(out.read_text())
    mine = dict(data["accuracy_life_sensitivity"])
    theirs = json.loads(render_json(api.accuracy_life_sensitivity("rv80e", duty_cycle="robot-joint", hours=300,
                                                                  spec_lost_motion_arcmin=1.4, samples=64,
                                                                  seed=3).to_dict()))
    for key in ("elapsed_s", "schema_version", "rvbacklash_version"):
        mine.pop(key, None), theirs.pop(key, None)
    assert mine == theirs  # the same units, the same trajectory, the same estimators: the same numbers
    assert mine["output"] == "accuracy_life" and mine["samples"] == 64 and mine["seed"] == 3
    assert 0.0 < mine["mean"] < 300.0  # the life censored at the last hour, some units out at 0 h
    top = {g["input"] for g in mine["groups"][:5]}  # the cycloid stage's factors buy the hours
    assert top <= {"equidistance_modification_error", "moving_distance_modification_error", "pin_circle_radius",
                   "pin_cumulative_pitch", "disc_runout", "disc_cumulative_pitch", "pin_hole_clearance",
                   "crank_bearing_clearance", "pin_radius"}, top
    schema = json.loads(run_cli("schema", "--output", "service-life").stdout)
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
    without = json.loads(run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "--hours", "0,300", "-n", "0",
                                 "--json", "-", "-q").stdout)
    assert without["accuracy_life_sensitivity"] is None


@pytest.mark.parametrize("args, flag", [
    (("--sensitivity", "--sensitivity-samples", "100"), "--sensitivity-samples"),
    (("--sensitivity", "--sensitivity-samples", "x"), "--sensitivity-samples"),
    (("--sensitivity-samples", "64",), "--sensitivity-samples"),
    (("--sensitivity", "--hours", "0"), "--hours"),
    (("--sensitivity", "--unit-wear", "nominal"), "--unit-wear"),
])
def test_service_life_sensitivity_bad_input_is_one_line(args, flag):
    one_line_error(run_cli("service-life", "rv80e", "--duty-cycle", "robot-joint", "-n", "0", *args), f"error: {flag}")
