"""Allocation of grades and classes (issue 39, continued): each option's cost is its terms' sum
(closed form from [costs.selection]), random assembly's option is the plain allocation, the chosen
option is the cheapest feasible one; the CLI's --select-classes and its errors."""

import json

import pytest

from helpers import one_line_error, run_cli
from rvbacklash.analysis.allocation import allocate_monte_carlo
from rvbacklash.analysis.allocation.classes import allocate_grades_and_classes, menu_selection
from rvbacklash.design.costs import selection_prices
from rvbacklash.design.loading import design_from_dict
from rvbacklash.problem import prepare

KW = dict(model="contact", spec_arcmin=1.0, yield_target=0.9, samples=2000, seed=1)


@pytest.fixture(scope="module")
def priced(rv80e):
    d = rv80e.model_dump(mode="json", exclude_none=True)
    d["costs"] = {"selection": {"measuring_cost_per_unit": 2.0, "class_cost": 0.75, "surplus_cost_share": 0.5}}
    problem = prepare(design_from_dict(d))
    return problem, allocate_grades_and_classes(problem, menu=((1, 1), (3, 1), (5, 3)), **KW)


def test_each_option_costs_the_sum_of_its_terms(priced):
    problem, r = priced
    prices = selection_prices(problem.design.costs)
    assert (prices.measuring_cost_per_unit, prices.class_cost, prices.surplus_cost_share) == (2.0, 0.75, 0.5)
    assert (r.measuring_cost_per_unit, r.class_cost, r.surplus_cost_share) == (2.0, 0.75, 0.5)
    fixed = {(1, 1): 0.0, (3, 1): 2.0 + 0.75 * 2, (5, 3): 2.0 + 0.75 * 6}
    for o in r.options:
        assert o.selection_cost == pytest.approx(fixed[(o.pin_classes, o.roller_classes)])
        if o.feasible:
            assert o.total_cost == pytest.approx(o.grades_cost + o.selection_cost + o.surplus_cost)
            assert o.pin_sets_per_unit >= 1.0 and o.roller_sets_per_unit >= 1.0
            assert (o.surplus_cost == 0.0) == (o.pin_classes == 1 and o.roller_classes == 1)
    feasible = [o for o in r.options if o.feasible]
    best = min(feasible, key=lambda o: o.total_cost)
    assert best.chosen and sum(o.chosen for o in r.options) == 1 and r.chosen == best.selection
    assert r.allocation.cost == pytest.approx(best.grades_cost)


def test_random_option_is_the_plain_allocation(priced):
    problem, r = priced
    plain = allocate_monte_carlo(problem, **KW)
    o = r.options[0]
    assert o.selection == "random assembly" and o.grades == plain.grades and o.grades_cost == plain.cost
    assert r.random_allocation.grades == plain.grades


def test_menu_selection_and_refusals(rv80e_problem):
    assert menu_selection(1, 1) is None
    s = menu_selection(5, 3)
    assert (s.pins.count, s.rollers.count, s.pins.width_um) == (5, 3, 2.0)
    from rvbacklash.errors import InputError

    with pytest.raises(InputError, match="contact, elastic, transmission"):
        allocate_grades_and_classes(rv80e_problem, model="linear", spec_arcmin=1.0, yield_target=0.9)


def test_cli_select_classes(tmp_path):
    p = run_cli("allocate", "rv80e", "--model", "contact", "--spec-arcmin", "1", "--yield", "0.9", "-n", "2000", "--seed", "1",
                "--select-classes", "1:1,5:3", "--json", tmp_path / "a.json", "--write-design", tmp_path / "d.toml")
    assert p.returncode == 0, p.stderr
    d = json.loads((tmp_path / "a.json").read_text())
    assert [o["selection"] for o in d["options"]] == ["random assembly", "pins=5x2um,rollers=3x2um"]
    assert "grades and classes" in p.stdout
    text = (tmp_path / "d.toml").read_text()
    assert ("[selection]" in text) == (d["chosen"] != "random assembly")
    one_line_error(run_cli("allocate", "rv80e", "--model", "contact", "--spec-arcmin", "1", "--yield", "0.9",
                           "--select-classes", "5x3"), "PINS:ROLLERS")
    one_line_error(run_cli("allocate", "rv80e", "--spec-arcmin", "1", "--yield", "0.9", "--select-classes",
                           "default"), "contact, elastic or transmission")


def test_json_validates_against_the_allocate_schema(priced):
    import jsonschema

    from rvbacklash.report.files import render_json
    from rvbacklash.report.schemas import output_schema

    data = json.loads(render_json(priced[1].to_dict()))
    schema = output_schema("allocate")
    jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
    data["options"][0]["moved"] = 1
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(data, schema, cls=jsonschema.Draft202012Validator)
