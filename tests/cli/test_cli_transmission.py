"""End-to-end runs of ``rvbacklash transmission-error`` and the measured-unit format's kinematics table."""

from __future__ import annotations

import json

import pytest

from helpers import one_line_error, run_cli
from rvbacklash.design.loading import load_design
from rvbacklash.design.measured import units_from_toml, units_to_toml

UNIT = """
[pins]
radius_um = [{pins}]
[kinematics]
centre_gear_eccentricity_um = [1.0, -2.0]
planet_eccentricity_um = [[1.0, 0.0], [0.0, 1.0], [0.5, 0.5]]
carrier_crank_holes_um = [[2.0, 0.0], [0.0, 0.0], [0.0, -1.0]]
disc_crank_holes_um = [[[0.0, 0.0], [1.0, 1.0], [0.0, 0.0]], [[0.0, 0.0], [0.0, 0.0], [-3.0, 0.0]]]
"""


def test_nominal_curve_json_csv_plot(tmp_path):
    p = run_cli("transmission-error", "rv80e", "--positions", "400", "--json", tmp_path / "te.json", "--csv",
                tmp_path / "te.csv", "--plot", tmp_path / "te.svg")
    assert p.returncode == 0, p.stderr
    data = json.loads((tmp_path / "te.json").read_text())
    assert data["te_peak_to_peak_arcsec"] == 0.0 and len(data["te_ccw_arcsec"]) == 400
    assert len(data["spectrum_amplitude_arcsec"]) == 201
    assert 1.0 < data["cycloid_stage_reference_arcmin"] < 1.2  # the cycloid stage alone
    # the output's lost motion: the stage plus the other stages (their linear means for the nominal unit)
    assert data["other_stages_from"] == "linear means" and data["other_stages_arcmin"] > 0.1
    assert data["lost_motion_reference_arcmin"] == pytest.approx(data["cycloid_stage_reference_arcmin"]
                                                                 + data["other_stages_arcmin"], rel=1e-12)
    assert data["lost_motion_max_arcmin"] == pytest.approx(max(data["lost_motion_arcmin"]), rel=1e-12)
    assert (tmp_path / "te.csv").read_text().splitlines()[0].startswith("output_angle_deg")
    assert (tmp_path / "te.svg").read_text().lstrip().startswith("<")


def test_the_error_free_unit_has_no_table_of_noise(tmp_path):
    """Regression: `transmission-error rv80e` listed 'leading orders' 512, 511, 510 ... all 0.000
    (the sorted zeros of the error-free unit's spectrum); it says instead that there is none."""
    p = run_cli("transmission-error", "rv80e", "--positions", "400", "--json", tmp_path / "te.json")
    assert p.returncode == 0, p.stderr
    text = " ".join(p.stdout.split())
    assert "Leading orders" not in text and "no spectrum: TE is measured from the error-free unit" in text
    data = json.loads((tmp_path / "te.json").read_text())
    assert f"{data['nominal_ripple_arcsec']:.3f} arcsec peak-to-peak" in text  # the modifications' ripple: not TE
    assert data["nominal_ripple_arcsec"] > 0.01
    assert data["leading_orders"] == [] and max(data["spectrum_amplitude_arcsec"]) == 0.0


def test_measured_unit_with_kinematics(tmp_path):
    design = load_design("rv80e")
    text = UNIT.format(pins=", ".join(["1.0"] * design.second_stage.pins))
    units = units_from_toml(text, design)
    again = units_from_toml(units_to_toml(units), design)
    assert again[0].kinematics == units[0].kinematics
    f = tmp_path / "unit.toml"
    f.write_text(text)
    p = run_cli("transmission-error", "rv80e", "--measured", f, "--positions", "400", "--json", tmp_path / "u.json")
    assert p.returncode == 0, p.stderr
    data = json.loads((tmp_path / "u.json").read_text())
    assert data["te_peak_to_peak_arcsec"] > 0.1
    lines = data["leading_orders"]  # real lines only, largest first
    assert lines and all(x["amplitude_arcsec"] > 1e-3 for x in lines)
    assert [x["amplitude_arcsec"] for x in lines] == sorted((x["amplitude_arcsec"] for x in lines), reverse=True)
    assert "Leading orders" in p.stdout
    groups = {g["group"] for g in data["group_shares"]}
    assert {"crank holes (disc, carrier)", "involute stage (gear eccentricities)"} <= groups


@pytest.mark.parametrize("args, fragment", [
    (("--positions", "100"), "--positions = 100"),
    (("--load-direction", "up"), "--load-direction = 'up'"),
    (("--unit", "0"), "--unit = 0"),
])
def test_bad_input_is_one_line(tmp_path, args, fragment):
    out = tmp_path / "te.json"
    one_line_error(run_cli("transmission-error", "rv80e", *args, "--json", out), fragment)
    assert not out.exists()


def test_bad_kinematics_shape_names_the_field():
    design = load_design("rv80e")
    bad = "[kinematics]\nplanet_eccentricity_um = [[1.0, 0.0]]\n"
    with pytest.raises(Exception) as e:
        units_from_toml(bad, design)
    assert "kinematics.planet_eccentricity_um" in str(e.value)


def test_a_saved_transmission_unit_runs_in_every_measured_unit_command(tmp_path):
    """--save-units with the transmission model writes each unit with its kinematic errors; the file
    names the command that re-runs a unit (transmission-error), and the models that do not read
    kinematic errors take the same file (regression: contact and hysteresis crashed on them)."""
    units = tmp_path / "te.toml"
    p = run_cli("simulate", "rv80e", "--model", "transmission", "-n", "20", "--seed", "3", "--save-units", "3", units,
                "-q")
    assert p.returncode == 0, p.stderr
    text = units.read_text()
    assert text.count("[unit.kinematics]") == 3 and "re-run one: rvbacklash transmission-error rv80e" in text
    for command in ("transmission-error", "contact", "hysteresis"):
        out = tmp_path / f"{command}.json"
        p = run_cli(command, "rv80e", "--measured", units, "--unit", "1", "--json", out, "-q")
        assert p.returncode == 0 and "Traceback" not in p.stderr, (command, p.stderr[-2000:])
        assert json.loads(out.read_text())["schema_version"]


def test_lost_motion_means_the_same_in_the_run_and_for_one_unit(tmp_path):
    """Issue 36 item 11: a unit saved by `simulate --model transmission` re-run alone by
    `transmission-error --measured` reads the run's backlash as its lost motion at the reference
    position (the cycloid stage plus the unit's involute and crank stages, as in `contact`), and
    the run's cycloid stage as ``cycloid_stage_reference_arcmin``. Before, the command's
    ``lost_motion_reference_arcmin`` was the cycloid stage alone (unit 2 of seed 3: 0.1627 against
    the run's 0.7053)."""
    units, run_json = tmp_path / "u.toml", tmp_path / "run.json"
    p = run_cli("simulate", "rv80e", "--model", "transmission", "-n", "8", "--seed", "3", "--save-units", "8", units,
                "--json", run_json, "-q")
    assert p.returncode == 0, p.stderr
    import rvbacklash as rb
    from rvbacklash.design.measured import load_units

    run = rb.simulate("rv80e", model="transmission", samples=8, seed=3, save_units=8, workers=1)
    saved = load_units(units, load_design("rv80e"))
    checked = 0
    for k, (r, linear_arcmin, stage_arcmin) in enumerate(run.units):
        out = tmp_path / f"{k}.json"
        q = run_cli("transmission-error", "rv80e", "--measured", units, "--unit", str(k), "--json", out, "-q")
        assert q.returncode == 0, q.stderr
        d = json.loads(out.read_text())
        assert d["other_stages_from"] == "given"
        assert d["other_stages_arcmin"] == pytest.approx(saved[k].other_stages_arcmin, rel=1e-12)
        assert d["other_stages_arcmin"] == pytest.approx(linear_arcmin, rel=1e-8)  # as the TOML file keeps it
        assert d["lost_motion_reference_arcmin"] == pytest.approx(d["cycloid_stage_reference_arcmin"]
                                                                  + d["other_stages_arcmin"], rel=1e-12)
        # the run's backlash of this unit; the run linearises each flank at its position, the command
        # solves it exactly: they differ by up to 0.010 arcmin here (unit 7: 0.2104 / 0.2003), far
        # less than the other stages (>= 0.11 arcmin) that the command used to leave out
        assert d["lost_motion_reference_arcmin"] == pytest.approx(linear_arcmin + stage_arcmin, abs=0.02)
        checked += stage_arcmin > 0.0
    assert checked >= 2
