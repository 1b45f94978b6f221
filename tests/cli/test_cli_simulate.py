"""`rvbacklash simulate` and `compare` end to end (Ctrl-C: test_cli_interrupt.py)."""

import json

import pytest

from helpers import one_line_error, run_cli


def test_simulate_json(tmp_path):
    out = tmp_path / "s.json"
    p = run_cli("simulate", "sun2014", "--samples", "200000", "--seed", "1", "--spec-arcmin", "3", "--json", out)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    assert (d["samples"], d["samples_done"], d["seed"], d["method"], d["partial"]) == (200000, 200000, 1, "default",
                                                                                      False)
    o = d["outputs"]["backlash"]
    assert o["unit"] == "arcmin" and [q["probability"] for q in o["quantiles"]["table"]] == [0.00135, 0.5, 0.99865]
    assert o["yield"]["count"] == round(o["yield"]["fraction"] * 200000)
    h = o["histogram"]
    assert len(h["edges"]) == len(h["counts"]) + 1 and sum(h["counts"]) == 200000
    assert o["mean_ci95_low"] <= d["linear_reference"]["mean_arcmin"] <= o["mean_ci95_high"]
    assert o["mean"] == pytest.approx(1.851, abs=0.006)


def test_simulate_exact_and_scientific_sample_count(tmp_path):
    p = run_cli("simulate", "rv80e", "--method", "exact", "--spec-arcmin", "1.5", "--json", tmp_path / "e.json")
    assert p.returncode == 0, p.stderr
    d = json.loads((tmp_path / "e.json").read_text())
    assert d["method"] == "exact" and d["samples"] is None
    assert 0 < d["outputs"]["backlash"]["yield"]["fraction"] < 1
    p = run_cli("simulate", "rv80e", "-n", "1e5", "--quantile", "0.9", "--json", tmp_path / "f.json")
    assert p.returncode == 0, p.stderr
    table = json.loads((tmp_path / "f.json").read_text())["outputs"]["backlash"]["quantiles"]["table"]
    assert 0.9 in [q["probability"] for q in table]


def test_one_sample_prints_no_warning():
    p = run_cli("simulate", "rv80e", "-n", "1")
    assert p.returncode == 0 and p.stderr == "", p.stderr


BAD_ARGS = {
    "N = 0": (["--samples", "0"], "--samples"),
    "N < 0": (["--samples", "-5"], "--samples"),
    "N non-integer": (["--samples", "1.5"], "--samples"),
    "N not a number": (["--samples", "many"], "--samples"),
    "N too large": (["--samples", "1e13"], "--samples"),
    "N too large for sobol": (["--samples", "2e9", "--method", "sobol"], "--samples"),
    "negative spec": (["--spec-arcmin", "-1"], "--spec-arcmin"),
    "unknown method": (["--method", "latin"], "--method"),
    "negative seed": (["--seed", "-1"], "--seed"),
    "bad quantile": (["--quantile", "1.5"], "--quantile"),
    "unknown model": (["--model", "gears"], "--model"),
    "contact + sobol": (["--model", "contact", "--method", "sobol"], "--method"),
    "contact + exact": (["--model", "contact", "--method", "exact"], "--method"),
}


@pytest.mark.parametrize("case", sorted(BAD_ARGS))
def test_bad_arguments(case, tmp_path):
    args, flag = BAD_ARGS[case]
    out = tmp_path / "s.json"
    line = one_line_error(run_cli("simulate", "sun2014", "--samples", "1000", *args, "--json", out),
                          f"error: {flag}")
    assert "allowed" in line
    assert not out.exists()


def test_compare_json_and_plot(tmp_path):
    out, svg = tmp_path / "c.json", tmp_path / "c.svg"
    p = run_cli("compare", "rv80e", "--paper", "--scenario", "mine:all=4", "--samples", "65536", "--seed", "3",
                "--spec-arcmin", "3", "--json", out, "--plot", svg)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    assert [s["name"][0] for s in d["scenarios"]] == ["a", "b", "c", "d", "m"] and d["partial"] is False
    assert all(0 < s["yield"] <= 1 and s["q99865_arcmin"] > s["mean_arcmin"] for s in d["scenarios"])
    assert svg.read_text().lstrip().startswith("<?xml") and "<svg" in svg.read_text()
