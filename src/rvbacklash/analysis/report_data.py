"""Everything one report shows, gathered as results (the report layer only renders it)."""

from __future__ import annotations

import datetime as _dt
import re
from dataclasses import dataclass, field

from rvbacklash._version import __version__
from rvbacklash.analysis.contact import NominalContact
from rvbacklash.analysis.scenarios import Comparison
from rvbacklash.analysis.simulation import SimulationResult
from rvbacklash.analysis.stackup import StackupResult
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result


@dataclass(frozen=True, repr=False)
class ReportData(Result):
    """The results of one report: stack-up, simulation, scenarios, nominal contact, warnings."""

    problem: Problem = field(metadata={EXPORT: False})
    stackup: StackupResult
    simulation: SimulationResult
    spec_arcmin: float | None
    comparison: Comparison | None
    contact: NominalContact | None
    warnings: tuple[str, ...]
    created_utc: str
    sensitivity: object | None = None  # analysis.sensitivity_global.SensitivityResult
    allocation: object | None = None  # analysis.allocation.AllocationResult
    elastic: object | None = None  # analysis.hysteresis.ElasticSection
    sweep: object | None = None  # the sweep section (analysis.sweep), when the report shows one
    transmission: object | None = None  # analysis.transmission.TransmissionSection
    capacity: object | None = None  # analysis.capacity.CapacityResult (issue 37)
    capacity_trade: object | None = None  # analysis.capacity.CapacityTrade: lost motion against life
    efficiency: object | None = None  # analysis.losses.EfficiencyResult (issue 40): losses, efficiency, temperature
    selection: object | None = None  # analysis.selection.run.SelectionResult: the run selected (issue 39)
    selection_sweep: object | None = None  # analysis.selection.run.ClassSweep: yield vs the pin classes
    service_life: object | None = None  # analysis.service_life.ServiceLifeResult (issue 38): precision over time

    @property
    def partial(self) -> bool:
        return self.simulation.partial or any(getattr(x, "partial", False) for x in (self.comparison, self.sensitivity,
                                                                                       self.allocation,
                                                                                       self.capacity_trade,
                                                                                       self.selection,
                                                                                       self.service_life))

    def key_numbers(self) -> dict:
        """The numbers the page marks, by the JSON path they have in ``to_dict``, the chosen model's
        first (as the page's first screen): for the linear model its stack-up (``total.*``) and
        run; for the others their run's figures, then the nominal unit's, then the linear stack-up
        that explains them (``design.*``, ``total.*``)."""
        t, s = self.stackup.total, self.simulation
        linear = {"design.ratio": self.stackup.geometry.ratio, "design.K1": self.stackup.geometry.K1,
                  "total.mean_arcmin": t.mean_arcmin, "total.sigma_arcmin": t.sigma_arcmin,
                  "total.plus3sigma_arcmin": t.plus3sigma_arcmin, "total.worst_case_arcmin": t.worst_case_arcmin,
                  "total.rss_arcmin": t.rss_arcmin}
        run = {"simulation.mean_arcmin": s.mean_arcmin, "simulation.sigma_arcmin": s.sigma_arcmin,
               "simulation.q99865_arcmin": s.quantiles.at(0.99865).value}
        if s.yield_ is not None:
            run["simulation.yield"] = s.yield_.fraction
        nominal = {}
        if self.elastic is not None:
            n = self.elastic.nominal
            nominal.update({"elastic.nominal.lost_motion_arcmin": n.lost_motion_arcmin,
                            "elastic.nominal.backlash_arcmin": n.backlash_arcmin,
                            "elastic.nominal.torsional_rigidity_nm_per_arcmin": n.torsional_rigidity_nm_per_arcmin})
        if self.transmission is not None:
            nominal["transmission.nominal.te_peak_to_peak_arcsec"] = self.transmission.nominal.te_peak_to_peak_arcsec
        allocation = {"allocation.cost": self.allocation.cost} if self.allocation is not None else {}
        selected = {}
        if self.selection is not None:  # the first spec's yield selected (random: simulation.<output>.yield)
            y = self.selection.yields[0]
            if y.selected is not None:
                selected[f"selection.selected_outputs.{y.output}.yield"] = y.selected.fraction
        if self.model == "linear":
            return {**linear, **run, **self.model_numbers(), **allocation, **nominal}
        return {**self.model_numbers(), **run, **selected, **nominal, **allocation, **linear}

    @property
    def model(self) -> str:
        return self.simulation.model

    def headline_outputs(self) -> tuple[str, ...]:
        """The outputs the first screen shows for the chosen model (linear: the stack-up's cards)."""
        return {"contact": ("backlash",), "elastic": ("lost_motion", "backlash", "rigidity"),
                "transmission": ("transmission_error", "backlash")}.get(self.model, ())

    def specs(self) -> dict[str, float]:
        """Every spec given, by output (the yields the report shows)."""
        return {k: o.spec_limit for k, o in self.simulation.outputs.items() if o.spec_limit is not None}

    def model_numbers(self) -> dict:
        """The chosen model's headline figures by JSON path (``simulation.<quantity>.<statistic>``):
        mean, the quantile on the spec's side (99.865 %, or 0.135 % for a lower limit such as the
        rigidity), the yield of every output with a spec, the joint yield and the preloaded share."""
        s, out = self.simulation, {}
        for name in self.headline_outputs():
            o = s.outputs.get(name)
            if o is None:
                continue
            out[f"simulation.{name}.mean"] = o.mean
            tail = 0.00135 if name == "rigidity" else 0.99865
            out[f"simulation.{name}.q{tail * 1e5:05.0f}"] = o.quantiles.at(tail).value
        if self.model != "linear":
            for name, o in s.outputs.items():
                if o.yield_ is not None:
                    out[f"simulation.{name}.yield"] = o.yield_.fraction
            if s.joint_yield is not None:
                out["simulation.joint_yield"] = s.joint_yield.fraction
            if s.preload_fraction is not None:
                out["simulation.preload_fraction"] = s.preload_fraction
        return out

    def metadata(self) -> dict:
        sim = self.simulation
        return {"rvbacklash_version": __version__, "design": self.problem.name, "input": self.problem.source,
                "input_sha256": self.problem.source_sha256, "seed": sim.seed, "method": sim.method,
                "samples": sim.samples, "samples_done": sim.samples_done, "model": sim.model,
                "spec_arcmin": self.spec_arcmin, "specs": self.specs(), "partial": self.partial,
                "standards": standards_used(self.stackup), "created_utc": self.created_utc}

    def to_dict(self) -> dict:
        def d(x):
            return x.to_dict() if x is not None else None

        return {"metadata": self.metadata(), "warnings": list(self.warnings), "key_numbers": self.key_numbers(),
                "analysis": self.stackup.to_dict(), "simulation": self.simulation.to_dict(),
                "comparison": d(self.comparison), "contact_nominal": d(self.contact),
                "sensitivity": d(self.sensitivity), "allocation": d(self.allocation), "elastic": d(self.elastic),
                "sweep": d(self.sweep), "transmission": d(self.transmission), "capacity": d(self.capacity),
                "capacity_trade": d(self.capacity_trade), "efficiency": d(self.efficiency),
                "selection": self._selection_dict(),
                "selection_sweep": d(self.selection_sweep), "service_life": d(self.service_life)}

    def _selection_dict(self) -> dict | None:
        """The selection's result without its two runs' full figures: the random run is ``simulation``;
        the selected run's outputs are kept (``selected_outputs``)."""
        if self.selection is None:
            return None
        d = self.selection.to_dict()
        d.pop("random_run")
        run = d.pop("selected_run")
        d["selected_outputs"] = run["outputs"]
        d["selected_joint_yield"] = run.get("joint_yield")
        return d

    def rows(self) -> list[dict]:
        """The key numbers, each row marked ``partial`` when the report was interrupted."""
        return [{"key": k, "value": v, "partial": self.partial} for k, v in self.key_numbers().items()]

    def summary(self) -> list[str]:
        return [f"report of {self.problem.name}" + (" [PARTIAL: interrupted]" if self.partial else "")] + \
            self.stackup.summary()[:1] + self.simulation.summary()[1:2]


_STANDARD = re.compile(r"(ISO(?:/TR)? \d+(?:-\d)?(?::\d{4})?|GB(?:/T)? [\d.]+-\d{2,4}|assumption)")


def standards_used(stackup: StackupResult) -> list[str]:
    """Standards and editions named in the zones' origins (plus 'assumption' if any)."""
    found = []
    for f in stackup.factors:
        for m in _STANDARD.findall(f.zone_origin):
            if m not in found:
                found.append(m)
    return found


def validity_warnings(problem: Problem, stackup: StackupResult, sim: SimulationResult) -> tuple[str, ...]:
    w = []
    g = stackup.geometry
    if g.K1 > 0.9:
        w.append(f"K1 = {g.K1:.3f} is close to 1: the cycloid profile is near its looping limit.")
    if stackup.total.minus3sigma_arcmin < 0:
        frac = sim.output.negative_fraction
        share = f" ({frac * 100:.2f} % of the samples)" if frac is not None and sim.model == "linear" else ""
        if sim.model == "linear":
            w.append(f"mean − 3σ = {stackup.total.minus3sigma_arcmin:.3f} arcmin < 0: the linear model predicts "
                     f"interference (negative lost motion){share}; it cannot see that a gap stops at zero.")
        else:
            w.append(f"linear stack-up (the explanatory section): mean − 3σ = {stackup.total.minus3sigma_arcmin:.3f} "
                     f"arcmin < 0, interference the linear model cannot place; the {sim.model} model's figures "
                     f"above see a closed gap as contact (lost motion never below zero).")
    zero_mean_mods = [f for f in stackup.factors if f.key in ("equidistance_modification", "moving_distance_modification")
                      and f.zone_origin == "explicit" and f.zone_lower_um == -f.zone_upper_um and f.zone_upper_um > 0]
    if zero_mean_mods:
        w.append("the profile modifications are read as zero-mean errors (the paper's reading, errata E7); a designed "
                 "modification has a mean: leave its zone out to use the nominal value.")
    if any("assumption" in f.zone_origin for f in stackup.factors):
        w.append("some zones rest on documented assumptions (docs/standards.md), e.g. the cycloid stage "
                 "(no public JB/T 10419-2005): check them against supplier data.")
    if sim.preload_fraction is not None and sim.preload_fraction > 0.01 and sim.model == "elastic":
        w.append(f"elastic model: the cycloid stage is preloaded (rigid interference at some pin) in "
                 f"{sim.preload_fraction * 100:.1f} % of the units; their pins carry load from zero torque, so "
                 f"the cycloid stage adds no dead band to their lost motion (docs/elastic.md).")
    elif sim.preload_fraction is not None and sim.preload_fraction > 0.01:
        w.append(f"contact model: the cycloid stage is preloaded (rigid interference at some pin) in "
                 f"{sim.preload_fraction * 100:.1f} % of the units; per-pin scatter is large against the "
                 f"designed clearance (docs/contact.md).")
    if g.crank_circle_radius_is_default:
        w.append(f"crank circle radius a0 not given: the first-stage centre distance {g.crank_circle_radius_mm:g} mm is used.")
    if sim.partial:
        w.append(f"interrupted: the simulation covers {sim.samples_done:,} of {sim.samples:,} samples.")
    w += [f"{sim.model} model: {x}" for x in sim.warnings]  # e.g. lost motion read in friction's stick band
    return tuple(w)


def build_report_data(problem: Problem, stackup: StackupResult, simulation: SimulationResult,
                      spec_arcmin: float | None, comparison: Comparison | None = None,
                      contact: NominalContact | None = None, sensitivity=None, allocation=None, elastic=None,
                      sweep=None, transmission=None, capacity=None,
                      capacity_trade=None, efficiency=None, selection=None, selection_sweep=None,
                      service_life=None) -> ReportData:
    warnings = validity_warnings(problem, stackup, simulation)
    if elastic is not None:  # the elastic section's nominal unit (also beside another model's run)
        warnings += tuple(f"elastic section: {w}" for w in elastic.nominal.warnings
                          if not any(w in x for x in warnings))
    return ReportData(problem, stackup, simulation, spec_arcmin, comparison, contact, warnings,
                      _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), sensitivity, allocation,
                      elastic, sweep, transmission, capacity, capacity_trade, efficiency, selection, selection_sweep,
                      service_life)
