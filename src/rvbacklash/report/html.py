"""The HTML report: one self-contained file (inline CSS and SVG, no network), rendered with
Jinja2 from the results it is given (``rvbacklash.api.make_report`` gathers them)."""

from __future__ import annotations

from rvbacklash.analysis.report_data import ReportData
from rvbacklash.report import headline, plots
from rvbacklash.report.elastic_plots import elastic_figures
from rvbacklash.report.transmission_plots import transmission_figures
from rvbacklash.report.sweep import section_context as sweep_section_context
from rvbacklash.report.what_to_tighten import what_to_tighten_context
from rvbacklash.report.templating import environment


def render_html(data: ReportData) -> str:
    env = environment()
    sim = data.simulation
    comparison = data.comparison
    figures = {
        "pareto": plots.inline_svg(plots.pareto_svg(data.stackup)),
        "tornado": plots.inline_svg(plots.tornado_svg(data.stackup)),
        # the elastic model's distributions are in its own section (three outputs, their specs)
        "histogram": plots.inline_svg(plots.histogram_svg(sim, data.spec_arcmin)) if sim.model != "elastic" else None,
        "convergence": plots.inline_svg(plots.convergence_svg(sim)) if plots.shows_convergence(sim) else None,
        "scenarios": plots.inline_svg(plots.scenario_overlay_svg(comparison.scenarios, data.spec_arcmin))
        if comparison is not None and comparison.scenarios else None,
        "contact": plots.inline_svg(plots.contact_svg(data.contact)) if data.contact is not None else None,
        "preload": plots.inline_svg(plots.preload_svg(sim)) if "backlash_free" in sim.outputs else None,
    }
    extra = what_to_tighten_context(data.sensitivity, data.allocation)
    if data.elastic is not None:
        extra.update(elastic=data.elastic, elastic_figures=elastic_figures(data.elastic))
    if data.transmission is not None:
        extra.update(transmission=data.transmission, transmission_figures=transmission_figures(data.transmission))
    if data.sweep is not None:
        extra.update(sweep_section_context(data.sweep))
    if data.capacity is not None:
        from rvbacklash.report.capacity_plots import loads_svg, trade_svg

        extra.update(capacity=data.capacity, capacity_figure=plots.inline_svg(loads_svg(data.capacity)))
        if data.capacity_trade is not None:
            extra.update(trade=data.capacity_trade, trade_figure=plots.inline_svg(trade_svg(data.capacity_trade)))
    if data.efficiency is not None:
        from rvbacklash.report.efficiency_plots import efficiency_svg

        extra.update(efficiency=data.efficiency, efficiency_figure=plots.inline_svg(efficiency_svg(data.efficiency)))
    if data.service_life is not None:
        from rvbacklash.report.service_life_plots import service_life_svg

        extra.update(service_life=data.service_life,
                     service_life_figure=plots.inline_svg(service_life_svg(data.service_life)))
    if data.selection is not None:
        extra.update(selection=data.selection)
        if data.selection_sweep is not None:
            from rvbacklash.report.selection import class_sweep_svg

            extra.update(selection_sweep=data.selection_sweep,
                         selection_figure=plots.inline_svg(class_sweep_svg(data.selection_sweep)))
    head = {"title": headline.title(data), "lead": headline.lead(data), "cards": headline.cards(data),
            "model_name": headline.model_name(data.model)}
    return env.get_template("report.html.j2").render(
        d=data, design=data.problem.design, r=data.stackup, sim=sim, out=sim.output, meta=data.metadata(),
        keys=data.key_numbers(), figures=figures, comparison=comparison, contact=data.contact, head=head,
        problem_contact_error_model=data.problem.design.contact.error_model, **extra)
