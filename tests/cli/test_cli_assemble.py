"""`rvbacklash assemble` end to end (issue 39 item 4): a generated batch's sheet, its figures equal to
`hysteresis --measured` on the units as assembled, same seed same sheet, bad input one line."""

import json

import pytest

from helpers import one_line_error, run_cli
import rvbacklash.api as api


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    d = tmp_path_factory.mktemp("batch")
    p = run_cli("assemble", "rv80e", "--generate", "6", "--seed", "3", "--units", d / "u.toml", "--parts", d / "p.csv")
    assert p.returncode == 0, p.stderr
    return d


def test_sheet_figures_equal_hysteresis_measured(batch):
    d = batch
    p = run_cli("assemble", "rv80e", "--units", d / "u.toml", "--parts", d / "p.csv", "--select",
                "pins=5x2um,rollers=3x2um,noise=0.5um", "--spec-lost-motion-arcmin", "1", "--json", d / "s.json",
                "--csv", d / "s.csv", "--assembled", d / "a.toml", "--force")
    assert p.returncode == 0, p.stderr
    sheet = json.loads((d / "s.json").read_text())
    assert sheet["units"] == 6 and list(sheet)[:2] == ["schema_version", "rvbacklash_version"]
    built = [r for r in sheet["sheet"] if r["built"]]
    assert len(built) == sheet["units_built"] >= 4
    assert (d / "s.csv").read_text().splitlines()[0].startswith("unit,built,pin_class")
    for k, row in enumerate(built):
        h = api.hysteresis("rv80e", measured=d / "a.toml", unit=k)
        assert h.lost_motion_arcmin == pytest.approx(row["lost_motion_arcmin"], rel=1e-7)  # the TOML round trip of the parts
        assert h.backlash_arcmin == pytest.approx(row["backlash_arcmin"], rel=1e-7)  # the TOML round trip of the parts
        assert h.torsional_rigidity_nm_per_arcmin == pytest.approx(row["rigidity_nm_per_arcmin"], rel=1e-7)  # the TOML round trip of the parts
        assert 0.0 <= row["pass_probability"] <= 1.0
        assert len(row["pin_serials"].split(";")) == 40
    for row in sheet["sheet"]:
        if not row["built"]:
            assert row["reason"]


def test_same_seed_same_sheet_and_the_optimum_beats_greedy_or_ties(batch, tmp_path):
    d = batch
    a = api.assemble("rv80e", units=d / "u.toml", parts=d / "p.csv")[0].to_dict()
    p = run_cli("assemble", "rv80e", "--generate", "6", "--seed", "3", "--units", tmp_path / "u.toml", "--parts",
                tmp_path / "p.csv")
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "p.csv").read_text() == (d / "p.csv").read_text()
    assert (tmp_path / "u.toml").read_text().split("\n", 2)[2] == (d / "u.toml").read_text().split("\n", 2)[2]
    b = api.assemble("rv80e", units=tmp_path / "u.toml", parts=tmp_path / "p.csv")[0].to_dict()
    assert a == b and a["units_in_window"] >= a["units_in_window_greedy"]


@pytest.mark.parametrize("content, fragment", [
    ("serial,kind\nP1,pin\n", "header"),
    ("serial,kind,diameter_um\nP1,bolt,1.0\n", "column kind"),
    ("serial,kind,diameter_um\nP1,pin,abc\n", "row 2 column diameter_um"),
    ("serial,kind,diameter_um\nP1,pin,1\nP1,pin,2\n", "row 3 column serial"),
])
def test_bad_parts_one_line_exit_2_nothing_written(batch, tmp_path, content, fragment):
    bad = tmp_path / "bad.csv"
    bad.write_text(content)
    p = run_cli("assemble", "rv80e", "--units", batch / "u.toml", "--parts", bad, "--csv", tmp_path / "s.csv")
    one_line_error(p, fragment)
    assert not (tmp_path / "s.csv").exists()


def test_bad_select_one_line(batch):
    one_line_error(run_cli("assemble", "rv80e", "--units", batch / "u.toml", "--parts", batch / "p.csv",
                           "--select", "pins=5"), "--select")
