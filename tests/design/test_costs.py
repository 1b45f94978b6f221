"""The cost model as data: default part groups, the reciprocal-power formula, the design's
[costs] table (merging, validation with one clear line)."""

from __future__ import annotations

import math

import pytest

from helpers import example_with
from rvbacklash.design.costs import (NOMINAL_FACTORS, Costs, default_cost_data, part_groups,
                                     reciprocal_power_cost)
from rvbacklash.design.loading import design_from_toml, example_text
from rvbacklash.design.schema import OPTIONAL_FACTORS
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG, factor_by_key


def _with_costs(body: str):
    return design_from_toml(example_text("rv80e") + "\n" + body + "\n")


def test_reciprocal_power_cost_hand_values():
    # C = A + B (t_ref / t)^k: hand-worked
    assert reciprocal_power_cost(10.0, 10.0, 2.0, 3.0, 1.0) == pytest.approx(5.0)  # at t_ref: A + B
    assert reciprocal_power_cost(5.0, 10.0, 2.0, 3.0, 1.0) == pytest.approx(2.0 + 3.0 * 2.0)  # reciprocal
    assert reciprocal_power_cost(5.0, 10.0, 2.0, 3.0, 2.0) == pytest.approx(2.0 + 3.0 * 4.0)  # Spotts, k = 2
    assert reciprocal_power_cost(20.0, 10.0, 2.0, 3.0, 0.5) == pytest.approx(2.0 + 3.0 / math.sqrt(2.0))
    # tighter is dearer, and the cost tends to A for a loose tolerance
    assert reciprocal_power_cost(1.0, 10.0, 2.0, 3.0, 1.0) > reciprocal_power_cost(2.0, 10.0, 2.0, 3.0, 1.0)
    assert reciprocal_power_cost(1e9, 10.0, 2.0, 3.0, 1.0) == pytest.approx(2.0)
    with pytest.raises(ValueError):
        reciprocal_power_cost(0.0, 10.0, 2.0, 3.0, 1.0)


def test_default_groups_cover_every_graded_factor_once():
    groups = part_groups()
    keys = [k for g in groups for k in g.factors]
    assert len(keys) == len(set(keys))
    assert set(keys) == {f.key for f in CATALOG} - NOMINAL_FACTORS
    assert NOMINAL_FACTORS == OPTIONAL_FACTORS  # the designed modifications have no grade
    for g in groups:
        assert {factor_by_key(k).stage.label for k in g.factors} == {g.grade_table}
        assert g.tolerance_factor in g.factors
        assert g.origin == "default" and g.cost_by_grade is None
        assert g.candidate_grades == tuple(range(g.grade_min, g.grade_max + 1))
    # the documented normalisation: the default groups cost 100 together at the reference grade
    assert sum(g.fixed_cost + g.precision_cost for g in groups) == pytest.approx(100.0)
    assert default_cost_data()["reference_grade"] == 5


def test_costs_table_changes_a_group_and_adds_one():
    d = _with_costs("[costs]\nunit = \"EUR\"\n[costs.groups.pins]\nprecision_cost = 9.0\nexponent = 2.0\n"
                    "[costs.groups.pin_fit]\nfactors = [\"pin_hole_clearance\"]\nfixed_cost = 1.0\n"
                    "precision_cost = 2.0\n")
    groups = {g.name: g for g in part_groups(d.costs)}
    # pin_hole_clearance left the default group "pins" for the new group
    assert groups["pins"].factors == ("pin_radius",)
    assert groups["pins"].precision_cost == 9.0 and groups["pins"].exponent == 2.0
    assert groups["pins"].fixed_cost == 4.0  # kept from the default
    assert groups["pins"].origin == "default, changed by [costs]"
    assert groups["pin_fit"].factors == ("pin_hole_clearance",) and groups["pin_fit"].grade_table == "cycloid"
    assert groups["pin_fit"].origin == "[costs]"
    assert d.costs.unit == "EUR"


def test_cost_by_grade_and_only_listed_groups():
    d = _with_costs("[costs]\nonly_listed_groups = true\n[costs.groups.cycloid_discs]\n"
                    "cost_by_grade = { 6 = 17.0, 4 = 31.0, 5 = 22.0 }\n")
    (g,) = part_groups(d.costs)
    assert g.name == "cycloid_discs"
    assert g.cost_by_grade == ((4, 31.0), (5, 22.0), (6, 17.0))
    assert g.candidate_grades == (4, 5, 6)
    assert g.tabulated_cost(5) == 22.0 and g.tabulated_cost(7) is None


def test_every_factor_its_own_group():
    body = "[costs]\nonly_listed_groups = true\n" + "".join(
        f"[costs.groups.{k}]\nfactors = [\"{k}\"]\nfixed_cost = 1.0\nprecision_cost = 1.0\n"
        for k in ("disc_cumulative_pitch", "pin_radius", "crank_bearing_clearance"))
    groups = part_groups(_with_costs(body).costs)
    assert [g.factors for g in groups] == [("disc_cumulative_pitch",), ("pin_radius",), ("crank_bearing_clearance",)]


@pytest.mark.parametrize("body, fragment", [
    ("[costs.groups.pins]\nfactors = [\"foo\"]", "unknown factor 'foo'"),
    ("[costs.groups.pins]\nfactors = [\"pin_radius\", \"crank_eccentricity\"]", "one stage"),
    ("[costs.groups.pins]\nfactors = [\"equidistance_modification\"]", "nominal value"),
    ("[costs.groups.pins]\nexponent = -1.0", "> 0"),
    ("[costs.groups.pins]\ncolour = 1", "allowed fields: description"),
    ("[costs.groups.pins]\ncost_by_grade = { x = 1.0 }", "grades 0 to 12"),
    ("[costs.groups.pins]\ncost_by_grade = { 4 = -1.0 }", "cost >= 0"),
    ("[costs.groups.pins]\ngrade_min = 7\ngrade_max = 4", "grade_min = 7 > grade_max = 4"),
    ("[costs.groups.pins]\ntolerance_factor = \"disc_runout\"", "one of the group's factors"),
    ("[costs.groups.new_group]\nfixed_cost = 1.0", "needs factors"),
    ("[costs.groups.new_group]\nfactors = [\"pin_radius\"]", "no cost"),
    ("[costs.groups.a]\nfactors = [\"pin_radius\"]\nfixed_cost = 1.0\nprecision_cost = 1.0\n"
     "[costs.groups.b]\nfactors = [\"pin_radius\"]\nfixed_cost = 1.0\nprecision_cost = 1.0", "in groups 'a' and 'b'"),
    ("[costs.groups.Bad-Name]\nfactors = [\"pin_radius\"]\nfixed_cost = 1.0\nprecision_cost = 1.0", "lower-case"),
    ("[costs]\ncolour = 1", "allowed fields here: unit, only_listed_groups, groups"),
])
def test_costs_table_errors_name_the_field(body, fragment):
    with pytest.raises(InputError) as e:
        _with_costs(body)
    assert str(e.value).startswith("costs"), str(e.value)
    assert fragment in str(e.value)
    assert "\n" not in str(e.value)


def test_design_without_costs_is_unchanged(rv80e):
    assert rv80e.costs is None
    assert example_with("rv80e").costs is None
    assert Costs().groups == {}
