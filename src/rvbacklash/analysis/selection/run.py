"""A production run with and without selective assembly, side by side (``rvbacklash simulate
--select``; docs/selective-assembly.md): the same seed, the same units (common random numbers),
the yields of every spec and the joint yield, each class's share of the parts bought and of the
units built, and the parts left over.

The surplus with an unlimited supply: parts are bought as sets (a unit's pins, a unit's rollers)
drawn from the part's law, so class c receives a share p_c of them while the rule takes a share q_c
of the units. Building N units needs N r sets, r = max_c q_c / p_c, and leaves N (r p_c - q_c) sets
of class c unused; the surplus fraction is 1 - 1 / r (Kannan & Jeevanandam's mismatch of selective
assembly, in its simplest form: every class of the law's mass).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from rvbacklash.analysis.selection.classes import ClassSet, ClassTable, Selection, band_edges_um
from rvbacklash.analysis.selection.source import SelectedElasticSource, selected_source
from rvbacklash.analysis.simulation import SimulationResult, simulate
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem
from rvbacklash.results import KEY, Result


@dataclass(frozen=True, repr=False)
class ClassUse(Result):
    """One class of a part kind: its band of the factor [um] (pins: radius deviation; rollers: the
    crank bearings' radial clearance), its mean, its share of the parts bought and of the units
    built, and its surplus per unit built [sets]."""

    part: str
    class_index: int
    lower_um: float
    upper_um: float
    mean_um: float
    share_bought: float
    share_used: float
    units: int
    surplus_sets_per_unit: float


@dataclass(frozen=True, repr=False)
class YieldPair(Result):
    """One spec's yield from random assembly and from selection (same units)."""

    output: str
    spec: float
    unit: str
    random: Proportion | None
    selected: Proportion | None

    @property
    def gain(self) -> float | None:
        if self.random is None or self.selected is None:
            return None
        return self.selected.fraction - self.random.fraction


@dataclass(frozen=True, repr=False)
class SelectionResult(Result):
    """A production run with and without selective assembly (module docstring)."""

    design_name: str
    model: str
    selection: Selection
    seed: int
    samples_done: int
    partial: bool
    yields: tuple[YieldPair, ...]
    classes: tuple[ClassUse, ...]
    pin_sets_per_unit: float  # pin sets bought per unit built (r of the module docstring)
    pin_surplus_fraction: float
    roller_sets_per_unit: float
    roller_surplus_fraction: float
    elapsed_random_s: float
    elapsed_selected_s: float
    random_run: SimulationResult  # the same units assembled at random
    selected_run: SimulationResult  # and selected (its saved units: the selected ones)

    @property
    def random(self) -> SimulationResult:
        return self.random_run

    @property
    def selected(self) -> SimulationResult:
        return self.selected_run

    def rows(self) -> list[dict]:
        out = [{"table": "yield", "output": y.output, "spec": y.spec, "unit": y.unit,
                "random": y.random.fraction if y.random else None,
                "random_ci95_low": y.random.ci95_low if y.random else None,
                "random_ci95_high": y.random.ci95_high if y.random else None,
                "selected": y.selected.fraction if y.selected else None,
                "selected_ci95_low": y.selected.ci95_low if y.selected else None,
                "selected_ci95_high": y.selected.ci95_high if y.selected else None} for y in self.yields]
        out += [{"table": "classes", **c.to_dict()} for c in self.classes]
        return [{**r, "partial": self.partial} for r in out]

    def summary(self) -> list[str]:
        lines = [f"{self.design_name}, {self.model} model, {self.samples_done:,} units, seed {self.seed}: "
                 f"selective assembly {self.selection}" + ("  [PARTIAL: interrupted]" if self.partial else "")]
        for y in self.yields:
            r = f"{y.random.fraction:.2%}" if y.random else "-"
            s = f"{y.selected.fraction:.2%}" if y.selected else "-"
            lines.append(f"yield {y.output} (spec {y.spec:g} {y.unit}): random {r} -> selected {s}")
        lines.append(f"pins: {self.pin_sets_per_unit:.3f} sets bought per unit built, "
                     f"surplus {self.pin_surplus_fraction:.1%}; rollers: {self.roller_sets_per_unit:.3f}, "
                     f"surplus {self.roller_surplus_fraction:.1%}")
        return lines


def surplus(share_bought: np.ndarray, share_used: np.ndarray) -> tuple[float, np.ndarray]:
    """(r, surplus per unit built of each class [sets]) with an unlimited supply (module docstring)."""
    bought, used = np.asarray(share_bought, float), np.asarray(share_used, float)
    if np.any((used > 0) & (bought <= 0)):
        return math.inf, np.full(bought.size, math.inf)
    ratio = np.divide(used, bought, out=np.zeros_like(used), where=bought > 0)
    r = float(max(ratio.max(initial=0.0), 1.0)) if used.sum() > 0 else 1.0
    return r, r * bought - used


def class_uses(part: str, table: ClassTable, edges_um: np.ndarray, counts: np.ndarray) -> tuple[
        tuple[ClassUse, ...], float, float]:
    n = int(counts.sum())
    used = counts / n if n else np.zeros(counts.size)
    r, left = surplus(table.share, used)
    uses = tuple(ClassUse(part, c, float(edges_um[c]), float(edges_um[c + 1]), float(table.mean_um[c]),
                          float(table.share[c]), float(used[c]), int(counts[c]), float(left[c]))
                 for c in range(counts.size))
    return uses, r, (1.0 - 1.0 / r) if math.isfinite(r) and r > 0 else math.nan


def simulate_selected(problem: Problem, selection: Selection, *, samples: int, seed: int = 0,
                      spec_arcmin: float | None = None, specs: Mapping[str, float] | None = None,
                      quantiles: tuple[float, ...] = (), workers: int | None = None, model: str = "elastic",
                      progress: Callable[[int], None] | None = None, error_model: str | None = None,
                      save_units: int = 0) -> SelectionResult:
    """The run of ``model`` (elastic) with random assembly, then with ``selection``: the same seed
    and units (module docstring). ``save_units`` keeps the selected run's first units."""
    if model != "elastic":
        raise InputError("model", model, "allowed with selection: elastic (the contact and transmission models: "
                                         "not yet)")
    if not (specs or spec_arcmin is not None):
        raise InputError("specs", None, "selection needs a spec to compare yields: e.g. --spec-lost-motion-arcmin 1")
    kw = dict(samples=samples, seed=seed, spec_arcmin=spec_arcmin, specs=specs, quantiles=quantiles, workers=workers,
              model=model, error_model=error_model)
    first = progress

    def second(done: int) -> None:
        if progress is not None:
            progress(samples + done)

    random = simulate(problem, progress=first, **kw)
    holder: list[SelectedElasticSource] = []
    wrap = selected_source(selection)

    def keep(source):
        s = wrap(source)
        holder.append(s)
        return s

    selected = simulate(problem, progress=second, save_units=save_units, wrap=keep, **kw)
    src = holder[0]
    return selection_result(problem, selection, random, selected, src)


def selection_result(problem: Problem, selection: Selection, random: SimulationResult, selected: SimulationResult,
                     src: SelectedElasticSource) -> SelectionResult:
    from rvbacklash.analysis.selection.classes import factor_law
    from rvbacklash.analysis.selection.source import PIN_RADIUS
    from rvbacklash.sampling.unit_draw import CRANK_CLEARANCE

    laws = src.base.contact.laws

    def edges(f: int, classes: ClassSet, scale: float) -> np.ndarray:
        law = factor_law(int(laws.code[f]), float(laws.loc[f]), float(laws.scale[f]), float(laws.lower[f]),
                         float(laws.upper[f]), "select")
        return band_edges_um(law, classes, scale)

    pin_counts, roller_counts = src.class_counts()
    pins, rp, sp = class_uses("pins", src.tables.pins, edges(PIN_RADIUS, selection.pins, 0.5), pin_counts)
    roller_edges = edges(CRANK_CLEARANCE, selection.rollers, 1.0)[::-1]  # numbered by roller size
    rollers, rr, sr = class_uses("rollers", src.tables.rollers, roller_edges, roller_counts)
    yields = []
    for name, o in selected.outputs.items():
        if o.spec_limit is None:
            continue
        yields.append(YieldPair(name, float(o.spec_limit), o.unit, random.outputs[name].yield_, o.yield_))
    if selected.joint_yield is not None:
        yields.append(YieldPair("joint", math.nan, "", random.joint_yield, selected.joint_yield))
    return SelectionResult(problem.name, selected.model, selection, int(selected.seed),
                           int(min(random.samples_done or 0, selected.samples_done or 0)),
                           random.partial or selected.partial, tuple(yields), pins + rollers, rp, sp, rr, sr,
                           random.elapsed_s, selected.elapsed_s, random, selected)


@dataclass(frozen=True, repr=False)
class ClassSweepPoint(Result):
    """One selection of a class sweep: its pin classes, its yield of the first spec and its surplus."""

    pin_classes: int
    pin_width_um: float
    noise_um: float
    yield_: Proportion = field(metadata={KEY: "yield"})
    pin_surplus_fraction: float


@dataclass(frozen=True, repr=False)
class ClassSweep(Result):
    """Yield of the first spec versus the number of pin classes, their width and the measurement's
    uncertainty (the rollers' classes fixed), beside random assembly: the same units throughout."""

    design_name: str
    output: str
    spec: float
    samples: int
    seed: int
    rollers: ClassSet
    random_yield: Proportion
    points: tuple[ClassSweepPoint, ...]

    def rows(self) -> list[dict]:
        return [{"pin_classes": p.pin_classes, "pin_width_um": p.pin_width_um, "noise_um": p.noise_um,
                 "yield": p.yield_.fraction, "ci95_low": p.yield_.ci95_low, "ci95_high": p.yield_.ci95_high,
                 "pin_surplus_fraction": p.pin_surplus_fraction} for p in self.points]


def class_sweep(problem: Problem, *, counts=(1, 3, 5, 7, 9), widths=(1.0, 2.0, 4.0), noises=(0.0,),
                rollers: ClassSet = ClassSet(3, 2.0), samples: int = 4000, seed: int = 0,
                specs: Mapping[str, float] | None = None, workers: int | None = None) -> ClassSweep:
    """The yield of ``specs``' first output for every (pin classes, width, noise) (module docstring:
    the same seed, the same units), beside random assembly."""
    from rvbacklash.analysis.selection.classes import make_selection

    specs = dict(specs or {"lost_motion": 1.0})
    name = next(iter(specs))
    base = simulate(problem, samples=samples, seed=seed, specs=specs, workers=workers, model="elastic")
    points = []
    for noise in noises:
        for width in widths:
            for k in counts:
                sel = make_selection(pins=ClassSet(int(k), float(width)), rollers=rollers, noise_um=float(noise))
                holder: list = []

                def keep(source, wrap=selected_source(sel)):
                    holder.append(wrap(source))
                    return holder[-1]

                run = simulate(problem, samples=samples, seed=seed, specs=specs, workers=workers, model="elastic",
                               wrap=keep)
                r = selection_result(problem, sel, base, run, holder[0])
                points.append(ClassSweepPoint(int(k), float(width), float(noise), run.outputs[name].yield_,
                                              r.pin_surplus_fraction))
    return ClassSweep(problem.name, name, float(specs[name]), int(samples), int(seed), rollers,
                      base.outputs[name].yield_, tuple(points))
