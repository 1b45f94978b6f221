"""End-to-end runs of the command line: outputs, one meaning per flag, one-line errors."""

import json
import re
import subprocess
import sys

import pytest

from helpers import one_line_error, run_cli, run_cli_process


def test_analyze_sun2014_json_and_csv(tmp_path):
    out, csv_out = tmp_path / "r.json", tmp_path / "r.csv"
    p = run_cli("analyze", "sun2014", "--json", out, "--csv", csv_out)
    assert p.returncode == 0, p.stderr
    assert "What to tighten" in p.stdout and f"wrote {out}" in p.stdout
    data = json.loads(out.read_text())
    assert data["design"]["ratio"] == 153 and data["design"]["K1"] == pytest.approx(60 / 77.5)
    f = {x["id"]: x for x in data["factors"]}
    # Table 2 row 17 (mu 18, sigma 6) and row 10 (sigma 7.68), straight from the file
    assert f[17]["mean_um"] == pytest.approx(18.0) and f[17]["sigma_um"] == pytest.approx(6.0)
    assert f[10]["sigma_um"] == pytest.approx(7.68, abs=5e-3)
    assert data["total"]["mean_arcmin"] == pytest.approx(1.851, abs=5e-4)
    lines = csv_out.read_text().splitlines()
    assert len(lines) == 22 and lines[0].startswith("id,key,name,stage")
    assert lines[17].split(",")[1] == "pin_cumulative_pitch"


def test_analyze_a_file_written_from_an_example(tmp_path):
    p = run_cli("examples", "rv80e")
    assert p.returncode == 0
    f = tmp_path / "mine.toml"
    f.write_text(p.stdout)
    q = run_cli("analyze", f, "--json", tmp_path / "o.json", "-q")
    assert q.returncode == 0 and q.stdout == "", q.stderr
    data = json.loads((tmp_path / "o.json").read_text())
    mods = [x for x in data["factors"] if x["key"] in ("equidistance_modification", "moving_distance_modification")]
    assert all(m["sigma_um"] == 0 and m["distribution"] == "fixed" for m in mods)
    assert mods[0]["mean_um"] == pytest.approx(10.0)  # 2 x 5 um


def test_schema_describes_the_design_file():
    p = run_cli("schema")
    schema = json.loads(p.stdout)
    defs = schema["$defs"]
    assert defs["FirstStage"]["properties"]["module_mm"]["description"] == "module m [mm]"
    assert set(defs["ToleranceZone"]["properties"]["distribution"]["enum"]) == {
        "normal", "uniform", "truncated_normal", "rayleigh", "fixed"}
    assert schema["required"] == ["name", "first_stage", "second_stage"]
    p = run_cli("examples")
    assert {"rv80e", "sun2014"} <= {line.split()[0] for line in p.stdout.splitlines() if line.strip()}


def test_version_and_help_show_units():
    """Regression (issue 9): --version printed 'Missing command.'; [mm], [arcmin], [deg] were
    eaten as rich markup in --help."""
    from rvbacklash._version import __version__

    p = run_cli_process("--version")
    assert p.returncode == 0 and p.stdout.strip() == f"rvbacklash {__version__}"
    assert "[arcmin]" in run_cli("simulate", "--help").stdout
    assert "[deg]" in run_cli("contact", "--help").stdout
    assert "[mm]" in run_cli("tolerance", "iso1328", "--help").stdout


def test_help_does_not_load_the_heavy_modules():
    """`rvbacklash --help` must not import scipy, numba, numpy or pydantic (start-up time)."""
    # read in an exit handler: the console script's main() ends the process itself (cli.main)
    code = ("import atexit, sys\nfrom rvbacklash.cli import main\nsys.argv=['rvbacklash','--help']\n"
            "atexit.register(lambda: print('LOADED:' + '|'.join(m for m in ('scipy', 'numba', 'numpy', "
            "'pydantic', 'matplotlib') if m in sys.modules)))\n"
            "main()\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.stdout.strip().splitlines()[-1] == "LOADED:", p.stdout


COMMANDS = {  # every command with a result, and a cheap invocation
    "analyze": ["analyze", "sun2014"],
    "simulate": ["simulate", "sun2014", "-n", "2000"],
    "compare": ["compare", "rv80e", "--scenario", "x:all=5", "-n", "2000"],
    "contact": ["contact", "rv80e"],
    "iso1328": ["tolerance", "iso1328", "--module", "1.75", "--diameter", "66.5", "--width", "15", "--grade", "5"],
    "iso286": ["tolerance", "iso286", "--size", "8", "--grade", "IT6", "--fit", "H7/g6"],
}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_one_meaning_per_flag(name, tmp_path):
    """--json FILE, --csv FILE, --format json|csv on stdout and -q/--quiet on every command
    with a result (issue 9): the stdout formats are the files' contents."""
    args = COMMANDS[name]
    j, c = tmp_path / "r.json", tmp_path / "r.csv"
    p = run_cli(*args, "--json", j, "--csv", c, "-q")
    assert p.returncode == 0 and p.stdout == "", p.stderr
    as_json = run_cli(*args, "--format", "json")
    as_csv = run_cli(*args, "--format", "csv")
    assert json.loads(as_json.stdout).keys() == json.loads(j.read_text()).keys()
    assert as_csv.stdout.splitlines()[0] == c.read_text().splitlines()[0]
    assert len(as_csv.stdout.splitlines()) == len(c.read_text().splitlines()) >= 2
    dash = run_cli(*args, "--json", "-")
    assert dash.returncode == 0 and json.loads(dash.stdout).keys() == json.loads(j.read_text()).keys()
    assert not (tmp_path / "-").exists()


@pytest.mark.parametrize("args,fragment", [
    (["simulate", "rv80e", "--seed", "abc"], "error: --seed = 'abc': allowed: a valid integer"),
    (["simulate", "rv80e", "--workers", "two"], "error: --workers = 'two'"),
    (["simulate", "rv80e", "--spec-arcmin", "tight"], "error: --spec-arcmin = 'tight': allowed: a valid number"),
    (["tolerance", "iso1328", "--module", "1", "--diameter", "20", "--width", "10", "--grade", "five"],
     "error: --grade = 'five'"),
    (["analyze", "sun2014", "--format", "xml"], "one of 'table', 'json', 'csv'"),
    (["analyze", "sun2014", "--json", "-", "--format", "json"], "already writes to standard output"),
    (["contact", "rv80e", "--crank-angle-deg", "1e20"], "--crank-angle-deg = 1e+20: allowed: -360 <= angle <= 360"),
    (["contact", "rv80e", "--crank-angle-deg", "nan"], "--crank-angle-deg"),
    (["compare", "rv80e", "--scenario", "a:involute=5,involute=6"], "given twice"),
    (["compare", "rv80e", "--scenario", "a:"], "is not key=grade"),
    (["compare", "rv80e", "--scenario", "x:pin_wheel=5"], "unknown key"),
    (["compare", "rv80e", "--scenario", "x:involute=14"], "grades.involute"),
    (["compare", "rv80e"], "at least one --scenario"),
    (["analyze"], "Missing argument"),
    (["analyze", "rv90x"], "design = 'rv90x': allowed: a path to an existing .toml file or a built-in example "
                           "(rv80e, sun2014)"),
    (["tolerance", "iso1328", "--module", "1.75", "--diameter", "66.5", "--width", "15", "--grade", "13"],
     "--grade = 13: allowed: ISO 1328-1:1995 grades 0 to 12"),
    (["tolerance", "iso1328", "--edition", "2001", "--module", "1.75", "--diameter", "66.5", "--width", "15",
      "--grade", "5"], "--edition = '2001': allowed: 1995, 2013"),
    (["tolerance", "iso1328", "--module", "1.75", "--diameter", "12000", "--width", "15", "--grade", "5"],
     "--diameter = 12000.0: ISO 1328-1:1995 covers 5 <= d <= 10000"),
    (["tolerance", "iso286", "--size", "800", "--grade", "IT6"], "--size = 800.0"),
    (["tolerance", "iso286", "--size", "8", "--grade", "IT13"], "IT1 to IT12"),
    # review regressions: flags, not Python names; the range that is checked; the flag that was given
    (["report", "rv80e", "-o", "r.html", "--allocate", "--yield", "0.99"], "error: --spec-arcmin = None: allowed: "
                                                                          "a spec > 0 [arcmin]"),
    (["report", "rv80e", "-o", "r.html", "--allocate", "--spec-arcmin", "3"], "0.5 < P < 1"),
    (["report", "rv80e", "-o", "r.html", "--sweep", "no-such-dir"], "error: --sweep = 'no-such-dir'"),
    (["simulate", "rv80e", "-n", "1000", "--error-model", "independent"],
     "error: --error-model = 'independent': allowed with the contact or elastic model only"),
    (["sensitivity", "rv80e", "--model", "contact", "--output", "rigidity"],
     "error: --output = 'rigidity': allowed outputs of the contact model: backlash"),
    (["allocate", "rv80e", "--model", "contact", "--spec-arcmin", "2", "--yield", "0.9", "-n", "1e9"],
     "error: --samples = 1000000000: allowed: a whole number of samples per candidate, 1000 to 1e7"),
])
def test_bad_input_is_one_line(args, fragment, tmp_path):
    out = tmp_path / "o.json"
    p = run_cli(*args, *(["--json", out] if "--json" not in args else []))
    one_line_error(p, fragment)
    assert not out.exists()


def test_the_same_file_for_two_outputs_is_refused(tmp_path):
    f = tmp_path / "x.out"
    one_line_error(run_cli("analyze", "sun2014", "--json", f, "--csv", f), "also given to --json")
    assert not f.exists()


def test_bad_design_file_through_the_cli(tmp_path, sun2014_toml):
    bad = tmp_path / "bad.toml"
    bad.write_text(sun2014_toml.replace("planets = 3", "planets = true"))
    one_line_error(run_cli("simulate", bad, "-n", "1000", "--json", tmp_path / "s.json"),
                   "first_stage.planets = True")
    assert list(tmp_path.iterdir()) == [bad]


def test_unwritable_output(tmp_path):
    one_line_error(run_cli("analyze", "sun2014", "--json", tmp_path / "no" / "such" / "dir.json"), "error: --json")


def test_tolerance_values():
    p = run_cli("tolerance", "iso1328", "--edition", "1995", "--module", "1.75", "--diameter", "66.5", "--width",
                "15", "--grade", "5", "--format", "json")
    d = json.loads(p.stdout)
    # ISO 1328-1:1995 table rows for 50 < d <= 125, 0.5 <= m <= 2, grade 5 (data/iso1328-1_1995.csv)
    assert (d["fpt_um"], d["Fp_um"], d["Falpha_um"], d["ffalpha_um"], d["Fr_um"]) == (5.5, 18, 6.0, 4.5, 15)
    d = json.loads(run_cli("tolerance", "iso286", "--size", "8", "--grade", "IT6", "--fit", "H7/g6", "--json",
                           "-").stdout)
    assert d["IT_um"] == 9 and d["fit"]["clearance_min_um"] == 5 and d["fit"]["clearance_max_um"] == 29


def test_contact_command(tmp_path):
    out = tmp_path / "c.json"
    p = run_cli("contact", "rv80e", "--json", out, "--plot", tmp_path / "c.svg", "--crank-angle-deg", "3")
    assert p.returncode == 0, p.stderr
    assert "play ccw [arcmin]" in p.stdout and "disc" in p.stdout
    d = json.loads(out.read_text())
    assert d["crank_angle_deg"] == pytest.approx(3) and [x["disc"] for x in d["discs"]] == [1, 2]
    assert d["cycloid_stage_preloaded"] is False and d["cycloid_stage_arcmin"] > 0
    assert (tmp_path / "c.svg").read_text().count("<svg") == 1


def test_contact_of_a_preloaded_design_is_reported_not_crashed(tmp_path, rv80e_toml):
    """Regression (issue 9): report and contact on rv80e with equidistance -20 um crashed with a
    45-line ArithmeticError traceback."""
    f = tmp_path / "tight.toml"
    f.write_text(rv80e_toml.replace("equidistance_modification_um = 5.0", "equidistance_modification_um = -20.0"))
    p = run_cli("contact", f)
    assert p.returncode == 0 and "preloaded" in p.stdout, p.stderr
    p = run_cli("report", f, "-n", "20000", "-o", tmp_path / "r.html")
    assert p.returncode == 0, p.stderr
    assert "preloaded" in (tmp_path / "r.html").read_text()


def test_every_model_flag_lists_every_model():
    """Regression: the help of `simulate --model` (and compare's, report's) left out transmission;
    every --model / --allocate-model help names every model the commands accept."""
    import typer

    from rvbacklash.analysis.simulation import MODELS
    from rvbacklash.cli.entry import app

    seen = []
    for name, command in typer.main.get_command(app).commands.items():
        for param in getattr(command, "params", []):
            if {"--model", "--allocate-model"} & set(getattr(param, "opts", ())):
                words = set(re.findall(r"[a-z]+", param.help))
                assert set(MODELS) <= words, (name, param.opts, set(MODELS) - words)
                seen.append(name)
    assert sorted(seen) == ["allocate", "compare", "report", "report", "sensitivity", "simulate"]


LONG = "x" * 300  # longer than any file system's NAME_MAX (255 bytes on Linux, macOS, Windows)


@pytest.mark.parametrize("args, flag", [
    (["analyze", "sun2014", "--json", "{d}/" + LONG + ".json"], "--json"),
    (["analyze", "sun2014", "--csv", "{d}/" + LONG], "--csv"),
    (["contact", "rv80e", "--plot", "{d}/" + LONG + "/c.svg"], "--plot"),
    (["report", "rv80e", "-n", "1000", "-o", "{d}/" + LONG], "--output"),
    (["simulate", "rv80e", "--model", "contact", "-n", "1000", "--save-units", "2", "{d}/" + LONG], "--save-units"),
    (["contact", "rv80e", "--measured", "{d}/" + LONG + ".toml"], "--measured"),
    (["allocate", "rv80e", "--spec-arcmin", "3", "--yield", "0.9", "--write-design", "{d}/" + LONG], "--write-design"),
    (["sweep", "modifications-sweep", "--out", "{d}/" + LONG], "--out"),
    (["sweep", "{d}/" + LONG + ".toml"], "sweep"),
    (["analyze", "{d}/" + LONG + ".toml"], "design"),
])
def test_a_file_name_too_long_is_one_line(tmp_path, args, flag):
    """Regression: a name longer than the file system allows crashed every command that takes a
    path (OSError: File name too long, exit 1); now one line naming the flag, exit 2, nothing written."""
    line = one_line_error(run_cli(*[a.format(d=tmp_path) for a in args]), f"error: {flag} = ")
    assert "file name too long (30" in line and "at most 255 bytes" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, flag", [
    (["transmission-error", "rv80e", "--positions", "400", "--json", "newdir/"], "--json"),
    (["hysteresis", "rv80e", "--plot", "newdir2/"], "--plot"),
    (["report", "rv80e", "-n", "1000", "-o", "newdir3/"], "--output"),
    (["analyze", "sun2014", "--csv", "./"], "--csv"),
])
def test_a_trailing_slash_names_a_directory_not_a_file(tmp_path, monkeypatch, args, flag):
    """Regression: `--json newdir/` for a folder that does not exist wrote a *file* named newdir
    and exited 0 (pathlib drops the slash)."""
    monkeypatch.chdir(tmp_path)
    line = one_line_error(run_cli(*args), f"error: {flag} = '{args[-1]}': ends in a slash, which names a directory")
    assert "allowed: a file path" in line
    assert list(tmp_path.iterdir()) == []
