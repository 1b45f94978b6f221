"""`rvbacklash hysteresis` and `simulate --model elastic` end to end."""

import json

import pytest

from helpers import one_line_error, run_cli


def test_hysteresis_json_plot_and_table(tmp_path):
    out, svg, csv_out = tmp_path / "h.json", tmp_path / "loop.svg", tmp_path / "loop.csv"
    p = run_cli("hysteresis", "rv80e", "--json", out, "--plot", svg, "--csv", csv_out)
    assert p.returncode == 0, p.stderr
    for text in ("lost motion", "backlash", "torsional rigidity", "pins in contact at +T_R", "cycloid pins"):
        assert text in p.stdout
    d = json.loads(out.read_text())
    for key in ("rated_torque_nm", "measuring_torque_fraction", "rigidity_interval_fraction", "lost_motion_arcmin",
                "backlash_arcmin", "torsional_rigidity_nm_per_arcmin"):
        assert key in d
    assert d["rated_torque_nm"] == 784.0 and d["measuring_torque_fraction"] == 0.03
    assert [b["branch"] for b in d["loop"]] == ["load+", "unload+", "load-", "unload-"]
    assert set(d["loop"][0]) == {"branch", "torque_nm", "angle_arcmin"}
    # the definitions, recomputed from the loop (np.interp is exact at the nodes the definitions read)
    import numpy as np

    def at(name, t):
        b = next(b for b in d["loop"] if b["branch"] == name)
        tt, aa = np.array(b["torque_nm"]), np.array(b["angle_arcmin"])
        order = np.argsort(tt, kind="stable")
        return float(np.interp(t, tt[order], aa[order]))

    tr, x = d["rated_torque_nm"], d["measuring_torque_fraction"] * d["rated_torque_nm"]
    lm = 0.5 * (at("load+", x) + at("unload+", x)) - 0.5 * (at("load-", -x) + at("unload-", -x))
    assert lm == pytest.approx(d["lost_motion_arcmin"], rel=1e-9)
    lo, hi = (v * tr for v in d["rigidity_interval_fraction"])
    k = 2 * (hi - lo) / ((at("load+", hi) - at("load+", lo)) + (at("load-", -lo) - at("load-", -hi)))
    assert k == pytest.approx(d["torsional_rigidity_nm_per_arcmin"], rel=1e-9)
    assert svg.read_text().lstrip().startswith(("<?xml", "<svg"))
    rows = csv_out.read_text().splitlines()
    assert rows[0] == "branch,torque_nm,angle_arcmin" and len(rows) == 1 + sum(len(b["torque_nm"]) for b in d["loop"])


def test_hysteresis_errors_name_the_flag_or_field(tmp_path):
    one_line_error(run_cli("hysteresis", "sun2014"), "error: elastic")
    one_line_error(run_cli("hysteresis", "rv80e", "--points", "1"), "error: --points")
    one_line_error(run_cli("hysteresis", "rv80e", "--unit", "0"), "error: --unit")
    one_line_error(run_cli("hysteresis", "rv80e", "--measured", tmp_path / "none.toml"), "error: --measured")


def test_simulate_elastic_with_both_specs(tmp_path):
    out = tmp_path / "s.json"
    p = run_cli("simulate", "rv80e", "--model", "elastic", "-n", "2000", "--seed", "4", "--spec-lost-motion-arcmin",
                "1", "--spec-rigidity-nm-per-arcmin", "1200", "--json", out)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    assert list(d["outputs"]) == ["lost_motion", "backlash", "rigidity", "preload"]
    assert d["outputs"]["lost_motion"]["spec_limit"] == 1.0 and d["outputs"]["rigidity"]["spec_limit"] == 1200.0
    assert d["outputs"]["rigidity"]["spec_is_upper"] is False
    assert d["joint_yield"]["count"] <= d["outputs"]["lost_motion"]["yield"]["count"]
    assert "joint yield" in p.stdout


@pytest.mark.parametrize("args, flag", [
    (["--spec-lost-motion-arcmin", "1"], "--spec-lost-motion-arcmin"),
    (["--spec-rigidity-nm-per-arcmin", "100"], "--spec-rigidity-nm-per-arcmin"),
    (["--spec-preload-um", "5"], "--spec-preload-um"),
])
def test_elastic_specs_need_the_elastic_model(args, flag):
    line = one_line_error(run_cli("simulate", "rv80e", "-n", "100", *args), f"error: {flag}")
    assert "elastic" in line and "allowed with --model" in line


def test_preload_spec_on_the_elastic_model_is_a_joint_spec(tmp_path):
    out = tmp_path / "s.json"
    p = run_cli("simulate", "rv80e", "--model", "elastic", "-n", "2000", "--seed", "4", "--spec-arcmin", "1",
                "--spec-preload-um", "5", "--json", out)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    assert d["outputs"]["preload"]["spec_limit"] == 5.0 and d["outputs"]["lost_motion"]["spec_limit"] == 1.0
    assert d["joint_yield"]["count"] <= d["outputs"]["lost_motion"]["yield"]["count"]
    assert 0 < d["preload_fraction"] < 1


def test_elastic_spec_values_are_checked():
    one_line_error(run_cli("simulate", "rv80e", "-n", "100", "--model", "elastic", "--spec-rigidity-nm-per-arcmin",
                           "-5"), "error: --spec-rigidity-nm-per-arcmin")
    one_line_error(run_cli("simulate", "rv80e", "-n", "100", "--model", "elastic", "--spec-arcmin", "1",
                           "--spec-lost-motion-arcmin", "1"), "error: --spec-lost-motion-arcmin")


def test_a_unit_saved_by_the_elastic_run_reproduces_its_figures(tmp_path):
    """Review regression: the saved unit carries its crank-bearing clearance (and so its involute
    share) and its gaps are the Monte-Carlo's own (the contact kernel's), so the loop of the unit
    re-run alone gives the run's figures exactly (one unit: mean = the unit's value)."""
    units, sim = tmp_path / "e.toml", tmp_path / "s.json"
    p = run_cli("simulate", "rv80e", "--model", "elastic", "-n", "1", "--seed", "3", "--save-units", "1", units,
                "--json", sim)
    assert p.returncode == 0, p.stderr
    assert "rvbacklash hysteresis rv80e --measured FILE" in units.read_text()
    assert "crank_bearing_clearance_um = " in units.read_text()
    h = run_cli("hysteresis", "rv80e", "--measured", units, "--format", "json")
    assert h.returncode == 0, h.stderr
    d, s = json.loads(h.stdout), json.loads(sim.read_text())["outputs"]
    assert d["lost_motion_arcmin"] == pytest.approx(s["lost_motion"]["mean"], rel=1e-7)
    assert d["backlash_arcmin"] == pytest.approx(s["backlash"]["mean"], rel=1e-7)
    assert d["torsional_rigidity_nm_per_arcmin"] == pytest.approx(s["rigidity"]["mean"], rel=1e-7)


def test_the_preload_yield_counts_the_free_units_as_meeting_it(tmp_path):
    """Review regression: P(preload <= P) is over every unit (a free cycloid stage meets it), as in
    the joint yield and the allocation; the moments and quantiles stay those of the preloaded units,
    and every quantile lies within the samples' range."""
    out = tmp_path / "s.json"
    p = run_cli("simulate", "rv80e", "--model", "contact", "-n", "3000", "--seed", "4", "--spec-preload-um", "5",
                "--json", out)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    pre = d["outputs"]["preload"]
    n, preloaded = d["samples_done"], pre["samples"]
    assert 0 < preloaded < n
    assert pre["yield"]["total"] == n
    passing_preloaded = pre["yield"]["count"] - (n - preloaded)
    assert 0 < passing_preloaded < preloaded
    assert pre["cp"] is None and pre["cpk"] is None
    for o in d["outputs"].values():
        for q in o["quantiles"]["table"]:
            for v in (q["value"], q["ci95_low"], q["ci95_high"]):
                assert v is None or o["min"] <= v <= o["max"]


@pytest.mark.parametrize("edit, fragment", [
    (lambda t: t.replace("other_stages_arcmin = ", "other_stages_arcmin = -500 #", 1), "other_stages_arcmin = -500"),
    (lambda t: t.replace("runout_um = [", "runout_um = [1e9, ", 1).replace("[1e9, ", "[1e9, 0.0] #", 1),
     "runout_um"),
    (lambda t: "unit = []\n", "unit = []"),
])
def test_measured_unit_errors_name_the_file_and_the_field(tmp_path, edit, fragment):
    units = tmp_path / "u.toml"
    assert run_cli("simulate", "rv80e", "--model", "contact", "-n", "100", "--save-units", "1", units).returncode == 0
    units.write_text(edit(units.read_text()))
    line = one_line_error(run_cli("contact", "rv80e", "--measured", units), f"error: {units}: ")
    assert fragment in line and "--unit" not in line


def test_save_units_needs_at_least_one_unit(tmp_path):
    one_line_error(run_cli("simulate", "rv80e", "--model", "contact", "-n", "100", "--save-units", "0",
                           tmp_path / "x.toml"), "error: --save-units = 0")
    assert not (tmp_path / "x.toml").exists()


def test_report_summary_leads_with_the_chosen_model(tmp_path):
    """Regression: `report rv80e --model elastic` printed the linear stack-up's figures first
    (total.mean_arcmin 2.105 ...) before the elastic production run; the page leads with the
    elastic figures, and so do the terminal, the JSON's key_numbers and the CSV."""
    js, csv_out = tmp_path / "r.json", tmp_path / "r.csv"
    p = run_cli("report", "rv80e", "--model", "elastic", "-n", "2000", "-o", tmp_path / "r.html", "--json", js,
                "--csv", csv_out)
    assert p.returncode == 0, p.stderr
    lines = [line.strip() for line in p.stdout.splitlines()]
    assert lines[0] == "elastic model:" and lines[1].split()[0] == "simulation.lost_motion.mean"
    assert lines.index("linear stack-up (explains the figures above):") < \
        next(k for k, line in enumerate(lines) if line.startswith("total.mean_arcmin"))
    keys = list(json.loads(js.read_text())["key_numbers"])
    assert keys[:2] == ["simulation.lost_motion.mean", "simulation.lost_motion.q99865"]
    assert keys.index("elastic.nominal.lost_motion_arcmin") < keys.index("total.mean_arcmin")
    assert csv_out.read_text().splitlines()[1].startswith("simulation.lost_motion.mean,")
