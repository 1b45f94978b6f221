"""The HTML report: one self-contained file (inline CSS and SVG, no network), rendered with
Jinja2 from the same result objects the CLI and the Python API return."""

from __future__ import annotations

import datetime as _dt
import hashlib
import re
from dataclasses import dataclass, field

import jinja2

from rvbacklash import __version__
from rvbacklash.analysis.scenarios import ScenarioResult
from rvbacklash.analysis.simulation import SimulationResult
from rvbacklash.analysis.stackup import StackupResult
from rvbacklash.design.schema import Design
from rvbacklash.report import plots


@dataclass
class ReportData:
    design: Design
    source: str
    source_sha256: str
    stackup: StackupResult
    simulation: SimulationResult
    spec_arcmin: float | None
    scenarios: list[ScenarioResult] = field(default_factory=list)
    contact: object | None = None  # analysis.contact.NominalContact
    warnings: list[str] = field(default_factory=list)
    created_utc: str = ""

    def key_numbers(self) -> dict:
        """The numbers the page shows, by the JSON path they have in ``to_dict``."""
        t, s = self.stackup.total, self.simulation.stats
        out = {
            "design.ratio": self.stackup.geometry.ratio, "design.K1": self.stackup.geometry.K1,
            "total.mean_arcmin": t.mean_arcmin, "total.sigma_arcmin": t.sigma_arcmin,
            "total.plus3sigma_arcmin": t.plus3sigma_arcmin, "total.worst_case_arcmin": t.worst_case_arcmin,
            "total.rss_arcmin": t.rss_arcmin,
            "simulation.mean_arcmin": s["mean_arcmin"], "simulation.std_arcmin": s["std_arcmin"],
            "simulation.q99865_arcmin": s["quantiles"]["0.99865"]["value"],
        }
        if s.get("yield") is not None:
            out["simulation.yield"] = s["yield"]["fraction"]
        return out

    def to_dict(self) -> dict:
        return {"metadata": self.metadata(), "warnings": self.warnings, "key_numbers": self.key_numbers(),
                "analysis": self.stackup.to_dict(), "simulation": self.simulation.to_dict(),
                "scenarios": [s.to_dict() for s in self.scenarios],
                "contact_nominal": self.contact.to_dict() if self.contact is not None else None}

    def metadata(self) -> dict:
        sim = self.simulation
        return {"rvbacklash_version": __version__, "design": self.design.name, "input": self.source,
                "input_sha256": self.source_sha256, "seed": sim.seed, "method": sim.method,
                "samples": sim.samples, "model": sim.model, "spec_arcmin": self.spec_arcmin,
                "standards": standards_used(self.stackup), "created_utc": self.created_utc}


_STANDARD = re.compile(r"(ISO(?:/TR)? \d+(?:-\d)?(?::\d{4})?|GB(?:/T)? [\d.]+-\d{2,4}|assumption)")


def standards_used(stackup: StackupResult) -> list[str]:
    """Standards and editions named in the zones' origins (plus 'assumption' if any)."""
    found = []
    for f in stackup.factors:
        for m in _STANDARD.findall(f.zone_origin):
            if m not in found:
                found.append(m)
    return found


def validity_warnings(design: Design, stackup: StackupResult, sim: SimulationResult) -> list[str]:
    w = []
    g = stackup.geometry
    if g.K1 > 0.9:
        w.append(f"K1 = {g.K1:.3f} is close to 1: the cycloid profile is near its looping limit.")
    if stackup.total.minus3sigma_arcmin < 0:
        frac = sim.stats.get("interference_fraction")
        share = f" ({frac * 100:.2f} % of the samples)" if frac is not None else ""
        w.append(f"mean − 3σ = {stackup.total.minus3sigma_arcmin:.3f} arcmin < 0: the linear model predicts "
                 f"interference (negative lost motion){share}; it cannot see that a gap stops at zero.")
    zero_mean_mods = [f for f in stackup.factors if f.key in ("equidistance_modification", "moving_distance_modification")
                      and f.zone_origin == "explicit" and f.zone_lower_um == -f.zone_upper_um and f.zone_upper_um > 0]
    if zero_mean_mods:
        w.append("the profile modifications are read as zero-mean errors (the paper's reading, errata E7); a designed "
                 "modification has a mean: leave its zone out to use the nominal value.")
    if any("assumption" in f.zone_origin for f in stackup.factors):
        w.append("some zones rest on documented assumptions (docs/standards.md), e.g. the cycloid stage "
                 "(no public JB/T 10419-2005): check them against supplier data.")
    if sim.model == "contact" and (sim.stats.get("interference_fraction") or 0) > 0.01:
        w.append(f"contact model: the cycloid stage is preloaded (rigid interference at some pin) in "
                 f"{sim.stats['interference_fraction'] * 100:.1f} % of the units; per-pin scatter is large against the "
                 f"designed clearance (docs/contact.md).")
    if g.crank_circle_radius_is_default:
        w.append(f"crank circle radius a0 not given: the first-stage centre distance {g.crank_circle_radius_mm:g} mm is used.")
    return w


def sha256_text(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def build_report_data(design: Design, source: str, source_text: str, stackup: StackupResult,
                      simulation: SimulationResult, spec_arcmin: float | None,
                      scenarios: list[ScenarioResult] | None = None, contact=None) -> ReportData:
    return ReportData(design, source, sha256_text(source_text), stackup, simulation, spec_arcmin,
                      scenarios or [], contact, validity_warnings(design, stackup, simulation),
                      _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"))


def make_report(source: str, samples: int | None = 1_000_000, seed: int | None = 0, method: str = "default",
                spec_arcmin: float | None = None, scenarios: list[tuple[str, dict]] | None = None,
                paper: bool = False, progress=None, model: str = "linear") -> ReportData:
    """Everything a report shows, for a design file or example name: stack-up, simulation and
    the scenarios (those given, plus the paper's Fig. 4 set when ``paper``)."""
    from rvbacklash.analysis.contact import nominal_contact
    from rvbacklash.analysis.scenarios import compare, paper_scenarios
    from rvbacklash.analysis.simulation import simulate
    from rvbacklash.analysis.stackup import analyze
    from rvbacklash.design.loading import design_from_toml, read_design_text

    text, origin = read_design_text(source)
    design = design_from_toml(text, origin)
    stack = analyze(design)
    sim = simulate(design, samples, seed, method, spec_arcmin, model=model, progress=progress)
    chosen = (paper_scenarios(design) if paper else []) + list(scenarios or [])
    scen = list(compare(design, chosen, min(samples, 1_000_000) if samples else None, seed, method, spec_arcmin,
                        model)) if chosen else []
    nominal = nominal_contact(design)
    return build_report_data(design, origin, text, stack, sim, spec_arcmin, scen, nominal)


def render_html(data: ReportData) -> str:
    env = jinja2.Environment(loader=jinja2.PackageLoader("rvbacklash.report", "templates"),
                             autoescape=jinja2.select_autoescape(["html", "j2"]), undefined=jinja2.StrictUndefined)
    env.filters["fmt"] = lambda v, spec=".4f": "–" if v is None else format(v, spec)
    figures = {
        "pareto": plots.inline_svg(plots.pareto_svg(data.stackup)),
        "tornado": plots.inline_svg(plots.tornado_svg(data.stackup)),
        "histogram": plots.inline_svg(plots.histogram_svg(data.simulation, data.spec_arcmin)),
        "convergence": plots.inline_svg(plots.convergence_svg(data.simulation)) if data.simulation.convergence else None,
        "scenarios": plots.inline_svg(plots.scenario_overlay_svg(data.scenarios, data.spec_arcmin))
        if data.scenarios else None,
        "contact": plots.inline_svg(plots.contact_svg(data.contact)) if data.contact is not None else None,
    }
    return env.get_template("report.html.j2").render(
        d=data, r=data.stackup, sim=data.simulation, s=data.simulation.stats, meta=data.metadata(),
        keys=data.key_numbers(), figures=figures, scenarios=[sc.to_dict() for sc in data.scenarios],
        contact=data.contact.to_dict() if data.contact is not None else None)
