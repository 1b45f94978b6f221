"""`rvbacklash contact --measured` and `simulate --save-units`: any unit of a Monte-Carlo run, or a
unit measured on a CMM, through the exact geometry (issue 10)."""

import json

import pytest

from helpers import one_line_error, run_cli

PINS = 40


def _unit(**pins) -> str:
    lines = ["[pins]"] + [f"{k} = [{', '.join(map(str, v))}]" for k, v in pins.items()]
    return "\n".join(lines) + "\n"


def test_saved_units_run_again_to_their_play(tmp_path):
    """The first units of a run, written with --save-units and re-run one by one with
    --measured FILE --unit K at their crank angle, give back the play the Monte-Carlo found."""
    units, js = tmp_path / "units.toml", tmp_path / "s.json"
    p = run_cli("simulate", "rv80e", "--model", "contact", "-n", "3000", "--seed", "5", "--save-units", "6", units,
                "--json", js)
    assert p.returncode == 0, p.stderr
    text = units.read_text()
    assert text.count("[[unit]]") == 6 and text.count("[[unit.discs]]") == 12
    import tomllib
    saved = tomllib.loads(text)["unit"]
    for k, u in enumerate(saved):
        out = tmp_path / f"c{k}.json"
        q = run_cli("contact", "rv80e", "--measured", units, "--unit", k, "--json", out, "-q")
        assert q.returncode == 0, q.stderr
        d = json.loads(out.read_text())
        assert d["crank_angle_deg"] == pytest.approx(u["crank_angle_deg"])
        assert d["cycloid_stage_arcmin"] == pytest.approx(u["cycloid_stage_arcmin"], rel=1e-6, abs=1e-9)
        assert d["cycloid_stage_preloaded"] == (u["cycloid_stage_arcmin"] == 0)
        assert (d["preload_um"] > 0) == d["cycloid_stage_preloaded"]
    s = json.loads(js.read_text())
    assert set(s["outputs"]) == {"backlash", "backlash_free", "preload"}
    assert 0 < s["preload_fraction"] < 1
    assert s["outputs"]["backlash_free"]["samples"] + s["outputs"]["preload"]["samples"] == 3000


def test_a_measured_unit_by_hand(tmp_path):
    """Missing arrays are zeros; every pin 2 um smaller than nominal on rv80e (5 um equidistance,
    3 um moving distance, no hole clearance): the stage is free by 2 (5 + 2) - 2 * 3 sqrt(1 - K1^2)
    = 10.2 um at the disc pitch circle, within the discrete-pin effect (< 0.5 %)."""
    import math

    f = tmp_path / "unit.toml"
    f.write_text(_unit(radius_um=[-2.0] * PINS))
    p = run_cli("contact", "rv80e", "--measured", f, "--json", "-")
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    k1 = 1.5 * 40 / 77.5
    expected = (2 * 7 - 6 * math.sqrt(1 - k1 * k1)) / 58500 * 10800 / math.pi
    assert d["cycloid_stage_arcmin"] == pytest.approx(expected, rel=0.005)
    assert d["cycloid_stage_preloaded"] is False and d["preload_um"] == 0 and d["unit"] == str(f)


def test_an_oversized_pin_at_the_tip_preloads(tmp_path):
    f = tmp_path / "unit.toml"
    radius = [0.0] * PINS
    radius[0] = 12.0  # pin 0 on the eccentric's line at crank angle 0: no lever arm
    f.write_text(_unit(radius_um=radius))
    d = json.loads(run_cli("contact", "rv80e", "--measured", f, "--json", "-").stdout)
    assert d["cycloid_stage_preloaded"] is True and d["cycloid_stage_arcmin"] == 0
    assert d["preload_um"] == pytest.approx(12.0 - 5.0 + 3.0, abs=0.05)  # 12 - (dr_rp - dr_p) at phi = 0


@pytest.mark.parametrize("text,fragment", [
    (_unit(radius_um=[1.0] * 39), "pins.radius_um = '39 values': allowed: z_p = 40 values"),
    (_unit(radius_um=[1.0] * 39 + ["nan"]), "pins.radius_um"),
    ("[pins]\nradius_mm = [1.0]\n", "pins.radius_mm = [1.0]: unknown field"),
    ("[[discs]]\ncumulative_pitch_um = [0.0]\n", "discs = '1 tables': allowed: one [[discs]] table per disc (2)"),
    ("[[discs]]\ncumulative_pitch_um = [0.0]\n[[discs]]\ncumulative_pitch_um = [0.0]\n",
     "discs[0].cumulative_pitch_um = '1 values': allowed: z_c = 39 values"),
    (_unit(hole_clearance_um=[-1.0] * PINS), "pins.hole_clearance_um = -1.0"),
    ("[pins\n", "malformed TOML"),
])
def test_bad_measured_unit_is_one_line(tmp_path, text, fragment):
    f = tmp_path / "bad.toml"
    f.write_text(text.replace('"nan"', "nan"))
    one_line_error(run_cli("contact", "rv80e", "--measured", f, "--json", tmp_path / "o.json"), fragment)
    assert not (tmp_path / "o.json").exists()


def test_unit_index_and_missing_file(tmp_path):
    f = tmp_path / "u.toml"
    f.write_text(_unit(radius_um=[0.0] * PINS))
    one_line_error(run_cli("contact", "rv80e", "--measured", f, "--unit", "3"), "--unit = 3: allowed: 0 to 0")
    one_line_error(run_cli("contact", "rv80e", "--measured", tmp_path / "none.toml"), "--measured")
    one_line_error(run_cli("contact", "rv80e", "--unit", "0"), "--unit = 0: allowed only with measured units")
    one_line_error(run_cli("simulate", "rv80e", "-n", "100", "--save-units", "5", tmp_path / "x.toml"),
                   "--save-units = 5: allowed with the contact, elastic and transmission models")


@pytest.mark.parametrize("command,text", [("contact", ""), ("hysteresis", ""), ("contact", "# exported, no rows\n"),
                                          ("hysteresis", "[pins]\n"), ("contact", "crank_angle_deg = 0.0\n"),
                                          ("contact", "[[unit]]\ncrank_angle_deg = 0.0\n[unit.pins]\n")])
def test_empty_or_unitless_measured_file_is_one_line_error(tmp_path, text, command):
    """Issue 18: an empty export was read silently as a perfect unit (a plausible answer from nothing)."""
    f = tmp_path / "empty.toml"
    f.write_text(text)
    line = one_line_error(run_cli(command, "rv80e", "--measured", f, "--json", tmp_path / "o.json"),
                          "no measured values")
    assert str(f) in line and "at least one measured array" in line
    assert not (tmp_path / "o.json").exists()
