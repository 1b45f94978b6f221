"""Designs written in grades, the precedence of tolerance sources, and the paper's Fig. 4
scenarios as tests of its conclusions."""

import json

import pytest

from conftest import run_cli
from rvbacklash import analyze, load_design
from rvbacklash.analysis.scenarios import apply_overrides, compare, paper_scenarios, parse_scenario
from rvbacklash.design.derived import resolve_zones
from rvbacklash.design.loading import design_from_dict
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.standards.iso1328 import iso1328_tolerances


@pytest.fixture(scope="module")
def rv80e():
    return load_design("rv80e")


def zone(design, key):
    return resolve_zones(design)[FACTOR_KEYS.index(key)]


def test_a_design_entirely_in_grades(rv80e):
    zones = resolve_zones(rv80e)
    origins = [z.origin for z in zones]
    assert sum(o == "explicit" for o in origins) == 1  # bearing eccentricity, supplier data
    assert all("ISO" in o or "assumption" in o or o.startswith(("explicit", "second_stage")) for o in origins)
    # stage 1 single pitch: RSS of centre gear (d 17.5) and planet (d 66.5), grade 5: hypot(4.7, 5.5)
    z = zone(rv80e, "single_pitch")
    assert z.upper_um == pytest.approx((4.7 ** 2 + 5.5 ** 2) ** 0.5) and "ISO 1328-1:1995" in z.origin
    # cycloid stage: labelled an assumption
    assert "assumption" in zone(rv80e, "disc_cumulative_pitch").origin


def test_precedence_explicit_then_factor_grade_then_stage_grade(rv80e):
    data = rv80e.model_dump(exclude_none=True)
    data["grades"]["factors"] = {"single_pitch": 8, "tooth_alignment": 8}
    data["factors"]["tooth_alignment"] = {"plus_minus_um": 1.0}
    d = design_from_dict(data)
    planet8 = iso1328_tolerances("1995", 1.75, 66.5, 15.0, 8)
    sun8 = iso1328_tolerances("1995", 1.75, 17.5, 15.0, 8)
    assert zone(d, "single_pitch").upper_um == pytest.approx((planet8.fpt_um ** 2 + sun8.fpt_um ** 2) ** 0.5)
    assert zone(d, "tooth_alignment").upper_um == 1.0 and zone(d, "tooth_alignment").origin == "explicit"
    assert zone(d, "tooth_profile").upper_um == zone(rv80e, "tooth_profile").upper_um  # stage grade 5


def test_edition_2013_changes_the_gear_zones(rv80e):
    d = apply_overrides(rv80e, {"edition": "2013"})
    assert "ISO 1328-1:2013" in zone(d, "single_pitch").origin
    assert zone(d, "single_pitch").upper_um != zone(rv80e, "single_pitch").upper_um


@pytest.mark.parametrize("edit,fragment", [
    (lambda d: d["first_stage"].pop("face_width_mm"), "first_stage.face_width_mm"),
    (lambda d: d["grades"].update(involute=13), "grades.involute"),
    (lambda d: d["grades"].update(edition="2013", cycloid=12), "allowed grades 1 to 11"),
    (lambda d: d["grades"].update(factors={"pin_wheel": 5}), "unknown factor 'pin_wheel'"),
    (lambda d: d.pop("grades"), "no tolerance"),
])
def test_bad_grade_input(rv80e, edit, fragment):
    data = rv80e.model_dump(exclude_none=True)
    edit(data)
    with pytest.raises(InputError) as e:
        analyze(design_from_dict(data))
    assert fragment in str(e.value)


# --- the paper's scenarios (Sun et al. 2014, section 5 and Fig. 4) ----------------------------

@pytest.fixture(scope="module")
def paper(rv80e):
    return {r.name[0]: r for r in compare(rv80e, paper_scenarios(rv80e), None, None, method="exact")}


def test_b_stage_one_grade_changes_the_total_little(paper):
    """Fig. 4 (b): 'if the precision in the first stage is 5-grade ... total backlash is improved little'."""
    a, b = paper["a"].result.stats, paper["b"].result.stats
    assert abs(b["std_arcmin"] - a["std_arcmin"]) / a["std_arcmin"] < 0.02
    assert abs(b["mean_arcmin"] - a["mean_arcmin"]) / a["mean_arcmin"] < 0.02


def test_c_stage_two_grade_changes_it_much_more(paper):
    """Fig. 4 (c): 'the backlash change heavily ... the second stage plays an important role'."""
    a, b, c = (paper[k].result.stats for k in "abc")
    assert (a["std_arcmin"] - c["std_arcmin"]) > 10 * (a["std_arcmin"] - b["std_arcmin"])
    assert c["std_arcmin"] < 0.8 * a["std_arcmin"]


def test_d_largest_reduction_per_tightened_tolerance(paper):
    """Fig. 4 (d): grade 5 on the most influential factors 'reduced greatly': per factor
    tightened, (d) reduces the 99.865 % quantile more than (b) or (c)."""
    q = {k: paper[k].result.stats["quantiles"]["0.99865"]["value"] for k in "abcd"}
    per = {k: (q["a"] - q[k]) / paper[k].tightened for k in "bcd"}
    assert paper["d"].tightened == 3
    assert per["d"] > per["c"] > per["b"] > 0


def test_scenario_parsing():
    assert parse_scenario("x: involute=5, pin_radius=4") == ("x", {"involute": 5, "pin_radius": 4})
    for bad, fragment in [("noname", "NAME:"), ("x:wheel=5", "unknown key 'wheel'"), ("x:involute=five", "integer"),
                          ("x:involute", "not key=value")]:
        with pytest.raises(InputError, match=fragment):
            parse_scenario(bad)


def test_paper_set_needs_grades(sun2014):
    with pytest.raises(InputError, match="no factor takes its tolerance from a grade"):
        paper_scenarios(sun2014)


# --- command line -------------------------------------------------------------------------

def test_compare_cli_json_and_plot(tmp_path):
    out, svg = tmp_path / "c.json", tmp_path / "c.svg"
    p = run_cli("compare", "rv80e", "--paper", "--scenario", "mine:all=4", "--samples", "65536", "--seed", "3",
                "--spec-arcmin", "3", "--json", out, "--plot", svg)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    assert [s["name"][0] for s in d["scenarios"]] == ["a", "b", "c", "d", "m"]
    for s in d["scenarios"]:
        assert {"name", "mean_arcmin", "sigma_arcmin", "q99865_arcmin", "yield"} <= set(s)
        assert set(s["yield"]) >= {"fraction", "ci95"}
    assert svg.read_text().lstrip().startswith("<?xml") and "<svg" in svg.read_text()


@pytest.mark.parametrize("args,fragment", [
    (["compare", "rv80e", "--scenario", "x:pin_wheel=5"], "unknown key 'pin_wheel'"),
    (["compare", "rv80e", "--scenario", "x:involute=14"], "grades.involute"),
    (["compare", "rv80e"], "at least one --scenario"),
    (["tolerance", "iso1328", "--module", "1.75", "--diameter", "66.5", "--width", "15", "--grade", "13"],
     "grades 0 to 12"),
    (["tolerance", "iso1328", "--edition", "2001", "--module", "1.75", "--diameter", "66.5", "--width", "15",
      "--grade", "5"], "allowed: 1995, 2013"),
    (["tolerance", "iso1328", "--module", "1.75", "--diameter", "12000", "--width", "15", "--grade", "5"],
     "5 <= d <= 10000"),
    (["tolerance", "iso286", "--size", "800", "--grade", "IT6"], "0 < size <= 500"),
    (["tolerance", "iso286", "--size", "8", "--grade", "IT13"], "IT1 to IT12"),
])
def test_bad_standards_input(args, fragment, tmp_path):
    p = run_cli(*args, "--json") if args[0] == "tolerance" else run_cli(*args, "--json", tmp_path / "o.json")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert fragment in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert not (tmp_path / "o.json").exists()


def test_tolerance_cli_json():
    p = run_cli("tolerance", "iso1328", "--edition", "1995", "--module", "1.75", "--diameter", "66.5", "--width",
                "15", "--grade", "5", "--json")
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    # ISO 1328-1:1995 table rows for 50 < d <= 125, 0.5 <= m <= 2, grade 5 (data/iso1328-1_1995.csv)
    assert (d["fpt_um"], d["Fp_um"], d["Falpha_um"], d["ffalpha_um"], d["Fr_um"]) == (5.5, 18, 6.0, 4.5, 15)
    p = run_cli("tolerance", "iso286", "--size", "8", "--grade", "IT6", "--fit", "H7/g6", "--json")
    d = json.loads(p.stdout)
    assert d["IT_um"] == 9 and d["fit"]["clearance_min_um"] == 5 and d["fit"]["clearance_max_um"] == 29
