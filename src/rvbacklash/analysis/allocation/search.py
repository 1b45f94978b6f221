"""Tolerance allocation under the Monte-Carlo models: a local search over candidates with common
random numbers, verified on an independent stream (the formulation: the package docstring,
``rvbacklash.analysis.allocation``).

Monte-Carlo models (contact, elastic). Every candidate is simulated with the same seed and stream
(common random numbers: differences between candidates are not sampling noise of independent
runs). The search starts from the linear optimum, tightens the group with the best yield gain
per cost until the yield interval clears P, then takes the cheapest feasible single-group
coarsening (or coarsen-one-tighten-another swap) until none is cheaper. A candidate is feasible
only when the lower end of its 95 % yield interval is at least P. The chosen design is re-run on
an independent stream; if that fails, the next cheapest feasible candidate is verified.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from rvbacklash.analysis.allocation.candidates import (binding_constraint, design_description, groups_table,
                                                       named_grades, neighbour_grades, pareto_front, swap_grades,
                                                       uniform_grades)
from rvbacklash.analysis.allocation.milp import LinearSolution, solve_linear
from rvbacklash.analysis.allocation.results import AllocationResult, Baseline, Binding, FrontPoint
from rvbacklash.analysis.allocation.specs import SPEC_PARAMETERS, check_targets, extra_specs, specs_text
from rvbacklash.analysis.grade_choices import GradeChoices, grade_choices
from rvbacklash.analysis.sensitivity_global import ThreadExecutor
from rvbacklash.analysis.simulation import simulate
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.interrupt import stop_requested
from rvbacklash.problem import Problem, prepare

DEFAULT_MC_SAMPLES = 1 << 16
SEARCH_STREAM, VERIFY_STREAM = 0, 1


@dataclass(frozen=True)
class Evaluation:
    """Yield of one candidate in one Monte-Carlo run (picklable: it may come from a worker)."""

    yield_: Proportion  # joint when there is more than one spec
    yields: dict  # output -> Proportion
    partial: bool
    output: str = "backlash"  # the primary output, whose spec is spec_arcmin
    pin_sets_per_unit: float = 1.0  # with selective assembly: the part sets bought per unit built
    roller_sets_per_unit: float = 1.0


def evaluate_candidate(task: tuple) -> Evaluation:
    """Simulate one candidate design (a task of the executor: module-level, picklable arguments; a
    ninth, optional: the Selection its units are assembled with, analysis.selection)."""
    design, model, samples, seed, stream, spec_arcmin, specs, workers = task[:8]
    selection = task[8] if len(task) > 8 else None
    holder: list = []
    wrap = None
    if selection is not None:
        from rvbacklash.analysis.selection.source import selected_source

        def wrap(source, pick=selected_source(selection)):
            holder.append(pick(source))
            return holder[-1]
    r = simulate(prepare(design), model=model, samples=samples, seed=seed, stream=stream, spec_arcmin=spec_arcmin,
                 specs=specs, workers=workers, wrap=wrap)
    per = {name: o.yield_ for name, o in r.outputs.items() if o.yield_ is not None}
    joint = r.joint_yield if r.joint_yield is not None else r.yield_
    sets = (1.0, 1.0)
    if holder:
        from rvbacklash.analysis.selection.run import surplus

        src = holder[0]
        counts = src.class_counts()
        sets = tuple(surplus(t.share, c / max(c.sum(), 1))[0] for t, c in zip((src.tables.pins, src.tables.rollers),
                                                                              counts))
    return Evaluation(joint, per, r.partial, r.output.quantity, float(sets[0]), float(sets[1]))


def evaluate_accuracy_life(task: tuple) -> Evaluation:
    """A task of the executor as ``evaluate_candidate``'s, its ninth element the AccuracyLifeTarget:
    the share of the candidate's units whose accuracy life reaches the target's hours
    (analysis.service_life.accuracy_yield). The search stream draws the units `service-life` draws
    (spawn key (1,)), the verification stream the next (2,)."""
    from rvbacklash.analysis.service_life.accuracy_yield import SERVICE_LIFE_STREAM, accuracy_life_yield

    design, _model, samples, seed, stream = task[:5]
    target = task[8]
    y, partial = accuracy_life_yield(prepare(design), target, samples=samples, seed=seed,
                                     stream=(SERVICE_LIFE_STREAM[0] + stream[0],))
    if y is None:
        y = Proportion(math.nan, math.nan, math.nan)
    return Evaluation(y, {"accuracy_life": y}, partial, "accuracy_life")


class _Runs:
    """Candidates of a Monte-Carlo search, evaluated through an executor and cached."""

    def __init__(self, choices: GradeChoices, model: str, samples: int, seed: int, spec_arcmin: float,
                 specs: dict | None, executor, workers: int | None, stop, progress, selection=None,
                 evaluate: Callable[[tuple], Evaluation] = evaluate_candidate):
        self.ch, self.model, self.samples, self.seed = choices, model, samples, seed
        # every candidate's units assembled with it (None: at random); with ``evaluate_accuracy_life``, the
        # AccuracyLifeTarget (the ninth element of every task)
        self.selection = selection
        self.evaluate_task = evaluate
        self.spec, self.specs, self.stop, self.progress = spec_arcmin, specs, stop, progress
        # in this process: candidates side by side, one thread each, for a run of one block (the
        # default 65536 samples) uses one core only; a lone candidate gets every thread. A
        # candidate's numbers do not depend on its threads (the engine's contract).
        self.executor = executor
        self.threads = (workers or ThreadExecutor().workers) if executor is None else 1
        self.cache: dict[tuple[int, ...], Evaluation] = {}
        self.designs: dict[tuple[int, ...], Design] = {}
        self.runs = 0
        self.interrupted = False

    def design(self, grades: tuple[int, ...]) -> Design:
        if grades not in self.designs:
            self.designs[grades] = self.ch.design(grades)
        return self.designs[grades]

    def evaluate(self, candidates: Sequence[tuple[int, ...]], stream: int = SEARCH_STREAM) -> list[Evaluation | None]:
        todo = [c for c in dict.fromkeys(candidates) if stream != SEARCH_STREAM or c not in self.cache]
        executor, threads = self.executor, 1
        if executor is None:
            side_by_side = max(1, min(len(todo), self.threads))
            executor, threads = ThreadExecutor(side_by_side), max(1, self.threads // side_by_side)
        tasks = [(self.design(c), self.model, self.samples, self.seed, (stream,), self.spec, self.specs, threads)
                 + ((self.selection,) if self.selection is not None else ()) for c in todo]
        out: dict[tuple[int, ...], Evaluation] = {}
        if tasks and not self.stop.is_set():
            for i, ev in executor.map_unordered(self.evaluate_task, tasks, stop=self.stop):
                self.runs += 1
                if ev.partial:
                    self.interrupted = True
                else:
                    out[todo[i]] = ev
                    if self.progress is not None:
                        self.progress(self.runs)
                if self.stop.is_set():  # a stop: no candidate queued behind this one starts
                    self.interrupted = True
                    break
        if self.stop.is_set():
            self.interrupted = True
        if stream == SEARCH_STREAM:
            self.cache.update(out)
            return [self.cache.get(c) for c in candidates]
        return [out.get(c) for c in candidates]


def _feasible(ev: Evaluation | None, target: float) -> bool:
    return ev is not None and ev.yield_.ci95_low >= target


def search_monte_carlo(ch: GradeChoices, start: tuple[int, ...], runs: _Runs, target: float,
                       max_evaluations: int) -> tuple[int, ...] | None:
    """Local search from ``start`` (module docstring); the cheapest feasible candidate found."""
    current = start
    ev = runs.evaluate([current])[0]
    # 1. tighten until feasible: the move with the most yield per cost
    while not _feasible(ev, target) and not runs.interrupted and len(runs.cache) < max_evaluations:
        moves = neighbour_grades(ch, current, -1)
        if not moves or ev is None:
            return None
        evs = runs.evaluate(moves)
        scored = [(m, e) for m, e in zip(moves, evs) if e is not None]
        if not scored:
            return None
        feasible = [(ch.cost(m), m) for m, e in scored if _feasible(e, target)]
        if feasible:
            current = min(feasible)[1]
        else:
            gain = [((e.yield_.fraction - ev.yield_.fraction) / max(ch.cost(m) - ch.cost(current), 1e-12), m)
                    for m, e in scored]
            current = max(gain)[1]
        ev = runs.cache.get(current)
    if not _feasible(ev, target):
        return None
    # 2. cheaper neighbours while any is feasible: the feasible single-group coarsenings, cheapest
    #    first, are combined one by one while the combination stays feasible (several groups per step)
    while not runs.interrupted and len(runs.cache) < max_evaluations:
        moves = [m for m in neighbour_grades(ch, current, +1) if ch.cost(m) < ch.cost(current)]
        evs = runs.evaluate(moves)
        better = sorted((ch.cost(m), m) for m, e in zip(moves, evs) if _feasible(e, target))
        if not better:
            moves = swap_grades(ch, current)
            evs = runs.evaluate(moves)
            better = sorted((ch.cost(m), m) for m, e in zip(moves, evs) if _feasible(e, target))
            if not better:
                break
            current = better[0][1]
            continue
        combo = better[0][1]
        for _, m in better[1:]:
            if runs.interrupted or len(runs.cache) >= max_evaluations:
                break
            trial = tuple(b if b != a else c for a, b, c in zip(current, m, combo))
            if _feasible(runs.evaluate([trial])[0], target):
                combo = trial
        current = combo
    return current


def allocate_monte_carlo(problem: Problem, *, model: str, spec_arcmin: float, yield_target: float,
                         spec_rigidity_nm_per_arcmin: float | None = None, spec_preload_um: float | None = None,
                         spec_te_arcsec: float | None = None, spec_life_h: float | None = None,
                         spec_rated_torque_nm: float | None = None, samples: int = DEFAULT_MC_SAMPLES,
                         seed: int = 0, executor=None, workers: int | None = None, max_evaluations: int = 200,
                         progress: Callable[[int], None] | None = None, selection=None,
                         accuracy_life=None) -> AllocationResult:
    """Allocation under a Monte-Carlo model (module docstring): common random numbers for every
    candidate, local search from the linear optimum, verification on an independent stream.
    ``selection`` (analysis.selection.classes.Selection): every candidate's units assembled with it
    (the grades-and-classes allocation, allocation.classes). ``accuracy_life``
    (analysis.service_life.accuracy_yield.AccuracyLifeTarget; the elastic model, no other spec): the
    yield is the share of units whose lost motion stays within ``spec_arcmin`` for the target's hours of
    its duty cycle, each unit with its own wear (docs/service-life.md)."""
    started = time.perf_counter()
    check_targets(spec_arcmin, yield_target, spec_rigidity_nm_per_arcmin, spec_preload_um, spec_te_arcsec, spec_life_h,
                  spec_rated_torque_nm)
    least = 1000 if accuracy_life is None else 100  # a unit's accuracy life costs ~1000 units' lost motion
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not least <= samples <= 10**7:
        raise InputError("samples", samples, f"allowed: a whole number of samples per candidate, {least} to 1e7 "
                                             "(a search evaluates up to 200 candidates)")
    evaluate = evaluate_candidate
    if accuracy_life is not None:
        accuracy_life.check()
        if model != "elastic":
            raise InputError("model", model, "the accuracy life comes from the elastic model's wear; allowed: elastic")
        others = extra_specs(spec_rigidity_nm_per_arcmin, spec_preload_um, spec_te_arcsec, spec_life_h,
                             spec_rated_torque_nm)
        if others:
            name = SPEC_PARAMETERS[next(iter(others))]
            raise InputError(name, others[next(iter(others))], "not allowed with spec_accuracy_life_h (one spec: the "
                                                               "lost motion over the hours)")
        if selection is not None:
            raise InputError("spec_accuracy_life_h", accuracy_life.hours, "not allowed with selective assembly")
        evaluate, selection = evaluate_accuracy_life, accuracy_life
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", seed, "allowed: an integer >= 0")
    ch = grade_choices(problem)
    specs = extra_specs(spec_rigidity_nm_per_arcmin, spec_preload_um, spec_te_arcsec, spec_life_h,
                        spec_rated_torque_nm) or None
    notes = list(ch.notes)
    if model == "elastic" and problem.design.elastic is not None:  # friction and x T_R: the same for every grade
        from rvbacklash.models.elastic import elastic_model
        from rvbacklash.models.elastic.chain import stick_band_warning

        said = stick_band_warning(elastic_model(problem).chain)
        if said:
            notes.append(f"lost motion: {said}")
    try:
        lin = solve_linear(ch, spec_arcmin, yield_target)
    except InputError:
        lin = LinearSolution(None, None, None, 0, False)
    uniform = uniform_grades(ch)
    with stop_requested() as stop:
        runs = _Runs(ch, model, int(samples), int(seed), float(spec_arcmin), specs, executor, workers, stop, progress,
                     selection, evaluate)
        # the linear optimum and every uniform grade (the baseline) first; the search starts from the
        # cheapest of them that is feasible, else from the linear optimum (or the finest grades)
        first_batch = ([lin.grades] if lin.grades is not None else []) + [c for _, c in uniform]
        try:
            evs = runs.evaluate(first_batch)
        except InputError as e:
            if e.field == "specs":
                name = SPEC_PARAMETERS[e.value]
                raise InputError(name, specs[e.value], f"the {model} model has no {e.value} output; {e.allowed}") \
                    from None
            raise
        output = next((e.output for e in evs if e is not None), "backlash")
        feasible = sorted((ch.cost(c), c) for c, e in zip(first_batch, evs) if _feasible(e, yield_target))
        if feasible:
            start = feasible[0][1]
        elif lin.grades is not None:
            start = lin.grades
        else:
            start = tuple(c.grades[0] for c in ch.groups)
            notes.append("neither the linear optimum nor a uniform grade meets the target; the search starts from "
                         "the finest grades")
        best = search_monte_carlo(ch, start, runs, yield_target, max_evaluations)
        verified, verification = None, None
        if best is not None and not runs.interrupted:
            ranked = sorted((ch.cost(c), c) for c, e in runs.cache.items() if _feasible(e, yield_target))
            ranked = [c for _, c in ranked if ch.cost(c) >= ch.cost(best) - 1e-9][:3]
            for cand in ranked:
                check = runs.evaluate([cand], stream=VERIFY_STREAM)[0]
                if check is not None and _feasible(check, yield_target):
                    verified, verification = cand, check.yield_
                    break
                if check is not None:
                    y = check.yield_
                    notes.append(f"candidate {named_grades(ch, cand)} failed verification: yield {y.fraction:.6f} "
                                 f"[{y.ci95_low:.6f}, {y.ci95_high:.6f}] on an independent stream")
    partial = runs.interrupted
    chosen = verified if verified is not None else (best if partial else None)
    if chosen is None:
        seen = max(runs.cache.values(), key=lambda e: e.yield_.fraction, default=None)
        what = f"the best candidate reached {seen.yield_.fraction:.6f} [{seen.yield_.ci95_low:.6f}, " \
               f"{seen.yield_.ci95_high:.6f}]" if seen is not None else "no candidate was evaluated"
        failed = [n for n in notes if "failed verification" in n]
        if failed:  # the search found feasible designs; the cheapest ones did not hold on a second stream
            what = f"{len(failed)} cheapest feasible candidates failed verification on an independent stream; " \
                   f"first: {failed[0].removeprefix('candidate ')}"
        raise InputError("yield_target", yield_target, f"no design confirmed under the {model} model ({what}); "
                                                       f"allowed: a lower yield, a larger spec, or more samples (-n)")
    ev = runs.cache[chosen]
    what = f"{output} <= {spec_arcmin:g} arcmin" if accuracy_life is None else accuracy_life.text()
    label = f"grades allocated by rvbacklash: P({what}" + specs_text(specs or {}) + f") >= {yield_target:g}, {model} model"
    design = ch.design(chosen, design_description(problem, label))
    points = [FrontPoint(ch.cost(c), e.yield_, named_grades(ch, c), "candidate", None, c == chosen)
              for c, e in runs.cache.items()]
    uni_points = tuple(FrontPoint(ch.cost(c), runs.cache[c].yield_, named_grades(ch, c), "uniform", None)
                       for _, c in uniform if c in runs.cache)
    feasible_uniform = sorted((ch.cost(c), g) for g, c in uniform if _feasible(runs.cache.get(c), yield_target))
    base = Baseline(feasible_uniform[0][1], feasible_uniform[0][0],
                    runs.cache[tuple(feasible_uniform[0][1] for _ in ch.groups)].yield_) if feasible_uniform \
        else Baseline(None, None, None)
    cost = ch.cost(chosen)
    saving = base.cost - cost if base.cost is not None else None
    current = ch.current
    before = None
    if all(g is not None and g in c.grades for g, c in zip(current, ch.groups)):
        before_ev = runs.evaluate([tuple(current)])[0]
        before = before_ev.yield_ if before_ev is not None else None
    cost_before = sum(c.current_cost for c in ch.groups) if all(c.current_cost is not None for c in ch.groups) \
        else None
    constraint = f"P({what}" + specs_text(specs or {}) + f") >= {yield_target:g}"
    binding = binding_constraint(constraint, ev.yield_, yield_target, ch, chosen)
    if specs and ev.yields:
        worst = min(ev.yields.items(), key=lambda kv: kv[1].ci95_low)
        binding = Binding(f"{constraint}; tightest: {worst[0]}", ev.yield_.fraction, ev.yield_.ci95_low, yield_target,
                          ev.yield_.ci95_low - yield_target, binding.at_finest)
    if partial:
        notes.append("interrupted: the best candidate so far, not verified")
    return AllocationResult(
        design_name=problem.name, model=model, method="monte-carlo", output=output, optimality=(
            "local search with common random numbers from the linear optimum; verified on an independent stream"),
        spec_arcmin=float(spec_arcmin), spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin,
        spec_preload_um=spec_preload_um, spec_te_arcsec=spec_te_arcsec, yield_target=float(yield_target), unit=ch.unit,
        cost=cost, cost_before=cost_before, yield_=ev.yield_,
        yield_before=before, yields=dict(ev.yields), grades=named_grades(ch, chosen), groups=groups_table(ch, chosen),
        binding=binding, baseline=base, saving=saving,
        saving_fraction=saving / base.cost if saving is not None and base.cost else None,
        front=pareto_front(points), uniform=uni_points, samples=int(samples), seed=int(seed), evaluations=runs.runs,
        verification=verification, elapsed_s=time.perf_counter() - started, partial=partial, notes=tuple(notes),
        spec_life_h=spec_life_h, spec_rated_torque_nm=spec_rated_torque_nm, design=design,
        spec_accuracy_life_h=None if accuracy_life is None else float(accuracy_life.hours),
        duty_cycle=None if accuracy_life is None else accuracy_life.cycle.source)
