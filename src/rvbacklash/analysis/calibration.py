"""Calibration of the design-stage unknowns to measured loops (``rvbacklash calibrate``;
docs/bench-data.md, "Calibration").

The model: the design's elastic model (models.elastic) of its nominal unit, with three parameters
the design stage cannot know:

- ``structure_stiffness_nm_per_arcmin`` K_s: one series stiffness for the crankshafts, their
  support bearings and the carrier (``elastic.structure_stiffness_nm_per_arcmin``: it replaces what
  [structure] derives) - the model's least certain element (docs/elastic.md);
- ``friction_torque_nm`` T_f: the constant Coulomb friction at the output (``elastic.friction_torque_nm``);
  with ``[elastic] friction_model = "contacts"`` instead ``static_friction_coefficient`` mu_s, the
  friction model's uncertain coefficient ([lubrication]): the loop's friction T_0 + (mu_s a + b) |T|
  (``models.elastic.twist_friction``; T_0 from the bearings and the seal, not fitted);
- ``crank_clearance_offset_um`` dG: the crank needle bearings' radial clearance as assembled less
  its zone mean, one per unit (a batch's units differ by their clearances); the units' mean is
  the calibrated design's ``[factors.crank_bearing_clearance] mean_um``, their spread is compared
  with the zone's sigma. Of the dead bands in
  series (pins, crank bearings, involute stage) a loop sees only their sum, the zero-torque
  width; the crank bearings' is the one the design leaves widest open (a zone [0, IT5] with no
  fit chosen) and a pure dead band in the model, so it carries the offset of the sum.

Least squares (scipy.optimize.least_squares, trust region reflective with bounds) of every
measured sample's angle at its torque against the model's branch at that torque, plus one angle
offset per unit (a nuisance: the bench's zero). Samples of the loading branches inside the dead
band's jump (|T| < x T_R) are left out: there the angle is no function of torque. Confidence
intervals: 95 % from the Jacobian (forward differences at the solution), cov = s^2 (J^T J)^-1
with s^2 the residual variance, cut at the bounds (friction and clearance >= 0); from three units
on, the bootstrap over units' standard deviation where it is the larger. Not identifiable, an
InputError naming the parameter: a column of the scaled Jacobian (nearly) a combination of the
others (condition number > IDENTIFIABLE_CONDITION), or a structure stiffness that runs off to
rigid or whose standard error exceeds half its value (a loop of a stiff structure says only
"stiffer than this").

Fit quality: the intervals assume a model that follows the loops. The residual is set against
what each sample's noise (the bench reader's, from differences: no fit enters) and the model's
resolution (its interpolated loop against the loop solved at each sample's torque) explain; above
LACK_OF_FIT_RATIO times that, ``lack_of_fit`` with the residuals per branch and |T| band
(``misfit``: where it sits). A parameter left at a bound (any unit's clearance at zero, friction at
zero, ...) is ``at_bound``: its value is no estimate. Both are in ``flags`` (the table, the JSON and
the written design's comments).
"""

from __future__ import annotations

import dataclasses
import datetime
import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from rvbacklash.analysis.bench import BenchLoop, BenchResult, read_bench
from rvbacklash.analysis.hysteresis import build_loop
from rvbacklash.analysis.loop_reading import BRANCHES
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.models.elastic import FALL, RISE, PreparedUnit, elastic_model, nominal_unit
from rvbacklash.models.elastic.twist_friction import twist_friction
from rvbacklash.problem import Problem, prepare
from rvbacklash.results import EXPORT, Result
from rvbacklash.units import ARCMIN_PER_RAD

PARAMETERS = ("structure_stiffness_nm_per_arcmin", "friction_torque_nm", "crank_clearance_offset_um")
CONTACT_PARAMETERS = ("structure_stiffness_nm_per_arcmin", "static_friction_coefficient", "crank_clearance_offset_um")
IDENTIFIABLE_CONDITION = 1e6  # of the Jacobian scaled to unit columns: beyond, a parameter is the others' combination
MODEL_POINTS = 41  # loop nodes per branch the samples are interpolated on
DENSE_NODES = np.linspace(0.0, 0.12, 21)[1:]  # and these fractions of T_R on every branch
RIGID_NM_PER_ARCMIN = 1e9  # the schema's largest stated stiffness: the structure as good as rigid
LACK_OF_FIT_RATIO = 1.25  # residual rms over what the noise and the model's resolution explain: beyond, a misfit
SEGMENT_BANDS = (0.0, 0.1, 0.3, 0.6, 1.0)  # |T| / T_R bands along each branch where the misfit is shown
KINDS = (RISE, FALL, FALL, RISE)  # of the BRANCHES


@dataclass(frozen=True, repr=False)
class FittedParameter(Result):
    """One calibrated parameter with its 95 % confidence interval."""

    name: str
    design_value: float | None  # before: the design's (None: derived / not stated)
    value: float
    ci95_low: float
    ci95_high: float
    ci_from: str  # jacobian | bootstrap over units
    at_bound: str | None = None  # lower | upper: the fit stops at a bound (for the clearance, of any unit)


@dataclass(frozen=True, repr=False)
class MisfitSegment(Result):
    """The fit's residuals (measured less model) on one stretch of the loops: a branch and a band
    of |T| / T_R, every unit's samples there."""

    branch: str
    from_fraction: float  # of T_R, |T|
    to_fraction: float
    samples: int
    residual_rms_arcmin: float
    residual_mean_arcmin: float
    over_expected: float  # rms / what the noise and the model's resolution explain there


@dataclass(frozen=True, repr=False)
class CalibrationResult(Result):
    """The design-stage unknowns fitted to measured loops, and the calibrated design."""

    design_name: str
    sources: tuple[str, ...]
    parameters: tuple[FittedParameter, ...]
    crank_clearance_um_per_unit: tuple[float, ...]  # each unit's fitted clearance (its zone mean + its offset)
    residual_rms_arcmin: float  # of the fitted samples
    noise_arcmin: tuple[float, ...]  # each unit's, as the bench reader estimates it
    samples_fitted: int
    evaluations: int
    jacobian_condition: float  # of the Jacobian scaled to unit columns (parameters only)
    correlation: tuple[tuple[float, ...], ...]  # of the parameters, from the Jacobian
    angle_offsets_arcmin: tuple[float, ...]  # the nuisance zero of each unit
    bootstrap_resamples: int
    fitted_at: str  # UTC, ISO 8601
    before: dict[str, float]  # the nominal unit's figures with the design as given
    after: dict[str, float]  # and with the calibrated design
    measured: dict[str, float]  # the units' mean figures, as the bench reads them
    spread: dict[str, dict[str, float]]  # figure (and crank_clearance_um) -> unit-to-unit sigma, measured vs
    #                                      predicted (the production run's; the clearance zone's sigma)
    design: Design = field(metadata={EXPORT: False})  # the calibrated design
    bench: BenchResult = field(metadata={EXPORT: False})
    before_loop: object = field(default=None, metadata={EXPORT: False})  # HysteresisResult
    after_loop: object = field(default=None, metadata={EXPORT: False})
    warnings: tuple[str, ...] = ()  # of the before/after figures, e.g. a lost motion read in a stick band
    expected_residual_arcmin: float = math.nan  # rms the noise and the model's resolution explain
    residual_over_expected: float = math.nan  # residual_rms_arcmin / expected_residual_arcmin
    lack_of_fit: bool = False  # residual_over_expected > LACK_OF_FIT_RATIO: the intervals assume a model that fits
    misfit: tuple[MisfitSegment, ...] = ()  # the residuals along the loop (branch, |T| band)
    flags: tuple[str, ...] = ()  # lack of fit (where it sits), parameters at a bound

    def parameter(self, name: str) -> FittedParameter:
        return next(p for p in self.parameters if p.name == name)

    def rows(self) -> list[dict]:
        return [p.to_dict() for p in self.parameters]

    def summary(self) -> list[str]:
        return [f"{p.name} = {p.value:.4g} (95 %: {p.ci95_low:.4g} .. {p.ci95_high:.4g}, {p.ci_from})"
                for p in self.parameters] + [f"residual {self.residual_rms_arcmin:.4f} arcmin rms over "
                                             f"{self.samples_fitted} samples"]


class _Loops:
    """The model's loop of the nominal unit for a parameter vector, read at the measured samples."""

    def __init__(self, problem: Problem, loops: Sequence[BenchLoop]):
        e = problem.design.elastic
        base = problem.design.model_copy(update={"elastic": e.model_copy(update={
            "structure_stiffness_nm_per_arcmin": e.structure_stiffness_nm_per_arcmin or RIGID_NM_PER_ARCMIN})})
        self.model = elastic_model(prepare(base))  # the structure stated: what [structure] derives is replaced
        self.problem = problem
        self.contacts = e.loop_friction_model == "contacts"
        self._twist: dict = {}
        self.names = CONTACT_PARAMETERS if self.contacts else PARAMETERS
        if self.contacts and e.friction_load_fraction is not None:
            raise InputError("elastic.friction_load_fraction", e.friction_load_fraction,
                             "stated with friction_model = \"contacts\": the friction model's coefficient would not "
                             "change the loop; allowed: leave it out (the model's), or friction_model = \"stated\"")
        self.unit = nominal_unit(problem)
        self.x = e.measuring_torque_fraction * e.rated_torque_nm
        self.fit_masks = []
        for u in loops:
            keep = np.ones(u.torque_nm.size, bool)
            for k, name in enumerate(BRANCHES):
                if name.startswith("load"):
                    keep &= ~((u.branch_index == k) & (np.abs(u.torque_nm) < self.x))
            self.fit_masks.append(keep)
        self.loops = loops
        self.evaluations = 0
        self._cache: dict = {}

    def branches(self, k_s: float, t_f: float, dg: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        key = (float(k_s), float(t_f), float(dg))
        if key in self._cache:
            return self._cache[key]
        if len(self._cache) > 64:
            self._cache.clear()
        pu, loop, offset = self._prepared(k_s, t_f, dg)
        self.evaluations += 1
        out = {}
        tr = self.model.chain.rated_torque_nm
        for b, kind, sign in zip(loop, KINDS, (1.0, 1.0, -1.0, -1.0)):
            # more nodes near zero torque, where the branches bend most (the contacts' first load)
            extra = sign * tr * DENSE_NODES
            angles = [(pu.branch(float(t), kind).sum() - offset) * ARCMIN_PER_RAD for t in extra]
            out[b.branch] = (np.concatenate([b.torque_nm, extra]), np.concatenate([b.angle_arcmin, angles]))
        self._cache[key] = out
        return out

    def friction(self, k_s: float, p: float) -> tuple[float, float]:
        """(T_f0 [N m], mu [-]) of the chain's Coulomb friction for the friction parameter p: the
        constant T_f itself, or (contacts) the static coefficient through the twist friction's law of
        the chain with the structure stiffness K_s (the pins' share of each twist depends on it)."""
        c = self.model.chain
        if not self.contacts:
            return p, c.friction_fraction
        key = float(k_s)
        if key not in self._twist:
            if len(self._twist) > 64:
                self._twist.clear()
            model = dataclasses.replace(self.model, chain=c._replace(
                structure_stiffness_nm_per_rad=k_s * ARCMIN_PER_RAD))
            self._twist[key] = twist_friction(self.problem, model)
        return c.friction_nm, self._twist[key].load_fraction_for(p)

    def _prepared(self, k_s: float, t_f: float, dg: float):
        t0, lam = self.friction(k_s, t_f)
        c = self.model.chain._replace(structure_stiffness_nm_per_rad=k_s * ARCMIN_PER_RAD, friction_nm=t0,
                                      friction_fraction=lam)
        model = dataclasses.replace(self.model, chain=c)
        unit = self.unit._replace(crank_clearance_um=float(self.unit.crank_clearance_um + dg))
        pu = PreparedUnit(model, unit)
        loop, offset = build_loop(pu, MODEL_POINTS)
        return pu, loop, offset

    def exact(self, k_s: float, t_f: float, dg: float, unit: int) -> np.ndarray:
        """The model's angle [arcmin] at each fitted sample of ``unit`` solved at its own torque (no
        interpolation between nodes): ``predicted`` less this is the model's resolution."""
        pu, _, offset = self._prepared(k_s, t_f, dg)
        u, keep = self.loops[unit], self.fit_masks[unit]
        return np.array([(pu.branch(float(t), KINDS[k]).sum() - offset) * ARCMIN_PER_RAD
                         for t, k in zip(u.torque_nm[keep], u.branch_index[keep])])

    def predicted(self, k_s: float, t_f: float, dg: float, unit: int) -> np.ndarray:
        """The model's angle [arcmin] at each fitted sample of ``unit`` with clearance offset dg."""
        b = self.branches(k_s, t_f, dg)
        u, keep = self.loops[unit], self.fit_masks[unit]
        out = np.empty(int(keep.sum()))
        t, idx = u.torque_nm[keep], u.branch_index[keep]
        for k, name in enumerate(BRANCHES):
            sel = idx == k
            nodes_t, nodes_a = b[name]
            order = np.argsort(nodes_t, kind="stable")
            out[sel] = np.interp(t[sel], nodes_t[order], nodes_a[order])
        return out

    def residuals(self, x: np.ndarray, units: Sequence[int]) -> np.ndarray:
        """x = [K_s, T_f, dG of each unit..., angle offset of each unit...]."""
        m = len(units)
        return np.concatenate([self.loops[u].angle_arcmin[self.fit_masks[u]] - x[2 + m + j]
                               - self.predicted(x[0], x[1], x[2 + j], u) for j, u in enumerate(units)])


def _start(problem: Problem, fit: _Loops, loops: Sequence[BenchLoop]) -> np.ndarray:
    """Initial values: the series stiffness that turns the rigid-structure model's rigidity into the
    measured one (1/K_s = 1/K_measured - 1/K_rest), the design's friction (at least 0.1 % T_R),
    no clearance offset."""
    from rvbacklash.analysis.loop_reading import rigidity_nm_per_arcmin

    e = problem.design.elastic
    lo, hi = e.rigidity_interval_fraction
    friction = (max(problem.design.lubrication.static_friction_coefficient, 0.01) if fit.contacts
                else max(e.stated_friction_nm, 1e-3 * e.rated_torque_nm))
    k_rest = rigidity_nm_per_arcmin(fit.branches(RIGID_NM_PER_ARCMIN, friction, 0.0), e.rated_torque_nm, lo, hi)
    k_meas = float(np.mean([u.torsional_rigidity_nm_per_arcmin for u in loops]))
    k_s = 1.0 / (1.0 / k_meas - 1.0 / k_rest) if k_meas < 0.999 * k_rest else 100.0 * k_rest
    return np.array([k_s, friction, 0.0])


def _jacobian(fit: _Loops, x: np.ndarray, units: Sequence[int], upper: np.ndarray) -> np.ndarray:
    """d residual / d x at x: forward differences for K_s, T_f and each unit's dG (inward at an
    upper bound), -1 for each unit's own offset on its samples (least_squares' own Jacobian has
    the columns of parameters at a bound zeroed)."""
    m = len(units)
    f0 = fit.residuals(x, units)
    cols = []
    for k in range(2 + m):
        floor, top = ((1.0, upper[0]), (0.01, upper[1]))[k] if k < 2 else (0.01, upper[2])
        h = 1e-4 * max(abs(x[k]), floor)
        h = -h if x[k] + h > top else h
        xk = x.copy()
        xk[k] += h
        cols.append((fit.residuals(xk, units) - f0) / h)
    offsets = np.zeros((f0.size, m))
    start = 0
    for j, u in enumerate(units):
        n = int(fit.fit_masks[u].sum())
        offsets[start:start + n, j] = -1.0
        start += n
    return np.column_stack(cols + [offsets])


def _solve(fit: _Loops, start: np.ndarray, units: Sequence[int], bounds, max_evaluations: int,
           tolerance: float = 1e-8):
    """least_squares over x = [K_s, T_f, dG per unit, offset per unit] from ``start`` (K_s, T_f, dG)."""
    from scipy.optimize import least_squares

    m = len(units)
    x0 = np.concatenate([start[:2], np.full(m, start[2]), np.zeros(m)])
    lo = np.concatenate([bounds[0][:2], np.full(m, bounds[0][2]), np.full(m, -np.inf)])
    hi = np.concatenate([bounds[1][:2], np.full(m, bounds[1][2]), np.full(m, np.inf)])
    x0 = np.clip(x0, lo, hi)
    scale = np.concatenate([np.maximum(np.abs(start[:2]), [1.0, 0.1]), np.full(m, 0.1), np.ones(m)])
    return least_squares(fit.residuals, x0, args=(units,), bounds=(lo, hi), x_scale=scale, diff_step=1e-3,
                         max_nfev=max_evaluations, method="trf", ftol=tolerance, xtol=tolerance)


def _fit_quality(fit: _Loops, x: np.ndarray, residuals: np.ndarray, tr: float):
    """(expected rms, residual rms over it, segments): what the fit leaves against what the noise
    (each sample's own, as the bench reader estimates it) and the model's resolution (its loop
    interpolated between nodes against solved at each sample's torque) explain, in all and per
    branch and band of |T| / T_R."""
    parts, start = [], 0
    for j, u in enumerate(fit.loops):
        keep = fit.fit_masks[j]
        n = int(keep.sum())
        res = fit.predicted(x[0], x[1], x[2 + j], j) - fit.exact(x[0], x[1], x[2 + j], j)
        sigma = u.sample_sigma_arcmin[keep] if u.sample_sigma_arcmin is not None else np.full(n, u.noise_arcmin)
        parts.append((residuals[start:start + n], sigma ** 2 + res ** 2, np.abs(u.torque_nm[keep]) / tr,
                      u.branch_index[keep]))
        start += n
    r, var, frac, branch = (np.concatenate([p[i] for p in parts]) for i in range(4))
    expected = math.sqrt(float(np.mean(var)))
    ratio = math.sqrt(float(np.mean(r * r))) / expected if expected > 0 else math.inf
    segments = []
    for k, name in enumerate(BRANCHES):
        for lo, hi in zip(SEGMENT_BANDS[:-1], SEGMENT_BANDS[1:]):
            sel = (branch == k) & (frac >= lo) & ((frac < hi) | (hi == SEGMENT_BANDS[-1]))
            if not sel.any():
                continue
            rms = math.sqrt(float(np.mean(r[sel] ** 2)))
            exp_here = math.sqrt(float(np.mean(var[sel])))
            segments.append(MisfitSegment(name, lo, hi, int(sel.sum()), rms, float(np.mean(r[sel])),
                                          rms / exp_here if exp_here > 0 else math.inf))
    return expected, ratio, tuple(segments)


def _misfit_flag(rms: float, expected: float, ratio: float, segments) -> str:
    worst = sorted((s for s in segments if s.over_expected > LACK_OF_FIT_RATIO), key=lambda s: -s.over_expected)[:3]
    where = "; ".join(f"{s.branch} {100 * s.from_fraction:g}-{100 * s.to_fraction:g} % T_R (rms "
                      f"{s.residual_rms_arcmin:.4f}, mean {s.residual_mean_arcmin:+.4f} arcmin, "
                      f"{s.over_expected:.1f}x)" for s in worst)
    return (f"lack of fit: residual {rms:.4f} arcmin rms, {ratio:.1f} times what the noise and the model's "
            f"resolution explain ({expected:.4f}); the model does not follow these loops and the 95 % intervals, "
            f"which assume it does, are too narrow; the misfit sits on {where or 'the whole loop'}")


def _bound_flags(x: np.ndarray, sd: np.ndarray, bounds, sources, names=PARAMETERS) -> tuple[list, list[str]]:
    """Which of K_s, T_f and the clearance offset (any unit's) the fit left at a bound: within a
    tenth of its standard error of it (or 1e-9 of the bound)."""
    m = len(sources)
    lo = np.concatenate([bounds[0][:2], np.full(m, bounds[0][2])])
    hi = np.concatenate([bounds[1][:2], np.full(m, bounds[1][2])])
    v, s = x[:2 + m], sd[:2 + m]

    def near(b):
        return np.maximum(0.1 * s, 1e-9 * np.maximum(np.abs(b), 1.0))

    side = np.where(v - lo <= near(lo), -1, np.where(hi - v <= near(hi), 1, 0))
    what = {("structure_stiffness_nm_per_arcmin", -1): "its lower bound {b:g} N m/arcmin",
            ("structure_stiffness_nm_per_arcmin", 1): "its upper bound {b:g} N m/arcmin (rigid)",
            ("friction_torque_nm", -1): "its lower bound {b:g} N m (no friction)",
            ("friction_torque_nm", 1): "its upper bound {b:g} N m",
            ("static_friction_coefficient", -1): "its lower bound {b:g} (no friction on the pins and the mesh)",
            ("static_friction_coefficient", 1): "its upper bound {b:g}",
            ("crank_clearance_offset_um", -1): "its lower bound {b:g} um (zero clearance)",
            ("crank_clearance_offset_um", 1): "its upper bound {b:g} um"}
    at = [None, None, None]
    flags = []
    for i in range(2 + m):
        if side[i] == 0:
            continue
        p = names[min(i, 2)]
        b = lo[i] if side[i] < 0 else hi[i]
        at[min(i, 2)] = at[min(i, 2)] or ("lower" if side[i] < 0 else "upper")
        unit = f" for {sources[i - 2]}" if i >= 2 else ""
        flags.append(f"{p} at {what[p, int(side[i])].format(b=b)}{unit}: the fit stops there, the loop asks for "
                     f"beyond it; a value at a bound is no estimate and its interval no interval (the model cannot "
                     f"follow the loop there)")
    return at, flags


def calibrate(problem: Problem, files: Sequence, *, rated_torque_nm: float | None = None, units_flags=None,
              bootstrap: int = 50, seed: int = 0, samples: int = 0, max_evaluations: int = 200) -> CalibrationResult:
    """Fit K_s, T_f and dG (module docstring) to the loops of ``files`` (paths, or BenchLoops read
    already); ``samples`` > 0 also places the units in the design's production run (spread)."""
    e = problem.design.elastic
    if e is None:
        raise InputError("elastic", allowed="the design has no [elastic] table; allowed: a design with one")
    if isinstance(bootstrap, bool) or not isinstance(bootstrap, int) or not 0 <= bootstrap <= 10000:
        raise InputError("bootstrap", bootstrap, "allowed: 0 to 10000 resamples over units")
    bench = read_bench(list(files), None, rated_torque_nm=rated_torque_nm or e.rated_torque_nm, units=units_flags)
    loops = [u for u in bench.units if isinstance(u, BenchLoop)]
    if len(loops) != len(bench.units):
        bad = next(u.source for u in bench.units if not isinstance(u, BenchLoop))
        raise InputError(bad, allowed="a transmission-error curve; allowed: hysteresis loops (torque and angle)")
    for u in loops:
        if abs(u.rated_torque_nm - e.rated_torque_nm) > 1e-9 * e.rated_torque_nm:
            raise InputError("rated_torque_nm", u.rated_torque_nm, f"the design's is {e.rated_torque_nm:g} N m; "
                                                                   f"allowed: the design's (the model runs to it)")
    fit = _Loops(problem, loops)
    sources = tuple(u.source for u in loops)
    where = ", ".join(sources)
    start = _start(problem, fit, loops)
    nominal_g = float(fit.unit.crank_clearance_um)
    tr = e.rated_torque_nm
    if fit.contacts:  # the coefficient: up to 1 (the schema's) or the friction fraction 0.45
        tw = twist_friction(problem, fit.model)
        top = (0.45 - tw.load_fraction_bearings) / tw.load_fraction_per_coefficient \
            if tw.load_fraction_per_coefficient > 0 else 1.0
        friction_top = float(min(1.0, top))
    else:
        friction_top = 0.45 * tr * (1.0 - e.stated_friction_fraction)
    bounds = (np.array([1e-3 * start[0], 0.0, -nominal_g]), np.array([RIGID_NM_PER_ARCMIN, friction_top, 100.0]))
    all_units = list(range(len(loops)))
    sol = _solve(fit, start, all_units, bounds, max_evaluations)
    if sol.status <= 0 or not np.all(np.isfinite(sol.x)):
        raise InputError(f"{where}: calibration", allowed=f"did not converge in {sol.nfev} model evaluations "
                                                          f"({sol.message}); allowed: loops the model can follow "
                                                          f"(check the units and the rated torque)")
    m = len(loops)
    jac = _jacobian(fit, sol.x, all_units, bounds[1])
    dof = max(sol.fun.size - sol.x.size, 1)
    s2 = float(sol.fun @ sol.fun) / dof
    norms = np.linalg.norm(jac, axis=0)
    names = list(fit.names[:2]) + [f"crank_clearance_offset_um ({src})" for src in sources]
    weakest, why = None, ""
    if not np.all(norms[:2 + m] > 0):
        weakest = names[int(np.argmin(norms[:2 + m]))]
        why = "the loop does not change with it"
    else:
        scaled = jac / norms  # unit columns: the covariance of parameters of any size
        cond = float(np.linalg.cond(scaled[:, :2 + m]))
        cov_all = s2 * np.linalg.pinv(scaled.T @ scaled) / np.outer(norms, norms)
        sd_all = np.sqrt(np.maximum(np.diag(cov_all), 0.0))
        if cond > IDENTIFIABLE_CONDITION:
            weakest = names[int(np.argmax(np.abs(np.linalg.svd(scaled[:, :2 + m])[2][-1])))]
            why = f"the Jacobian's condition number {cond:.3g} > {IDENTIFIABLE_CONDITION:g}: it changes the loop as " \
                  f"the others do"
        elif sol.x[0] >= 0.5 * bounds[1][0] or sd_all[0] > 0.5 * sol.x[0]:
            weakest = fit.names[0]
            why = (f"the fit runs to {sol.x[0]:.3g} N m/arcmin with a standard error of {sd_all[0]:.3g}: the "
                   f"structure is stiffer than these loops resolve")
    if weakest is not None:
        raise InputError(f"{where}: calibration", weakest, f"not identifiable from these loops ({why}); allowed: "
                                                           f"state it in the design, or loops that resolve it")
    dgs = sol.x[2:2 + m]
    # the mean clearance offset: the units' mean, its variance the fits' (1' C 1 / m^2) and the units' spread
    c_dg = cov_all[2:2 + m, 2:2 + m]
    spread_g = float(np.std(dgs, ddof=1)) if m >= 2 else 0.0
    values = np.array([sol.x[0], sol.x[1], float(np.mean(dgs))])
    sd = np.array([sd_all[0], sd_all[1], math.sqrt(float(c_dg.sum()) / m ** 2 + spread_g ** 2 / m)])
    w = np.zeros((3, jac.shape[1]))
    w[0, 0] = w[1, 1] = 1.0
    w[2, 2:2 + m] = 1.0 / m
    cov = w @ cov_all @ w.T
    cov[2, 2] = sd[2] ** 2
    corr = cov / np.outer(np.where(sd > 0, sd, 1.0), np.where(sd > 0, sd, 1.0))
    # 95 %: +-1.96 sigma, cut at the bounds (friction >= 0, clearance >= 0)
    ci = [(max(v - 1.96 * s_, lo_), min(v + 1.96 * s_, hi_))
          for v, s_, lo_, hi_ in zip(values, sd, bounds[0], bounds[1])]
    ci_from = ["jacobian"] * 3
    boot = 0
    if m >= 3 and bootstrap > 0:
        rng = np.random.default_rng(seed)
        draws = []
        for _ in range(bootstrap):
            pick = sorted(rng.integers(0, m, m).tolist())
            r = _solve(fit, values, pick, bounds, max_evaluations, tolerance=1e-6)
            if r.status > 0:
                draws.append([r.x[0], r.x[1], float(np.mean(r.x[2:2 + m]))])
        if len(draws) >= max(3, bootstrap // 2):
            # the units' spread as the bootstrap sees it, or the fit's own if larger: a few resamples'
            # standard deviation is steadier than their 2.5 / 97.5 % quantiles
            boot_sd = np.std(np.array(draws), axis=0, ddof=1)
            sd = np.maximum(sd, boot_sd)
            ci = [(max(v - 1.96 * s_, lo_), min(v + 1.96 * s_, hi_))
                  for v, s_, lo_, hi_ in zip(values, sd, bounds[0], bounds[1])]
            ci_from, boot = ["jacobian or bootstrap over units (the wider)"] * 3, len(draws)
    spread = dict(bench.spread)
    zone_sigma = float(problem.sigmas_um[FACTOR_KEYS.index("crank_bearing_clearance")])
    if m >= 2:
        spread["crank_clearance_um"] = {"units": m, "measured_mean": float(nominal_g + values[2]),
                                        "measured_sigma": spread_g, "predicted_sigma": zone_sigma}
    if samples and m >= 2:
        from rvbacklash.analysis.bench import predicted_elastic

        predicted = predicted_elastic(problem, samples, seed)
        for k, v in bench.spread.items():
            spread[k] = {**v, "predicted_sigma": float(np.std(predicted[k])) if k in predicted else None}
    k_s, t_f, dg = (float(v) for v in values)
    calibrated = calibrated_design(problem.design, k_s, t_f, nominal_g + dg, sources, fit.contacts)
    from rvbacklash.analysis.hysteresis import hysteresis

    before = hysteresis(problem)
    after = hysteresis(prepare(calibrated))
    design_values = (e.structure_stiffness_nm_per_arcmin, problem.design.lubrication.static_friction_coefficient
                     if fit.contacts else e.stated_friction_nm, 0.0)
    rms = float(math.sqrt(float(sol.fun @ sol.fun) / sol.fun.size))
    expected, ratio, segments = _fit_quality(fit, sol.x, sol.fun, tr)
    lack = bool(ratio > LACK_OF_FIT_RATIO)
    at_bound, flags = _bound_flags(sol.x, sd_all, bounds, sources, fit.names)
    if lack:
        flags.insert(0, _misfit_flag(rms, expected, ratio, segments))
    params = tuple(FittedParameter(n, dv, float(v), float(a), float(b), f, ab) for n, dv, v, (a, b), f, ab in
                   zip(fit.names, design_values, values, ci, ci_from, at_bound))
    figs = ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin")
    fitted = int(sum(mask.sum() for mask in fit.fit_masks))
    return CalibrationResult(
        problem.name, sources, params, tuple(float(nominal_g + g) for g in dgs), rms,
        tuple(u.noise_arcmin for u in loops), fitted, fit.evaluations, cond,
        tuple(tuple(float(v) for v in row) for row in corr), tuple(float(v) for v in sol.x[2 + m:]), boot,
        datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat(),
        {k: getattr(before, k) for k in figs}, {k: getattr(after, k) for k in figs},
        {k: float(np.mean([getattr(u, k) for u in loops])) for k in figs}, spread, calibrated, bench,
        before, after, tuple([f"before (the design as given): {w}" for w in before.warnings]
                             + [f"after (the calibrated design): {w}" for w in after.warnings]),
        expected, float(ratio), lack, segments, tuple(flags))


def calibrated_design(design: Design, structure_stiffness_nm_per_arcmin: float, friction_torque_nm: float,
                      crank_clearance_um: float, sources: Sequence[str], contacts: bool = False) -> Design:
    """The design with the fitted values: the stated structure stiffness and friction in [elastic]
    (``contacts``: ``friction_torque_nm`` is the fitted static coefficient, into [lubrication]),
    the crank bearings' clearance as the mean of its zone (the zone itself, from the grade or the
    file, kept: the tolerance is not what a bench measures)."""
    data = design.model_dump(exclude_none=True)
    if contacts:
        data["elastic"].update(structure_stiffness_nm_per_arcmin=float(structure_stiffness_nm_per_arcmin))
        data.setdefault("lubrication", {})["static_friction_coefficient"] = float(friction_torque_nm)
    else:
        data["elastic"].update(structure_stiffness_nm_per_arcmin=float(structure_stiffness_nm_per_arcmin),
                               friction_torque_nm=float(friction_torque_nm))
    factors = data.setdefault("factors", {})
    zone = dict(factors.get("crank_bearing_clearance") or {})
    if zone.get("distribution", "normal") not in ("normal", "truncated_normal"):
        zone["distribution"] = "normal"
    zone["mean_um"] = float(crank_clearance_um)
    zone["note"] = f"mean calibrated on the bench: {', '.join(str(s) for s in sources)}"[:500]
    factors["crank_bearing_clearance"] = zone
    return Design.model_validate(data)


def calibration_header(result: CalibrationResult) -> str:
    """The comment lines of a calibrated design file: what was fitted, from which files, when."""
    lines = [f"Calibrated with `rvbacklash calibrate` on {result.fitted_at} (UTC) from {len(result.sources)} "
             f"measured loop(s):"]
    lines += [f"  {s}" for s in result.sources]
    lines.append("Fitted by least squares of the loops' angles against the nominal unit's loop (docs/bench-data.md):")
    for p in result.parameters:
        where = {"structure_stiffness_nm_per_arcmin": "[elastic] structure_stiffness_nm_per_arcmin (replaces what "
                                                      "[structure] derives)",
                 "friction_torque_nm": "[elastic] friction_torque_nm",
                 "static_friction_coefficient": "[lubrication] static_friction_coefficient (the loop's friction "
                                                "from the contacts)",
                 "crank_clearance_offset_um": "[factors.crank_bearing_clearance] mean_um = zone mean + offset"}[p.name]
        lines.append(f"  {p.name} = {p.value:.6g} (95 %: {p.ci95_low:.6g} .. {p.ci95_high:.6g}, {p.ci_from}) "
                     f"-> {where}")
    lines.append(f"Residual {result.residual_rms_arcmin:.4f} arcmin rms over {result.samples_fitted} samples; "
                 f"everything else as in the design {result.design_name!r}.")
    lines += [f"WARNING, {w}" for w in result.warnings if w.startswith("after")]  # of this design's figures
    lines += [f"WARNING, {f}" for f in result.flags]  # the fit's own: a misfit, a parameter at a bound
    return "\n".join(lines)
