"""`rvbacklash sweep` and `sweep-plot`: files point by point, a re-run resumes, one-line errors
naming the file's field or the flag, Ctrl-C keeps the finished points (exit 130)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import tomllib

import pytest

from helpers import ROOT, one_line_error, run_cli

SWEEP = """
design = "rv80e"
model = "linear"
samples = {samples}
seed = 2
spec_arcmin = 2.0

[[parameters]]
path = "second_stage.equidistance_modification_um"
label = "equidistance [um]"
start = 0
stop = {stop}
count = {count}

[[parameters]]
path = "second_stage.moving_distance_modification_um"
values = [0.0, 3.0]
"""


@pytest.fixture
def sweep_file(tmp_path):
    p = tmp_path / "mods.toml"
    p.write_text(SWEEP.format(samples=2000, stop=8, count=3))
    return p


def test_examples_list_and_print_the_example_sweep(tmp_path):
    listing = run_cli("examples").stdout.splitlines()
    assert any(line.startswith("modifications-sweep") and "sweep:" in line for line in listing)
    p = run_cli("examples", "modifications-sweep")
    assert p.returncode == 0
    data = tomllib.loads(p.stdout)
    assert data["design"] == "rv80e" and data["model"] == "contact" and len(data["parameters"]) == 2


def test_sweep_writes_the_results_and_a_rerun_skips_them(sweep_file, tmp_path):
    out = tmp_path / "out"
    p = run_cli("sweep", sweep_file, "--out", out, "--scheduler", "inline")
    assert p.returncode == 0, p.stderr
    assert "6 points run (inline), 0 found finished" in p.stdout and f"wrote {out / 'plot.svg'}" in p.stdout
    assert "best 6 of 6 points by backlash_yield" in p.stdout
    names = {f.name for f in out.iterdir()}
    assert {"sweep.json", "sweep.toml", "results.parquet", "results.csv", "plot.svg", "sweep.html", "points"} <= names
    assert len(list((out / "points").glob("*.json"))) == 6
    lines = (out / "results.csv").read_text().splitlines()
    assert lines[0].startswith("point,second_stage.equidistance_modification_um,"
                               "second_stage.moving_distance_modification_um,samples,") and len(lines) == 7
    assert (out / "plot.svg").read_text().lstrip().startswith("<?xml")
    html = (out / "sweep.html").read_text()
    assert html.startswith("<!DOCTYPE html>") and 'id="sweep-table"' in html and "<svg" in html
    assert "http://" not in html.replace("http://www.w3.org", "")  # self-contained
    state = json.loads((out / "sweep.json").read_text())
    assert state["status"] == "complete" and state["points_done"] == 6
    again = run_cli("sweep", sweep_file, "--out", out, "--format", "json")
    assert again.returncode == 0, again.stderr
    data = json.loads(again.stdout)
    assert data["skipped"] == 6 and data["partial"] is False and len(data["rows"]) == 6
    assert data["scheduler"] == "inline"  # nothing left to run: no cluster is started


def test_another_sweep_into_the_directory_is_refused_without_force(sweep_file, tmp_path):
    out = tmp_path / "out"
    assert run_cli("sweep", sweep_file, "--out", out, "--scheduler", "inline", "-q").returncode == 0
    other = tmp_path / "other.toml"
    other.write_text(SWEEP.format(samples=1000, stop=8, count=3))
    line = one_line_error(run_cli("sweep", other, "--out", out, "--scheduler", "inline"), "different sweep")
    assert line.startswith(f"error: --out = '{out}'") and "--force" in line
    p = run_cli("sweep", other, "--out", out, "--scheduler", "inline", "--force", "--format", "csv")
    assert p.returncode == 0 and p.stdout.splitlines()[1].split(",")[3] == "1000"


@pytest.mark.parametrize("change,fragment", [
    (("second_stage.moving_distance_modification_um", "second_stage.moving_um"),
     "mods.toml: parameters[1].path = 'second_stage.moving_um': unknown field 'moving_um' in second_stage"),
    (("stop = 8", "stop = 1200"), "mods.toml: point 4 (second_stage.equidistance_modification_um = 1200.0, "
                                  "second_stage.moving_distance_modification_um = 0.0): parameters[0] "
                                  "second_stage.equidistance_modification_um = 1200.0: "),
    (("samples = 2000", "samples = -3"), "mods.toml: samples = -3: "),
    # review regressions: a negative limit ran with yield 0 everywhere; a name with a path escaped --out
    (("spec_arcmin = 2.0", "spec_arcmin = 2.0\n[specs]\nbacklash = -1.0"),
     "mods.toml: specs.backlash = -1.0: allowed: a finite limit > 0"),
    (('design = "rv80e"', 'name = "../evil"\ndesign = "rv80e"'), "mods.toml: name = '../evil': String should match"),
])
def test_a_bad_sweep_is_one_line_naming_the_field(sweep_file, tmp_path, change, fragment):
    sweep_file.write_text(sweep_file.read_text().replace(*change))
    one_line_error(run_cli("sweep", sweep_file, "--out", tmp_path / "o"), fragment)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("args,fragment", [
    (["nope.toml"], "error: sweep = 'nope.toml': allowed: a path to an existing SWEEP.toml file or a built-in "
                    "example sweep (modifications-sweep)"),
    (["--scheduler", "dask"], "error: --scheduler = 'dask': allowed: inline, local, or the address"),
    (["--workers", "-1"], "error: --workers = -1"),
    (["--scheduler", "tcp://127.0.0.1:1", "--workers", "2"], "error: --workers = 2: allowed only with scheduler"),
])
def test_bad_flags_are_one_line(sweep_file, tmp_path, args, fragment):
    argv = args if args[0] == "nope.toml" else [str(sweep_file), *args]
    one_line_error(run_cli("sweep", *argv, "--out", tmp_path / "o"), fragment)


def test_sweep_plot_draws_a_chosen_figure(sweep_file, tmp_path):
    out = tmp_path / "out"
    assert run_cli("sweep", sweep_file, "--out", out, "--scheduler", "inline", "-q").returncode == 0
    svg, page = tmp_path / "q.svg", tmp_path / "q.html"
    p = run_cli("sweep-plot", out, "--figure", "backlash_q99865", "--x", "equidistance [um]", "--plot", svg,
                "--html", page)
    assert p.returncode == 0, p.stderr
    # least clearance, least backlash: no equidistance and the most moving-distance modification
    assert "best backlash_q99865 = " in p.stdout and "at point 1 " in p.stdout
    assert svg.read_text() != (out / "plot.svg").read_text()  # not the default figure (the yield)
    assert page.read_text().count("<svg") >= 2
    one_line_error(run_cli("sweep-plot", out, "--plot", svg), "--plot")  # exists: --force to replace
    one_line_error(run_cli("sweep-plot", out, "--figure", "yield"), "error: --figure = 'yield': allowed: a column")
    one_line_error(run_cli("sweep-plot", out, "--x", "nope"), "error: --x = 'nope': allowed: a parameter of the sweep")
    one_line_error(run_cli("sweep-plot", tmp_path, "--plot", tmp_path / "z.svg"), f"error: DIR = '{tmp_path}': holds "
                                                                                  f"no sweep results")


def test_ctrl_c_keeps_the_finished_points_and_the_next_run_finishes(tmp_path):
    """A real SIGINT to the command: exit 130, the finished points kept and marked partial; the
    same command again runs only the rest (no point lost or repeated)."""
    sweep = tmp_path / "long.toml"
    # points long enough (~0.1-0.2 s each on 2 cores) that the signal lands while the sweep runs:
    # at 500 000 samples the whole sweep could end between two polls of the points written
    sweep.write_text(SWEEP.format(samples=5_000_000, stop=14, count=8))
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.Popen([sys.executable, "-m", "rvbacklash", "sweep", str(sweep), "--out", str(out),
                             "--scheduler", "inline", "-q"], stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None and len(list(out.glob("points/*.json"))) < 2:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=120)[1]
    assert proc.returncode == 130, err
    assert "interrupted:" in err and "run the same command again to resume" in err and "Traceback" not in err
    state = json.loads((out / "sweep.json").read_text())
    done = state["points_done"]
    assert state["status"] == "partial" and 2 <= done < 16
    assert len(list((out / "points").glob("*.json"))) == done
    p = run_cli("sweep", sweep, "--out", out, "--scheduler", "inline", "--format", "json")
    assert p.returncode == 0, p.stderr
    data = json.loads(p.stdout)
    assert data["skipped"] == done and [r["point"] for r in data["rows"]] == list(range(16))


def test_a_sampled_design_and_a_one_parameter_sweep_are_drawn(tmp_path):
    """Latin hypercube over three parameters (one of them a string): points coloured by the
    figure; one parameter: a line. Both pages and figures are written."""
    lhs = tmp_path / "lhs.toml"
    lhs.write_text('design = "rv80e"\nsamples = 1000\nspec_arcmin = 2.0\nsampling = "latin-hypercube"\npoints = 6\n'
                   '[[parameters]]\npath = "second_stage.equidistance_modification_um"\nlow = 0\nhigh = 10\n'
                   '[[parameters]]\npath = "grades.cycloid"\nlow = 3\nhigh = 6\n'
                   '[[parameters]]\npath = "grades.edition"\nvalues = ["1995", "2013"]\n')
    one = tmp_path / "one.toml"
    one.write_text('design = "rv80e"\nsamples = 1000\n[[parameters]]\npath = "grades.cycloid"\nvalues = [4, 6]\n')
    for f in (lhs, one):
        p = run_cli("sweep", f, "--out", tmp_path / f.stem, "--scheduler", "inline", "--format", "csv")
        assert p.returncode == 0, p.stderr
        assert (tmp_path / f.stem / "plot.svg").is_file() and (tmp_path / f.stem / "sweep.html").is_file()
    rows = p.stdout.splitlines()
    assert rows[0].startswith("point,grades.cycloid,samples,") and len(rows) == 3
    q = [float(r.split(",")[rows[0].split(",").index("backlash_q99865")]) for r in rows[1:]]
    assert q[0] < q[1]  # grade 4 (tighter) before grade 6: less lost motion
    p = run_cli("sweep-plot", tmp_path / "lhs", "--x", "grades.edition", "--y", "grades.cycloid", "--plot",
                tmp_path / "e.svg")
    assert p.returncode == 0 and (tmp_path / "e.svg").is_file(), p.stderr
