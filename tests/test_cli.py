"""End-to-end runs of the command line, including every class of bad input."""

import json

import pytest

from conftest import run_cli


def test_analyze_sun2014_json_and_csv(tmp_path):
    out, csv_out = tmp_path / "r.json", tmp_path / "r.csv"
    p = run_cli("analyze", "sun2014", "--json", out, "--csv", csv_out)
    assert p.returncode == 0, p.stderr
    assert "What to tighten" in p.stdout
    data = json.loads(out.read_text())
    assert {"ratio", "K1"} <= set(data["design"])
    assert [f["id"] for f in data["factors"]] == list(range(1, 22))
    need = {"id", "key", "name", "stage", "mean_um", "sigma_um", "sensitivity_arcmin_per_um", "weight",
            "variance_share", "mean_arcmin", "sigma_arcmin"}
    assert all(need <= set(f) for f in data["factors"])
    assert {"mean_arcmin", "sigma_arcmin", "minus3sigma_arcmin", "plus3sigma_arcmin", "worst_case_arcmin",
            "rss_arcmin"} <= set(data["total"])
    assert set(data["stages"]) == {"involute", "cycloid", "crank"}
    # Table 2 row 17 (mu 18, sigma 6) and row 10 (sigma 7.68) straight from the file
    f = {x["id"]: x for x in data["factors"]}
    assert f[17]["mean_um"] == pytest.approx(18.0) and f[17]["sigma_um"] == pytest.approx(6.0)
    assert f[10]["sigma_um"] == pytest.approx(7.68, abs=5e-3)
    lines = csv_out.read_text().splitlines()
    assert len(lines) == 22 and lines[0].startswith("id,key,name,stage")


def test_analyze_a_file_and_the_other_example(tmp_path):
    p = run_cli("examples", "rv80e")
    assert p.returncode == 0
    f = tmp_path / "mine.toml"
    f.write_text(p.stdout)
    q = run_cli("analyze", f, "--json", tmp_path / "o.json", "-q")
    assert q.returncode == 0, q.stderr
    data = json.loads((tmp_path / "o.json").read_text())
    # designed modifications are fixed nominal values: a mean, no variance
    mods = [x for x in data["factors"] if x["key"] in ("equidistance_modification", "moving_distance_modification")]
    assert all(m["sigma_um"] == 0 and m["distribution"] == "fixed" for m in mods)
    assert mods[0]["mean_um"] == pytest.approx(10.0)


def test_schema_and_examples_list():
    p = run_cli("schema")
    assert p.returncode == 0
    schema = json.loads(p.stdout)
    assert {"first_stage", "second_stage", "factors"} <= set(schema["properties"])
    p = run_cli("examples")
    assert "sun2014" in p.stdout and "rv80e" in p.stdout


BAD = {
    # class: (text substitution (old, new), fragment the message must contain)
    "missing field": (("module_mm = 1.75\n", ""), "first_stage.module_mm: missing"),
    "unknown field": (("planets = 3\n", "planets = 3\ngear_ratio = 2\n"), "first_stage.gear_ratio"),
    "nan": (("pin_radius_mm = 4.0", "pin_radius_mm = nan"), "second_stage.pin_radius_mm = nan"),
    "inf": (("eccentricity_mm = 1.5", "eccentricity_mm = inf"), "second_stage.eccentricity_mm = inf"),
    "negative radius": (("pin_circle_radius_mm = 77.5", "pin_circle_radius_mm = -77.5"),
                        "second_stage.pin_circle_radius_mm = -77.5"),
    "negative teeth": (("planet_teeth = 38", "planet_teeth = -38"), "first_stage.planet_teeth = -38"),
    "K1 >= 1": (("eccentricity_mm = 1.5", "eccentricity_mm = 2.0"), "K1"),
    "zp != zc + 1": (("pins = 40", "pins = 42"), "pins = cycloid_teeth + 1"),
    "lower > upper": (("lower_um = 1.0\nupper_um = 4.0", "lower_um = 4.0\nupper_um = 1.0"),
                      "factors.crank_bearing_clearance"),
    "malformed TOML": (("[second_stage]", "[second_stage"), "malformed TOML"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_one_line_exit_2_nothing_written(case, tmp_path, sun2014_toml):
    (old, new), fragment = BAD[case]
    assert old in sun2014_toml
    bad = tmp_path / "bad.toml"
    bad.write_text(sun2014_toml.replace(old, new, 1))
    out = tmp_path / "out.json"
    p = run_cli("analyze", bad, "--json", out, "--csv", tmp_path / "out.csv")
    assert p.returncode == 2
    assert "Traceback" not in p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), p.stderr
    assert fragment in lines[0]
    assert not out.exists() and not (tmp_path / "out.csv").exists()
    assert list(tmp_path.iterdir()) == [bad]


def test_unknown_example_name(tmp_path):
    p = run_cli("analyze", "rv90x", "--json", tmp_path / "o.json")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert p.stderr.strip() == ("error: design = 'rv90x': allowed: a path to an existing .toml file or a "
                                "built-in example (rv80e, sun2014)")
    assert not (tmp_path / "o.json").exists()


def test_unwritable_output(tmp_path):
    p = run_cli("analyze", "sun2014", "--json", tmp_path / "no" / "such" / "dir.json")
    assert p.returncode == 2 and p.stderr.startswith("error: --json")
