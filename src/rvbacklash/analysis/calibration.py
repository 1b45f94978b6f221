"""Calibration of the design-stage unknowns to measured loops (``rvbacklash calibrate``;
docs/bench-data.md, "Calibration").

The model: the design's elastic model (models.elastic) of its nominal unit, with three parameters
the design stage cannot know:

- ``structure_stiffness_nm_per_arcmin`` K_s: one series stiffness for the crankshafts, their
  support bearings and the carrier (``elastic.structure_stiffness_nm_per_arcmin``: it replaces what
  [structure] derives) - the model's least certain element (docs/elastic.md);
- ``friction_torque_nm`` T_f: the constant Coulomb friction at the output (``elastic.friction_torque_nm``);
- ``crank_clearance_offset_um`` dG: the crank needle bearings' radial clearance as assembled less
  its zone mean (written as ``[factors.crank_bearing_clearance] mean_um``). Of the dead bands in
  series (pins, crank bearings, involute stage) a loop sees only their sum, the zero-torque
  width; the crank bearings' is the one the design leaves widest open (a zone [0, IT5] with no
  fit chosen) and a pure dead band in the model, so it carries the offset of the sum.

Least squares (scipy.optimize.least_squares, trust region reflective with bounds) of every
measured sample's angle at its torque against the model's branch at that torque, plus one angle
offset per unit (a nuisance: the bench's zero). Samples of the loading branches inside the dead
band's jump (|T| < x T_R) are left out: there the angle is no function of torque. Confidence
intervals: 95 % from the Jacobian, cov = s^2 (J^T J)^-1 with s^2 the residual variance (one
unit), and a bootstrap over units when there are three or more. A parameter whose column of the
scaled Jacobian is (nearly) a combination of the others (condition number > IDENTIFIABLE_CONDITION)
is not identifiable from these loops: an InputError naming it.
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
from rvbacklash.models.elastic import FALL, RISE, PreparedUnit, elastic_model, nominal_unit
from rvbacklash.problem import Problem, prepare
from rvbacklash.results import EXPORT, Result
from rvbacklash.units import ARCMIN_PER_RAD

PARAMETERS = ("structure_stiffness_nm_per_arcmin", "friction_torque_nm", "crank_clearance_offset_um")
IDENTIFIABLE_CONDITION = 1e6  # of the Jacobian scaled to unit columns: beyond, a parameter is a combination of the others
MODEL_POINTS = 81  # loop nodes per branch the samples are interpolated on
DENSE_NODES = np.linspace(0.0, 0.12, 31)[1:]  # and these fractions of T_R on every branch
RIGID_NM_PER_ARCMIN = 1e9  # the schema's largest stated stiffness: the structure as good as rigid


@dataclass(frozen=True, repr=False)
class FittedParameter(Result):
    """One calibrated parameter with its 95 % confidence interval."""

    name: str
    design_value: float | None  # before: the design's (None: derived / not stated)
    value: float
    ci95_low: float
    ci95_high: float
    ci_from: str  # jacobian | bootstrap over units


@dataclass(frozen=True, repr=False)
class CalibrationResult(Result):
    """The design-stage unknowns fitted to measured loops, and the calibrated design."""

    design_name: str
    sources: tuple[str, ...]
    parameters: tuple[FittedParameter, ...]
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
    spread: dict[str, dict[str, float]]  # figure -> unit-to-unit sigma measured vs predicted (several units)
    design: Design = field(metadata={EXPORT: False})  # the calibrated design
    bench: BenchResult = field(metadata={EXPORT: False})
    before_loop: object = field(default=None, metadata={EXPORT: False})  # HysteresisResult
    after_loop: object = field(default=None, metadata={EXPORT: False})

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

    def branches(self, k_s: float, t_f: float, dg: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        c = self.model.chain._replace(structure_stiffness_nm_per_rad=k_s * ARCMIN_PER_RAD, friction_nm=t_f)
        model = dataclasses.replace(self.model, chain=c)
        unit = self.unit._replace(crank_clearance_um=float(self.unit.crank_clearance_um + dg))
        pu = PreparedUnit(model, unit)
        loop, offset = build_loop(pu, MODEL_POINTS)
        self.evaluations += 1
        out = {}
        tr = self.model.chain.rated_torque_nm
        for b, kind, sign in zip(loop, (RISE, FALL, FALL, RISE), (1.0, 1.0, -1.0, -1.0)):
            # more nodes near zero torque, where the branches bend most (the contacts' first load)
            extra = sign * tr * DENSE_NODES
            angles = [(pu.branch(float(t), kind).sum() - offset) * ARCMIN_PER_RAD for t in extra]
            out[b.branch] = (np.concatenate([b.torque_nm, extra]), np.concatenate([b.angle_arcmin, angles]))
        return out

    def predicted(self, params: np.ndarray, unit: int) -> np.ndarray:
        """The model's angle [arcmin] at each fitted sample of ``unit``."""
        b = self._cache(params)
        u, keep = self.loops[unit], self.fit_masks[unit]
        out = np.empty(int(keep.sum()))
        t, idx = u.torque_nm[keep], u.branch_index[keep]
        for k, name in enumerate(BRANCHES):
            sel = idx == k
            nodes_t, nodes_a = b[name]
            order = np.argsort(nodes_t, kind="stable")
            out[sel] = np.interp(t[sel], nodes_t[order], nodes_a[order])
        return out

    def _cache(self, params):
        key = tuple(float(v) for v in params[:3])
        if getattr(self, "_key", None) != key:
            self._key, self._branches = key, self.branches(*key)
        return self._branches

    def residuals(self, params: np.ndarray, units: Sequence[int]) -> np.ndarray:
        offsets = params[3:]
        return np.concatenate([self.loops[u].angle_arcmin[self.fit_masks[u]] - offsets[j] - self.predicted(params, u)
                               for j, u in enumerate(units)])


def _start(problem: Problem, fit: _Loops, loops: Sequence[BenchLoop]) -> np.ndarray:
    """Initial values: the series stiffness that turns the rigid-structure model's rigidity into the
    measured one (1/K_s = 1/K_measured - 1/K_rest), the design's friction (at least 0.1 % T_R),
    no clearance offset."""
    from rvbacklash.analysis.loop_reading import rigidity_nm_per_arcmin

    e = problem.design.elastic
    lo, hi = e.rigidity_interval_fraction
    k_rest = rigidity_nm_per_arcmin(fit.branches(RIGID_NM_PER_ARCMIN, e.friction_torque_nm, 0.0), e.rated_torque_nm,
                                    lo, hi)
    k_meas = float(np.mean([u.torsional_rigidity_nm_per_arcmin for u in loops]))
    k_s = 1.0 / (1.0 / k_meas - 1.0 / k_rest) if k_meas < 0.999 * k_rest else 100.0 * k_rest
    return np.array([k_s, max(e.friction_torque_nm, 1e-3 * e.rated_torque_nm), 0.0])


def _solve(fit: _Loops, start: np.ndarray, units: Sequence[int], bounds, max_evaluations: int):
    from scipy.optimize import least_squares

    x0 = np.concatenate([start, np.zeros(len(units))])
    lo = np.concatenate([bounds[0], np.full(len(units), -np.inf)])
    hi = np.concatenate([bounds[1], np.full(len(units), np.inf)])
    x0 = np.clip(x0, lo, hi)
    scale = np.concatenate([np.maximum(np.abs(start), [1.0, 0.1, 0.1]), np.ones(len(units))])
    return least_squares(fit.residuals, x0, args=(units,), bounds=(lo, hi), x_scale=scale,
                         diff_step=np.concatenate([[1e-3, 1e-3, 1e-3], np.full(len(units), 1e-3)]),
                         max_nfev=max_evaluations, method="trf")


def calibrate(problem: Problem, files: Sequence, *, rated_torque_nm: float | None = None, units_flags=None,
              bootstrap: int = 50, seed: int = 0, samples: int = 0, max_evaluations: int = 200) -> CalibrationResult:
    """Fit K_s, T_f and dG (module docstring) to the loops of ``files`` (paths, or BenchLoops read
    already); ``samples`` > 0 also places the units in the design's production run (spread)."""
    e = problem.design.elastic
    if e is None:
        raise InputError("elastic", allowed="the design has no [elastic] table; allowed: a design with one")
    if isinstance(bootstrap, bool) or not isinstance(bootstrap, int) or not 0 <= bootstrap <= 10000:
        raise InputError("bootstrap", bootstrap, "allowed: 0 to 10000 resamples over units")
    bench = read_bench(list(files), problem if samples else None, rated_torque_nm=rated_torque_nm, units=units_flags,
                       samples=max(samples, 100), seed=seed) if samples else \
        read_bench(list(files), None, rated_torque_nm=rated_torque_nm or e.rated_torque_nm, units=units_flags)
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
    bounds = (np.array([1e-3 * start[0], 0.0, -nominal_g]),
              np.array([RIGID_NM_PER_ARCMIN, 0.45 * tr * (1.0 - e.friction_load_fraction), 100.0]))
    all_units = list(range(len(loops)))
    sol = _solve(fit, start, all_units, bounds, max_evaluations)
    if sol.status <= 0 or not np.all(np.isfinite(sol.x)):
        raise InputError(f"{where}: calibration", allowed=f"did not converge in {sol.nfev} model evaluations "
                                                          f"({sol.message}); allowed: loops the model can follow "
                                                          f"(check the units and the rated torque)")
    j = sol.jac[:, :3]
    norms = np.linalg.norm(j, axis=0)
    dof = max(sol.fun.size - sol.x.size, 1)
    s2 = float(sol.fun @ sol.fun) / dof
    scaled = j / np.where(norms > 0, norms, 1.0)
    sv, vt = np.linalg.svd(np.column_stack([scaled, sol.jac[:, 3:]]), full_matrices=False)[1:]
    cond = float(np.linalg.cond(scaled)) if np.all(norms > 0) else math.inf
    if not math.isfinite(cond) or cond > IDENTIFIABLE_CONDITION:
        weakest = PARAMETERS[int(np.argmax(np.abs(np.linalg.svd(scaled)[2][-1])))] if np.all(norms > 0) else \
            PARAMETERS[int(np.argmin(norms))]
        raise InputError(f"{where}: calibration", weakest, f"not identifiable from these loops (the Jacobian's "
                                                           f"condition number {cond:.3g} > "
                                                           f"{IDENTIFIABLE_CONDITION:g}: the loop does not change "
                                                           f"with it, or changes as with the others); allowed: "
                                                           f"state it in the design and fit the rest")
    cov = s2 * np.linalg.pinv(sol.jac.T @ sol.jac)[:3, :3]
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    corr = cov / np.outer(np.where(sd > 0, sd, 1.0), np.where(sd > 0, sd, 1.0))
    ci = [(v - 1.96 * s, v + 1.96 * s) for v, s in zip(sol.x[:3], sd)]
    ci_from = ["jacobian"] * 3
    boot = 0
    if len(loops) >= 3 and bootstrap > 0:
        rng = np.random.default_rng(seed)
        draws = []
        for _ in range(bootstrap):
            pick = sorted(rng.integers(0, len(loops), len(loops)).tolist())
            r = _solve(fit, sol.x[:3], pick, bounds, max_evaluations)
            if r.status > 0:
                draws.append(r.x[:3])
        if len(draws) >= max(5, bootstrap // 2):
            d = np.array(draws)
            ci = [tuple(np.quantile(d[:, k], [0.025, 0.975])) for k in range(3)]
            ci_from, boot = ["bootstrap over units"] * 3, len(draws)
    k_s, t_f, dg = (float(v) for v in sol.x[:3])
    calibrated = calibrated_design(problem.design, k_s, t_f, nominal_g + dg, sources)
    from rvbacklash.analysis.hysteresis import hysteresis

    before = hysteresis(problem)
    after = hysteresis(prepare(calibrated))
    design_values = (e.structure_stiffness_nm_per_arcmin, e.friction_torque_nm, 0.0)
    params = tuple(FittedParameter(n, dv, float(v), float(a), float(b), f) for n, dv, v, (a, b), f in
                   zip(PARAMETERS, design_values, sol.x[:3], ci, ci_from))
    figs = ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin")
    fitted = int(sum(m.sum() for m in fit.fit_masks))
    return CalibrationResult(
        problem.name, sources, params, float(math.sqrt(float(sol.fun @ sol.fun) / sol.fun.size)),
        tuple(u.noise_arcmin for u in loops), fitted, fit.evaluations, cond,
        tuple(tuple(float(v) for v in row) for row in corr), tuple(float(v) for v in sol.x[3:]), boot,
        datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat(),
        {k: getattr(before, k) for k in figs}, {k: getattr(after, k) for k in figs},
        {k: float(np.mean([getattr(u, k) for u in loops])) for k in figs}, dict(bench.spread), calibrated, bench,
        before, after)


def calibrated_design(design: Design, structure_stiffness_nm_per_arcmin: float, friction_torque_nm: float,
                      crank_clearance_um: float, sources: Sequence[str]) -> Design:
    """The design with the fitted values: the stated structure stiffness and friction in [elastic],
    the crank bearings' clearance as the mean of its zone (the zone itself, from the grade or the
    file, kept: the tolerance is not what a bench measures)."""
    data = design.model_dump(exclude_none=True)
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
                 "crank_clearance_offset_um": "[factors.crank_bearing_clearance] mean_um = zone mean + offset"}[p.name]
        lines.append(f"  {p.name} = {p.value:.6g} (95 %: {p.ci95_low:.6g} .. {p.ci95_high:.6g}, {p.ci_from}) "
                     f"-> {where}")
    lines.append(f"Residual {result.residual_rms_arcmin:.4f} arcmin rms over {result.samples_fitted} samples; "
                 f"everything else as in the design {result.design_name!r}.")
    return "\n".join(lines)
