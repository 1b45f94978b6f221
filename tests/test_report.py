"""The HTML report: end to end, in a real headless browser, and its bad inputs."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import run_cli

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    d = tmp_path_factory.mktemp("report")
    html, js = d / "report.html", d / "report.json"
    p = run_cli("report", "rv80e", "--paper", "--spec-arcmin", "3", "--samples", "200000", "--seed", "1",
                "-o", html, "--json", js)
    assert p.returncode == 0, p.stderr
    assert str(html.resolve()) in p.stdout
    return html, json.loads(js.read_text())


def test_report_is_self_contained(report):
    html, data = report
    text = html.read_text()
    # works offline: nothing is fetched from anywhere (only XML namespaces and in-page url(#id))
    import re
    assert not re.search(r"https?://(?!www\.w3\.org/)", text)
    assert not re.search(r"url\((?!#)", text)
    for needle in ("<script src", "<link ", "@import", "<img src=\"http"):
        assert needle not in text, needle
    for section in ("Design", "Stack-up", "Factors", "Monte-Carlo simulation", "Cycloid–pin contact",
                    "Precision-grade scenarios", "Run"):
        assert f">{section}" in text
    for fig in ("fig-pareto", "fig-tornado", "fig-histogram", "fig-convergence", "fig-scenarios", "fig-contact"):
        assert f'id="{fig}"' in text
    meta = data["metadata"]
    assert meta["seed"] == 1 and meta["samples"] == 200000 and meta["method"] == "default"
    assert len(meta["input_sha256"]) == 64 and meta["rvbacklash_version"]
    assert "ISO 1328-1:1995" in meta["standards"] and "assumption" in meta["standards"]
    assert len(data["scenarios"]) == 4


def test_report_in_a_real_browser(report, tmp_path):
    """Open the report in Debian's chromium: no console errors, every figure has a size, and
    every number marked in the page equals the JSON output."""
    if os.environ.get("RVBACKLASH_SKIP_BROWSER") == "1":
        pytest.skip("RVBACKLASH_SKIP_BROWSER=1")
    assert Path(CHROMIUM).exists(), "chromium missing: run tools/ensure-chromium (make test does)"
    from playwright.sync_api import sync_playwright

    html, data = report
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1200, "height": 1500})
        problems = []
        page.on("console", lambda m: problems.append(m.text) if m.type in ("error", "warning") else None)
        page.on("pageerror", lambda e: problems.append(str(e)))
        page.goto(html.resolve().as_uri())
        page.wait_for_load_state("load")
        boxes = [f.bounding_box() for f in page.query_selector_all("figure svg")]
        marked = page.eval_on_selector_all(
            "[data-key]", "els => els.map(e => [e.dataset.key, e.dataset.value, e.textContent, e.dataset.scale || '1'])")
        page.screenshot(path=str(tmp_path / "report.png"))
        browser.close()
    assert problems == []
    assert len(boxes) == 6 and all(b and b["width"] > 100 and b["height"] > 100 for b in boxes)
    keys = data["key_numbers"]
    assert {k for k, *_ in marked} == set(keys)
    for key, value, text, scale in marked:
        assert float(value) == keys[key], key
        shown = float(text)
        decimals = len(text.partition(".")[2])
        assert shown == pytest.approx(keys[key] * float(scale), abs=0.5 * 10 ** -decimals + 1e-12), key
    assert (tmp_path / "report.png").stat().st_size > 10_000


def test_existing_file_needs_force(tmp_path):
    out = tmp_path / "r.html"
    out.write_text("keep me")
    p = run_cli("report", "sun2014", "-n", "1000", "-o", out)
    assert p.returncode == 2 and "--force" in p.stderr and "Traceback" not in p.stderr
    assert out.read_text() == "keep me"
    p = run_cli("report", "sun2014", "-n", "1000", "-o", out, "--force")
    assert p.returncode == 0 and out.read_text().startswith("<!DOCTYPE html>")


@pytest.mark.parametrize("case", ["unwritable", "directory", "invalid design", "bad samples"])
def test_bad_input_leaves_nothing_behind(case, tmp_path, sun2014_toml):
    target = tmp_path / "out" / "r.html"
    target.parent.mkdir()
    design = "sun2014"
    extra = []
    if case == "unwritable":
        if os.geteuid() == 0:  # root writes anywhere: use a path whose parent is a file
            blocker = tmp_path / "out" / "blocker"
            blocker.write_text("")
            target = blocker / "r.html"
        else:
            target.parent.chmod(0o500)
    elif case == "directory":
        target = tmp_path / "out"
    elif case == "invalid design":
        bad = tmp_path / "bad.toml"
        bad.write_text(sun2014_toml.replace("pins = 40", "pins = 41"))
        design = str(bad)
    else:
        extra = ["-n", "-3"]
    before = sorted(p.name for p in (tmp_path / "out").iterdir())
    p = run_cli("report", design, "-o", target, *extra)
    assert p.returncode == 2, p.stderr
    assert "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == before  # no partial or temporary file


def test_formats_are_consistent(tmp_path):
    for cmd in (["analyze", "sun2014"], ["simulate", "sun2014", "-n", "1000"],
                ["compare", "rv80e", "--scenario", "x:all=5", "-n", "1000"],
                ["tolerance", "iso286", "--size", "8", "--grade", "IT6"]):
        j = run_cli(*cmd, "--format", "json")
        assert j.returncode == 0, j.stderr
        json.loads(j.stdout)
        c = run_cli(*cmd, "--format", "csv")
        assert c.returncode == 0 and "," in c.stdout.splitlines()[0]
    p = run_cli("analyze", "sun2014", "--format", "xml")
    assert p.returncode == 2


def test_quickstart_example_runs_top_to_bottom(tmp_path):
    script = Path(__file__).parents[1] / "examples" / "quickstart.py"
    p = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "yield" in p.stdout
    assert (tmp_path / "quickstart-report.html").read_text().startswith("<!DOCTYPE html>")
    assert (tmp_path / "quickstart-factors.csv").read_text().startswith("id,")
