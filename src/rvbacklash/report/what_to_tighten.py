"""The "What to tighten" additions of the HTML report: the partial template
``templates/_what_to_tighten.html.j2`` (Sobol indices of any model, the tolerance allocation and
its Pareto front) and the variables it needs. The report includes the partial in its "What to
tighten" section with ``what_to_tighten_context(...)`` merged into its own variables."""

from __future__ import annotations

from rvbacklash.report.allocation_plots import front_svg
from rvbacklash.report.plots import inline_svg
from rvbacklash.report.sensitivity_plots import sobol_svg
from rvbacklash.report.templating import environment

PARTIAL = "_what_to_tighten.html.j2"


def what_to_tighten_context(sensitivity=None, allocation=None) -> dict:
    """Variables of the partial: the results (either may be None) and their inline SVG figures."""
    figures = {}
    if sensitivity is not None:
        figures["sobol"] = inline_svg(sobol_svg(sensitivity))
    if allocation is not None:
        figures["front"] = inline_svg(front_svg(allocation))
    return {"sensitivity": sensitivity, "allocation": allocation, "tighten_figures": figures}


def render_what_to_tighten(sensitivity=None, allocation=None) -> str:
    """The partial rendered on its own (an HTML fragment), with the report's environment settings."""
    env = environment()
    return env.get_template(PARTIAL).render(**what_to_tighten_context(sensitivity, allocation))
