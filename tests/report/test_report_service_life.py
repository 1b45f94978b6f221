"""The report's service-life section (issue 38 item 6): rendered from the ServiceLifeResult it is
given; its cards and table show the numbers ``rvbacklash service-life`` computes for the same
design, duty cycle, seed, hours and units; ``--duty-cycle`` is its cycle and a bad one fails first."""

import json
import re

import pytest

import rvbacklash as rb
from helpers import one_line_error, run_cli
from rvbacklash.report.html import render_html

UNITS = 200  # the report's production run is min(samples, 2000) units


def shown(page: str, key: str) -> float | None:
    m = re.search(rf'data-key="{re.escape(key)}" data-value="([^"]+)"', page)
    assert m, key
    return json.loads(m.group(1))


@pytest.fixture(scope="module")
def slow_cycle(tmp_path_factory):
    """A duty cycle of its own (half robot-joint's torques): the section must use the one given."""
    path = tmp_path_factory.mktemp("cycle") / "half.csv"
    path.write_text("time_s,output_speed_rpm,output_torque_nm\n0.2,7.5,750\n1.0,15,250\n0.2,7.5,-400\n"
                    "0.6,0,150\n0.2,7.5,-750\n1.0,15,-250\n")
    return path


def test_the_section_shows_the_service_life_commands_numbers():
    data = rb.make_report("rv80e", samples=UNITS, seed=1, service_life=True, service_life_hours=(0, 1000))
    got = data.to_dict()["service_life"]
    alone = rb.service_life("rv80e", duty_cycle="robot-joint", hours=[0, 1000], samples=UNITS, seed=1).to_dict()
    assert got == alone  # the section is the service-life command's result, robot-joint by default
    assert "robot-joint" in got["duty_cycle"] and data.to_dict()["efficiency"] is None
    assert got["production"]["units"] == UNITS and got["points"][-1]["hours"] == 1000.0
    assert got["points"][-1]["lost_motion_arcmin"] > got["points"][0]["lost_motion_arcmin"]  # it wears
    page = render_html(data)
    start = page.index('id="service-life"')
    section = page[start:page.index("</section>", start)]
    for text in ("Precision over the service life", 'id="service-life-yield-card"', 'id="service-life-life-card"',
                 'id="fig-service-life"', "<svg", 'id="service-life-hours"', f"{UNITS} units", "robot-joint"):
        assert text in section, text
    assert shown(page, "service_life.trajectory.0.lost_motion_arcmin") == got["trajectory"][0]["lost_motion_arcmin"]
    assert got["trajectory"][0]["hours"] == 0.0
    assert shown(page, "service_life.points.1.lost_motion_arcmin") == got["points"][1]["lost_motion_arcmin"]
    assert shown(page, "service_life.production.yield_at_hours.1.fraction") == \
        got["production"]["yield_at_hours"][1]["fraction"]
    assert shown(page, "service_life.production.accuracy_life_quantiles_h.50%") == \
        got["production"]["accuracy_life_quantiles_h"]["50%"]
    table = section[section.index('id="service-life-hours"'):]
    for p, y in zip(got["points"], got["production"]["yield_at_hours"]):
        assert f"<td>{p['lost_motion_arcmin']:.3f}</td>" in table and f"<td>{100 * y['fraction']:.1f} %</td>" in table
    assert 'id="service-life"' not in render_html(rb.make_report("rv80e", samples=200, seed=1))


def test_the_reports_json_has_the_section_of_the_duty_cycle_given(tmp_path, slow_cycle):
    """--duty-cycle with --service-life is the section's cycle (and, so, does not imply --efficiency)."""
    out, page = tmp_path / "r.json", tmp_path / "r.html"
    p = run_cli("report", "rv80e", "-n", "50", "--seed", "2", "--service-life", "--duty-cycle", slow_cycle,
                "--hours", "0,500", "-o", page, "--json", out, "-q")
    assert p.returncode == 0, p.stderr
    data = json.loads(out.read_text())
    alone = rb.service_life("rv80e", duty_cycle=slow_cycle, hours=[0, 500], samples=50, seed=2).to_dict()
    assert data["service_life"] == json.loads(json.dumps(alone))
    assert data["efficiency"] is None
    assert 'id="service-life"' in page.read_text()


def test_a_bad_duty_cycle_or_hours_fail_first_with_one_line(tmp_path):
    bad = tmp_path / "cycle.csv"
    bad.write_text("time_share,output_torque_nm\n1.0,100\n")  # no speed column
    html = tmp_path / "r.html"
    one_line_error(run_cli("report", "rv80e", "-n", "100", "--service-life", "--duty-cycle", bad, "-o", html))
    one_line_error(run_cli("report", "rv80e", "-n", "100", "--service-life", "--hours", "0,x", "-o", html), "hours")
    one_line_error(run_cli("report", "rv80e", "-n", "100", "--hours", "0,500", "-o", html), "--service-life")
    assert not html.exists()


def test_the_elastic_models_lost_motion_spec_is_the_sections():
    data = rb.make_report("rv80e", samples=50, seed=1, model="elastic", spec_arcmin=1.2, service_life=True,
                          service_life_hours=(0,))
    assert data.service_life.production.spec_lost_motion_arcmin == 1.2 and data.service_life.production.units == 50
