"""The elastic model's figures and the report partial render from results."""

import pytest

from rvbacklash.analysis.hysteresis import elastic_section
from rvbacklash.analysis.simulation import simulate
from rvbacklash.problem import prepare
from rvbacklash.report.elastic_plots import elastic_figures, loop_svg
from rvbacklash.report.templating import environment


@pytest.fixture(scope="module")
def section(rv80e):
    problem = prepare(rv80e)
    sim = simulate(problem, samples=1000, seed=1, model="elastic", specs={"lost_motion": 1.0, "rigidity": 1200.0})
    return elastic_section(problem, simulation=sim, specs={"lost_motion": 1.0, "rigidity": 1200.0}, samples=100,
                           points=5)


def test_loop_svg_is_deterministic(section):
    a = loop_svg(section.nominal)
    assert a.lstrip().startswith("<?xml") and "<svg" in a
    assert loop_svg(section.nominal) == a


def test_partial_renders_with_every_figure(section):
    figures = elastic_figures(section)
    assert figures["elastic_loop"].startswith("<svg") and figures["elastic_histograms"].startswith("<svg")
    html = environment().get_template("_elastic_section.html.j2").render(elastic=section, elastic_figures=figures)
    assert 'id="elastic"' in html and 'id="fig-elastic-loop"' in html and 'id="fig-elastic-histograms"' in html
    assert f"{section.nominal.lost_motion_arcmin:.3f}" in html
    assert "every spec at once" in html and "cycloid pins" in html
