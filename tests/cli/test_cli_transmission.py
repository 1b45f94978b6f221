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
    assert 1.0 < data["lost_motion_reference_arcmin"] < 1.2
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
