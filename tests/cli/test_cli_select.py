"""`--select` and the design's [selection] table on the command line (issue 39, continued): the
contact and transmission models' selected runs, the table as an alternative to the flag (the flag
wins, `none` turns it off), bad input one line, exit 2, nothing written."""

import json

from helpers import one_line_error, run_cli
from rvbacklash.design.loading import example_text


def _design_with_selection(tmp_path, body: str):
    path = tmp_path / "d.toml"
    path.write_text(example_text("rv80e") + "\n[selection]\n" + body)
    return path


def test_contact_model_selected_run_prints_both_yields(tmp_path):
    p = run_cli("simulate", "rv80e", "--model", "contact", "-n", "400", "--seed", "2", "--spec-arcmin", "1.5",
                "--select", "pins=-4,-2,0,2,4um,rollers=3x2um", "--json", tmp_path / "s.json")
    assert p.returncode == 0, p.stderr
    assert "random assembly vs selected" in p.stdout
    d = json.loads((tmp_path / "s.json").read_text())
    assert d["model"] == "contact" and d["selection"]["pins"]["boundaries_um"] == [-4.0, -2.0, 0.0, 2.0, 4.0]
    y = d["yields"][0]
    assert y["output"] == "backlash" and y["selected"]["fraction"] > y["random"]["fraction"]


def test_design_table_is_used_and_the_flag_overrides_it(tmp_path):
    design = _design_with_selection(tmp_path, 'pins = "5x2um"\nrollers = "3x2um"\n')
    args = ("simulate", design, "--model", "contact", "-n", "300", "--seed", "1", "--spec-arcmin", "1.5")
    p = run_cli(*args, "--json", tmp_path / "t.json")
    assert p.returncode == 0, p.stderr
    table = json.loads((tmp_path / "t.json").read_text())
    assert table["selection"]["pins"]["count"] == 5 and table["selection"]["rollers"]["count"] == 3
    p = run_cli(*args, "--select", "pins=3x1um", "--json", tmp_path / "f.json")
    assert p.returncode == 0, p.stderr
    flag = json.loads((tmp_path / "f.json").read_text())
    assert flag["selection"]["pins"]["count"] == 3 and flag["selection"]["rollers"]["count"] == 1
    p = run_cli(*args, "--select", "none", "--json", tmp_path / "n.json")
    assert p.returncode == 0, p.stderr
    plain = json.loads((tmp_path / "n.json").read_text())
    assert "selection" not in plain and plain["outputs"]["backlash"]["yield"]["total"] == 300
    # the same seed, the same random run underneath
    assert plain["outputs"] == table["random_run"]["outputs"]


def test_bad_selection_table_one_line_exit_2_nothing_written(tmp_path):
    design = _design_with_selection(tmp_path, 'pins = "0x2um"\n')
    p = run_cli("simulate", design, "--model", "contact", "-n", "100", "--spec-arcmin", "1.5", "--json",
                tmp_path / "s.json")
    line = one_line_error(p, "selection.pins")
    assert "count" in line and "500" in line
    assert not (tmp_path / "s.json").exists()
    design = _design_with_selection(tmp_path, 'pins = "5x2um"\nnoise_um = -1.0\n')
    one_line_error(run_cli("simulate", design, "-n", "100", "--spec-arcmin", "1.5"), "selection.noise_um")


def test_select_refuses_the_linear_model_and_a_run_without_spec(tmp_path):
    one_line_error(run_cli("simulate", "rv80e", "-n", "100", "--spec-arcmin", "1.5", "--select", "pins=5x2um"),
                   "contact or transmission")
    one_line_error(run_cli("simulate", "rv80e", "--model", "contact", "-n", "100", "--select", "pins=5x2um"),
                   "needs a spec")


def test_a_design_with_a_selection_table_runs_the_commands_the_table_does_not_fit(tmp_path):
    """A valid design never fails a command: the [selection] table applies where a run can select
    (a sampled contact, elastic or transmission run with a spec); elsewhere the run is the random
    assembly and a note says why. Before: `simulate D` (linear model) and `report D` stopped with
    exit 2 on the table ('allowed with --model elastic, contact or transmission')."""
    design = _design_with_selection(tmp_path, 'pins = "5x2um"\n')
    p = run_cli("simulate", design, "-n", "200", "--spec-arcmin", "1.5", "--json", tmp_path / "s.json")
    assert p.returncode == 0, p.stderr
    assert "[selection] table is not applied (the linear model draws no parts)" in p.stderr
    assert "selection" not in json.loads((tmp_path / "s.json").read_text())
    p = run_cli("simulate", design, "--model", "contact", "-n", "200", "--json", tmp_path / "c.json")
    assert p.returncode == 0, p.stderr
    assert "no spec to compare the yields" in p.stderr
    p = run_cli("report", design, "-n", "200", "-o", tmp_path / "r.html")
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "r.html").exists()
