"""The test bench's hysteresis loop of one unit (``rvbacklash hysteresis``) and the report's
elastic section (docs/elastic.md).

The loop is the steady cycle 0 -> +T_R -> 0 -> -T_R -> 0 with the input locked, as four branches
of (torque, angle) nodes. Each branch holds the torques the definitions read (+-x T_R, the
rigidity interval, 0) as nodes, so the figures can be recomputed from the loop exactly:

    lost motion = 1/2 [load+(x T_R) + unload+(x T_R)] - 1/2 [load-(-x T_R) + unload-(-x T_R)]
    backlash    = unload+(0) - unload-(0)
    rigidity    = 2 (h - l) T_R / ([load+(h T_R) - load+(l T_R)] + [load-(-l T_R) - load-(-h T_R)])

(at a torque where a branch jumps through the dead bands, the first node at that torque: the end
the branch arrives from). Angles are centred: the middle of the zero-torque width is 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from rvbacklash.analysis.contact import unit_realization
from rvbacklash.design.measured import load_units
from rvbacklash.analysis.loop_reading import (BRANCHES, SECANT_INTERVALS, as_branches,  # noqa: F401 (BRANCHES)
                                              backlash_arcmin, lost_motion_arcmin, rigidity_nm_per_arcmin)
from rvbacklash.errors import InputError
from rvbacklash.models import compliance as cm
from rvbacklash.models.elastic import (BACKLASH, ELEMENT_LOST_MOTION, ELEMENTS, FALL, LOST_MOTION, RIGIDITY, RISE,
                                       SHARES, ElasticModel, ElasticUnit, PreparedUnit, elastic_model, nominal_unit,
                                       other_stages_nominal, unit_from_realization)
from rvbacklash.models.elastic.chain import lost_motion_in_stick_band, stick_band_warning
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result
from rvbacklash.units import ARCMIN_PER_RAD

DEFAULT_POINTS = 41  # grid nodes per branch (the definition torques are added)
ASSUMPTIONS = (
    "input locked, housing fixed; the elastic chain in series: cycloid pins (Hertz line contacts, both discs on one "
    "rotation), crank needle bearings (tangential load, radial clearance as a dead band), involute mesh (dead band + "
    "stiffness), stated structure stiffnesses; disc and crank-bearing deflections referred to the output by the lever "
    "factor; Coulomb friction at the output in parallel; the housing rigid (its ring < 0.5 %), the rest rigid unless "
    "[structure] or a stated stiffness says otherwise (docs/elastic.md)")
ASSUMPTIONS_SEATS = "; the pins' seats in the housing grooves (conforming line contacts in series with the flanks)"
ASSUMPTIONS_STRUCTURE = (
    "; the whole torque path from [structure]: crankshafts (beams with shear between their support bearings, "
    "torsion to the planet gear), tapered-roller support bearings (roller load zone, clearance as a dead band), "
    "{carrier}, the discs' sideways motion on their needle bearings ({translation}), {discs}; main bearings unloaded "
    "by a pure torque; joints rigid")
CARRIER_FE = ("the carrier (output flange, pillars, end plate) as one 3-D finite-element body held at the flange's "
              "outer face")
CARRIER_BEAMS = "carrier pillars (clamped beams in rigid plates)"
DISCS_FE = ("the disc bodies by plane-stress finite elements (loaded by the nominal unit's change of pin forces over "
            "the rigidity interval, bores on the needle bearings' secant stiffness)")
DISCS_RIGID = "the disc bodies rigid"


def structure_assumptions(model: ElasticModel) -> str:
    """What the assumptions say of the seats and the [structure] table's elements, as the model has them."""
    out = ASSUMPTIONS_SEATS if model.chain.seat_a > 0.0 else ""
    if model.structure is not None:
        out += ASSUMPTIONS_STRUCTURE.format(carrier=CARRIER_FE if model.carrier_body is not None else CARRIER_BEAMS,
                                            translation=model.structure.disc_translation,
                                            discs=DISCS_FE if model.disc_body is not None else DISCS_RIGID)
    return out


def profile_assumptions(model: ElasticModel) -> str:
    """What the assumptions add for profiled rollers (docs/rigidity-elements.md); nothing for straight ones."""
    out = ""
    fit = model.needle_fit
    if fit is not None:
        out += (f"; needle rollers {model.inputs.crank_bearing_roller_profile} (by slices, ISO/TS 16281), their law "
                f"fitted as delta = {fit.a:.4g} Q^{fit.n:.4g} over {fit.load_min_n:.3g}-{fit.load_max_n:.4g} N (largest "
                f"error {fit.max_relative_error:.1%})")
    if model.support_roller.x_mm.size:
        out += (f"; support rollers {model.structure.support_bearing_roller_profile} by slices (ISO/TS 16281), tilted "
                f"by the crankshaft's slope at the bearing")
    return out


@dataclass(frozen=True, repr=False)
class HysteresisBranch(Result):
    """One branch of the loop: torque [N m] and output angle [arcmin] at its nodes, in the order run."""

    branch: str  # load+ | unload+ | load- | unload-
    torque_nm: tuple[float, ...]
    angle_arcmin: tuple[float, ...]

    def rows(self) -> list[dict]:
        return [{"branch": self.branch, "torque_nm": t, "angle_arcmin": a}
                for t, a in zip(self.torque_nm, self.angle_arcmin)]


@dataclass(frozen=True, repr=False)
class RigiditySecant(Result):
    """The rigidity read as the secant of both loading branches over [from, to] of T_R (the
    definition of ``torsional_rigidity_nm_per_arcmin`` with another interval)."""

    from_fraction: float
    to_fraction: float
    rigidity_nm_per_arcmin: float


@dataclass(frozen=True, repr=False)
class HysteresisResult(Result):
    """The hysteresis loop of one unit and the test bench's figures read from it."""

    design_name: str
    unit: str  # which unit: nominal, measured (path), a Monte-Carlo quantile unit
    rated_torque_nm: float
    measuring_torque_fraction: float
    rigidity_interval_fraction: tuple[float, float]
    lost_motion_arcmin: float
    backlash_arcmin: float
    torsional_rigidity_nm_per_arcmin: float
    rigidity_secants: tuple[RigiditySecant, ...]  # SECANT_INTERVALS, read from the loop by the same definition
    lost_motion_share_arcmin: dict[str, float]  # of each element of the chain; they sum to the lost motion
    dead_band_arcmin: dict[str, float]  # free play of each element (the loop width with no load and no friction)
    pins_in_contact_at_rated: tuple[int, ...]  # per disc, at +T_R (load+)
    pins_in_contact_at_measuring: tuple[int, ...]  # per disc, at +x T_R (load+)
    max_pin_force_at_rated_n: float
    friction_torque_nm: float
    friction_load_fraction: float
    friction_model: str  # stated | contacts ([elastic] friction_model: the friction above from the contacts)
    friction_at_rated_nm: float  # T_f0 + mu |T_el| at T_R on the loading branch: half the loop's torque width there
    hysteresis_loss_j: float  # the loop's area, the energy one 0 -> +T_R -> 0 -> -T_R -> 0 cycle dissipates [J]
    contact_law: str
    lever_arms: str
    lever_factor: float
    involute_stiffness_nm_per_arcmin: float
    structure_stiffness_nm_per_arcmin: float | None  # stated (elastic.structure_stiffness_nm_per_arcmin); None: not stated
    structure_model: str  # derived ([structure]) | stated (structure_stiffness_nm_per_arcmin) | rigid (neither)
    disc_translation: str  # across | full | none ([structure].disc_translation; none without [structure])
    compliance_share: dict[str, float]  # of each element in the rigidity's angle span; they sum to 1
    element_stiffness_nm_per_arcmin: dict[str, float | None]  # each element's secant over the interval; None: rigid
    wind_up_arcmin: float  # lost motion less the dead bands: the elastic part (and friction's)
    crank_clearance_um: float
    involute_backlash_arcmin: float
    crank_angle_deg: float
    assumptions: str
    loop: tuple[HysteresisBranch, ...]
    pin_forces_at_rated_n: np.ndarray = field(metadata={EXPORT: False})  # (discs, z_p), for figures
    # friction >= x T_R: the lost motion is the stick band's width, not the play (chain.lost_motion_in_stick_band)
    lost_motion_in_stick_band: bool = False
    warnings: tuple[str, ...] = ()  # what the figures above need said beside them

    def branch(self, name: str) -> HysteresisBranch:
        return next(b for b in self.loop if b.branch == name)

    def rows(self) -> list[dict]:
        return [r for b in self.loop for r in b.rows()]

    def summary(self) -> list[str]:
        return [f"{self.design_name} ({self.unit}): lost motion {self.lost_motion_arcmin:.4f} arcmin"
                + (" (stick band)" if self.lost_motion_in_stick_band else "") + " at "
                f"±{self.measuring_torque_fraction * 100:g} % of {self.rated_torque_nm:g} N m, backlash "
                f"{self.backlash_arcmin:.4f} arcmin, rigidity {self.torsional_rigidity_nm_per_arcmin:.1f} N m/arcmin",
                "rigidity secants: " + ", ".join(f"{x.from_fraction * 100:g}-{x.to_fraction * 100:g} % T_R "
                                                 f"{x.rigidity_nm_per_arcmin:.1f}" for x in self.rigidity_secants)
                + " N m/arcmin",
                f"pins in contact at rated torque: {', '.join(map(str, self.pins_in_contact_at_rated))} (per disc)"]


def _nodes(start: float, end: float, points: int, extra: Sequence[float]) -> np.ndarray:
    """Torques from start to end: a uniform grid plus the extra torques inside, in running order."""
    grid = np.linspace(start, end, max(points, 2))
    lo, hi = min(start, end), max(start, end)
    t = np.unique(np.concatenate([grid, [x for x in extra if lo <= x <= hi]]))
    return t if end >= start else t[::-1]


def build_loop(pu: PreparedUnit, points: int = DEFAULT_POINTS) -> tuple[tuple[HysteresisBranch, ...], float]:
    """The four branches of the steady loop [N m, arcmin, centred] and the centring offset [rad]."""
    c = pu.model.chain
    tr, tf, mu = c.rated_torque_nm, c.friction_nm, c.friction_fraction
    xt, lt, ht = c.measuring_fraction * tr, c.rigidity_low * tr, c.rigidity_high * tr
    stick_m = cm.applied_torque_nm(cm.elastic_torque_nm(-tr, False, tf, mu), True, tf, mu)
    stick_p = cm.applied_torque_nm(cm.elastic_torque_nm(tr, True, tf, mu), False, tf, mu)
    offset = 0.5 * (pu.branch(0.0, FALL).sum() + pu.branch(0.0, RISE).sum())
    jump = {RISE: (tf, 1.0), FALL: (-tf, -1.0)}  # where the chain's torque passes 0, and the side it goes to
    secant_ends = tuple(f * tr for interval in SECANT_INTERVALS for f in interval)
    specs = (("load+", RISE, 0.0, tr, (xt, lt, ht, tf, stick_m, *secant_ends)),
             ("unload+", FALL, tr, 0.0, (xt, stick_p)),
             ("load-", FALL, 0.0, -tr, (-xt, -lt, -ht, -tf, stick_p, *(-t for t in secant_ends))),
             ("unload-", RISE, -tr, 0.0, (-xt, stick_m)))
    branches = []
    for name, kind, start, end, extra in specs:
        torques, angles = [], []
        jt, side = jump[kind]
        for t in _nodes(start, end, points, extra):
            a = pu.branch(t, kind).sum()
            torques.append(float(t))
            angles.append(a)
            if t == jt and name in ("load+", "load-"):  # through the dead bands at this torque
                after = pu.chain(0.0, side).sum()
                if after != a:
                    torques.append(float(t))
                    angles.append(after)
        branches.append(HysteresisBranch(name, tuple(torques),
                                         tuple(float((a - offset) * ARCMIN_PER_RAD) for a in angles)))
    return tuple(branches), offset


def loop_area_j(loop: Sequence[HysteresisBranch]) -> float:
    """The area the loop's four branches enclose [J = N m rad]: the energy friction dissipates in one
    cycle (the hysteresis loss), by the shoelace formula over the branches in running order (load+,
    unload+, load-, unload-: a closed curve; the jumps through the dead bands are its vertical pieces).
    Branches that coincide (no friction) enclose 0."""
    t = np.concatenate([np.asarray(b.torque_nm, float) for b in loop])
    a = np.concatenate([np.asarray(b.angle_arcmin, float) for b in loop]) / ARCMIN_PER_RAD
    return float(abs(0.5 * np.sum(a * np.roll(t, -1) - np.roll(a, -1) * t)))


def loop_figures_from_branches(loop: Sequence[Mapping], rated_torque_nm: float, measuring_fraction: float,
                               interval: Sequence[float]) -> dict[str, float]:
    """The three figures recomputed from a loop (e.g. the JSON's ``loop``) by the one reader of
    model and measured loops (``analysis.loop_reading``): each branch read at the first node with
    the torque asked for (interpolated between nodes elsewhere)."""
    b = as_branches(loop)
    return {"lost_motion_arcmin": lost_motion_arcmin(b, rated_torque_nm, measuring_fraction),
            "backlash_arcmin": backlash_arcmin(b),
            "torsional_rigidity_nm_per_arcmin": rigidity_nm_per_arcmin(b, rated_torque_nm, *interval)}


def unit_hysteresis_result(problem: Problem, model: ElasticModel, unit: ElasticUnit, label: str,
                           points: int = DEFAULT_POINTS) -> HysteresisResult:
    """The loop and the figures of one unit."""
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or not 2 <= points <= 10000:
        raise InputError("points", points, "allowed: a whole number of loop nodes per branch, 2 to 10000")
    pu = PreparedUnit(model, unit)
    c = model.chain
    fig = pu.figures()
    spans = fig[SHARES:]
    total = float(spans.sum())
    torque_span = 2.0 * (c.rigidity_high - c.rigidity_low) * c.rated_torque_nm
    loop, _ = build_loop(pu, int(points))
    loop_rows = [{"branch": b.branch, "torque_nm": b.torque_nm, "angle_arcmin": b.angle_arcmin} for b in loop]
    secants = tuple(RigiditySecant(lo, hi, loop_figures_from_branches(
        loop_rows, c.rated_torque_nm, c.measuring_fraction, (lo, hi))["torsional_rigidity_nm_per_arcmin"])
        for lo, hi in SECANT_INTERVALS)
    tr = c.rated_torque_nm
    at_rated = pu.pins_angle_rad(tr, RISE)
    at_x = pu.pins_angle_rad(c.measuring_fraction * tr, RISE)
    forces = pu.pin_forces_n(at_rated)
    free = pu.chain(0.0, 1.0) - pu.chain(0.0, -1.0)
    e = model.inputs
    return HysteresisResult(
        design_name=problem.name, unit=label, rated_torque_nm=tr, measuring_torque_fraction=c.measuring_fraction,
        rigidity_interval_fraction=(c.rigidity_low, c.rigidity_high), lost_motion_arcmin=float(fig[LOST_MOTION]),
        backlash_arcmin=float(fig[BACKLASH]), torsional_rigidity_nm_per_arcmin=float(fig[RIGIDITY]),
        rigidity_secants=secants, lost_motion_share_arcmin={k: float(v) for k, v in zip(ELEMENTS, fig[ELEMENT_LOST_MOTION:SHARES])},
        dead_band_arcmin={k: float(v * ARCMIN_PER_RAD) for k, v in zip(ELEMENTS, free)},
        compliance_share={k: float(v / total) if total > 0 else 0.0 for k, v in zip(ELEMENTS, spans)},
        element_stiffness_nm_per_arcmin={k: float(torque_span / v) if v > 0 else None for k, v in zip(ELEMENTS, spans)},
        wind_up_arcmin=float(fig[LOST_MOTION] - free.sum() * ARCMIN_PER_RAD),
        structure_model=("derived" if model.derived else
                         "stated" if e.structure_stiffness_nm_per_arcmin is not None else "rigid"),
        disc_translation=model.structure.disc_translation if model.structure is not None else "none",
        pins_in_contact_at_rated=tuple(int(n) for n in (pu.pin_closures_um(at_rated) > 0).sum(axis=1)),
        pins_in_contact_at_measuring=tuple(int(n) for n in (pu.pin_closures_um(at_x) > 0).sum(axis=1)),
        max_pin_force_at_rated_n=float(forces.max()), friction_torque_nm=c.friction_nm,
        friction_load_fraction=c.friction_fraction, friction_model=e.loop_friction_model,
        friction_at_rated_nm=float(tr - cm.elastic_torque_nm(tr, True, c.friction_nm, c.friction_fraction)),
        hysteresis_loss_j=loop_area_j(loop), contact_law=e.contact_law, lever_arms=e.lever_arms,
        lever_factor=c.lever_factor, involute_stiffness_nm_per_arcmin=model.involute_stiffness_nm_per_arcmin,
        structure_stiffness_nm_per_arcmin=(model.structure_stiffness_nm_per_arcmin
                                           if math.isfinite(model.structure_stiffness_nm_per_arcmin) else None),
        crank_clearance_um=float(unit.crank_clearance_um),
        involute_backlash_arcmin=float(max(unit.involute_backlash_rad, 0.0) * ARCMIN_PER_RAD),
        crank_angle_deg=float(math.degrees(unit.chi_rad)),
        assumptions=ASSUMPTIONS + structure_assumptions(model) + profile_assumptions(model), loop=loop,
        pin_forces_at_rated_n=forces, lost_motion_in_stick_band=lost_motion_in_stick_band(c),
        warnings=tuple(w for w in (stick_band_warning(c),) if w))


def measured_unit(problem: Problem, path: str | Path, unit: int | None = None) -> tuple[ElasticUnit, str]:
    """Unit ``unit`` (0-based; default the first) of a measured-unit file (UNIT.toml, design/measured.py) and its label. Its
    cycloid-stage errors give the gaps (the contact kernel's, as the Monte-Carlo has them); the
    crank bearings' clearance and the involute stage from ``crank_bearing_clearance_um`` and
    ``other_stages_arcmin`` when the file gives them, else at their nominal values."""
    units = load_units(path, problem.design)
    k = 0 if unit is None else unit
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k < len(units):
        raise InputError("unit", unit, f"allowed: 0 to {len(units) - 1} (the units of {path}, 0-based)")
    r = unit_realization(problem, units[k])
    label = f"measured: unit {k} of {path}" if len(units) > 1 else f"measured: {path}"
    involute, crank = other_stages_nominal(problem)
    if r.involute_backlash_rad is not None:
        involute = r.involute_backlash_rad
    if r.crank_clearance_um is not None:
        crank = r.crank_clearance_um
    return unit_from_realization(problem, r, involute, crank), label


def hysteresis(problem: Problem, *, measured: str | Path | None = None, unit: int | None = None,
               points: int = DEFAULT_POINTS) -> HysteresisResult:
    """The loop of the nominal unit (designed modifications, pin/hole clearance and crank-bearing
    clearance at their zone means, the involute stage at its linear mean, crank angle 0), or of a
    measured unit (``measured``: its file; ``unit``: which of its units, 0-based, default the first)."""
    if unit is not None and measured is None:
        raise InputError("unit", unit, "allowed with measured units only (--measured)")
    model = elastic_model(problem)
    if measured is not None:
        u, label = measured_unit(problem, measured, unit)
        return unit_hysteresis_result(problem, model, u, label, points)
    return unit_hysteresis_result(problem, model, nominal_unit(problem), "nominal", points)


# --- the report's elastic section --------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class ElasticSection(Result):
    """What the report's elastic section shows: the nominal loop, the loops of the units at given
    quantiles of lost motion (drawn from a sample of ``samples`` units), and a production run."""

    nominal: HysteresisResult
    quantile_units: dict[str, HysteresisResult]  # "5 %" -> the unit nearest that quantile of lost motion
    samples: int
    seed: int
    simulation: object | None = field(default=None, metadata={EXPORT: False})  # SimulationResult, model elastic
    specs: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"nominal": self.nominal.to_dict(),
                "quantile_units": {k: v.to_dict() for k, v in self.quantile_units.items()},
                "samples": self.samples, "seed": self.seed, "specs": dict(self.specs),
                "simulation": self.simulation.to_dict() if self.simulation is not None else None}

    def summary(self) -> list[str]:
        return self.nominal.summary()[:1] + [f"{k} unit: {v.lost_motion_arcmin:.4f} arcmin"
                                             for k, v in self.quantile_units.items()]


def elastic_section(problem: Problem, *, simulation=None, specs: Mapping[str, float] | None = None,
                    probabilities: Sequence[float] = (0.05, 0.95), samples: int = 2000, seed: int = 0,
                    points: int = DEFAULT_POINTS) -> ElasticSection:
    """The report's elastic section: the nominal loop and the loops of the units nearest the given
    quantiles of lost motion in ``samples`` units drawn with ``seed`` (the Monte-Carlo sampler's
    drawing), beside a simulation run with ``model="elastic"`` if given."""
    from rvbacklash.models.elastic import loop_design
    from rvbacklash.sampling.elastic_source import design_pin_laws, evaluate_batch, sample_units

    for p in probabilities:
        if isinstance(p, bool) or not isinstance(p, (int, float)) or not 0 < p < 1:
            raise InputError("probabilities", p, "allowed: probabilities 0 < p < 1")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or not 10 <= samples <= 10**6:
        raise InputError("samples", samples, "allowed: 10 to 1e6 units")
    model = elastic_model(problem)
    units = sample_units(problem, int(seed), int(samples))
    lm = evaluate_batch(loop_design(model, design_pin_laws(model)), units)[0]
    picked = {}
    for p in probabilities:
        i = int(np.argmin(np.abs(lm - np.quantile(lm, p))))
        unit = ElasticUnit(units.gap_um[i], units.lever_um_per_rad[i], float(units.chi_rad[i]),
                           float(units.involute_backlash_rad[i]), float(units.crank_clearance_um[i]))
        label = f"{p * 100:g} %"
        picked[label] = unit_hysteresis_result(problem, model, unit, f"unit at the {label} quantile of lost motion "
                                                                     f"({samples} units, seed {seed})", points)
    nominal = unit_hysteresis_result(problem, model, nominal_unit(problem), "nominal", points)
    return ElasticSection(nominal, picked, int(samples), int(seed), simulation, dict(specs or {}))
