"""Tolerance allocation under the linear model: exact yields and the MILP by outer approximation
(the formulation: the package docstring, ``rvbacklash.analysis.allocation``).

Linear model (exact). Y is the linear model's output (Eq. (2)). With normal inputs,
Y ~ N(mu(x), sigma(x)^2), mu(x) = mu_0 + sum M_jg x_jg and sigma(x) = ||L^T w(x)||, where
w(x) = w_0 + sum W_jg x_jg holds S_i sigma_i(g) of each factor and L L^T = R (the correlation).
The constraint is mu(x) + z_P sigma(x) <= s with z_P = Phi^-1(P) > 0: a second-order cone in x,
convex in the continuous relaxation. It is solved exactly by outer approximation (Kelley's
cutting planes; Duran & Grossmann, Math. Programming 36 (1986) 307): a MILP over the binaries
(``scipy.optimize.milp``, HiGHS) whose yield constraint is replaced by cuts

    mu(x) + z_P u_k . (L^T w(x)) <= s,      u_k a unit vector,

valid because ||v|| >= u . v for every unit u (a cut never removes a feasible design). The MILP
optimum is checked with the exact distribution; if it fails, the cut at that candidate
(u = its own direction) removes it and the MILP is solved again. The first candidate that passes
is optimal, since every MILP minimised over a superset of the feasible designs. With non-normal
inputs the exact yield comes from the FFT convolution (``analysis.exact``): the cuts are then a
normal surrogate, every rejected candidate also gets a no-good cut, and single-group coarsening
moves checked with the exact distribution try cheaper neighbours ("verified, surrogate-optimal").
"""

from __future__ import annotations

import contextlib
import itertools
import os
import sys
import threading
import time
from dataclasses import dataclass, field
from statistics import NormalDist
from typing import Sequence

import numpy as np

from rvbacklash.analysis.allocation.candidates import (binding_constraint, design_description, groups_table,
                                                       named_grades, neighbour_grades, pareto_front, swap_grades,
                                                       uniform_grades)
from rvbacklash.analysis.allocation.results import AllocationResult, Baseline, FrontPoint
from rvbacklash.analysis.allocation.specs import check_targets
from rvbacklash.analysis.exact import ExactDistribution, exact_distribution
from rvbacklash.analysis.grade_choices import GradeChoices, grade_choices, moments_arcmin
from rvbacklash.analysis.simulation import exact_result
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem, prepare

PARETO_YIELDS = (0.5, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.998, 0.999, 0.9995, 0.9999, 0.99999, 0.999999)
MAX_OA_ITERATIONS = 1000
# FFT grid of the exact distribution while searching (non-normal inputs): cdf error ~1e-7, 15x
# faster than the reporting grid (analysis.exact.GRID_POINTS) that gives the final yield
SEARCH_GRID_POINTS = 1 << 16
CALIBRATIONS, CALIBRATION_MARGIN = 6, 0.1  # surrogate recalibrations for non-normal outputs, and the margin in z


# One solve at a time redirects the process's standard output (file descriptor 1): two
# overlapping redirections (the workbench runs allocations in threads) would save each other's
# /dev/null as "the real stdout" and lose it for good.
_STDOUT_LOCK = threading.Lock()


def _flush_c_stdio() -> None:
    """Flush the C library's stdio buffers (what the solver printed, still buffered when fd 1 is
    a pipe or a file, goes where fd 1 points now, not after it is restored)."""
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError, TypeError):  # pragma: no cover - no C library to call (Windows)
        pass


@contextlib.contextmanager
def solver_output_silenced():
    """Send what the MILP solver writes to file descriptor 1 to the null device, and restore it
    afterwards (also on an exception or Ctrl-C). HiGHS (scipy's bundled solver) prints debug
    lines ("HighsMipSolverData::transformNewIntegerFeasibleSolution tmpSolver.run();", HiGHS
    issue 2783) with printf whatever its output options say, past ``sys.stdout``: machine-readable
    standard output (``--format json``) must not carry them. Only the solve is wrapped; a thread
    writing to fd 1 meanwhile loses those bytes (the CLI writes its result after the solve; the
    workbench answers over HTTP and logs to stderr)."""
    with _STDOUT_LOCK:
        try:
            sys.stdout.flush()  # Python's own buffered text first, to the real stdout
        except (AttributeError, ValueError, OSError):
            pass
        try:
            saved = os.dup(1)
        except OSError:  # no fd 1 (a closed stdout): nothing to protect
            saved = None
        if saved is None:
            yield
            return
        try:
            null = os.open(os.devnull, os.O_WRONLY)
            try:
                os.dup2(null, 1)
            finally:
                os.close(null)
            yield
        finally:
            _flush_c_stdio()
            os.dup2(saved, 1)
            os.close(saved)


class ExactYields:
    """Exact P(backlash <= spec) of candidates of the linear model, cached: closed form when every
    random input is normal (``ExactDistribution``, the code path of ``simulate --method exact``),
    else the FFT convolution of ``analysis.exact`` on a 2^16-point grid. For the latter it also
    keeps each candidate's standardised quantiles z(x) = (q_P(x) - mu(x)) / sigma(x) at the
    ``levels`` asked for (the calibration of the surrogate; Phi^-1(P) for a normal output)."""

    def __init__(self, choices: GradeChoices, spec_arcmin: float, levels: Sequence[float] = ()):
        self.choices, self.spec = choices, float(spec_arcmin)
        self.closed_form = choices.all_normal()
        self.levels = tuple(sorted({float(x) for x in levels}))
        self.cache: dict[tuple[int, ...], float] = {}
        self.zcache: dict[tuple[int, ...], dict[float, float]] = {}

    def _distribution(self, key: tuple[int, ...]) -> ExactDistribution:
        return exact_distribution(self.choices.candidate_problem(key), grid_points=SEARCH_GRID_POINTS)

    def _remember(self, key: tuple[int, ...], dist: ExactDistribution, levels: Sequence[float]) -> None:
        z = self.zcache.setdefault(key, {})
        if dist.std > 0:
            q = dist.ppf(np.array(levels, dtype=float))
            z.update({lv: float((qi - dist.mean) / dist.std) for lv, qi in zip(levels, q)})
        else:
            z.update({lv: 0.0 for lv in levels})

    def __call__(self, grades: Sequence[int]) -> float:
        key = tuple(grades)
        if key not in self.cache:
            if self.closed_form:
                _, means, sigmas = self.choices.moments(key)
                mu, sigma = moments_arcmin(self.choices.problem, means, sigmas)
                self.cache[key] = float(ExactDistribution(mean=mu, std=sigma).cdf(self.spec))
            else:
                dist = self._distribution(key)
                self.cache[key] = float(dist.cdf(self.spec))
                self._remember(key, dist, self.levels)
        return self.cache[key]

    def z(self, grades: Sequence[int], level: float) -> float:
        """Standardised ``level``-quantile of a candidate's output."""
        if self.closed_form:
            return NormalDist().inv_cdf(level)
        key = tuple(grades)
        self(key)
        if level not in self.zcache.get(key, {}):
            self._remember(key, self._distribution(key), (level,))
        return self.zcache[key][level]

    @property
    def evaluations(self) -> int:
        return len(self.cache)


@dataclass
class _Milp:
    """The outer-approximation MILP of one GradeChoices (module docstring)."""

    choices: GradeChoices
    offsets: list[int] = field(default_factory=list)
    cost: np.ndarray | None = None
    mean: np.ndarray | None = None  # M_jg
    spread: np.ndarray | None = None  # (n_var, 21): W_jg mapped through L
    mu0: float = 0.0
    w0: np.ndarray | None = None
    lt: np.ndarray | None = None  # L^T
    units: list[np.ndarray] = field(default_factory=list)  # cut directions u_k (in L^T w space)
    nogoods: list[tuple[int, ...]] = field(default_factory=list)

    def __post_init__(self):
        ch = self.choices
        p = ch.problem
        s = p.sensitivities_arcmin_per_um
        allocated = [i for c in ch.groups for i in c.factors]
        rest = np.ones(s.size, dtype=bool)
        rest[allocated] = False
        self.mu0 = float(s[rest] @ p.means_um[rest])
        self.w0 = np.where(rest, s * p.sigmas_um, 0.0)
        vals, vecs = np.linalg.eigh(p.correlation)
        self.lt = (vecs * np.sqrt(np.clip(vals, 0.0, None))).T
        cost, mean, spread = [], [], []
        for c in ch.groups:
            self.offsets.append(len(cost))
            for g, cg in zip(c.grades, c.costs):
                w = np.zeros(s.size)
                idx = list(c.factors)
                w[idx] = s[idx] * ch.sigmas_at[g][idx]
                cost.append(cg)
                mean.append(float(s[idx] @ ch.means_at[g][idx]))
                spread.append(w)
        self.cost, self.mean, self.spread = np.array(cost), np.array(mean), np.array(spread)

    def direction(self, grades: Sequence[int]) -> np.ndarray | None:
        x = self.indicator(grades)
        v = self.lt @ (self.w0 + x @ self.spread)
        n = float(np.linalg.norm(v))
        return v / n if n > 0 else None

    def indicator(self, grades: Sequence[int]) -> np.ndarray:
        x = np.zeros(self.cost.size)
        for off, c, g in zip(self.offsets, self.choices.groups, grades):
            x[off + c.grades.index(g)] = 1.0
        return x

    def add_cut(self, grades: Sequence[int]) -> None:
        u = self.direction(grades)
        if u is not None and not any(np.allclose(u, v, rtol=0, atol=1e-12) for v in self.units):
            self.units.append(u)

    def solve(self, spec: float, z: float) -> tuple[int, ...] | None:
        """The cheapest candidate that satisfies every cut and no-good cut (None: none)."""
        from scipy.optimize import Bounds, LinearConstraint, milp

        ch = self.choices
        n_var, n_grp = self.cost.size, len(ch.groups)
        eq = np.zeros((n_grp, n_var))
        for j, (off, c) in enumerate(zip(self.offsets, ch.groups)):
            eq[j, off:off + len(c.grades)] = 1.0
        cons = [LinearConstraint(eq, 1.0, 1.0)]
        if self.units:
            rows = np.array([z * (self.spread @ (self.lt.T @ u)) + self.mean for u in self.units])
            rhs = np.array([spec - self.mu0 - z * float(u @ (self.lt @ self.w0)) for u in self.units])
            cons.append(LinearConstraint(rows, -np.inf, rhs))
        if self.nogoods:
            rows = np.array([self.indicator(g) for g in self.nogoods])
            cons.append(LinearConstraint(rows, -np.inf, n_grp - 1.0))
        with solver_output_silenced():
            res = milp(self.cost, integrality=np.ones(n_var), bounds=Bounds(0.0, 1.0), constraints=cons,
                       options={"mip_rel_gap": 0.0, "presolve": True})
        if res.status == 2 or res.x is None:  # infeasible
            return None
        if res.status != 0:  # pragma: no cover - HiGHS limits
            raise RuntimeError(f"MILP solver: {res.message}")
        return tuple(c.grades[int(np.argmax(res.x[off:off + len(c.grades)]))]
                     for off, c in zip(self.offsets, ch.groups))


@dataclass(frozen=True)
class LinearSolution:
    grades: tuple[int, ...] | None  # None: no candidate meets the target
    cost: float | None
    yield_fraction: float | None
    iterations: int
    proven: bool  # optimal (closed-form exact distribution) rather than verified surrogate-optimal


def _outer_approximation(choices: GradeChoices, spec: float, target: float, z: float, yields: ExactYields,
                          oa: _Milp, tried: list) -> tuple[tuple[int, ...] | None, int]:
    """The cheapest candidate that passes the exact test among those the cuts at ``z`` leave;
    every candidate tried is appended to ``tried``; (candidate or None, MILP solves)."""
    seen: set[tuple[int, ...]] = set()
    for it in range(1, MAX_OA_ITERATIONS + 1):
        cand = oa.solve(spec, z)
        if cand is None:
            return None, it
        tried.append(cand)
        if yields(cand) >= target:
            return cand, it
        if cand in seen or not yields.closed_form:
            oa.nogoods.append(cand)  # numerically on the boundary, or a surrogate cut that does not remove it
        seen.add(cand)
        oa.add_cut(cand)
    raise RuntimeError("outer approximation did not converge")  # pragma: no cover - finite, but guard the loop


def solve_linear(choices: GradeChoices, spec_arcmin: float, yield_target: float, yields: ExactYields | None = None,
                 milp_state: _Milp | None = None) -> LinearSolution:
    """The cheapest candidate whose exact yield is at least ``yield_target`` (module docstring).

    Normal output: outer approximation with z = Phi^-1(P), proven optimal. Otherwise the cuts use
    the smallest standardised P-quantile z(x) met so far (minus a margin), so that they relax the
    exact constraint for candidates like those tried; rejected candidates get no-good cuts; the
    calibration is repeated until no tried candidate has a smaller z(x); last, cheaper single-group
    coarsenings and swaps are checked exactly."""
    yields = yields or ExactYields(choices, spec_arcmin, (yield_target,))
    oa = milp_state or _Milp(choices)
    if not oa.units:  # start with the cuts at the coarsest and the finest design
        oa.add_cut(tuple(c.grades[-1] for c in choices.groups))
        oa.add_cut(tuple(c.grades[0] for c in choices.groups))
    nogoods_before = len(oa.nogoods)
    z = NormalDist().inv_cdf(yield_target)
    tried: list[tuple[int, ...]] = []
    iterations = 0
    for _ in range(CALIBRATIONS if not yields.closed_form else 1):
        found, it = _outer_approximation(choices, spec_arcmin, yield_target, z, yields, oa, tried)
        iterations += it
        if yields.closed_form:
            break
        z_seen = min(yields.z(c, yield_target) for c in tried) if tried else z
        if z_seen >= z - 1e-9:
            break
        z = z_seen - CALIBRATION_MARGIN
    del oa.nogoods[nogoods_before:]  # no-good cuts belong to this target only
    if found is None:
        return LinearSolution(None, None, None, iterations, yields.closed_form)
    if not yields.closed_form:
        found = _polish_exact(choices, found, yields, yield_target)
    return LinearSolution(found, choices.cost(found), yields(found), iterations, yields.closed_form)


def _polish_exact(choices: GradeChoices, grades: tuple[int, ...], yields: ExactYields,
                  target: float) -> tuple[int, ...]:
    """Cheaper single-group coarsenings and coarsen-one-tighten-another swaps that still meet the
    target exactly, cheapest first, until none."""
    current = grades
    while True:
        moves = neighbour_grades(choices, current, +1) + swap_grades(choices, current)
        better = sorted((choices.cost(m), m) for m in moves if choices.cost(m) < choices.cost(current) - 1e-12)
        nxt = next((m for _, m in better if yields(m) >= target), None)
        if nxt is None:
            return current
        current = nxt


def brute_force(choices: GradeChoices, spec_arcmin: float, yield_target: float,
                yields: ExactYields | None = None) -> tuple[tuple[int, ...] | None, float | None]:
    """(grades, cost) of the cheapest candidate meeting the target, by enumeration: every
    candidate (the product of the groups' grade lists) sorted by cost, the first that meets the
    target wins (for tests and small cases)."""
    yields = yields or ExactYields(choices, spec_arcmin)
    ranked = sorted(itertools.product(*(c.grades for c in choices.groups)), key=choices.cost)
    for cand in ranked:
        if yields(cand) >= yield_target:
            return cand, choices.cost(cand)
    return None, None


def allocate_linear(problem: Problem, *, spec_arcmin: float, yield_target: float, pareto: bool = True,
                    choices: GradeChoices | None = None) -> AllocationResult:
    """Exact allocation for the linear model (module docstring)."""
    started = time.perf_counter()
    check_targets(spec_arcmin, yield_target)
    ch = choices or grade_choices(problem)
    yields = ExactYields(ch, spec_arcmin, (yield_target,) + (PARETO_YIELDS if pareto else ()))
    oa = _Milp(ch)
    sol = solve_linear(ch, spec_arcmin, yield_target, yields, oa)
    if sol.grades is None:
        finest = tuple(c.grades[0] for c in ch.groups)
        raise InputError("yield_target", yield_target,
                         f"not reachable with the allowed grades: the finest ({', '.join(map(str, finest))}) give "
                         f"P(backlash <= {spec_arcmin:g} arcmin) = {yields(finest):.6g}; allowed: a lower yield, a "
                         f"larger spec, or finer grades (grade_min in [costs])")
    label = f"grades allocated by rvbacklash: P(backlash <= {spec_arcmin:g} arcmin) >= {yield_target:g}, linear model"
    chosen = ch.design(sol.grades, design_description(problem, label))
    # the reported yield is that of the written design through simulate's own exact path
    y_exact = exact_result(prepare(chosen), spec_arcmin=float(spec_arcmin)).yield_
    points = [FrontPoint(sol.cost, y_exact, named_grades(ch, sol.grades), "optimum", float(yield_target), True)]
    if pareto:
        for level in PARETO_YIELDS:
            if level == yield_target:
                continue
            s = solve_linear(ch, spec_arcmin, level, yields, oa)
            if s.grades is not None:
                points.append(FrontPoint(s.cost, Proportion.exact(s.yield_fraction), named_grades(ch, s.grades),
                                         "optimum", level))
    uniform = []
    for g, cand in uniform_grades(ch):
        uniform.append(FrontPoint(ch.cost(cand), Proportion.exact(yields(cand)), named_grades(ch, cand), "uniform", None))
    feasible_uniform = [(p.cost, g) for (g, _), p in zip(uniform_grades(ch), uniform) if p.yield_.fraction >= yield_target]
    if feasible_uniform:
        cost_b, grade_b = min(feasible_uniform)
        base = Baseline(grade_b, cost_b, next(p.yield_ for (g, _), p in zip(uniform_grades(ch), uniform) if g == grade_b))
    else:
        base = Baseline(None, None, None)
    current = ch.current
    cost_before = sum(c.current_cost for c in ch.groups) if all(c.current_cost is not None for c in ch.groups) \
        else None
    before = exact_result(problem, spec_arcmin=float(spec_arcmin)).yield_
    saving = base.cost - sol.cost if base.cost is not None else None
    notes = list(ch.notes)
    if any(g is None for g in current):
        notes.append("groups whose factors had different grades show no grade before")
    optimality = ("proven optimal: outer approximation on the closed-form normal output (MILP, scipy.optimize.milp / "
                  "HiGHS)" if sol.proven else
                  "verified with the exact (FFT) distribution; optimal for the normal surrogate, then improved by "
                  "single-group coarsening")
    constraint = f"P(backlash <= {spec_arcmin:g} arcmin) >= {yield_target:g}"
    return AllocationResult(
        design_name=problem.name, model="linear", method="exact", optimality=optimality, output="backlash",
        spec_arcmin=float(spec_arcmin), spec_rigidity_nm_per_arcmin=None, spec_preload_um=None, spec_te_arcsec=None,
        yield_target=float(yield_target),
        unit=ch.unit, cost=sol.cost, cost_before=cost_before, yield_=y_exact, yield_before=before,
        yields={"backlash": y_exact}, grades=named_grades(ch, sol.grades), groups=groups_table(ch, sol.grades),
        binding=binding_constraint(constraint, y_exact, yield_target, ch, sol.grades), baseline=base, saving=saving,
        saving_fraction=saving / base.cost if saving is not None and base.cost else None,
        front=pareto_front(points + uniform), uniform=tuple(uniform), samples=None, seed=None,
        evaluations=yields.evaluations, verification=None, elapsed_s=time.perf_counter() - started, partial=False,
        notes=tuple(notes), design=chosen)
