"""Figures: what a reader needs to see is there and legible."""

import matplotlib.pyplot as plt

from rvbacklash.analysis.scenarios import Scenario, compare
from rvbacklash.report import plots


def test_scenario_legend_sits_below_the_axes(rv80e_problem):
    """Regression (issue 9): the legend covered the upper tails of the distributions."""
    comp = compare(rv80e_problem, [Scenario("a", {"all": 6}), Scenario("b", {"all": 4})], method="exact")
    fig = plots.scenario_overlay_figure(comp.scenarios, 3.0)
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent()
    assert legend.y1 < ax.get_window_extent().y0  # entirely below the plotting area
    plt.close(fig)


def test_tornado_labels_are_legible_and_colours_explained(sun2014_result):
    """Regression (issue 9): ~5 px labels, unexplained colours."""
    fig = plots.tornado_figure(sun2014_result)
    ax = fig.axes[0]
    assert min(t.get_fontsize() for t in ax.get_yticklabels()) >= 9
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["more backlash", "less backlash"]
    plt.close(fig)


def test_svg_is_deterministic_and_offline(sun2014_result):
    a, b = plots.pareto_svg(sun2014_result), plots.pareto_svg(sun2014_result)
    assert a == b and "<metadata>" not in a and "http://" not in a.replace("http://www.w3.org", "")
