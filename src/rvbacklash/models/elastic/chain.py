"""The elastic hysteresis model: a unit's torque-angle loop as the test bench measures it
(docs/elastic.md).

Input locked, housing fixed, torque T on the output. The output angle is a chain of elements in
series, each referred to the output:

    theta(T) = theta_pins + theta_crank + theta_involute + theta_crankshafts + theta_support + theta_carrier
               + T_el / K_structure + T_el / K_main

- **cycloid pins** (both discs in parallel, tied by the cranks: one rotation): contact j closes
  by delta_j = (L_j / k) theta - g_j [um] (gap g_j and signed lever L_j of the contact model,
  ``models.contact.unit_gaps``; k the lever factor, ``compliance.cycloid_lever_factor``);
  its force F_j(delta_j) inverts the line-contact law; theta solves 1e-6 sum F_j L_j / k = T_el
  (monotone in theta; preloaded units start in contact);
- **crank (swivel-arm) needle bearings**: every bearing carries F = T_el k / (n a0); its rollers
  (rollers at 2 pi i / Z, one on the load line) close by delta_r cos(psi_i) - G_r / 2 (radial
  clearance G_r: the dead band); the disc turns delta_r / a0 against the carrier, the output k
  times that;
- **involute stage**: dead band b_1 (its backlash at the output) and stiffness K_1;
- **the rest of the torque path** from the design's [structure] table (``with_structure``):
  crankshafts (bending, shear, torsion: linear), support bearings (a tapered-roller set with its
  clearance, solved like the needle bearings, once per batch), carrier pillars (linear), and the
  discs' sideways motion on their needle bearings (a factor on their elastic part across the
  eccentric; with ``disc_translation = "full"`` also along it, ``solve_pins``);
- **structure** and **main bearings**: stated stiffnesses (a measured value wins).

Friction: a Coulomb torque T_f = T_f0 + mu |T_el| at the output in parallel with the chain
(``compliance.elastic_torque_nm``). The loop's rising branch (load+ and unload-) and falling
branch (load- and unload+) then differ; at the turning points the output sticks until the
torque has changed by twice the friction.

This module holds the chain: the design's ``Chain`` record (``closed_form_model``), each element's
set of contacts (``prepare_pins``, ``prepare_rollers``, ``prepare_support``), the angle of each
element at a torque (``chain_angles``) and the loop's figures (``loop_figures``). The solves are
in ``solver``, the unit (from a realisation or a measured unit, its figures) in ``unit``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from rvbacklash._numba import njit, njit_borrowing
from rvbacklash.design.elastic import ElasticInputs
from rvbacklash.design.structure import StructureInputs
from rvbacklash.errors import InputError
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models import compliance as cm
from rvbacklash.models.contact import crank_step_angle_rad
from rvbacklash.models.elastic.rollers import STRAIGHT, RollerLawFit, SlicedRoller, fit_load_range_n, fit_roller_law, \
    fitted_law_valid, sliced_roller
from rvbacklash.models.elastic.solver import (N_TRANSLATION_ROWS, NEGATIVE, POSITIVE, ContactLaw, ContactSet,
                                              DiscTranslation, PinSet, SupportMemo, SupportSet, closure_order,
                                              new_state, set_bounds, solve_pins, solve_set, support_deflection_um)
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD

ELEMENTS = ("cycloid_pins", "pin_seating", "disc_bodies", "crank_bearings", "involute_stage", "structure",
            "crankshafts", "support_bearings", "carrier", "main_bearings")
N_ELEMENTS = len(ELEMENTS)
# each element's place in a vector of the element angles (chain_angles), ELEMENTS order
(PINS, PIN_SEATING, DISC_BODIES, CRANK_BEARINGS, INVOLUTE, STRUCTURE, CRANKSHAFTS, SUPPORT_BEARINGS, CARRIER,
 MAIN_BEARINGS) = range(N_ELEMENTS)
# unit_hysteresis fills out[0:N_FIGURES]: lost motion [arcmin], backlash [arcmin], rigidity [N m/arcmin],
# then from ELEMENT_LOST_MOTION the lost motion of each element [arcmin] (they sum to the lost motion), then
# from SHARES each element's angle over the rigidity interval [arcmin] (they sum to the interval's angle: the
# compliance shares)
LOST_MOTION, BACKLASH, RIGIDITY = 0, 1, 2
ELEMENT_LOST_MOTION = 3
SHARES = ELEMENT_LOST_MOTION + N_ELEMENTS
N_FIGURES = 3 + 2 * N_ELEMENTS
TRANSLATION_ROUNDS = 60  # solve_pins' rounds (x solve, Newton step on the translations) at most
SUPPORT_MEMO = 24  # torques remembered by a support set (chain_angles' repeated calls)
RISE, FALL = 0, 1  # the rising branch (load+, unload-) and the falling branch (load-, unload+)
# Beam and shaft formulas are small-deflection theory: at the rated torque a crankshaft or a pillar
# may deflect at most this share of its length, a crankshaft twist this many radians (rv80e: 1e-4)
SMALL_DEFLECTION = 0.01


class Chain(NamedTuple):
    """Everything the kernels need of a design besides the unit's own arrays."""

    law_b: float  # contact law delta = F^n (a - b ln F) [um, N]: b and n, shared by every pin (flank + seat)
    law_n: float
    johnson: bool  # per-pin a from the flank curvature (Johnson); else a = palmgren_a for every pin
    palmgren_a: float
    contact_length_mm: float
    pin_radius_mm: float
    generating_radius_mm: float
    pin_circle_radius_mm: float
    k1: float
    pins: float
    discs: float
    pin_e_gpa: float
    pin_nu: float
    disc_e_gpa: float
    disc_nu: float
    lever_factor: float  # k: output rotation per disc rotation
    involute_stiffness_nm_per_rad: float
    structure_stiffness_nm_per_rad: float  # inf: rigid
    bearing_force_n_per_nm: float  # radial load of one crank bearing per N m of T_el
    bearing_angle_rad_per_um: float  # output rotation per um of radial bearing deflection
    roller_a: float  # law of one roller between its raceways (two contacts in series)
    roller_b: float
    rollers_symmetric: bool  # an even number of rollers (a load and its mirror deflect alike)
    rated_torque_nm: float
    measuring_fraction: float
    rigidity_low: float
    rigidity_high: float
    friction_nm: float
    friction_fraction: float
    # the whole torque path (design/structure.py; issue 16). Off: 1, inf, 0.
    translation_factor: float  # disc_translation_factor: the needle bearings' elastic part, times this
    radial_stiffness_n_per_um: float  # K_y of one disc's bearings along its eccentric (inf: no translation)
    crank_compliance_rad_per_nm: float  # crankshafts: bending + shear + torsion, at the output
    carrier_compliance_rad_per_nm: float
    main_bearing_compliance_rad_per_nm: float  # stated only (derived: unloaded by a pure torque)
    support_rollers: int  # rollers per support bearing (0: no support bearings modelled)
    support_cos_alpha: float
    support_clearance_um: float
    support_a: float  # Palmgren's law of one roller between its raceways (two contacts)
    support_symmetric: bool
    support_force_n_per_nm: float  # radial load of one support bearing per N m of T_el
    translation_rounds: int  # solve_pins: at most this many x solves per torque with the discs translating
    # issue 28: the pins' seats in the housing grooves (in every pin's law) and the discs' bodies. Off: 0.
    seat_a: float  # a of the seat's law, included in every pin's a (pin_law_a) [um/N^n]
    seat_b_fraction: float  # b_seat / law_b (Johnson: the seat's part of the shared b; Palmgren: 0)
    disc_body_compliance_rad_per_nm: float  # the discs' bodies (FE, mechanics.disc_body) at the output
    # the crank needle rollers' own exponent: delta = F^roller_n (roller_a - roller_b ln F) (law_n for straight
    # rollers; a profiled roller's fitted law, rollers.fit_roller_law)
    roller_n: float


@dataclass(frozen=True)
class ElasticModel:
    """The elastic model of a design: resolved inputs (``chain``), roller layout, and what the
    report says about them."""

    inputs: ElasticInputs
    geometry: ContactGeometry
    chain: Chain
    roller_cos: np.ndarray  # cos(psi_i) of the rollers of one crank bearing
    bearings: int  # crank needle bearings carrying the disc torque (discs x cranks)
    crank_circle_radius_mm: float
    raceway_diameter_mm: float
    structure: StructureInputs | None = None  # the whole torque path's dimensions (None: rigid)
    derived: bool = False  # the crankshafts, support bearings and carrier derived from ``structure``
    disc_body: Any = None  # mechanics.disc_body.DiscBodyResult: the discs' bodies by FE (None: rigid)
    carrier_body: Any = None  # mechanics.carrier_body.CarrierBodyResult: the carrier by FE (None: pillars)
    needle_fit: RollerLawFit | None = None  # profiled needle rollers: their sliced law's fit (None: straight)
    support_roller: SlicedRoller = STRAIGHT  # the support bearings' rollers by slices (STRAIGHT: Palmgren's law)

    @property
    def lever_factor(self) -> float:
        return self.chain.lever_factor

    @property
    def involute_stiffness_nm_per_arcmin(self) -> float:
        return self.chain.involute_stiffness_nm_per_rad / ARCMIN_PER_RAD

    @property
    def structure_stiffness_nm_per_arcmin(self) -> float:
        return self.chain.structure_stiffness_nm_per_rad / ARCMIN_PER_RAD

    @property
    def translating(self) -> bool:
        """The discs move sideways on their needle bearings (the pins' radial resultant followed)."""
        return math.isfinite(self.chain.radial_stiffness_n_per_um)


def closed_form_model(problem: Problem) -> ElasticModel:
    """Resolve the design's [elastic] table into the kernels' parameters (docs/elastic.md): every
    element from its closed form (``bodies.elastic_model`` adds the finite-element bodies)."""
    design = problem.design
    e = design.elastic
    if e is None:
        raise InputError("elastic", None, "allowed: an [elastic] table in the design with at least rated_torque_nm, "
                                          "disc_face_width_mm and the crank bearing's rollers (docs/elastic.md)")
    g = problem.cycloid
    s1, s2 = design.first_stage, design.second_stage
    if s1.face_width_mm is None:
        raise InputError("first_stage.face_width_mm", None, "required by the elastic model (involute mesh "
                                                            "stiffness); allowed: face width b [mm]")
    raceway = e.crank_bearing_raceway_diameter_mm or design.crank_stage.bearing_bore_mm
    if raceway is None:
        raise InputError("elastic.crank_bearing_raceway_diameter_mm", None,
                         "required when crank_stage.bearing_bore_mm is not given; allowed: diameter [mm]")
    length = e.disc_face_width_mm if e.pin_length_mm is None else min(e.disc_face_width_mm, e.pin_length_mm / g.discs)
    k = cm.cycloid_lever_factor(s2.cycloid_teeth, s2.pins, s1.centre_gear_teeth, s1.planet_teeth,
                                e.lever_arms == "kinematic")
    geo = problem.geometry
    k_inv = cm.mesh_torsional_stiffness_nm_per_rad(e.mesh_stiffness_n_per_mm_um, s1.face_width_mm,
                                                   geo.centre_gear_pitch_radius_mm, geo.ratio, s1.planets,
                                                   geo.pressure_angle_deg)
    k_struct = (math.inf if e.structure_stiffness_nm_per_arcmin is None
                else e.structure_stiffness_nm_per_arcmin * ARCMIN_PER_RAD)
    c_main = (0.0 if e.main_bearing_stiffness_nm_per_arcmin is None
              else 1.0 / (e.main_bearing_stiffness_nm_per_arcmin * ARCMIN_PER_RAD))
    a0 = geo.crank_circle_radius_mm
    bearings = g.discs * s1.planets
    dw, lw = e.crank_bearing_roller_diameter_mm, e.crank_bearing_roller_length_mm
    johnson = e.contact_law == "johnson"
    if johnson:
        inner = cm.capped_relative_radius_mm(dw / 2, raceway / 2, cm.RELATIVE_RADIUS_CAP * dw / 2)
        outer = cm.capped_relative_radius_mm(dw / 2, -(raceway / 2 + dw), cm.RELATIVE_RADIUS_CAP * dw / 2)
        roller = cm.Body(dw / 2, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio)
        roller_a = (cm.johnson_law_a_um_per_n(lw, roller, cm.Body(raceway / 2, e.disc_youngs_modulus_gpa,
                                                                  e.disc_poisson_ratio), inner)
                    + cm.johnson_law_a_um_per_n(lw, roller, cm.Body(raceway / 2 + dw, e.disc_youngs_modulus_gpa,
                                                                    e.disc_poisson_ratio), outer))
        b1 = cm.johnson_law_b_um_per_n(lw, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio, e.disc_youngs_modulus_gpa,
                                       e.disc_poisson_ratio)
        roller_b, law_b, law_n = 2.0 * b1, cm.johnson_law_b_um_per_n(
            length, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio, e.disc_youngs_modulus_gpa, e.disc_poisson_ratio), 1.0
    else:
        roller_a, roller_b = 2.0 * cm.palmgren_law_a(lw), 0.0
        law_b, law_n = 0.0, cm.PALMGREN_EXPONENT
    seat_a, seat_b_fraction = 0.0, 0.0
    if e.pin_seating == "groove":
        pin, housing = (cm.Body(g.rrp_mm, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio),
                        cm.Body(g.rrp_mm, e.housing_youngs_modulus_gpa, e.housing_poisson_ratio))
        if johnson:
            seat_a = cm.pin_seat_law_a_um_per_n(length, pin, housing)
            seat_b = cm.johnson_law_b_um_per_n(length, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio,
                                               e.housing_youngs_modulus_gpa, e.housing_poisson_ratio)
            seat_b_fraction = seat_b / (law_b + seat_b)
            law_b += seat_b
        else:  # Palmgren's law for a second line contact of the same length (steel on steel)
            seat_a = cm.palmgren_law_a(length)
    low, high = e.rigidity_interval_fraction
    chain = Chain(
        law_b=law_b, law_n=law_n, johnson=johnson, palmgren_a=cm.palmgren_law_a(length) + seat_a,
        contact_length_mm=length, pin_radius_mm=g.rrp_mm,
        generating_radius_mm=g.rrp_mm + s2.equidistance_modification_um * 1e-3, pin_circle_radius_mm=g.rp_mm,
        k1=g.K1, pins=float(g.zp), discs=float(g.discs), pin_e_gpa=e.pin_youngs_modulus_gpa, pin_nu=e.pin_poisson_ratio,
        disc_e_gpa=e.disc_youngs_modulus_gpa, disc_nu=e.disc_poisson_ratio, lever_factor=k,
        involute_stiffness_nm_per_rad=k_inv, structure_stiffness_nm_per_rad=k_struct,
        bearing_force_n_per_nm=k * 1e3 / (bearings * a0), bearing_angle_rad_per_um=k * 1e-3 / a0,
        roller_a=roller_a, roller_b=roller_b, rollers_symmetric=e.crank_bearing_rollers % 2 == 0,
        rated_torque_nm=e.rated_torque_nm,
        measuring_fraction=e.measuring_torque_fraction, rigidity_low=float(low), rigidity_high=float(high),
        friction_nm=e.friction_torque_nm, friction_fraction=e.friction_load_fraction,
        translation_factor=1.0, radial_stiffness_n_per_um=math.inf, crank_compliance_rad_per_nm=0.0,
        carrier_compliance_rad_per_nm=0.0, main_bearing_compliance_rad_per_nm=c_main, support_rollers=0,
        support_cos_alpha=1.0, support_clearance_um=0.0, support_a=1.0, support_symmetric=False,
        support_force_n_per_nm=0.0, translation_rounds=TRANSLATION_ROUNDS, seat_a=seat_a,
        seat_b_fraction=seat_b_fraction, disc_body_compliance_rad_per_nm=0.0, roller_n=law_n)
    psi = 2 * math.pi * np.arange(e.crank_bearing_rollers) / e.crank_bearing_rollers
    model = ElasticModel(e, g, chain, np.cos(psi), bearings, a0, float(raceway))
    if e.crank_bearing_roller_profile != "straight":
        model = with_profiled_needles(model)
    return with_structure(problem, model) if design.structure is not None else model


def with_profiled_needles(model: ElasticModel) -> ElasticModel:
    """The model with the crank needle rollers' profile (docs/rigidity-elements.md): their sliced law
    (``rollers.sliced_roller``, no tilt) fitted as a power law (``rollers.fit_roller_law``) over a
    range of roller loads set by the design's rated torque alone (``rollers.fit_load_range_n``): from
    half the most loaded roller's at FIT_LOW_TORQUE_FRACTION of T_R to the most loaded roller's at
    T_R, both without clearance (under the straight law's load sharing, then the fitted law's, the
    larger), so that neither where the loop is read (the measuring fraction) nor the clearance zone's
    width moves the law (issue 36). The kernel then runs today's code with these coefficients
    (roller_a, roller_b = 0, roller_n)."""
    e, c = model.inputs, model.chain
    roller = sliced_roller(e.crank_bearing_roller_profile, e.crank_bearing_roller_length_mm,
                           e.crank_bearing_roller_diameter_mm, False, e.crank_bearing_roller_crown_drop_um,
                           e.crank_bearing_roller_log_scale_um)
    rated = c.rated_torque_nm * c.bearing_force_n_per_nm
    q_min, q_max = fit_load_range_n(lambda load: most_loaded_roller_n(model.roller_cos, c, 0.0, load), rated)
    fit = fit_roller_law(roller, c.roller_a, c.roller_b, c.law_n, q_min, q_max)
    fitted = c._replace(roller_a=fit.a, roller_b=0.0, roller_n=fit.n)
    q_fit = most_loaded_roller_n(model.roller_cos, fitted, 0.0, rated)
    if q_fit > q_max:  # the profiled rollers share the load differently: cover their own range
        fit = fit_roller_law(roller, c.roller_a, c.roller_b, c.law_n, q_min, q_fit)
        fitted = c._replace(roller_a=fit.a, roller_b=0.0, roller_n=fit.n)
    if not fitted_law_valid(fit):
        raise InputError("elastic.crank_bearing_roller_profile", e.crank_bearing_roller_profile,
                         f"the profiled needle's law could not be represented over {fit.load_min_n:.4g}-"
                         f"{fit.load_max_n:.4g} N (fit a = {fit.a:.4g}, n = {fit.n:.4g}); allowed: straight, or a "
                         f"smaller crown or log-profile scale")
    return replace(model, chain=fitted, needle_fit=fit)


def most_loaded_roller_n(roller_cos: np.ndarray, c: Chain, clearance_um: float, load_n: float) -> float:
    """The largest roller load [N] of a crank needle bearing carrying ``load_n`` [N] with radial
    clearance ``clearance_um`` under the Chain's roller law (``prepare_rollers``, ``solve_set``)."""
    cs = prepare_rollers(clearance_um, roller_cos, c)
    x = solve_set(cs, ContactLaw(c.roller_b, c.roller_n, 1.0), load_n, 1.0, np.nan, (np.nan, np.nan)).x
    closures = roller_cos * x - 0.5 * clearance_um
    return max(cm.law_force_n(float(v), c.roller_a, c.roller_b, c.roller_n) for v in closures)


def with_structure(problem: Problem, model: ElasticModel) -> ElasticModel:
    """The model with the whole torque path of the design's [structure] table (docs/elastic.md,
    "The whole torque path"): crankshafts, support bearings and carrier derived from their
    dimensions (unless ``structure_stiffness_nm_per_arcmin`` states them: a measured value wins),
    and the discs' sideways motion on their needle bearings. Computed once per design.
    Other than two discs (issue 36): the crankshafts, support bearings and carrier are derived for two
    discs symmetric about the crankshaft's mid-span, so they must be stated
    (``structure_stiffness_nm_per_arcmin``); what holds for any number of discs is kept — the disc
    bodies' FE and the discs' sideways motion across the eccentric (``"full"``, solved against the
    crank bent by two discs' opposite forces, is refused)."""
    st = problem.design.structure
    e, c, geo = model.inputs, model.chain, problem.geometry
    s1 = problem.design.first_stage
    k, a0, nb_ = c.lever_factor, model.crank_circle_radius_mm, model.bearings
    changes: dict[str, float | int | bool] = {}
    derived = e.structure_stiffness_nm_per_arcmin is None
    discs = problem.cycloid.discs
    if discs != 2 and derived:
        raise InputError("second_stage.discs", discs,
                         "the crankshafts, support bearings and carrier that [structure] derives are for two discs, "
                         "symmetric about the crankshaft's mid-span; allowed: discs = 2, or state "
                         "elastic.structure_stiffness_nm_per_arcmin for those three ([structure] then still gives the "
                         "disc bodies' finite elements and the discs' sideways motion across the eccentric; without "
                         "[structure] both are left out and the chain reads stiffer)")
    if discs != 2 and st.disc_translation == "full":
        raise InputError("structure.disc_translation", st.disc_translation,
                         f"along the eccentric the discs' translation is solved against the crank bent by two discs' "
                         f"opposite forces; allowed with {discs} discs: across, none")
    if derived:
        offset = 0.5 * (st.crankshaft_support_span_mm - st.disc_spacing_mm)
        bend = cm.crank_symmetric_deflection_um_per_n(st.crankshaft_support_span_mm, offset, st.crankshaft_diameter_mm,
                                                      st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio)
        twist = cm.shaft_torsion_compliance_rad_per_nm(st.crankshaft_torsion_length_mm,
                                                       st.crankshaft_torsion_diameter_mm or st.crankshaft_diameter_mm,
                                                       st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio)
        pillar = cm.pillar_deflection_um_per_n(st.pillar_length_mm, st.pillar_width_mm, st.pillar_depth_mm,
                                               st.carrier_youngs_modulus_gpa, st.carrier_poisson_ratio)
        check_small_deflections(st, c, cm.crank_torque_nm(c.rated_torque_nm, geo.planet_pitch_radius_mm,
                                                          geo.centre_gear_pitch_radius_mm, geo.ratio, s1.planets),
                                cm.pillar_shear_force_n(c.rated_torque_nm, k, st.carrier_pillars, st.pillar_radius_mm))
        changes.update(
            crank_compliance_rad_per_nm=(
                cm.tangential_output_compliance_rad_per_nm(bend, k, nb_, a0)
                + cm.crank_torsion_output_compliance_rad_per_nm(twist, geo.planet_pitch_radius_mm,
                                                                geo.centre_gear_pitch_radius_mm, geo.ratio,
                                                                s1.planets)),
            carrier_compliance_rad_per_nm=cm.carrier_output_compliance_rad_per_nm(pillar, st.carrier_pillars,
                                                                                   st.pillar_radius_mm, k),
            support_rollers=int(st.support_bearing_rollers),
            support_cos_alpha=math.cos(math.radians(st.support_bearing_contact_angle_deg)),
            support_clearance_um=st.support_bearing_clearance_um - st.support_bearing_preload_um,
            support_a=2.0 * cm.palmgren_law_a(st.support_bearing_roller_length_mm),
            support_symmetric=st.support_bearing_rollers % 2 == 0,
            # each end of a crank takes half of both discs' forces on it (discs symmetric about mid-span)
            support_force_n_per_nm=c.bearing_force_n_per_nm * problem.cycloid.discs / 2.0)
    support_roller = STRAIGHT
    if derived and st.support_bearing_roller_profile != "straight":
        # the crank's slope at its supports tilts each support bearing's inner ring (Roark case 1e); per N
        # of the bearing's radial load: the crank carries bearing_force per eccentric, the bearing support_force
        offset = 0.5 * (st.crankshaft_support_span_mm - st.disc_spacing_mm)
        slope = cm.crank_support_slope_rad_per_n(st.crankshaft_support_span_mm, offset, st.crankshaft_diameter_mm,
                                                 st.shaft_youngs_modulus_gpa)
        support_roller = sliced_roller(st.support_bearing_roller_profile, st.support_bearing_roller_length_mm,
                                       st.support_bearing_roller_diameter_mm, True,
                                       st.support_bearing_roller_crown_drop_um, st.support_bearing_roller_log_scale_um,
                                       slope * c.bearing_force_n_per_nm / changes["support_force_n_per_nm"])
    if st.disc_translation != "none":
        rho = problem.cycloid.a_mm * problem.cycloid.zc
        changes.update(translation_factor=cm.disc_translation_factor(a0, rho))
    if st.disc_translation == "full":
        changes.update(radial_stiffness_n_per_um=radial_stiffness_n_per_um(model, st))
    return replace(model, chain=c._replace(**changes), structure=st, derived=derived, support_roller=support_roller)


def check_small_deflections(st: StructureInputs, c: Chain, crank_torque_nm: float, pillar_shear_n: float) -> None:
    """Beam and shaft formulas are small-deflection theory: at the rated torque each crankshaft may
    bend, and each carrier pillar bend, at most SMALL_DEFLECTION of its length, and a crankshaft twist
    SMALL_DEFLECTION rad (rv80e: ~1e-4). A part beyond is refused, naming the section dimension that
    sets its stiffness with the smallest value that would do (the rest as given)."""
    offset = 0.5 * (st.crankshaft_support_span_mm - st.disc_spacing_mm)
    shaft, carrier = (st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio), \
        (st.carrier_youngs_modulus_gpa, st.carrier_poisson_ratio)
    twisted = "crankshaft_torsion_diameter_mm" if st.crankshaft_torsion_diameter_mm else "crankshaft_diameter_mm"
    checks = (  # (field, what it does, its deflection as a function of the field's value, unit)
        ("crankshaft_diameter_mm", "crankshaft bends", "of its span", lambda d: cm.crank_symmetric_deflection_um_per_n(
            st.crankshaft_support_span_mm, offset, d, *shaft) * c.rated_torque_nm * c.bearing_force_n_per_nm * 1e-3
            / st.crankshaft_support_span_mm),
        ("pillar_width_mm", "carrier pillar bends", "of its length", lambda w: cm.pillar_deflection_um_per_n(
            st.pillar_length_mm, w, st.pillar_depth_mm, *carrier) * pillar_shear_n * 1e-3 / st.pillar_length_mm),
        (twisted, "crankshaft twists", "rad", lambda d: cm.shaft_torsion_compliance_rad_per_nm(
            st.crankshaft_torsion_length_mm, d, *shaft) * crank_torque_nm))
    modulus = {"pillar_width_mm": st.carrier_youngs_modulus_gpa}
    modulus.update({n: st.shaft_youngs_modulus_gpa for n in ("crankshaft_diameter_mm", twisted)})
    for name, part, unit, share in checks:
        value = getattr(st, name)
        if share(value) <= SMALL_DEFLECTION:
            continue
        lo, hi = value, value  # the smallest value that meets the limit: the deflection falls as the section grows
        while share(hi) > SMALL_DEFLECTION and hi < 1e6 * value:
            lo, hi = hi, 2.0 * hi
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if share(mid) > SMALL_DEFLECTION else (lo, mid)
        raise InputError(f"structure.{name}", value,
                         f"allowed: >= {hi:.4g} mm (the rest as given), a part stiff enough for beam and shaft "
                         f"formulas: at the rated torque it may deflect at most {SMALL_DEFLECTION:g} of its length "
                         f"or {SMALL_DEFLECTION:g} rad; this {part} {share(value):.3g} {unit} at "
                         f"{c.rated_torque_nm:g} N m (E = {modulus[name]:g} GPa)")


def radial_stiffness_n_per_um(model: ElasticModel, st: StructureInputs) -> float:
    """K_y: one disc's support along its eccentric by its needle bearings (one per crank, in
    parallel), each in series with its crank bent by the two discs' opposite radial forces
    (``crank_antisymmetric_deflection_um_per_n``). A bearing's stiffness is its secant at the
    rated torque's tangential load with zero clearance (a linear spring: the clearance stays a dead
    band of the tangential direction only; docs/elastic.md). [N/um]"""
    load = model.chain.rated_torque_nm * model.chain.bearing_force_n_per_nm
    offset = 0.5 * (st.crankshaft_support_span_mm - st.disc_spacing_mm)
    crank = cm.crank_antisymmetric_deflection_um_per_n(st.crankshaft_support_span_mm, offset, st.crankshaft_diameter_mm,
                                                       st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio)
    cranks = model.bearings // model.geometry.discs
    return cranks / (1.0 / needle_secant_stiffness_n_per_um(model, load) + crank)


def needle_secant_stiffness_n_per_um(model: ElasticModel, load_n: float) -> float:
    """One crank needle bearing's secant stiffness [N/um] at the radial load ``load_n`` [N], zero
    clearance (its rollers solved with the chain's law: ``prepare_rollers``, ``solve_set``)."""
    c = model.chain
    deflection = solve_set(prepare_rollers(0.0, model.roller_cos, c), ContactLaw(c.roller_b, c.roller_n, 1.0), load_n,
                           1.0, np.nan, (np.nan, np.nan)).x
    return load_n / deflection


# --- each element's set of contacts ------------------------------------------------------------

@njit(nogil=True, cache=True)
def pin_law_a(phi, c):
    """Coefficient a of pin j's contact law [um/N^n] at phase phi = psi_j - chi_d: Johnson's
    approach with the relative radius of the pin and the flank (``flank_radius_mm`` of
    ``pin_centre_curve_radius_mm``); the flank's body radius is its radius of curvature, at most
    r_p where the flank is nearly straight; plus the pin's seat in its housing groove (``seat_a``,
    in series: the a's add). Palmgren: the same for every pin."""
    if not c.johnson:
        return c.palmgren_a
    rho = cm.flank_radius_mm(cm.pin_centre_curve_radius_mm(phi, c.pin_circle_radius_mm, c.k1, c.pins),
                             c.generating_radius_mm)
    r_rel = cm.capped_relative_radius_mm(c.pin_radius_mm, rho, cm.RELATIVE_RADIUS_CAP * c.pin_radius_mm)
    body = min(abs(rho), c.pin_circle_radius_mm)
    return cm.johnson_law_a_um_per_n(c.contact_length_mm, cm.Body(c.pin_radius_mm, c.pin_e_gpa, c.pin_nu),
                                     cm.Body(body, c.disc_e_gpa, c.disc_nu), r_rel) + c.seat_a


@njit(nogil=True, cache=True, inline="always")
def seat_angle_rad(pins, x, t_el, c):
    """The seats' part of the pins' output angle x [rad] at chain torque t_el (the pins' solve just
    done: its forces are the closed contacts' at x): how much x owes to the seats' compliance, to first
    order. Every closed pin j closes by delta_j = L_j x - g_j = delta_flank(F_j) + delta_seat(F_j);
    stiffening the seats away (delta_seat -> s delta_seat, s: 1 -> 0) moves x by

        x_seat = sum_j k_j L_j delta_seat,j / sum_j k_j L_j^2      (k_j = dF_j/d delta_j, the pair's tangent)

    (implicit differentiation of 1e-6 sum F_j L_j = t_el at fixed torque: exact for one contact and for
    linear contacts; a preloaded set's opposing contacts cancel, as their seats move x by nothing).
    With one law form, delta = F^n (a - b ln F), and b_seat = sigma b: Johnson (n = 1):
    delta_seat = F a_s + sigma (delta_j - F a_j), d delta/dF = delta_j / F - b; Palmgren (b = 0):
    delta_seat = (a_s / a_j) delta_j, d delta/dF = n delta_j / F. No logarithm. 0 at zero torque and
    without seats."""
    if c.seat_a == 0.0 or t_el == 0.0:
        return 0.0
    cs = pins.contacts
    translating = c.radial_stiffness_n_per_um < np.inf
    gaps = pins.translation.shifted_gaps_um if translating else cs.gaps
    pos_end = max(cs.npos, 0)
    sorted_end = pos_end + cs.nneg if cs.npos >= 0 else 0
    m = gaps.size
    moved = 0.0
    stiffness = 0.0
    for run in range(3):  # set_load's runs: the closed contacts of a sorted run are its prefix
        lo_j = 0 if run == 0 else (pos_end if run == 1 else sorted_end)
        hi_j = pos_end if run == 0 else (sorted_end if run == 1 else m)
        for j in range(lo_j, hi_j):
            lever = cs.levers[j]
            d = lever * x - gaps[j]
            if d <= 0.0:
                if run < 2:
                    break
                continue
            f = cs.forces[j]
            if f <= 0.0:
                continue
            if c.johnson:
                seat = f * c.seat_a + c.seat_b_fraction * (d - f * cs.law_a[j])
                slope = d / f - c.law_b
            else:
                seat = d * c.seat_a / cs.law_a[j]
                slope = c.law_n * d / f
            k = 1.0 / slope
            moved += k * lever * seat
            stiffness += k * lever * lever
    return moved / stiffness if stiffness > 0.0 else 0.0


@njit(nogil=True, cache=True)
def pin_phase(index, chi, zp, discs):
    """Phase phi = psi_j - chi_d [rad] of the pin at flat index d z_p + j."""
    d = index // zp
    j = index - d * zp
    return 2.0 * math.pi * j / zp - (chi + 2.0 * math.pi * d / discs)


@njit(nogil=True, cache=True)
def fill_pin_law(chi, c, out):
    """pin_law_a of every pin of every disc at crank angle chi [rad] into out (discs, z_p)."""
    discs, zp = out.shape
    for d in range(discs):
        for j in range(zp):
            out[d, j] = pin_law_a(pin_phase(d * zp + j, chi, zp, discs), c)


@njit(nogil=True, cache=True)
def pin_law_table(c, zp, discs, steps):
    """pin_law_a of every pin (flat index d z_p + j) at the crank angles the contact model draws,
    chi_s = 2 pi / z_p (s + 1/2) / steps (contact_source.CRANK_STEPS): (steps, discs z_p), the
    same numbers as computed unit by unit, once per design."""
    out = np.empty((steps, discs * zp))
    for s in range(steps):
        fill_pin_law(crank_step_angle_rad(s, zp, steps), c, out[s].reshape((discs, zp)))
    return out


@njit(nogil=True, cache=True)
def unit_pin_laws(chi, c, zp, discs, table):
    """pin_law_a of every pin (flat) of a unit at crank angle chi: its row of ``pin_law_table``
    when chi is one of the table's angles (exactly), else computed."""
    if table is not None:
        steps = table.shape[0]
        s = int(math.floor(chi * zp * steps / (2.0 * math.pi)))
        if 0 <= s < steps and crank_step_angle_rad(s, zp, steps) == chi:
            return table[s]
    out = np.empty((discs, zp))
    fill_pin_law(chi, c, out)
    return out.ravel()


@njit(nogil=True, cache=True)
def prepare_pins(unit, c, translating, table):
    """The pin contacts of a unit (its ElasticUnit: gaps, levers, crank angle) referred to the output
    (levers / k), with their contact-law coefficients and bounds: a PinSet of every pin, each with
    its closure per um of its disc's translation along the eccentric
    (``compliance.pin_radial_closure``; 0 when the discs do not ``translate``), its disc, and the
    translations' state (``solve_pins``; empty rows when they do not translate). ``table``: the
    design's ``pin_law_table`` (no rows: each law computed).
    Without translation the contacts are in ``closure_order`` (npos, nneg: its runs; else -1, 0), so
    that a load evaluation stops at each run's first open contact; the pins that no torque up to
    +-T_R closes cost nothing there (a closed-form bound that dropped them, ~15 of 80 pins for rv80e,
    cost more than it saved: issue 28)."""
    return prepare_pins_indexed(unit, c, translating, table, np.empty(unit.gap_um.size, dtype=np.int64))


@njit(nogil=True, cache=True)
def prepare_pins_indexed(unit, c, translating, table, order_out):
    """``prepare_pins`` that also writes each contact's pin (flat index d z_p + j) into ``order_out``,
    so that the life can place each contact's force on its pin (models.elastic.unit_life)."""
    chi = unit.chi_rad
    discs, zp = unit.gap_um.shape
    g = unit.gap_um.ravel()
    lev = unit.lever_um_per_rad.ravel() / c.lever_factor
    m = g.size
    laws = unit_pin_laws(chi, c, zp, discs, table)
    npos, nneg = -1, 0
    if translating:
        order = np.arange(m)
    else:  # fixed gaps: in closure order (set_load stops each run at its first open contact)
        order, npos, nneg = closure_order(g, lev, m)
    gk = np.empty(m)
    lk = np.empty(m)
    ak = np.empty(m)
    rk = np.zeros(m)
    dk = np.empty(m, dtype=np.int64)
    for i in range(m):
        j = order[i]
        order_out[i] = j
        gk[i] = g[j]
        lk[i] = lev[j]
        ak[i] = laws[j]
        dk[i] = j // zp
        if translating:  # only translating discs read the radial closures (fixed: left 0)
            rk[i] = cm.pin_radial_closure(pin_phase(j, chi, zp, discs), c.k1)
    # the discs' translations' state: read only when they translate (solve_pins, seat_angle_rad)
    rows, n_shift, n_sys = (discs, m, discs) if translating else (0, 0, 0)
    translation = DiscTranslation(np.zeros((N_TRANSLATION_ROWS, rows)), np.empty(n_shift), np.empty((n_sys, n_sys)),
                                  np.empty(n_sys))
    return PinSet(ContactSet(gk, lk, ak, set_bounds(gk, lk, m), np.zeros(m), npos, nneg), rk, dk, translation)


@njit(nogil=True, cache=True)
def prepare_rollers(crank_clearance_um, roller_cos, c):
    """One crank bearing's rollers (a ContactSet): gap G_r / 2 each, lever cos(psi_i); each roller its
    own contact (``paired_rollers``: the set a unit's loop solves)."""
    z = roller_cos.size
    g = np.full(z, 0.5 * crank_clearance_um)
    la = np.full(z, c.roller_a)
    return ContactSet(g, roller_cos, la, set_bounds(g, roller_cos, z), np.zeros(z), -1, 0)


@njit(nogil=True, cache=True)
def paired_rollers(crank_clearance_um, roller_cos, c):
    """``prepare_rollers`` as a unit's loop solves it with the chain's roller law: under a power law
    (b = 0: delta = a F^n, the profiled needles' fitted law) the rollers at psi_i and -psi_i
    (psi_i = 2 pi i / Z: the same lever and gap) are one contact of twice the force, a 2^-n, so one
    power instead of two (the same load, to rounding; 10 contacts for 18 rollers); under Johnson's
    law, or a layout that is not symmetric, each roller is its own contact."""
    z = roller_cos.size
    paired = c.roller_b == 0.0
    for i in range(1, z):
        paired = paired and abs(roller_cos[i] - roller_cos[z - i]) <= 1e-12
    if not paired:
        return prepare_rollers(crank_clearance_um, roller_cos, c)
    m = z // 2 + 1
    lv = np.empty(m)
    la = np.empty(m)
    for i in range(m):
        lv[i] = roller_cos[i]
        la[i] = c.roller_a if i == 0 or 2 * i == z else c.roller_a * 2.0 ** -c.roller_n
    g = np.full(m, 0.5 * crank_clearance_um)
    return ContactSet(g, lv, la, set_bounds(g, lv, m), np.zeros(m), -1, 0)


def prepare_support(c: Chain, roller: SlicedRoller | None = None):
    """``support_set`` with the support rollers' slices (``ElasticModel.support_roller``; None:
    straight rollers, Palmgren's law per roller)."""
    return support_set(c, STRAIGHT if roller is None else roller)


@njit(nogil=True, cache=True)
def support_set(c, roller):
    """One crank support (tapered roller) bearing's rollers under a radial load, axially held (the
    two of a crank face each other and carry equal loads, so their induced axial forces cancel):
    roller i at psi_i = 2 pi i / Z closes, normal to its raceway, by (delta_r cos psi_i - G / 2)
    cos(alpha); its normal force Q_i bears cos(alpha) cos(psi_i) of itself radially. Levers
    cos(alpha) cos(psi_i), gaps G cos(alpha) / 2, Palmgren's law (Harris & Kotzalas, Rolling
    Bearing Analysis 5th ed., the load distribution of a radially loaded roller bearing with
    clearance; docs/elastic.md): a SupportSet; ``roller``: its rollers by slices
    (``rollers.SlicedRoller``: the profile and the crank's tilt, ``solver.solve_sliced_set``; no
    slices: Palmgren's law per roller). The support bearings' deflection is the same function of
    the chain's torque for every unit of a design: its memo keeps SUPPORT_MEMO torques, sides and
    deflections solved, so that repeated ``chain_angles`` calls on one set (a unit's loop table)
    solve each torque once (a batch of units reads the loop's ten from ``loop_points``)."""
    z = c.support_rollers
    lv = np.empty(z)
    for i in range(z):
        lv[i] = c.support_cos_alpha * math.cos(2.0 * math.pi * i / z)
    g = np.full(z, 0.5 * c.support_clearance_um * c.support_cos_alpha)
    la = np.full(z, c.support_a)
    return SupportSet(ContactSet(g, lv, la, set_bounds(g, lv, z), np.zeros(z), -1, 0),
                      SupportMemo(np.full(SUPPORT_MEMO, np.nan), np.full(SUPPORT_MEMO, np.nan),
                                  np.full(SUPPORT_MEMO, np.nan)), roller)


class LoopUnit(NamedTuple):
    """A unit prepared for its loop: its pins' and its crank bearings' contact sets, and the
    involute stage's backlash at the output [rad] (>= 0)."""

    pins: PinSet
    rollers: ContactSet
    involute_backlash_rad: float


class LoopPoints(NamedTuple):
    """The points of the loop that ``loop_figures`` reads (``loop_points``), LOOP_POINTS each: the
    chain torque T_el [N m], the side at zero torque, the support bearings' deflection there [um],
    the figure the point serves (BACKLASH_POINT, LOST_MOTION_POINT, SPAN_POINT) and its weight
    there."""

    torque_nm: np.ndarray
    side: np.ndarray
    support_um: np.ndarray
    figure: np.ndarray  # int64
    weight: np.ndarray


@njit(nogil=True, cache=True)
def chain_angles(t_el, side, unit, support, c, state, out):
    """Output angle of each element [rad] (ELEMENTS order) of a LoopUnit when the chain carries
    t_el [N m]; at t_el = 0, ``side`` picks the edge of the dead bands (+1: positive). ``state``:
    the unit's SOLVE_STATE (warm starts), updated. A translating disc's dead-band edge is read at
    TINY_TORQUE (its radial balance needs a load direction)."""
    s = side if t_el == 0.0 else (1.0 if t_el > 0.0 else -1.0)
    support_um = support_deflection_um(t_el, s, support, c, state) if c.support_rollers > 0 else 0.0
    _chain_angles(t_el, side, unit, support_um, c, state, out)


@njit(nogil=True, cache=True, inline="always")
def _chain_angles(t_el, side, unit, support_um, c, state, out):
    """``chain_angles`` with the support bearings' deflection given [um] (``loop_points``)."""
    st = state[0]
    s = side if t_el == 0.0 else (1.0 if t_el > 0.0 else -1.0)
    k = POSITIVE if s > 0.0 else NEGATIVE
    pins = solve_pins(unit.pins, t_el, s, st.pins_start[k], c, (st.pins_tangent_load_nm[k],
                                                                 st.pins_tangent_stiffness[k]))
    if not math.isnan(pins.stiffness):
        st.pins_tangent_load_nm[k] = t_el
        st.pins_tangent_stiffness[k] = pins.stiffness
    x = pins.x
    rollers = unit.rollers
    load = t_el * c.bearing_force_n_per_nm
    if c.rollers_symmetric and load != 0.0 and abs(load) == st.rollers_last_load_n:
        dr = s * st.rollers_last_um  # an even number of rollers, one on the load line: the mirror of the last solve
    else:
        sol = solve_set(rollers, ContactLaw(c.roller_b, c.roller_n, 1.0), load, s, st.rollers_start[k],
                        (st.rollers_tangent_load_n[k], st.rollers_tangent_stiffness[k]))
        dr = sol.x
        if not math.isnan(sol.stiffness):
            st.rollers_tangent_load_n[k] = load
            st.rollers_tangent_stiffness[k] = sol.stiffness
        st.rollers_last_load_n = abs(load)
        st.rollers_last_um = abs(dr)
    if t_el != 0.0:
        st.pins_start[k] = x
        st.rollers_start[k] = dr
    seat = seat_angle_rad(unit.pins, x, t_el, c)
    out[PINS] = x - seat
    out[PIN_SEATING] = seat
    out[DISC_BODIES] = t_el * c.disc_body_compliance_rad_per_nm
    if c.translation_factor != 1.0:  # the translation across the eccentric adds to the elastic part only
        edge = 0.0
        if rollers.bounds.lo <= rollers.bounds.hi:  # a clearance: the dead band's edge on this side
            edge = rollers.bounds.hi if s > 0.0 else rollers.bounds.lo
        dr = edge + (dr - edge) * c.translation_factor
    out[CRANK_BEARINGS] = dr * c.bearing_angle_rad_per_um
    out[INVOLUTE] = 0.5 * s * unit.involute_backlash_rad + t_el / c.involute_stiffness_nm_per_rad
    out[STRUCTURE] = t_el / c.structure_stiffness_nm_per_rad
    out[CRANKSHAFTS] = t_el * c.crank_compliance_rad_per_nm
    out[SUPPORT_BEARINGS] = support_um * c.bearing_angle_rad_per_um
    out[CARRIER] = t_el * c.carrier_compliance_rad_per_nm
    out[MAIN_BEARINGS] = t_el * c.main_bearing_compliance_rad_per_nm


@njit(nogil=True, cache=True)
def branch_point(torque_nm, branch, c):
    """(chain torque T_el [N m], side) on the rising (RISE: load+, unload-) or falling (FALL: load-,
    unload+) branch at applied torque T, in the steady loop 0 -> +T_R -> 0 -> -T_R -> 0: the output
    sticks at the turning point until friction is overcome; where the chain's torque passes 0 the
    side is the end the branch arrives from (the jump through the dead bands follows)."""
    tr = c.rated_torque_nm
    tf, mu = c.friction_nm, c.friction_fraction
    if branch == RISE:
        stick = cm.applied_torque_nm(cm.elastic_torque_nm(-tr, False, tf, mu), True, tf, mu)
        if torque_nm < stick:  # still held where the falling branch left it at -T_R
            return cm.elastic_torque_nm(-tr, False, tf, mu), 1.0
        return cm.elastic_torque_nm(torque_nm, True, tf, mu), -1.0
    stick = cm.applied_torque_nm(cm.elastic_torque_nm(tr, True, tf, mu), False, tf, mu)
    if torque_nm > stick:
        return cm.elastic_torque_nm(tr, True, tf, mu), -1.0
    return cm.elastic_torque_nm(torque_nm, False, tf, mu), 1.0


@njit(nogil=True, cache=True)
def branch_angles(torque_nm, branch, unit, support, c, state, out):
    """Element angles [rad] of a LoopUnit on a branch at applied torque T (``branch_point``,
    ``chain_angles``)."""
    t_el, side = branch_point(torque_nm, branch, c)
    chain_angles(t_el, side, unit, support, c, state, out)


def lost_motion_in_stick_band(c) -> bool:
    """Does friction hold the output inside the measuring torques (Chain ``c``)? On the rising
    branch at +x T_R the chain carries T_el = (x T_R - T_f0) / (1 -+ mu) (``branch_point``): for
    T_f0 >= x T_R it is still <= 0, the output has not crossed its dead bands (nor, on the falling
    branch at -x T_R, back). The lost motion's definition, the mean of the load and unload angles
    at +x T_R less that at -x T_R, then reads the width of the stick band — the chain's elastic
    wind-up between the two friction torques — and not the play, which the loop shows only in its
    width at zero torque (the backlash). A bench with this loop reads the same figure: it is the
    definition's, not an error of the model; what changes is what it means."""
    t_el, side = branch_point(c.measuring_fraction * c.rated_torque_nm, RISE, c)
    return t_el < 0.0 or (t_el == 0.0 and side < 0.0)


def stick_band_warning(c) -> str | None:
    """The warning every output that shows a lost motion of this design carries when
    ``lost_motion_in_stick_band`` (None otherwise): friction, x T_R and what the figure is."""
    if not lost_motion_in_stick_band(c):
        return None
    x, tr, tf = c.measuring_fraction, c.rated_torque_nm, c.friction_nm
    return (f"friction {tf:.4g} N m >= the measuring torque x T_R = {x * tr:.4g} N m ({x * 100:g} % of "
            f"{tr:.4g} N m): the loop's branches stick inside +-x T_R, so the lost motion read there is the "
            f"width of the stick band (the wind-up between the friction torques), not the play, and a yield "
            f"against a lost-motion spec counts that; the backlash (the loop's width at 0 N m) holds the play. "
            f"Check friction_torque_nm, or measure at x > T_f / T_R = {tf / tr:.4g} (docs/elastic.md, Friction).")


LOOP_POINTS = 10  # the loop's points that the figures read (loop_points)
BACKLASH_POINT, LOST_MOTION_POINT, SPAN_POINT = range(3)  # the figure a loop point serves


@njit(nogil=True, cache=True)
def loop_points(support, c):
    """The LoopPoints of the design (SupportSet ``support``, Chain ``c``), in loop_figures' order
    (from small to large torques, a torque and its mirror in turn, so that each solve starts from
    the previous one): zero torque on the falling and the rising branch (the backlash: weights +1,
    -1), +-x T_R on both branches (the lost motion: +-1/2), +-l T_R and +-h T_R loading (the
    rigidity's span: -+1, +-1). The same for every unit of a design: computed once per design."""
    tr = c.rated_torque_nm
    xt = c.measuring_fraction * tr
    lo, hi = c.rigidity_low * tr, c.rigidity_high * tr
    out = LoopPoints(np.empty(LOOP_POINTS), np.empty(LOOP_POINTS), np.empty(LOOP_POINTS),
                     np.empty(LOOP_POINTS, dtype=np.int64), np.empty(LOOP_POINTS))
    state = new_state()
    for q, (torque, branch, weight) in enumerate(((0.0, FALL, 1.0), (0.0, RISE, -1.0), (xt, RISE, 0.5),
                                                  (-xt, FALL, -0.5), (xt, FALL, 0.5), (-xt, RISE, -0.5),
                                                  (lo, RISE, -1.0), (-lo, FALL, 1.0), (hi, RISE, 1.0),
                                                  (-hi, FALL, -1.0))):
        t_el, side = branch_point(torque, branch, c)
        s = side if t_el == 0.0 else (1.0 if t_el > 0.0 else -1.0)
        out.torque_nm[q] = t_el
        out.side[q] = side
        out.support_um[q] = support_deflection_um(t_el, s, support, c, state) if c.support_rollers > 0 else 0.0
        out.figure[q] = BACKLASH_POINT if q < 2 else (LOST_MOTION_POINT if q < 6 else SPAN_POINT)
        out.weight[q] = weight
    return out


@njit_borrowing(nogil=True, cache=True)
def loop_figures(unit, points, c, state, out, a):
    """The test-bench figures of a prepared unit into out[0:N_FIGURES] (module docstring):

        lost motion = 1/2 [theta(+x T_R, load) + theta(+x T_R, unload)] - 1/2 [theta(-x T_R, load) + theta(-x T_R, unload)]
        backlash    = theta(0, unload+) - theta(0, unload-)           (the loop's width at zero torque)
        rigidity    = 2 (h - l) T_R / ([theta(h T_R) - theta(l T_R)]_load+ + [theta(-l T_R) - theta(-h T_R)]_load-)

    [arcmin, arcmin, N m/arcmin] of a LoopUnit ``unit``, then the lost motion of each element
    [arcmin], then each element's part of the rigidity's angle span [arcmin] (its compliance share
    times the span). ``points``: the design's ``loop_points``. ``state``: ``new_state()``; it holds
    the reach of the pins' solves afterwards. ``a``: scratch (N_ELEMENTS,). Allocates nothing:
    compiled without numba's runtime (``njit_borrowing``), it and the solvers it calls keep no
    reference counts."""
    width = 0.0
    for e in range(N_ELEMENTS):
        out[ELEMENT_LOST_MOTION + e] = 0.0  # the elements' lost motion, then their span, accumulated in place [rad]
        out[SHARES + e] = 0.0
    for q in range(LOOP_POINTS):
        _chain_angles(points.torque_nm[q], points.side[q], unit, points.support_um[q], c, state, a)
        w, figure = points.weight[q], points.figure[q]
        if figure == BACKLASH_POINT:
            total = 0.0
            for e in range(N_ELEMENTS):
                total += a[e]
            width += w * total
        for e in range(N_ELEMENTS):
            if figure == LOST_MOTION_POINT:
                out[ELEMENT_LOST_MOTION + e] += w * a[e]
            elif figure == SPAN_POINT:
                out[SHARES + e] += w * a[e]
    lm = 0.0
    total = 0.0
    for e in range(N_ELEMENTS):
        lm += out[ELEMENT_LOST_MOTION + e]
        total += out[SHARES + e]
    tr = c.rated_torque_nm
    out[LOST_MOTION] = lm * ARCMIN_PER_RAD
    out[BACKLASH] = width * ARCMIN_PER_RAD
    out[RIGIDITY] = 2.0 * (c.rigidity_high - c.rigidity_low) * tr / (total * ARCMIN_PER_RAD) if total > 0.0 else np.inf
    for e in range(N_ELEMENTS):
        out[ELEMENT_LOST_MOTION + e] *= ARCMIN_PER_RAD
        out[SHARES + e] *= ARCMIN_PER_RAD
