"""One unit in the elastic model: from a contact-model realisation (a unit of a production run,
or a unit measured on a CMM) to its pins' gaps and levers, and from those to its loop's figures
(docs/elastic.md; docs/architecture.md, "One unit's path").

``ElasticUnit`` is what the elastic kernels read of a unit: every pin's gap and lever (the
contact model's ``unit_gaps``), its crank angle, the involute stage's backlash, the crank
bearings' clearance. ``unit_hysteresis`` turns it into the test bench's figures with the
design's ``LoopDesign``; ``evaluate_units`` does that for a production run's batch;
``PreparedUnit`` keeps one unit's contact sets for a loop's many points (the hysteresis command,
the report).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.factors.catalog import FACTOR_KEYS, Stage
from rvbacklash.models.contact import mesh_table, pin_gaps, stage_work, unit_gaps
from rvbacklash.models.elastic.chain import (BACKLASH, LOST_MOTION, N_ELEMENTS, N_FIGURES, PIN_SEATING, PINS, RIGIDITY,
                                             Chain,
                                             ElasticModel, LoopPoints, LoopUnit, branch_angles, chain_angles,
                                             fill_pin_law, loop_figures, loop_points, paired_rollers, pin_phase,
                                             prepare_pins, prepare_support)
from rvbacklash.models.elastic.solver import Y, law_force, new_state
from rvbacklash.models.unit_errors import Realization, unit_errors
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD


class ElasticUnit(NamedTuple):
    """One unit as the elastic model sees it (``unit_hysteresis``); a batch of units has one more,
    leading axis on every field (``evaluate_units``)."""

    gap_um: np.ndarray  # (discs, z_p) free gap of pin j to disc d at zero rotation, normal to the profile
    #                     (negative: interference)
    lever_um_per_rad: np.ndarray  # (discs, z_p) gap(beta) = gap - lever beta for a disc rotation beta
    chi_rad: float  # the crank angle (pin j of disc d sits at phase 2 pi j / z_p - chi - 2 pi d / discs: it sets
    #                 the flank curvature of each contact)
    involute_backlash_rad: float  # the involute stage's backlash at the output (negative read as 0)
    crank_clearance_um: float  # radial clearance G_r of the crank needle bearings (negative: preloaded)


class LoopDesign(NamedTuple):
    """What every unit's loop of a design shares (``loop_design``): the Chain, the crank bearings'
    roller layout cos(psi_i), the loop's points, every pin's contact law at the contact model's
    crank-angle steps (``chain.pin_law_table``; no rows: each unit's laws computed)."""

    chain: Chain
    roller_cos: np.ndarray
    points: LoopPoints
    pin_laws: np.ndarray


def loop_design(model: ElasticModel, pin_laws: np.ndarray | None = None) -> LoopDesign:
    """The LoopDesign of an elastic model (``pin_laws``: its pin_law_table; None: none)."""
    c = model.chain
    table = pin_laws if pin_laws is not None else np.empty((0, model.geometry.discs * model.geometry.zp))
    return LoopDesign(c, model.roller_cos, loop_points(prepare_support(c, model.support_roller), c), table)


@njit(nogil=True, cache=True, inline="always")
def unit_hysteresis(unit, design, out):
    """The test-bench figures of one ElasticUnit (``chain.loop_figures``) into out (N_FIGURES) with
    the design's LoopDesign. Inlined into evaluate_units: a call per unit passing the design's
    records cost ~0.5 us (2 %) in reference counts."""
    c = design.chain
    pins = prepare_pins(unit, c, c.radial_stiffness_n_per_um < np.inf, design.pin_laws)
    rollers = paired_rollers(unit.crank_clearance_um, design.roller_cos, c)
    loop_figures(LoopUnit(pins, rollers, max(unit.involute_backlash_rad, 0.0)), design.points, c, new_state(), out,
                 np.empty(N_ELEMENTS))


@njit(nogil=True, cache=True)
def evaluate_units(units, design, out):
    """``unit_hysteresis`` of a batch of n units (an ElasticUnit with a leading axis, or anything with
    its fields) into out (3, n): lost motion [arcmin], backlash [arcmin], rigidity [N m/arcmin]."""
    fig = np.empty(N_FIGURES)
    for i in range(units.chi_rad.size):
        unit_hysteresis(ElasticUnit(units.gap_um[i], units.lever_um_per_rad[i], units.chi_rad[i],
                                    units.involute_backlash_rad[i], units.crank_clearance_um[i]), design, fig)
        out[0, i] = fig[LOST_MOTION]
        out[1, i] = fig[BACKLASH]
        out[2, i] = fig[RIGIDITY]


def other_stages_nominal(problem: Problem) -> tuple[float, float]:
    """(involute backlash at the output [rad], crank-bearing radial clearance [um]) of the nominal
    unit: the linear model's stage-1 mean (Eq. (1), exact lever i r_1; negative read as 0) and
    the zone mean of factor 20."""
    mask = problem.stage_mask(Stage.INVOLUTE)
    stage1 = float(problem.sensitivities_arcmin_per_um[mask] @ problem.means_um[mask])
    return max(stage1, 0.0) / ARCMIN_PER_RAD, float(problem.means_um[FACTOR_KEYS.index("crank_bearing_clearance")])


def unit_from_realization(problem: Problem, r: Realization, involute_backlash_rad: float,
                          crank_clearance_um: float) -> ElasticUnit:
    """The elastic model's view of a contact-model realisation: every pin's gap and lever from the
    contact kernel (``models.contact.unit_gaps`` at the unit's exact crank angle), as the
    Monte-Carlo computes them, so that a saved unit re-run alone gives its own figures."""
    g = problem.cycloid
    gaps = pin_gaps(g.discs, g.zp)
    unit_gaps(mesh_table(g, np.array([r.chi_rad]))[0], g.stage_geometry, unit_errors(r), gaps,
              stage_work(g.discs, g.zp))
    return ElasticUnit(gaps.gap_um, gaps.lever_um_per_rad, float(r.chi_rad), float(involute_backlash_rad),
                       float(crank_clearance_um))


def nominal_realization(problem: Problem, chi_rad: float = 0.0) -> Realization:
    """The designed unit: nominal modifications, pin/hole clearance at its zone mean (as
    ``analysis.contact.nominal_contact``)."""
    s2 = problem.design.second_stage
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    return Realization.nominal(problem.cycloid, s2.equidistance_modification_um, s2.moving_distance_modification_um,
                               clearance, chi_rad)


def nominal_unit(problem: Problem, chi_rad: float = 0.0) -> ElasticUnit:
    return unit_from_realization(problem, nominal_realization(problem, chi_rad), *other_stages_nominal(problem))


class PreparedUnit:
    """A unit prepared for repeated evaluation (loops, tables): its contact sets, kept between calls."""

    def __init__(self, model: ElasticModel, unit: ElasticUnit):
        self.model, self.unit = model, unit
        c = model.chain
        law = np.empty(unit.gap_um.shape)
        fill_pin_law(unit.chi_rad, c, law)
        self.law_a = law
        self.support = prepare_support(c, model.support_roller)
        pins = prepare_pins(unit._replace(chi_rad=float(unit.chi_rad)), c, model.translating,
                            np.empty((0, unit.gap_um.size)))
        self.loop = LoopUnit(pins, paired_rollers(unit.crank_clearance_um, model.roller_cos, c),
                             max(unit.involute_backlash_rad, 0.0))

    def figures(self) -> np.ndarray:
        out = np.empty(N_FIGURES)
        loop_figures(self.loop, loop_points(self.support, self.model.chain), self.model.chain, new_state(), out,
                     np.empty(N_ELEMENTS))
        return out

    def branch(self, torque_nm: float, branch: int) -> np.ndarray:
        """Element angles [rad] on a branch (``branch_angles``)."""
        out = np.empty(N_ELEMENTS)
        branch_angles(float(torque_nm), branch, self.loop, self.support, self.model.chain, new_state(), out)
        return out

    def chain(self, elastic_torque_nm: float, side: float) -> np.ndarray:
        """Element angles [rad] at a chain torque (``chain_angles``), e.g. both edges of the dead bands."""
        out = np.empty(N_ELEMENTS)
        chain_angles(float(elastic_torque_nm), float(side), self.loop, self.support, self.model.chain, new_state(),
                     out)
        return out

    def pins_angle_rad(self, torque_nm: float, branch: int) -> float:
        """The pins' output angle x [rad] on a branch: the flanks' and the seats' parts (their
        closures and forces read it)."""
        a = self.branch(torque_nm, branch)
        return float(a[PINS] + a[PIN_SEATING])

    def translation_um(self) -> np.ndarray:
        """Each disc's translation along its eccentric [um] at the last evaluation (0: none)."""
        if not self.model.translating:
            return np.zeros(self.unit.gap_um.shape[0])
        return self.loop.pins.translation.per_disc[Y].copy()

    def pin_closures_um(self, pins_angle_rad: float) -> np.ndarray:
        """Closure lever theta + radial y - gap of every pin of every disc [um] (> 0: in contact),
        with the discs' translations of the last evaluation."""
        u = self.unit
        d = u.lever_um_per_rad / self.model.chain.lever_factor * pins_angle_rad - u.gap_um
        if self.model.translating:
            discs, zp = u.gap_um.shape
            phi = np.array([[pin_phase(q * zp + j, float(u.chi_rad), zp, discs) for j in range(zp)]
                            for q in range(discs)])
            k1 = self.model.chain.k1
            radial = (np.cos(phi) - k1) / np.sqrt(1.0 + k1 * k1 - 2.0 * k1 * np.cos(phi))
            d = d + radial * self.translation_um()[:, None]
        return d

    def pin_forces_n(self, pins_angle_rad: float) -> np.ndarray:
        """Force of every pin of every disc [N] at the pins' output angle (and the discs' translations
        of the last evaluation)."""
        c = self.model.chain
        d = self.pin_closures_um(pins_angle_rad)
        f = np.zeros_like(d)
        for idx in zip(*np.nonzero(d > 0)):
            f[idx] = law_force(float(d[idx]), float(self.law_a[idx]), c.law_b, c.law_n, 0.0)[0]
        return f
