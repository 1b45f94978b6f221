"""``rvbacklash allocate --spec-accuracy-life-h`` (issue 38): the cheapest grades that keep a share of the
units' lost motion within the spec for some hours of a duty cycle, each unit with its own wear as
``service-life`` reads it. The chosen grades, re-simulated by ``service-life`` with the same seed and
units, keep the target (bit for bit the allocation's yield); a cheaper neighbour does not. Bad input:
one line naming the flag."""

import json

import jsonschema
import pytest

import rvbacklash.api as api
from helpers import one_line_error, run_cli
from rvbacklash.analysis.grade_choices import grade_choices
from rvbacklash.design.loading import example_text

FREE = ("pins", "crank_bearings")  # the groups the search may move (the others held at grade 5: a small search)
RUN = ("--duty-cycle", "robot-joint", "-n", "200", "--seed", "1", "--angles", "6", "--step-fraction", "0.3")
HOURS, SPEC, TARGET = 1000.0, 2.0, 0.8


@pytest.fixture(scope="module")
def design(tmp_path_factory):
    text = example_text("rv80e") + "\n[costs]\n"
    for g in ("first_stage_gears", "first_stage_mounting", "cycloid_discs", "disc_profile", "pin_housing",
              "crank_eccentrics"):
        text += f"[costs.groups.{g}]\ngrade_min = 5\ngrade_max = 5\n"
    for g in FREE:
        text += f"[costs.groups.{g}]\ngrade_min = 3\ngrade_max = 8\n"
    path = tmp_path_factory.mktemp("life") / "rv80e-costs.toml"
    path.write_text(text)
    return path


def _accuracy_life_yield(design, **kw) -> dict:
    """``service-life`` of a design to [0, HOURS] with the allocation's run: the accuracy-life yield."""
    r = api.service_life(design, duty_cycle="robot-joint", hours=[0, HOURS], spec_lost_motion_arcmin=SPEC,
                         samples=200, seed=1, angles=6, step_fraction=0.3, **kw)
    return r.production.accuracy_life_yield.to_dict()


def test_allocate_on_the_accuracy_life_keeps_the_target_and_a_cheaper_neighbour_does_not(design, tmp_path):
    best, out, svg = tmp_path / "best.toml", tmp_path / "a.json", tmp_path / "front.svg"
    p = run_cli("allocate", design, "--spec-accuracy-life-h", HOURS, "--spec-lost-motion-arcmin", SPEC, "--yield",
                TARGET, *RUN, "--write-design", best, "--json", out, "--plot", svg)
    assert p.returncode == 0, p.stderr
    assert "<svg" in svg.read_text()[:2000]
    assert "accuracy life >= 1000 h of robot-joint.csv at lost motion <= 2 arcmin" in p.stdout
    data = json.loads(out.read_text())
    assert data["model"] == "elastic" and data["output"] == "accuracy_life"
    assert data["spec_accuracy_life_h"] == HOURS and data["spec_arcmin"] == SPEC
    assert data["duty_cycle"].endswith("robot-joint.csv")
    y = data["yield"]
    assert y["ci95_low"] >= TARGET and data["verification"]["ci95_low"] >= TARGET
    chosen = data["grades"]
    assert any(chosen[g] < 5 for g in FREE)  # grade 5 everywhere (the design as given) does not keep the target
    assert data["yield_before"]["ci95_low"] < TARGET

    # the written design, re-simulated by service-life with the same seed and units: the same yield, bit for bit
    s = run_cli("service-life", best, "--hours", f"0,{HOURS:g}", "--spec-lost-motion-arcmin", SPEC, *RUN,
                "--json", "-", "-q")
    assert s.returncode == 0, s.stderr
    again = json.loads(s.stdout)["production"]["accuracy_life_yield"]
    assert (again["count"], again["total"]) == (y["count"], y["total"]) and again["ci95_low"] >= TARGET
    assert "Re-run: rvbacklash service-life FILE --duty-cycle robot-joint --hours 0,1000" in best.read_text()

    # every cheaper neighbour (one free group one grade coarser) misses the target when re-simulated
    ch = grade_choices(api.prepare(design))
    grades = tuple(chosen[c.name] for c in ch.groups)
    cheaper = [tuple(g + 1 if c.name == name else g for c, g in zip(ch.groups, grades))
               for name in FREE for c in ch.groups if c.name == name and chosen[name] < c.grades[-1]]
    assert cheaper and all(ch.cost(n) < ch.cost(grades) for n in cheaper)
    for neighbour in cheaper:
        assert _accuracy_life_yield(ch.design(neighbour))["ci95_low"] < TARGET, neighbour

    # its JSON is the allocate output's schema, on stdout as on a file
    schema = json.loads(run_cli("schema", "--output", "allocate").stdout)
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)


@pytest.mark.parametrize("args, flag", [
    (("--spec-accuracy-life-h", "1000", "--yield", "0.9"), "--duty-cycle"),
    (("--spec-accuracy-life-h", "-5", "--duty-cycle", "robot-joint", "--yield", "0.9"), "--spec-accuracy-life-h"),
    (("--spec-accuracy-life-h", "1000", "--duty-cycle", "robot-joint", "--yield", "0.9", "--model", "contact"),
     "--model"),
    (("--spec-accuracy-life-h", "1000", "--duty-cycle", "robot-joint", "--yield", "0.9",
      "--spec-rigidity-nm-per-arcmin", "200"), "--spec-rigidity-nm-per-arcmin"),
    (("--spec-accuracy-life-h", "1000", "--duty-cycle", "robot-joint", "--yield", "0.9", "--spec-arcmin", "1",
      "--spec-lost-motion-arcmin", "2"), "--spec-lost-motion-arcmin"),
    (("--spec-accuracy-life-h", "1000", "--duty-cycle", "robot-joint", "--yield", "0.9", "-n", "50"), "--samples"),
    (("--spec-accuracy-life-h", "1000", "--duty-cycle", "robot-joint", "--yield", "0.9", "--unit-wear", "x"),
     "--unit-wear"),
    (("--spec-arcmin", "2", "--yield", "0.9", "--duty-cycle", "robot-joint"), "--duty-cycle"),
    (("--yield", "0.9",), "--spec-arcmin"),
])
def test_accuracy_life_allocation_bad_input_is_one_line(args, flag):
    one_line_error(run_cli("allocate", "rv80e", *args), f"error: {flag}")
