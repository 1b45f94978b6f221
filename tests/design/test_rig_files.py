"""Rig files as they come (issue 35): the public RV rig's two-run TE file with its own header (typo
kept) read as one unit with forward and backward TE and its lost motion against output position,
header spellings, a column map and a format profile, metadata lines above the header, decimal
commas, .xlsx (the defects of reading a file: test_bench_file_defects.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rvbacklash.analysis import bench as bench_module
from rvbacklash.analysis import transmission as transmission_module
from rvbacklash.analysis.bench import BenchTwoRunTE, read_bench
from rvbacklash.analysis.bench_synthetic import (RIG_TWO_RUN_HEADER, model_loop_samples, two_run_te,
                                                 write_loop_csv, write_rig_te_csv)
from rvbacklash.design.bench_files import file_format, load_format_profile, parse_columns, read_bench_table
from rvbacklash.errors import InputError
from rvbacklash.models import kinematics

# tests/data/rig_two_runs.csv: the public rig's header and units (positions and TE in degrees), made by
#   two_run_te({1: 10.0, 2: 4.0, 39: 1.5}, 1.2, lost_motion_orders={1: 0.2}, samples=900, noise_arcsec=0.2,
#              seed=35, start_deg=37.0)
# a unit whose flanks share orders 1, 2, 39 (10, 4, 1.5 arcsec) and whose lost motion is 1.2 + 0.2 cos(theta)
# arcmin; the forward run below the common curve by half of it, the backward run above.
RIG_FILE = Path(__file__).parent.parent / "data" / "rig_two_runs.csv"
TRUTH = dict(orders={1: 10.0, 2: 4.0, 39: 1.5}, lost_motion_arcmin=1.2, lost_motion_orders={1: 0.2}, samples=900,
             noise_arcsec=0.2, seed=35, start_deg=37.0)


def runs(**change):
    args = {**TRUTH, **change}
    return two_run_te(args.pop("orders"), args.pop("lost_motion_arcmin"), **args)


def read_one(path, **kw):
    return read_bench([path], units=file_format(**kw) if kw else None).units[0]


def order(u, m):
    return next(s.amplitude_arcsec for s in u.leading_orders if s.order == m)


@pytest.fixture(scope="module")
def rig():
    return read_one(RIG_FILE)


def test_the_shipped_rig_file_is_what_its_comment_says(tmp_path):
    assert RIG_FILE.read_text().splitlines()[0] == ",".join(RIG_TWO_RUN_HEADER)
    assert write_rig_te_csv(tmp_path / "again.csv", *runs()).read_text() == RIG_FILE.read_text()


def test_public_rig_header_reads_as_one_unit_of_two_runs(rig):
    """Done-when check: its exact header (typo included), no map, no unit flag: one unit, both
    runs' TE and orders, and its lost motion against output position, the gap put in."""
    assert isinstance(rig, BenchTwoRunTE) and rig.kind == "transmission_error_two_runs"
    assert any("public RV test rig" in n and "degrees" in n for n in rig.notes)
    f, b = rig.forward, rig.backward
    assert f.samples == b.samples == 900 and f.revolutions == pytest.approx(1.0, abs=0.01)
    for u in (f, b):  # the orders both flanks share come back in each run
        assert order(u, 2) == pytest.approx(4.0, rel=0.03) and order(u, 39) == pytest.approx(1.5, rel=0.03)
    # order 1: the common 10 arcsec line -/+ half the gap's 0.2 arcmin = 6 arcsec line, at a phase the
    # seed chose; whatever it is, |a - c|^2 + |a + c|^2 = 2 (|a|^2 + |c|^2)
    assert order(f, 1) ** 2 + order(b, 1) ** 2 == pytest.approx(2 * (10.0 ** 2 + 6.0 ** 2), rel=0.02)
    assert rig.te_peak_to_peak_arcsec == f.te_peak_to_peak_arcsec and rig.ccw_run == "backward"
    theta = np.radians(rig.output_angle_deg)
    truth = 1.2 + 0.2 * np.cos(theta)
    assert np.sqrt(np.mean((rig.lost_motion_arcmin - truth) ** 2)) < 0.01  # noise 0.2 arcsec = 0.003 arcmin
    assert rig.lost_motion_mean_arcmin == pytest.approx(1.2, abs=0.005)
    assert rig.lost_motion_min_arcmin == pytest.approx(1.0, abs=0.03)
    assert rig.lost_motion_max_arcmin == pytest.approx(1.4, abs=0.03)
    np.testing.assert_array_equal(rig.output_angle_deg, f.output_angle_deg)
    np.testing.assert_array_equal(rig.output_angle_deg, b.output_angle_deg)  # one grid: the gap is position-wise


def test_the_gap_is_the_transmission_models_lost_motion_definition():
    """One definition: the transmission model and the bench call the same function."""
    assert bench_module.lost_motion_arcmin is kinematics.lost_motion_arcmin
    assert transmission_module.lost_motion_arcmin is kinematics.lost_motion_arcmin
    assert kinematics.lost_motion_arcmin(np.array([3e-4]), np.array([1e-4]))[0] == pytest.approx(
        2e-4 * 10800 / np.pi, rel=1e-12)


def test_two_runs_metamorphic(tmp_path, rig):
    """Swapping the runs flips which is ccw and keeps the gap; a constant added to the backward
    run's TE adds to the gap; a run's rows in reverse order change nothing."""
    fa, ft, ba, bt = runs()
    swapped = read_one(write_rig_te_csv(tmp_path / "swap.csv", ba, bt, fa, ft))
    assert swapped.ccw_run == "forward" and any("forward run's TE lies above" in n for n in swapped.notes)
    assert swapped.lost_motion_mean_arcmin == pytest.approx(rig.lost_motion_mean_arcmin, abs=1e-3)
    shifted = read_one(write_rig_te_csv(tmp_path / "shift.csv", fa, ft, ba, bt + 6.0))
    assert shifted.lost_motion_mean_arcmin == pytest.approx(rig.lost_motion_mean_arcmin + 0.1, abs=1e-9)
    np.testing.assert_allclose(shifted.lost_motion_arcmin, rig.lost_motion_arcmin + 0.1, atol=1e-9)
    assert shifted.te_peak_to_peak_backward_arcsec == pytest.approx(rig.te_peak_to_peak_backward_arcsec, abs=1e-6)
    reverse = read_one(write_rig_te_csv(tmp_path / "rev.csv", fa, ft, ba[::-1], bt[::-1]))
    np.testing.assert_allclose(reverse.lost_motion_arcmin, rig.lost_motion_arcmin, atol=1e-12)


def test_a_direction_column_reads_as_the_runs_side_by_side(tmp_path, rig):
    fa, ft, ba, bt = runs()
    rows = [f"{a:.10g},{t / 3600:.10g},{d}" for a, t, d in zip(fa, ft, ["Fw"] * fa.size)]
    rows += [f"{a:.10g},{t / 3600:.10g},{d}" for a, t, d in zip(ba, bt, ["Bw"] * ba.size)]
    f = tmp_path / "direction.csv"
    f.write_text("Output angle [deg],TE [deg],Direction\n" + "\n".join(rows) + "\n")
    u = read_one(f)  # "Direction" is a spelling it knows
    np.testing.assert_array_equal(u.lost_motion_arcmin, rig.lost_motion_arcmin)
    assert u.te_peak_to_peak_backward_arcsec == rig.te_peak_to_peak_backward_arcsec
    # values a profile names
    g = tmp_path / "cw.csv"
    g.write_text(f.read_text().replace(",Fw\n", ",CW\n").replace(",Bw\n", ",CCW\n").replace("Direction", "Sense"))
    with pytest.raises(InputError, match=r"values 'cw', 'ccw' name no run; allowed: fw/forward/\+1"):
        read_one(g, columns="direction=Sense")
    profile = tmp_path / "cw.toml"
    profile.write_text('[columns]\ndirection = "Sense"\n[directions]\nforward = "CW"\nbackward = ["CCW"]\n')
    np.testing.assert_array_equal(read_one(g, profile=profile).lost_motion_arcmin, rig.lost_motion_arcmin)


def test_a_column_map_or_a_profile_names_any_header(tmp_path, rig):
    """The same file under headers no rig spelling covers: mapped once, the same numbers."""
    fa, ft, ba, bt = runs()
    own = ("Winkel A", "Fehler A", "Winkel B", "Fehler B")
    f = write_rig_te_csv(tmp_path / "own.csv", fa, ft, ba, bt, header=own)
    with pytest.raises(InputError) as e:
        read_one(f)
    text = str(e.value)
    assert "no column of a known quantity (columns found: 'Winkel A', 'Fehler A', 'Winkel B', 'Fehler B')" in text
    assert "--columns" in text and "--format-profile" in text and "\n" not in text
    mapped = read_one(f, columns="angle=Winkel A,te=Fehler A,angle_bw=Winkel B,te_bw=Fehler B",
                      units={"angle_unit": "deg", "te_unit": "deg"})
    np.testing.assert_array_equal(mapped.lost_motion_arcmin, rig.lost_motion_arcmin)
    profile = tmp_path / "rig.toml"
    profile.write_text('name = "Pruefstand 2"\n[columns]\nangle_fw = "Winkel A"\nte_fw = "Fehler A"\n'
                       'angle_bw = "Winkel B"\nte_bw = "Fehler B"\n[units]\nangle = "deg"\nte = "deg"\n')
    by_profile = read_one(f, profile=profile)
    np.testing.assert_array_equal(by_profile.lost_motion_arcmin, rig.lost_motion_arcmin)
    assert "format profile 'Pruefstand 2'" in by_profile.notes
    # a flag beats the profile: TE in arcsec instead of degrees makes the gap 3600 times smaller
    flagged = read_one(f, profile=profile, units={"te_unit": "arcsec"})
    assert flagged.lost_motion_mean_arcmin == pytest.approx(rig.lost_motion_mean_arcmin / 3600, rel=1e-9)
    with pytest.raises(InputError, match=r"column map = 'te=Fehler C': no such column \(columns found: 'Winkel A'"):
        read_one(f, columns="te=Fehler C")


@pytest.mark.parametrize("text, allowed", [
    ("te", "ROLE=COLUMN pairs"), ("tee=X", "unknown role 'tee'"), ("te=", "no column named"),
    ("te=a,te=b", "a second te"),
])
def test_bad_column_maps(text, allowed):
    with pytest.raises(InputError, match="columns") as e:
        parse_columns(text)
    assert allowed in str(e.value)


@pytest.mark.parametrize("body, fragment", [
    ('colums = {}\n', "colums: unknown key; allowed: name, decimal"),
    ('[units]\nangle = "grad"\n', "units.angle = 'grad': unknown unit"),
    ('decimal = ";"\n', "decimal = ';': allowed: '.' or ','"),
    ('[columns]\ntorq = "T"\n', "columns = 'torq=T': unknown role"),
    ('name = \n', "not a TOML file"),
])
def test_bad_profiles_are_one_line_naming_the_key(tmp_path, body, fragment):
    p = tmp_path / "rig.toml"
    p.write_text(body)
    with pytest.raises(InputError) as e:
        load_format_profile(p)
    assert str(e.value).startswith(str(p)) and fragment in str(e.value) and "\n" not in str(e.value)


def test_metadata_lines_and_decimal_commas_read_without_editing(tmp_path, rig):
    fa, ft, ba, bt = runs()
    meta = ("Prüfstand RV-2;Seriennummer 1234", "Datum;2024-05-01;Bediener;K. M.", "Übersetzung;81")
    f = write_rig_te_csv(tmp_path / "german.csv", fa, ft, ba, bt, delimiter=";", decimal=",", metadata=meta)
    u = read_one(f)
    np.testing.assert_array_equal(u.lost_motion_arcmin, rig.lost_motion_arcmin)
    assert u.metadata == meta
    assert "3 lines above the header kept as metadata" in u.notes and "decimal commas read (separated by " \
                                                                       "semicolons)" in u.notes
    # tab-separated with decimal commas: read as such too
    g = tmp_path / "tabs.tsv"
    g.write_text(f.read_text().replace(";", "\t"))
    np.testing.assert_array_equal(read_one(g).lost_motion_arcmin, rig.lost_motion_arcmin)
    # a comma-separated file with quoted decimal commas: --decimal ,
    h = tmp_path / "quoted.csv"
    h.write_text("angle [deg],te [arcsec]\n" + "".join(f'"{a:.6f}","{t:.6f}"\n'.replace(".", ",")
                                                       for a, t in zip(fa, ft)))
    with pytest.raises(InputError, match=r"row 2: not a number \(a decimal comma\? give --decimal ,\)"):
        read_one(h)
    assert read_one(h, decimal=",").te_peak_to_peak_arcsec == pytest.approx(rig.forward.te_peak_to_peak_arcsec,
                                                                              abs=1e-3)


def test_a_hysteresis_loop_with_metadata_decimal_commas_and_own_headers(rv80e_problem, tmp_path):
    t, q, a = model_loop_samples(rv80e_problem, cycles=1, samples_per_branch=80, noise_arcmin=0.005, seed=4)
    plain = write_loop_csv(tmp_path / "plain.csv", t, q, a, angle_unit="deg")
    lines = plain.read_text().splitlines()
    german = ["Messung 17;Prüfling SN 42", "Zeit;Moment;Verdrehwinkel"] + \
             [line.replace(",", ";").replace(".", ",") for line in lines[1:]]
    f = tmp_path / "german.csv"
    f.write_text("\n".join(german) + "\n", encoding="cp1252")
    table = read_bench_table(f, file_format(columns="time=Zeit,torque=Moment,angle=Verdrehwinkel",
                                            units={"time_unit": "s", "torque_unit": "N m", "angle_unit": "deg"}))
    expected = read_bench_table(plain)
    for k in ("time", "torque", "angle"):
        np.testing.assert_array_equal(table.columns[k], expected.columns[k])
    assert table.metadata == ("Messung 17;Prüfling SN 42",) and "not UTF-8: read as Windows-1252" in table.notes


def test_xlsx_reads_as_its_csv(tmp_path, rig):
    import openpyxl

    fa, ft, ba, bt = runs()
    book = openpyxl.Workbook()
    ws = book.active
    ws.append(["RV test rig", "unit 7"])
    ws.append([])
    ws.append(list(RIG_TWO_RUN_HEADER))
    for row in zip(fa, ft / 3600.0, ba, bt / 3600.0):
        ws.append([float(float(f"{x:.10g}")) for x in row])  # the CSV's numbers
    f = tmp_path / "rig.xlsx"
    book.save(f)
    u = read_one(f)
    np.testing.assert_array_equal(u.lost_motion_arcmin, rig.lost_motion_arcmin)
    assert u.metadata == ("RV test rig, unit 7",)
    with pytest.raises(InputError, match="'Tabelle2': no such sheet; allowed: Sheet"):
        read_one(f, profile=_profile(tmp_path, 'sheet = "Tabelle2"\n'))
    bad = tmp_path / "broken.xlsx"
    bad.write_bytes(b"PK\x03\x04 not a workbook")
    with pytest.raises(InputError, match="not a readable .xlsx workbook"):
        read_one(bad)


def _profile(tmp_path, text):
    p = tmp_path / "p.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize("header, role, unit", [
    ("Torque_Nm", "torque", "nm"), ("Output Angle (deg)", "angle", "deg"),
    ("output_position_arcsec", "angle", "arcsec"),
    ("Transmission_Error_Bw", "te_bw", None), ("time_ms", "time", "ms"), ("Input Position [rad]", "input_angle", "rad"),
    ("Poisition_Output_Reducer_Fw", "angle", None), ("fwd-transmission-error", "te", None), ("Moment", None, None),
    ("T", None, None),
])
def test_header_spellings(header, role, unit):
    from rvbacklash.design.bench_files import _recognise

    assert _recognise(header) == (None if role is None else (role, unit))


def test_a_direction_column_in_a_hysteresis_file_is_ignored(tmp_path):
    """A loop has no runs to split: a recognised direction column there is left out (said), as any
    column of no use was before; mapped on purpose beside a torque column it is refused."""
    f = tmp_path / "loop.csv"
    f.write_text("time [s],torque [N m],angle [arcmin],Direction\n" +
                 "".join(f"{k * 0.01},{k},{k / 300},{'fw' if k % 2 else 'bw'}\n" for k in range(50)))
    table = read_bench_table(f)
    assert table.kind == "hysteresis" and "column 'Direction' ignored (a direction column in a hysteresis file)" \
        in table.notes
    with pytest.raises(InputError, match="a torque column beside columns of a backward run or a direction"):
        read_bench_table(f, file_format(columns="direction=Direction"))
