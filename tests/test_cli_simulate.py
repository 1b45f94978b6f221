"""`rvbacklash simulate` end to end, and its bad inputs."""

import json

import pytest

from conftest import run_cli


def test_simulate_json(tmp_path):
    out = tmp_path / "s.json"
    p = run_cli("simulate", "sun2014", "--samples", "200000", "--seed", "1", "--spec-arcmin", "3", "--json", out)
    assert p.returncode == 0, p.stderr
    d = json.loads(out.read_text())
    assert {"samples", "seed", "method", "mean_arcmin", "std_arcmin", "quantiles", "spec_arcmin", "yield", "cp",
            "cpk", "ppm_out", "histogram"} <= set(d)
    assert set(d["quantiles"]) >= {"0.00135", "0.5", "0.99865"}
    assert all(set(q) == {"value", "ci95"} for q in d["quantiles"].values())
    assert set(d["yield"]) >= {"fraction", "ci95"}
    assert {"edges", "counts"} <= set(d["histogram"])
    assert len(d["histogram"]["edges"]) == len(d["histogram"]["counts"]) + 1
    assert sum(d["histogram"]["counts"]) == 200000
    assert d["samples"] == 200000 and d["seed"] == 1 and d["method"] == "default"
    lo, hi = d["mean_ci95"]
    assert lo <= d["analytic"]["mean_arcmin"] <= hi


def test_simulate_exact_and_scientific_sample_count(tmp_path):
    p = run_cli("simulate", "rv80e", "--method", "exact", "--spec-arcmin", "1.5", "--json", tmp_path / "e.json")
    assert p.returncode == 0, p.stderr
    d = json.loads((tmp_path / "e.json").read_text())
    assert d["method"] == "exact" and d["samples"] is None
    assert 0 < d["yield"]["fraction"] < 1
    p = run_cli("simulate", "rv80e", "--samples", "1e5", "--seed", "0", "--quantile", "0.9", "--json", tmp_path / "f.json")
    assert p.returncode == 0, p.stderr
    assert "0.9" in json.loads((tmp_path / "f.json").read_text())["quantiles"]


BAD_ARGS = {
    "N = 0": (["--samples", "0"], "--samples"),
    "N < 0": (["--samples", "-5"], "--samples"),
    "N non-integer": (["--samples", "1.5"], "--samples"),
    "N not a number": (["--samples", "many"], "--samples"),
    "N too large": (["--samples", "1e13"], "--samples"),
    "N too large for sobol": (["--samples", "2e9", "--method", "sobol"], "--samples"),
    "negative spec": (["--spec-arcmin", "-1"], "--spec-arcmin"),
    "unknown method": (["--method", "latin"], "--method"),
    "negative seed": (["--seed", "-1"], "--seed"),
    "bad quantile": (["--quantile", "1.5"], "--quantile"),
}


@pytest.mark.parametrize("case", sorted(BAD_ARGS))
def test_bad_arguments(case, tmp_path):
    args, field = BAD_ARGS[case]
    out = tmp_path / "s.json"
    p = run_cli("simulate", "sun2014", "--samples", "1000", *args, "--json", out)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert "Traceback" not in p.stderr
    line = p.stderr.strip().splitlines()
    assert len(line) == 1 and line[0].startswith(f"error: {field}"), p.stderr
    assert "allowed" in line[0]
    assert not out.exists()


BAD_DESIGN = {
    "correlation not PSD": ('[correlation]\nfactors = ["disc_runout", "pin_radius", "pin_circle_radius"]\n'
                            'matrix = [[1, 0.9, -0.9], [0.9, 1, 0.9], [-0.9, 0.9, 1]]\n', "positive semi-definite"),
    "correlation unknown factor": ('[correlation]\nfactors = ["disc_runout", "pin_wheel"]\n'
                                   'matrix = [[1, 0.5], [0.5, 1]]\n', "unknown factor 'pin_wheel'"),
    "correlation not symmetric": ('[correlation]\nfactors = ["disc_runout", "pin_radius"]\n'
                                  'matrix = [[1, 0.5], [0.4, 1]]\n', "symmetric"),
}


@pytest.mark.parametrize("case", sorted(BAD_DESIGN))
def test_bad_correlation(case, tmp_path, sun2014_toml):
    extra, fragment = BAD_DESIGN[case]
    f = tmp_path / "d.toml"
    f.write_text(sun2014_toml + "\n" + extra)
    p = run_cli("simulate", f, "--samples", "1000", "--json", tmp_path / "s.json")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert p.stderr.startswith("error: correlation") and fragment in p.stderr, p.stderr
    assert not (tmp_path / "s.json").exists()


BAD_DISTRIBUTION = {
    "sigma <= 0": ("plus_minus_um = 6.5\nsigma_um = 0", "sigma_um = 0"),
    "scale <= 0": ("plus_minus_um = 18.0\ndistribution = \"rayleigh\"\nscale_um = -2", "scale_um = -2"),
    "parameter of another law": ("plus_minus_um = 6.5\ndistribution = \"uniform\"\nsigma_um = 2", "does not apply"),
    "unknown law": ("plus_minus_um = 6.5\ndistribution = \"weibull\"", "distribution"),
    "rayleigh on a signed quantity": ("plus_minus_um = 6.5\ndistribution = \"rayleigh\"", "magnitude-type"),
}


@pytest.mark.parametrize("case", sorted(BAD_DISTRIBUTION))
def test_bad_distribution_parameters(case, tmp_path, sun2014_toml):
    body, fragment = BAD_DISTRIBUTION[case]
    key = "gear_runout" if "scale" in case else "centre_distance"
    head = f"[factors.{key}]"
    start = sun2014_toml.index(head)
    end = sun2014_toml.index("\n[", start + 1)
    f = tmp_path / "d.toml"
    f.write_text(sun2014_toml[:start] + head + "\n" + body + sun2014_toml[end:])
    p = run_cli("simulate", f, "--samples", "1000", "--json", tmp_path / "s.json")
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert fragment in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert not (tmp_path / "s.json").exists()


def test_ctrl_c_reports_the_finished_blocks_marked_partial(tmp_path):
    """SIGINT during a long run: the statistics of the finished blocks, marked partial, exit 130."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "s.json"
    proc = subprocess.Popen([sys.executable, "-m", "rvbacklash", "simulate", "sun2014", "--samples", "1e10",
                             "--seed", "1", "--json", str(out), "--quiet"], stderr=subprocess.PIPE, text=True)
    time.sleep(4.0)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    d = json.loads(out.read_text())
    assert d["partial"] is True and 0 < d["samples_done"] < 10**10
    assert sum(d["histogram"]["counts"]) + d["histogram"]["underflow"] + d["histogram"]["overflow"] == d["samples_done"]
