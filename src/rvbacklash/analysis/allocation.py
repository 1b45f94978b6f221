"""Tolerance allocation: the cheapest precision grade for each part group such that the output
meets its spec at the target yield, P(backlash <= s [and rigidity >= K]) >= P.

Formulation (discrete, chance-constrained; Chase, Greenwood, Loosli & Hauglund, Manufacturing
Review 3(1) (1990) 49-59, for the discrete choice of processes)::

    minimise    sum_j sum_g c_jg x_jg                     (cost of group j at grade g)
    subject to  sum_g x_jg = 1 for every group j,  x_jg in {0, 1},
                P(Y(x) <= s) >= P.

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

Monte-Carlo models (contact, elastic). Every candidate is simulated with the same seed and stream
(common random numbers: differences between candidates are not sampling noise of independent
runs). The search starts from the linear optimum, tightens the group with the best yield gain
per cost until the yield interval clears P, then takes the cheapest feasible single-group
coarsening (or coarsen-one-tighten-another swap) until none is cheaper. A candidate is feasible
only when the lower end of its 95 % yield interval is at least P. The chosen design is re-run on
an independent stream; if that fails, the next cheapest feasible candidate is verified.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field
from statistics import NormalDist
from typing import Callable, Mapping, Sequence

import numpy as np

from rvbacklash.analysis.exact import ExactDistribution, exact_distribution
from rvbacklash.analysis.grade_choices import GradeChoices, grade_choices, moments_arcmin
from rvbacklash.analysis.sensitivity_global import ThreadExecutor
from rvbacklash.analysis.simulation import exact_result, simulate
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.interrupt import stop_requested
from rvbacklash.problem import Problem, prepare
from rvbacklash.results import EXPORT, Result

PARETO_YIELDS = (0.5, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.998, 0.999, 0.9995, 0.9999, 0.99999, 0.999999)
DEFAULT_MC_SAMPLES = 1 << 16
MAX_OA_ITERATIONS = 1000
SEARCH_STREAM, VERIFY_STREAM = 0, 1
# FFT grid of the exact distribution while searching (non-normal inputs): cdf error ~1e-7, 15x
# faster than the reporting grid (analysis.exact.GRID_POINTS) that gives the final yield
SEARCH_GRID_POINTS = 1 << 16
CALIBRATIONS, CALIBRATION_MARGIN = 6, 0.1  # surrogate recalibrations for non-normal outputs, and the margin in z


# --- results -----------------------------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class GroupGrade(Result):
    """A part group before and after the allocation."""

    group: str
    grade_table: str
    factors: tuple[str, ...]
    grade_before: int | None  # None: the group's factors had different grades
    grade_after: int
    cost_before: float | None
    cost_after: float
    grade_min: int
    grade_max: int
    description: str

    def summary(self) -> list[str]:
        before = "mixed" if self.grade_before is None else str(self.grade_before)
        return [f"{self.group}: grade {before} -> {self.grade_after}, cost {self.cost_after:.4g}"]


@dataclass(frozen=True, repr=False)
class FrontPoint(Result):
    """A design on the cost-yield plane."""

    cost: float
    yield_: Proportion = field(metadata={"key": "yield"})
    grades: Mapping[str, int]
    kind: str  # "optimum" (min cost at a yield target), "uniform", "candidate" (Monte-Carlo search)
    target: float | None  # the yield target it was the optimum for
    chosen: bool = False

    def row(self) -> dict:
        y = self.yield_
        return {"cost": self.cost, "yield": y.fraction, "yield_ci95_low": y.ci95_low, "yield_ci95_high": y.ci95_high,
                "kind": self.kind, "target": self.target, "chosen": self.chosen,
                **{f"grade.{k}": v for k, v in self.grades.items()}}


@dataclass(frozen=True, repr=False)
class Baseline(Result):
    """The cheapest uniform grade (every group alike) that meets the spec."""

    grade: int | None  # None: no uniform grade meets it
    cost: float | None
    yield_: Proportion | None = field(metadata={"key": "yield"})


@dataclass(frozen=True, repr=False)
class Binding(Result):
    """The constraint that decides the allocation and its slack; groups at their finest grade."""

    constraint: str
    value: float  # yield of the chosen design (point estimate)
    ci95_low: float  # lower end of its interval (= value when exact)
    target: float
    slack: float  # ci95_low - target
    at_finest: tuple[str, ...]  # groups at their finest allowed grade (bounds that bind)


@dataclass(frozen=True, repr=False)
class AllocationResult(Result):
    """The cheapest grades that meet the spec at the target yield, against the uniform-grade
    baseline, with the cost-yield Pareto front. ``rows()`` / ``to_frame()``: the grade table;
    ``front_rows()``: the front; ``design``: the chosen design (``--write-design``)."""

    design_name: str
    model: str
    method: str
    optimality: str
    output: str  # the output whose upper limit is spec_arcmin (backlash; lost_motion for the elastic model)
    spec_arcmin: float
    spec_rigidity_nm_per_arcmin: float | None
    spec_preload_um: float | None  # upper limit of the cycloid stage's preload (contact, elastic)
    spec_te_arcsec: float | None  # upper limit of the TE peak-to-peak (transmission model)
    yield_target: float
    unit: str
    cost: float
    cost_before: float | None
    yield_: Proportion = field(metadata={"key": "yield"})
    yield_before: Proportion | None
    yields: Mapping[str, Proportion]  # per output with a spec
    grades: Mapping[str, int]  # group -> grade after
    groups: tuple[GroupGrade, ...]
    binding: Binding
    baseline: Baseline
    saving: float | None  # baseline.cost - cost
    saving_fraction: float | None
    front: tuple[FrontPoint, ...]  # non-dominated designs, cheapest first
    uniform: tuple[FrontPoint, ...]  # every uniform grade
    samples: int | None  # per candidate (Monte-Carlo); None: exact
    seed: int | None
    evaluations: int  # candidates evaluated (exact yields, or Monte-Carlo runs)
    verification: Proportion | None  # yield of the chosen design on an independent stream
    elapsed_s: float
    partial: bool
    notes: tuple[str, ...]
    design: Design | None = field(default=None, metadata={EXPORT: False})
    _frame_index = "group"

    def rows(self) -> list[dict]:
        return [g.to_dict() for g in self.groups]

    def front_rows(self) -> list[dict]:
        return [p.row() for p in self.front]

    def summary(self) -> list[str]:
        y = self.yield_
        head = (f"{self.design_name}, {self.model} model: P({self.output} <= {self.spec_arcmin:g} arcmin) >= "
                f"{self.yield_target:g}" + ("  [PARTIAL: interrupted]" if self.partial else ""))
        lines = [head, f"cost {self.cost:.4g} {self.unit}, yield {y.fraction:.6f}"
                       + (f" [{y.ci95_low:.6f}, {y.ci95_high:.6f}]" if y.ci95_low != y.ci95_high else " (exact)")]
        if self.baseline.cost is not None:
            lines.append(f"baseline: uniform grade {self.baseline.grade}, cost {self.baseline.cost:.4g} "
                         f"(saving {self.saving:.4g}, {self.saving_fraction:.1%})")
        return lines + [line for g in self.groups for line in g.summary()]


# --- checks --------------------------------------------------------------------------------------

def check_targets(spec_arcmin, yield_target, spec_rigidity_nm_per_arcmin=None, spec_preload_um=None,
                  spec_te_arcsec=None) -> None:
    if spec_arcmin is None or isinstance(spec_arcmin, bool) or not isinstance(spec_arcmin, (int, float)) or \
            not (math.isfinite(spec_arcmin) and spec_arcmin > 0):
        raise InputError("spec_arcmin", spec_arcmin, "allowed: a finite number > 0 [arcmin]")
    if yield_target is None or isinstance(yield_target, bool) or not isinstance(yield_target, (int, float)) or \
            not 0.5 < yield_target < 1:
        raise InputError("yield_target", yield_target, "allowed: a probability 0.5 < P < 1, e.g. 0.99")
    if spec_rigidity_nm_per_arcmin is not None and (
            isinstance(spec_rigidity_nm_per_arcmin, bool) or not isinstance(spec_rigidity_nm_per_arcmin, (int, float))
            or not (math.isfinite(spec_rigidity_nm_per_arcmin) and spec_rigidity_nm_per_arcmin > 0)):
        raise InputError("spec_rigidity_nm_per_arcmin", spec_rigidity_nm_per_arcmin,
                         "allowed: a finite number > 0 [N m/arcmin]")
    if spec_preload_um is not None and (
            isinstance(spec_preload_um, bool) or not isinstance(spec_preload_um, (int, float))
            or not (math.isfinite(spec_preload_um) and spec_preload_um >= 0)):
        raise InputError("spec_preload_um", spec_preload_um, "allowed: a finite number >= 0 [um]")
    if spec_te_arcsec is not None and (
            isinstance(spec_te_arcsec, bool) or not isinstance(spec_te_arcsec, (int, float))
            or not (math.isfinite(spec_te_arcsec) and spec_te_arcsec > 0)):
        raise InputError("spec_te_arcsec", spec_te_arcsec, "allowed: a finite number > 0 [arcsec]")


SPEC_PARAMETERS = {"rigidity": "spec_rigidity_nm_per_arcmin", "preload": "spec_preload_um",
                   "transmission_error": "spec_te_arcsec"}  # output -> the API parameter of its spec


def extra_specs(spec_rigidity_nm_per_arcmin: float | None, spec_preload_um: float | None,
                spec_te_arcsec: float | None = None) -> dict[str, float]:
    """The specs beside the primary output's, by output name."""
    return {k: float(v) for k, v in (("rigidity", spec_rigidity_nm_per_arcmin), ("preload", spec_preload_um),
                                     ("transmission_error", spec_te_arcsec)) if v is not None}


def _specs_text(specs: Mapping[str, float]) -> str:
    words = {"rigidity": "rigidity >= {:g} N m/arcmin", "preload": "preload <= {:g} um",
             "transmission_error": "TE peak-to-peak <= {:g} arcsec"}
    return "".join(f", {words[k].format(v)}" for k, v in specs.items())


# --- the linear model: exact yields ------------------------------------------------------------------

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
        moves = _neighbours(choices, current, +1) + _swaps(choices, current)
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


def _binding(label: str, value: Proportion, target: float, choices: GradeChoices,
             grades: Sequence[int]) -> Binding:
    finest = tuple(c.name for c, g in zip(choices.groups, grades) if g == c.grades[0])
    return Binding(label, value.fraction, value.ci95_low, target, value.ci95_low - target, finest)


def _named(choices: GradeChoices, grades: Sequence[int]) -> dict[str, int]:
    return {c.name: int(g) for c, g in zip(choices.groups, grades)}


def _front(points: list[FrontPoint]) -> tuple[FrontPoint, ...]:
    """Non-dominated points (cheaper or higher yield than every other), cheapest first; one point
    per distinct design."""
    unique: dict[tuple, FrontPoint] = {}
    for p in points:
        key = tuple(sorted(p.grades.items()))
        if key not in unique or p.chosen:
            unique[key] = p
    pts = sorted(unique.values(), key=lambda p: (p.cost, -p.yield_.fraction))
    out: list[FrontPoint] = []
    best = -math.inf
    for p in pts:
        if p.yield_.fraction > best + 1e-15:
            out.append(p)
            best = p.yield_.fraction
    return tuple(out)


def _groups_table(choices: GradeChoices, grades: Sequence[int]) -> tuple[GroupGrade, ...]:
    return tuple(GroupGrade(c.name, c.group.grade_table, tuple(c.group.factors), c.current_grade, int(g),
                            c.current_cost, c.cost_of(g), c.grades[0], c.grades[-1], c.group.description)
                 for c, g in zip(choices.groups, grades))


def _uniform(choices: GradeChoices) -> list[tuple[int, tuple[int, ...]]]:
    common = set(choices.groups[0].grades).intersection(*(c.grades for c in choices.groups[1:]))
    return [(g, tuple(g for _ in choices.groups)) for g in sorted(common)]


def _description(problem: Problem, label: str) -> str:
    base = problem.design.description
    return (base + " | " if base else "") + label


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
    chosen = ch.design(sol.grades, _description(problem, label))
    # the reported yield is that of the written design through simulate's own exact path
    y_exact = exact_result(prepare(chosen), spec_arcmin=float(spec_arcmin)).yield_
    points = [FrontPoint(sol.cost, y_exact, _named(ch, sol.grades), "optimum", float(yield_target), True)]
    if pareto:
        for level in PARETO_YIELDS:
            if level == yield_target:
                continue
            s = solve_linear(ch, spec_arcmin, level, yields, oa)
            if s.grades is not None:
                points.append(FrontPoint(s.cost, Proportion.exact(s.yield_fraction), _named(ch, s.grades),
                                         "optimum", level))
    uniform = []
    for g, cand in _uniform(ch):
        uniform.append(FrontPoint(ch.cost(cand), Proportion.exact(yields(cand)), _named(ch, cand), "uniform", None))
    feasible_uniform = [(p.cost, g) for (g, _), p in zip(_uniform(ch), uniform) if p.yield_.fraction >= yield_target]
    if feasible_uniform:
        cost_b, grade_b = min(feasible_uniform)
        base = Baseline(grade_b, cost_b, next(p.yield_ for (g, _), p in zip(_uniform(ch), uniform) if g == grade_b))
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
        yields={"backlash": y_exact}, grades=_named(ch, sol.grades), groups=_groups_table(ch, sol.grades),
        binding=_binding(constraint, y_exact, yield_target, ch, sol.grades), baseline=base, saving=saving,
        saving_fraction=saving / base.cost if saving is not None and base.cost else None,
        front=_front(points + uniform), uniform=tuple(uniform), samples=None, seed=None,
        evaluations=yields.evaluations, verification=None, elapsed_s=time.perf_counter() - started, partial=False,
        notes=tuple(notes), design=chosen)


# --- Monte-Carlo models --------------------------------------------------------------------------

@dataclass(frozen=True)
class Evaluation:
    """Yield of one candidate in one Monte-Carlo run (picklable: it may come from a worker)."""

    yield_: Proportion  # joint when there is more than one spec
    yields: dict  # output -> Proportion
    partial: bool
    output: str = "backlash"  # the primary output, whose spec is spec_arcmin


def evaluate_candidate(task: tuple) -> Evaluation:
    """Simulate one candidate design (a task of the executor: module-level, picklable arguments)."""
    design, model, samples, seed, stream, spec_arcmin, specs, workers = task
    r = simulate(prepare(design), model=model, samples=samples, seed=seed, stream=stream, spec_arcmin=spec_arcmin,
                 specs=specs, workers=workers)
    per = {name: o.yield_ for name, o in r.outputs.items() if o.yield_ is not None}
    joint = r.joint_yield if r.joint_yield is not None else r.yield_
    return Evaluation(joint, per, r.partial, r.output.quantity)


class _Runs:
    """Candidates of a Monte-Carlo search, evaluated through an executor and cached."""

    def __init__(self, choices: GradeChoices, model: str, samples: int, seed: int, spec_arcmin: float,
                 specs: dict | None, executor, workers: int | None, stop, progress):
        self.ch, self.model, self.samples, self.seed = choices, model, samples, seed
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
                 for c in todo]
        out: dict[tuple[int, ...], Evaluation] = {}
        if tasks and not self.stop.is_set():
            for i, ev in executor.map_unordered(evaluate_candidate, tasks, stop=self.stop):
                self.runs += 1
                if ev.partial:
                    self.interrupted = True
                    continue
                out[todo[i]] = ev
                if self.progress is not None:
                    self.progress(self.runs)
        if self.stop.is_set():
            self.interrupted = True
        if stream == SEARCH_STREAM:
            self.cache.update(out)
            return [self.cache.get(c) for c in candidates]
        return [out.get(c) for c in candidates]


def _feasible(ev: Evaluation | None, target: float) -> bool:
    return ev is not None and ev.yield_.ci95_low >= target


def _neighbours(ch: GradeChoices, grades: tuple[int, ...], step: int) -> list[tuple[int, ...]]:
    """Candidates that move one group one grade coarser (step +1) or finer (step -1)."""
    out = []
    for j, c in enumerate(ch.groups):
        k = c.grades.index(grades[j]) + step
        if 0 <= k < len(c.grades):
            out.append(grades[:j] + (c.grades[k],) + grades[j + 1:])
    return out


def _swaps(ch: GradeChoices, grades: tuple[int, ...]) -> list[tuple[int, ...]]:
    """Coarsen one group and tighten another, when that is cheaper."""
    out = []
    for a in _neighbours(ch, grades, +1):
        for b in _neighbours(ch, a, -1):
            if b != grades and sum(x != y for x, y in zip(b, grades)) == 2 and ch.cost(b) < ch.cost(grades):
                out.append(b)
    return out


def search_monte_carlo(ch: GradeChoices, start: tuple[int, ...], runs: _Runs, target: float,
                       max_evaluations: int) -> tuple[int, ...] | None:
    """Local search from ``start`` (module docstring); the cheapest feasible candidate found."""
    current = start
    ev = runs.evaluate([current])[0]
    # 1. tighten until feasible: the move with the most yield per cost
    while not _feasible(ev, target) and not runs.interrupted and len(runs.cache) < max_evaluations:
        moves = _neighbours(ch, current, -1)
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
        moves = [m for m in _neighbours(ch, current, +1) if ch.cost(m) < ch.cost(current)]
        evs = runs.evaluate(moves)
        better = sorted((ch.cost(m), m) for m, e in zip(moves, evs) if _feasible(e, target))
        if not better:
            moves = _swaps(ch, current)
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
                         spec_te_arcsec: float | None = None, samples: int = DEFAULT_MC_SAMPLES,
                         seed: int = 0, executor=None, workers: int | None = None, max_evaluations: int = 200,
                         progress: Callable[[int], None] | None = None) -> AllocationResult:
    """Allocation under a Monte-Carlo model (module docstring): common random numbers for every
    candidate, local search from the linear optimum, verification on an independent stream."""
    started = time.perf_counter()
    check_targets(spec_arcmin, yield_target, spec_rigidity_nm_per_arcmin, spec_preload_um, spec_te_arcsec)
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 1000 <= samples <= 10**7:
        raise InputError("samples", samples, "allowed: a whole number of samples per candidate, 1000 to 1e7 "
                                             "(a search evaluates up to 200 candidates)")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", seed, "allowed: an integer >= 0")
    ch = grade_choices(problem)
    specs = extra_specs(spec_rigidity_nm_per_arcmin, spec_preload_um, spec_te_arcsec) or None
    notes = list(ch.notes)
    try:
        lin = solve_linear(ch, spec_arcmin, yield_target)
    except InputError:
        lin = LinearSolution(None, None, None, 0, False)
    uniform = _uniform(ch)
    with stop_requested() as stop:
        runs = _Runs(ch, model, int(samples), int(seed), float(spec_arcmin), specs, executor, workers, stop, progress)
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
                    notes.append(f"candidate {_named(ch, cand)} failed verification: yield {y.fraction:.6f} "
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
    label = (f"grades allocated by rvbacklash: P({output} <= {spec_arcmin:g} arcmin"
             + _specs_text(specs or {}) + f") >= {yield_target:g}, {model} model")
    design = ch.design(chosen, _description(problem, label))
    points = [FrontPoint(ch.cost(c), e.yield_, _named(ch, c), "candidate", None, c == chosen)
              for c, e in runs.cache.items()]
    uni_points = tuple(FrontPoint(ch.cost(c), runs.cache[c].yield_, _named(ch, c), "uniform", None)
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
    constraint = f"P({output} <= {spec_arcmin:g} arcmin" + _specs_text(specs or {}) + f") >= {yield_target:g}"
    binding = _binding(constraint, ev.yield_, yield_target, ch, chosen)
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
        yield_before=before, yields=dict(ev.yields), grades=_named(ch, chosen), groups=_groups_table(ch, chosen),
        binding=binding, baseline=base, saving=saving,
        saving_fraction=saving / base.cost if saving is not None and base.cost else None,
        front=_front(points), uniform=uni_points, samples=int(samples), seed=int(seed), evaluations=runs.runs,
        verification=verification, elapsed_s=time.perf_counter() - started, partial=partial, notes=tuple(notes),
        design=design)


def allocate(problem: Problem, *, spec_arcmin: float, yield_target: float, model: str = "linear",
             spec_rigidity_nm_per_arcmin: float | None = None, spec_preload_um: float | None = None,
             spec_te_arcsec: float | None = None, samples: int = DEFAULT_MC_SAMPLES, seed: int = 0,
             executor=None, workers: int | None = None, pareto: bool = True,
             progress: Callable[[int], None] | None = None) -> AllocationResult:
    """The cheapest grades per part group meeting the spec at the target yield: exact for the
    linear model, a Monte-Carlo search for the others (module docstring). A TE spec
    (``spec_te_arcsec``) turns the contact model into the transmission model (the same units turned
    through a revolution, models.kinematics), as ``simulate`` does."""
    if spec_te_arcsec is not None and model == "contact":
        model = "transmission"
    if model == "linear":
        if spec_te_arcsec is not None:
            raise InputError("spec_te_arcsec", spec_te_arcsec, "the linear model has no transmission-error output; "
                                                               "allowed with the contact or transmission model")
        if spec_rigidity_nm_per_arcmin is not None:
            raise InputError("spec_rigidity_nm_per_arcmin", spec_rigidity_nm_per_arcmin,
                             "the linear model has no rigidity output; allowed with a model that has one (elastic)")
        if spec_preload_um is not None:
            raise InputError("spec_preload_um", spec_preload_um,
                             "the linear model has no preload output; allowed with the contact or elastic model")
        return allocate_linear(problem, spec_arcmin=spec_arcmin, yield_target=yield_target, pareto=pareto)
    return allocate_monte_carlo(problem, model=model, spec_arcmin=spec_arcmin, yield_target=yield_target,
                                spec_rigidity_nm_per_arcmin=spec_rigidity_nm_per_arcmin,
                                spec_preload_um=spec_preload_um, spec_te_arcsec=spec_te_arcsec, samples=samples,
                                seed=seed,
                                executor=executor, workers=workers, progress=progress)
