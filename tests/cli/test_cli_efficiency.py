"""``rvbacklash efficiency``: the datasheet printed, its JSON/CSV/SVG, the duty cycle's thermal balance,
one-line errors (issue 40)."""

import json

from helpers import one_line_error, run_cli


def test_efficiency_table_json_csv_plot_and_duty_cycle(tmp_path):
    cycle = tmp_path / "cycle.csv"
    cycle.write_text("time_share,output_speed_rpm,output_torque_nm\n0.6,15,784\n0.4,0,0\n")
    out, csv_out, svg = tmp_path / "e.json", tmp_path / "e.csv", tmp_path / "e.svg"
    p = run_cli("efficiency", "rv80e", "--angles", "4", "--duty-cycle", cycle, "--json", out, "--csv", csv_out,
                "--plot", svg)
    assert p.returncode == 0, p.stderr
    for text in ("efficiency at 784 N m", "pins on flanks", "crank needle bearings", "involute mesh",
                 "Efficiency map", "No-load running torque", "starting (breakaway) torque", "back-driving torque",
                 "steady case temperature", "allowable duty at 60 degC", "lost motion / backlash at 20.0 degC"):
        assert text in p.stdout, text
    data = json.loads(out.read_text())
    assert data["schema_version"] and data["design_name"] == "rv80e"
    assert 0.5 < data["efficiency_at_rated"] < 1.0
    assert abs(sum(e["loss_w"] for e in data["elements"]) - data["total_loss_at_rated_w"]) < 1e-9
    assert data["thermal"]["steady_temperature_c"] > data["thermal"]["ambient_c"]
    assert [p["temperature_c"] for p in data["thermal"]["precision"]][:2] == [20.0, 60.0]
    assert csv_out.read_text().splitlines()[0].startswith("element,loss_w,share_of_losses")
    assert "<svg" in svg.read_text()[:400]


def test_efficiency_errors_name_the_flag_or_field(tmp_path):
    one_line_error(run_cli("efficiency", "sun2014"), "error: elastic")
    one_line_error(run_cli("efficiency", "rv80e", "--angles", "0"), "error: --angles")
    one_line_error(run_cli("efficiency", "rv80e", "--temperature", "500"), "error: --temperature")
    one_line_error(run_cli("efficiency", "rv80e", "--output-speed", "-1"), "error: --output-speed")
    one_line_error(run_cli("efficiency", "rv80e", "--duty-cycle", tmp_path / "none.csv"), "error: --duty-cycle")
    one_line_error(run_cli("efficiency", "rv80e", "-n", "-1"), "error: --samples")
    one_line_error(run_cli("efficiency", "rv80e", "--spec-min-efficiency", "0.8"), "error: --spec-min-efficiency")
    one_line_error(run_cli("efficiency", "rv80e", "-n", "2", "--spec-min-efficiency", "1.5"),
                   "error: --spec-min-efficiency")
    from rvbacklash.design.loading import example_text

    design = tmp_path / "d.toml"
    design.write_text(example_text("rv80e") + "\n[lubrication]\nviscosity_40c_mm2_s = -5.0\n")
    one_line_error(run_cli("efficiency", design), "lubrication.viscosity_40c_mm2_s")
