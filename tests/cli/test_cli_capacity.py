"""``rvbacklash capacity``: the datasheet printed, its JSON/CSV/SVG, the duty cycle, one-line errors."""

import json

from helpers import one_line_error, run_cli


def test_capacity_table_json_csv_plot_and_duty_cycle(tmp_path):
    cycle = tmp_path / "cycle.csv"
    cycle.write_text("time_s,output_speed_rpm,output_torque_nm,moment_nm\n1,15,784,300\n1,0,0,300\n")
    out, csv_out, svg = tmp_path / "c.json", tmp_path / "c.csv", tmp_path / "c.svg"
    p = run_cli("capacity", "rv80e", "--angles", "8", "--duty-cycle", cycle, "--json", out, "--csv", csv_out,
                "--plot", svg)
    assert p.returncode == 0, p.stderr
    for text in ("needle d0 c0", "support c2 B", "reducer L10", "derived rated torque", "momentary maximum",
                 "limiting" if False else "first static limit", "allowable acceleration torque", "moment rigidity",
                 "allowable moment", "Duty cycle", "makers' formula"):
        assert text in p.stdout, text
    data = json.loads(out.read_text())
    assert data["schema_version"] and data["design_name"] == "rv80e"
    assert abs(data["life_at_derived_rated_torque_h"] / data["rated_life_h"] - 1) < 1e-3
    assert data["limiting_element"] in {row["element"] for row in data["static_limits_at_momentary"]}
    assert data["duty_cycle"]["steps"] == 2 and data["duty_cycle"]["main_bearing_life_h"] > 0
    assert len(data["loads"]["crank_angle_rad"]) == 8
    assert csv_out.read_text().splitlines()[0].startswith("name,kind,dynamic_load_rating_n")
    assert svg.read_text().lstrip().startswith("<?xml") or "<svg" in svg.read_text()[:400]


def test_capacity_errors_name_the_flag_or_field(tmp_path):
    one_line_error(run_cli("capacity", "sun2014"), "error: elastic")
    one_line_error(run_cli("capacity", "rv80e", "--angles", "0"), "error: --angles")
    one_line_error(run_cli("capacity", "rv80e", "--life-method", "iso999"), "error: --life-method")
    one_line_error(run_cli("capacity", "rv80e", "--duty-cycle", tmp_path / "none.csv"), "error: --duty-cycle")
    bad = tmp_path / "bad.csv"
    bad.write_text("time_share,output_speed_rpm,output_torque_nm\n1,-5,100\n")
    line = one_line_error(run_cli("capacity", "rv80e", "--duty-cycle", bad), "bad.csv: step 1: output_speed_rpm")
    assert "-5" in line
