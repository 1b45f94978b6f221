"""The report's selective assembly section (issue 39, continued): the report's own run is the random
assembly the selection is compared with, the same units selected, the yield versus the pin classes,
the section on the page and in the JSON; the CLI's --select and the design's table."""

import json

import pytest

from helpers import one_line_error, run_cli


@pytest.fixture(scope="module")
def selected_report():
    import rvbacklash as rb

    data = rb.make_report("rv80e", samples=1500, seed=2, model="elastic", spec_arcmin=1.0,
                          select="pins=5x2um,rollers=3x2um")
    return data, rb.render_html(data)


def test_section_compares_the_reports_own_run_with_the_same_units_selected(selected_report):
    from rvbacklash.report.files import render_json

    data, html = selected_report
    s = data.selection
    y = s.yields[0]
    assert y.output == "lost_motion" and y.random == data.simulation.outputs["lost_motion"].yield_
    assert y.selected.fraction > y.random.fraction + 0.05
    d = json.loads(render_json(data.to_dict()))
    assert "random_run" not in d["selection"] and "selected_run" not in d["selection"]
    assert d["selection"]["selected_outputs"]["lost_motion"]["yield"]["fraction"] == y.selected.fraction
    assert data.key_numbers()["selection.selected_outputs.lost_motion.yield"] == y.selected.fraction
    sweep = d["selection_sweep"]
    assert [p["pin_classes"] for p in sweep["points"]] == [1, 3, 5, 9]
    one = sweep["points"][0]  # one pin class with the rollers selected: between random and the full selection
    assert sweep["random_yield"]["fraction"] <= one["yield"]["fraction"]
    assert 'id="selection"' in html and 'id="fig-selection-classes"' in html and 'id="selection-yields"' in html
    assert f'data-value="{y.selected.fraction}"' in html


def test_report_without_select_has_no_section(selected_report):
    import rvbacklash as rb

    data = rb.make_report("rv80e", samples=200, seed=2, model="contact", spec_arcmin=1.0)
    assert data.selection is None and data.to_dict()["selection"] is None
    assert 'id="selection"' not in rb.render_html(data)


def test_cli_report_select_and_its_errors(tmp_path):
    p = run_cli("report", "rv80e", "--model", "contact", "-n", "600", "--spec-arcmin", "1.5", "--select",
                "pins=3x2um", "-o", tmp_path / "r.html", "--json", tmp_path / "r.json")
    assert p.returncode == 0, p.stderr
    d = json.loads((tmp_path / "r.json").read_text())
    assert d["selection"]["selection"]["pins"]["count"] == 3 and 'id="selection"' in (tmp_path / "r.html").read_text()
    one_line_error(run_cli("report", "rv80e", "-n", "600", "--spec-arcmin", "1.5", "--select", "pins=3x2um", "-o",
                           tmp_path / "x.html"), "contact, elastic or transmission")
    one_line_error(run_cli("report", "rv80e", "--model", "contact", "-n", "600", "--select", "pins=3x", "-o",
                           tmp_path / "x.html"), "--select")
    assert not (tmp_path / "x.html").exists()
