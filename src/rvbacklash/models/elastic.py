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

The core ``unit_hysteresis`` is a function of one unit's arrays (gaps and levers of every pin
of every disc, its crank angle (the flank curvature at each pin), the involute backlash, the
crank-bearing clearance) and of the design's ``Chain``; compiled with numba (nogil) for the
Monte-Carlo.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit, njit_borrowing
from rvbacklash.design.elastic import ElasticInputs
from rvbacklash.design.structure import StructureInputs
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS, Stage
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models import compliance as cm
from rvbacklash.models.contact import Realization, mesh_table, stage_work, unit_arrays, unit_gaps
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD

# the elements of the chain, in series (the first four as before issue 16: their keys are an interface)
ELEMENTS = ("cycloid_pins", "crank_bearings", "involute_stage", "structure", "crankshafts", "support_bearings",
            "carrier", "main_bearings")
N_ELEMENTS = len(ELEMENTS)
# unit_hysteresis fills out[0:N_FIGURES]: lost motion [arcmin], backlash [arcmin], rigidity [N m/arcmin],
# then the lost motion of each element [arcmin] (they sum to the lost motion), then each element's
# angle over the rigidity interval [arcmin] (they sum to the interval's angle: the compliance shares)
LOST_MOTION, BACKLASH, RIGIDITY = 0, 1, 2
SHARES = 3 + N_ELEMENTS
N_FIGURES = 3 + 2 * N_ELEMENTS
N_STATE = 14  # chain_angles' warm starts, mirrored solves (pins, rollers, support bearings), pins' predictors
TRANSLATION_ROUNDS = 60.0  # solve_pins' rounds (x solve, Newton step on the translations) at most
TRANSLATION_STEP_UM = 1e-6  # solve_pins: a Newton step on the translations below this ends the rounds
SUPPORT_MEMO = 24  # torques remembered by a support set (chain_angles' repeated calls)
TINY_TORQUE = 1e-12  # of T_R: the torque at which a translating disc's dead-band edge is read
RISE, FALL = 0, 1  # the rising branch (load+, unload-) and the falling branch (load-, unload+)
TINY_LEVER = 1e-3  # of the largest lever: a contact that cannot bound a rotation (set_bounds)
SETTLE = 1e-4  # set_load: a force is stepped again while its relative error bound is above this
#                 (steps s/F > ~0.07: below, the (s/F)^2 bound holds well within solve_set's factor-2
#                 margin; 1e-3 let a bracket move wrongly)
LN_FORCE_GUESS = 6.0  # ln(400 N): start of the inversion of Johnson's law (pin and roller loads 10 N - 10 kN)


class Chain(NamedTuple):
    """Everything the kernels need besides the unit's own arrays (floats; numba takes it as is)."""

    law_b: float  # contact law delta = F^n (a - b ln F) [um, N]: b and n, shared by every pin
    law_n: float
    johnson: float  # 1: per-pin a from the flank curvature (Johnson); 0: a = palmgren_a for every pin
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
    rollers_symmetric: float  # 1: an even number of rollers (a load and its mirror deflect alike)
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
    support_rollers: float  # rollers per support bearing (0: no support bearings modelled)
    support_cos_alpha: float
    support_clearance_um: float
    support_a: float  # Palmgren's law of one roller between its raceways (two contacts)
    support_symmetric: float
    support_force_n_per_nm: float  # radial load of one support bearing per N m of T_el
    translation_rounds: float  # solve_pins: at most this many x solves per torque with the discs translating


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


def elastic_model(problem: Problem) -> ElasticModel:
    """Resolve the design's [elastic] table into the kernels' parameters (docs/elastic.md)."""
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
        roller_a = (cm.johnson_law_a_um_per_n(lw, dw / 2, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio, raceway / 2,
                                              e.disc_youngs_modulus_gpa, e.disc_poisson_ratio, inner)
                    + cm.johnson_law_a_um_per_n(lw, dw / 2, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio,
                                                raceway / 2 + dw, e.disc_youngs_modulus_gpa, e.disc_poisson_ratio,
                                                outer))
        b1 = cm.johnson_law_b_um_per_n(lw, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio, e.disc_youngs_modulus_gpa,
                                       e.disc_poisson_ratio)
        roller_b, law_b, law_n = 2.0 * b1, cm.johnson_law_b_um_per_n(
            length, e.pin_youngs_modulus_gpa, e.pin_poisson_ratio, e.disc_youngs_modulus_gpa, e.disc_poisson_ratio), 1.0
    else:
        roller_a, roller_b = 2.0 * cm.palmgren_law_a(lw), 0.0
        law_b, law_n = 0.0, cm.PALMGREN_EXPONENT
    low, high = e.rigidity_interval_fraction
    chain = Chain(
        law_b=law_b, law_n=law_n, johnson=1.0 if johnson else 0.0, palmgren_a=cm.palmgren_law_a(length),
        contact_length_mm=length, pin_radius_mm=g.rrp_mm,
        generating_radius_mm=g.rrp_mm + s2.equidistance_modification_um * 1e-3, pin_circle_radius_mm=g.rp_mm,
        k1=g.K1, pins=float(g.zp), discs=float(g.discs), pin_e_gpa=e.pin_youngs_modulus_gpa, pin_nu=e.pin_poisson_ratio,
        disc_e_gpa=e.disc_youngs_modulus_gpa, disc_nu=e.disc_poisson_ratio, lever_factor=k,
        involute_stiffness_nm_per_rad=k_inv, structure_stiffness_nm_per_rad=k_struct,
        bearing_force_n_per_nm=k * 1e3 / (bearings * a0), bearing_angle_rad_per_um=k * 1e-3 / a0,
        roller_a=roller_a, roller_b=roller_b, rollers_symmetric=1.0 if e.crank_bearing_rollers % 2 == 0 else 0.0,
        rated_torque_nm=e.rated_torque_nm,
        measuring_fraction=e.measuring_torque_fraction, rigidity_low=float(low), rigidity_high=float(high),
        friction_nm=e.friction_torque_nm, friction_fraction=e.friction_load_fraction,
        translation_factor=1.0, radial_stiffness_n_per_um=math.inf, crank_compliance_rad_per_nm=0.0,
        carrier_compliance_rad_per_nm=0.0, main_bearing_compliance_rad_per_nm=c_main, support_rollers=0.0,
        support_cos_alpha=1.0, support_clearance_um=0.0, support_a=1.0, support_symmetric=0.0,
        support_force_n_per_nm=0.0, translation_rounds=TRANSLATION_ROUNDS)
    psi = 2 * math.pi * np.arange(e.crank_bearing_rollers) / e.crank_bearing_rollers
    model = ElasticModel(e, g, chain, np.cos(psi), bearings, a0, float(raceway))
    return with_structure(problem, model) if design.structure is not None else model


def with_structure(problem: Problem, model: ElasticModel) -> ElasticModel:
    """The model with the whole torque path of the design's [structure] table (docs/elastic.md,
    "The whole torque path"): crankshafts, support bearings and carrier derived from their
    dimensions (unless ``structure_stiffness_nm_per_arcmin`` states them: a measured value wins),
    and the discs' sideways motion on their needle bearings. Computed once per design."""
    st = problem.design.structure
    e, c, geo = model.inputs, model.chain, problem.geometry
    s1 = problem.design.first_stage
    if problem.cycloid.discs != 2:
        raise InputError("second_stage.discs", problem.cycloid.discs,
                         "the derived torque path ([structure]) is for two discs, symmetric about the crankshaft's "
                         "mid-span; allowed: discs = 2, or remove [structure] and state "
                         "elastic.structure_stiffness_nm_per_arcmin")
    k, a0, nb_ = c.lever_factor, model.crank_circle_radius_mm, model.bearings
    changes: dict[str, float] = {}
    derived = e.structure_stiffness_nm_per_arcmin is None
    if derived:
        offset = 0.5 * (st.crankshaft_support_span_mm - st.disc_spacing_mm)
        bend = cm.crank_symmetric_deflection_um_per_n(st.crankshaft_support_span_mm, offset, st.crankshaft_diameter_mm,
                                                      st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio)
        twist = cm.shaft_torsion_compliance_rad_per_nm(st.crankshaft_torsion_length_mm,
                                                       st.crankshaft_torsion_diameter_mm or st.crankshaft_diameter_mm,
                                                       st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio)
        pillar = cm.pillar_deflection_um_per_n(st.pillar_length_mm, st.pillar_width_mm, st.pillar_depth_mm,
                                               st.carrier_youngs_modulus_gpa, st.carrier_poisson_ratio)
        changes.update(
            crank_compliance_rad_per_nm=(
                cm.tangential_output_compliance_rad_per_nm(bend, k, nb_, a0)
                + cm.crank_torsion_output_compliance_rad_per_nm(twist, geo.planet_pitch_radius_mm,
                                                                geo.centre_gear_pitch_radius_mm, geo.ratio,
                                                                s1.planets)),
            carrier_compliance_rad_per_nm=cm.carrier_output_compliance_rad_per_nm(pillar, st.carrier_pillars,
                                                                                   st.pillar_radius_mm, k),
            support_rollers=float(st.support_bearing_rollers),
            support_cos_alpha=math.cos(math.radians(st.support_bearing_contact_angle_deg)),
            support_clearance_um=st.support_bearing_clearance_um,
            support_a=2.0 * cm.palmgren_law_a(st.support_bearing_roller_length_mm),
            support_symmetric=1.0 if st.support_bearing_rollers % 2 == 0 else 0.0,
            # each end of a crank takes half of both discs' forces on it (discs symmetric about mid-span)
            support_force_n_per_nm=c.bearing_force_n_per_nm * problem.cycloid.discs / 2.0)
    if st.disc_translation != "none":
        rho = problem.cycloid.a_mm * problem.cycloid.zc
        changes.update(translation_factor=cm.disc_translation_factor(a0, rho))
    if st.disc_translation == "full":
        changes.update(radial_stiffness_n_per_um=radial_stiffness_n_per_um(model, st))
    return replace(model, chain=c._replace(**changes), structure=st, derived=derived)


def radial_stiffness_n_per_um(model: ElasticModel, st: StructureInputs) -> float:
    """K_y: one disc's support along its eccentric by its needle bearings (one per crank, in
    parallel), each in series with its crank bent by the two discs' opposite radial forces
    (``crank_antisymmetric_deflection_um_per_n``). A bearing's stiffness is its secant at the
    rated torque's tangential load with zero clearance (a linear spring: the clearance stays a dead
    band of the tangential direction only; docs/elastic.md). [N/um]"""
    c = model.chain
    load = c.rated_torque_nm * c.bearing_force_n_per_nm
    g, lv, la, z, bounds, work = prepare_rollers(0.0, model.roller_cos, c)
    deflection = solve_set(g, lv, la, c.roller_b, c.law_n, 1.0, z, bounds, work, load, 1.0, np.nan)
    offset = 0.5 * (st.crankshaft_support_span_mm - st.disc_spacing_mm)
    crank = cm.crank_antisymmetric_deflection_um_per_n(st.crankshaft_support_span_mm, offset, st.crankshaft_diameter_mm,
                                                       st.shaft_youngs_modulus_gpa, st.shaft_poisson_ratio)
    cranks = model.bearings // model.geometry.discs
    return cranks / (deflection / load + crank)


# --- the contact law and a set of contacts -----------------------------------------------------

@njit(nogil=True, cache=True)
def law_step(delta_um, a, b, n, f0):
    """One step towards the force of a contact closed by delta > 0 under delta = F^n (a - b ln F):
    (F [N], dF/ddelta [N/um], bound of F's relative error after the step).

    Palmgren (b = 0): the closed form, error 0. Johnson (n = 1): one Newton step on
    phi(F) = F (a - b ln F) - delta from f0 (e.g. the contact's force at the previous evaluation),
    or from the estimate delta / (a - b LN_FORCE_GUESS) when f0 is not positive or not below
    delta / (2 b). phi is concave (phi'' = -b/F): from the left the iterates rise monotonically to
    the root; from the right they land left of it, and stay positive for starts below delta / b.
    After a step s the relative error is b / (2 (g - b)) (s/F)^2 (g = a - b ln F), the bound
    returned. Johnson's formula stops increasing at ln F = a/b - 1 (half-width ~ radius: far
    outside its validity); beyond ln F_lim = a/b - 2, where d(delta)/dF = b, it is continued by
    that tangent so that every closure has one force (only brackets get there)."""
    if b == 0.0:
        f = (delta_um / a) ** (1.0 / n)
        return f, f / (n * delta_um), 0.0
    if 0.0 < f0 < 0.5 * delta_um / b:
        f = f0
    else:
        f = delta_um / max(a - b * LN_FORCE_GUESS, 2.0 * b)
    g = a - b * math.log(f)
    if g < 2.5 * b:  # near the end of the formula's range
        flim = math.exp(a / b - 2.0)
        dlim = 2.0 * b * flim
        if delta_um >= dlim:
            return flim + (delta_um - dlim) / b, 1.0 / b, 0.0
        f = min(f, 0.75 * flim)
        g = a - b * math.log(f)
    inv = 1.0 / (g - b)
    step = (f * g - delta_um) * inv
    if step >= f:  # keep the iterate positive (cannot happen from the starts above; a guard)
        step = 0.5 * f
    r = step / f
    return f - step, inv, 0.5 * b * inv * r * r


@njit(nogil=True, cache=True)
def law_force(delta_um, a, b, n, f0):
    """(F [N], dF/ddelta [N/um]) of a contact closed by delta > 0: ``law_step`` to convergence."""
    f, df, err = law_step(delta_um, a, b, n, f0)
    for _ in range(60):
        if err < 1e-15:
            break
        f, df, err = law_step(delta_um, a, b, n, f)
    return f, df


@njit(nogil=True, cache=True, inline="always")
def _settled_force(d, a, b, n, f0):
    """law_step from f0, repeated while its error bound is above SETTLE (set_load)."""
    f, df, e = law_step(d, a, b, n, f0)
    for _ in range(30):  # settle: quadratic once close, 1-3 steps from a warm start
        if e <= SETTLE:
            break
        f, df, e = law_step(d, a, b, n, f)
    return f, df, e


@njit(nogil=True, cache=True, inline="always")
def set_load(x, gaps, levers, law_a, b, n, scale, m, work, npos=-1, nneg=0):
    """(load, dload/dx, bound of the load's error, scale sum |F_j levers_j|) of the first m contacts
    of a set at x: contact j closes by delta_j = levers_j x - gaps_j and pushes back with
    F_j(delta_j) (``law_step`` from work[j], its force at the previous evaluation, repeated while
    the error bound is above SETTLE; 0 when open); load = scale sum F_j levers_j. Below SETTLE
    the forces are refined along with x (one step per evaluation, ``solve_set``), which stops
    only once the bound is below 1e-11 of the load.
    ``npos`` >= 0: the contacts are in closure order (``closure_order``): npos with levers > 0 by
    gap / lever rising, then nneg with levers < 0 by gap / lever falling, then the rest; the
    closed ones of each run are a prefix, so each run stops at its first open contact (whose
    work[j] is then left as it was: only a start for law_step)."""
    g = 0.0
    dg = 0.0
    err = 0.0
    gabs = 0.0
    pos_end = max(npos, 0)
    sorted_end = pos_end + nneg if npos >= 0 else 0
    for run in range(3):  # the two sorted runs, then the contacts in no order
        lo_j = 0 if run == 0 else (pos_end if run == 1 else sorted_end)
        hi_j = pos_end if run == 0 else (sorted_end if run == 1 else m)
        for j in range(lo_j, hi_j):
            d = levers[j] * x - gaps[j]
            if d <= 0.0:
                if run < 2:
                    break  # a sorted run: every contact after it is open too
                work[j] = 0.0
                continue
            f, df, e = _settled_force(d, law_a[j], b, n, work[j])
            work[j] = f
            fl = f * abs(levers[j])
            g += f * levers[j]
            dg += df * levers[j] * levers[j]
            err += e * fl
            gabs += fl
    return g * scale, dg * scale, err * scale, gabs * scale


@njit(nogil=True, cache=True)
def closure_order(gaps, levers, m):
    """(order, npos, nneg): the contacts with levers > 0 by gap / lever rising, then those with
    levers < 0 by gap / lever falling, then those without a lever (set_load's runs). Insertion
    sorts (stable): a unit keeps a few dozen contacts."""
    order = np.empty(m, dtype=np.int64)
    key = np.empty(m)
    npos = nneg = 0
    for j in range(m):  # count the runs, so that each is sorted in place
        if levers[j] > 0.0:
            npos += 1
        elif levers[j] < 0.0:
            nneg += 1
    ip, ineg, irest = 0, npos, npos + nneg
    for j in range(m):
        if levers[j] > 0.0:
            k, v, lo = ip, gaps[j] / levers[j], 0
            ip += 1
        elif levers[j] < 0.0:
            k, v, lo = ineg, -gaps[j] / levers[j], npos  # falling gap / lever: rising -gap / lever
            ineg += 1
        else:
            order[irest] = j
            irest += 1
            continue
        while k > lo and key[k - 1] > v:
            key[k] = key[k - 1]
            order[k] = order[k - 1]
            k -= 1
        key[k] = v
        order[k] = j
    return order, npos, nneg


@njit(nogil=True, cache=True)
def set_bounds(gaps, levers, m, out):
    """out = [hi, j_hi, lo, j_lo, tiny]: the first contact turning positive (smallest gap/lever over
    lever > 0) and negative (largest over lever < 0). hi >= lo: free between them; hi < lo:
    preloaded (no coordinate frees every contact). Contacts whose lever is below TINY_LEVER of the
    largest (pins facing a tooth tip or root) cannot bound a rotation: left out; tiny = 1 when one
    of them interferes (it pushes at every rotation, with a torque too small to matter, and the
    solver then checks its brackets)."""
    big = 0.0
    for j in range(m):
        big = max(big, abs(levers[j]))
    small = TINY_LEVER * big
    hi = np.inf
    lo = -np.inf
    jhi = -1
    jlo = -1
    tiny = 0.0
    for j in range(m):
        if abs(levers[j]) <= small:
            if gaps[j] < 0.0:
                tiny = 1.0
            continue
        r = gaps[j] / levers[j]
        if levers[j] > 0.0:
            if r < hi:
                hi = r
                jhi = j
        elif r > lo:
            lo = r
            jlo = j
    out[0] = hi
    out[1] = jhi
    out[2] = lo
    out[3] = jlo
    out[4] = tiny


@njit(nogil=True, cache=True)
def solve_set(gaps, levers, law_a, b, n, scale, m, bounds, work, load, side, guess, rtol=1e-11, npos=-1, nneg=0,
              slope=None):
    """The coordinate x at which the contact set carries ``load`` (its sign: the direction).
    load = 0: the edge of the free band on ``side`` (+1: the positive edge), or the preloaded
    equilibrium. ``guess``: a start inside the bracket (NaN: none).

    Bracket (load > 0; mirrored for load < 0): at the first contact hi the loaded side is still
    free, so load(hi) <= 0. The contact with the largest lever L alone carries the load once it
    has closed by delta(load / (scale L)), at x_t; beyond lo nothing pulls back; so
    load(max(lo, x_t)) >= load. Newton inside the bracket, bisection when a step leaves it. The
    contacts' forces are refined along (one ``law_step`` per evaluation); the bracket moves only
    where the load's error bound cannot flip the sign of the residual, else the forces settle in
    place. Stops when the residual and its error bound are below 1e-11 of the load (or of the
    contacts' loads, at a preloaded equilibrium; ``rtol``). ``npos``, ``nneg``: set_load's.
    ``slope`` (2,): the load at which ``guess`` was solved and the set's stiffness dload/dx there
    (NaN: unknown); the solve then starts from the tangent's prediction guess + (load - load_0) /
    K_0 when it lies in the bracket, or from the bracket's loaded end when the prediction passes
    it (saving the evaluation at the guess); updated with this solve's load and stiffness
    (load != 0)."""
    hi, lo = bounds[0], bounds[2]
    if load == 0.0:
        if lo <= hi:
            return hi if side > 0 else lo
        xl, xh = hi, lo
    else:
        jm = 0
        for j in range(m):  # the largest lever on the loaded side
            if levers[j] * load > levers[jm] * load:
                jm = j
        lev = abs(levers[jm])
        dx = cm.law_approach_um(abs(load) / (scale * lev), law_a[jm], b, n) / lev
        xt = gaps[jm] / levers[jm] + (dx if load > 0.0 else -dx)
        if npos >= 0:  # closure order: the first contacts to close, each alone, bound it too (tighter
            # for a small load, where the set is only beginning to close); only levers near the
            # largest: a small lever would need a force beyond the law's range
            first, count = (0, npos) if load > 0.0 else (npos, nneg)
            for j in range(first, first + min(count, 3)):
                lv = abs(levers[j])
                if lv < 0.5 * lev:
                    continue
                dxj = cm.law_approach_um(abs(load) / (scale * lv), law_a[j], b, n) / lv
                xj = gaps[j] / levers[j] + (dxj if load > 0.0 else -dxj)
                xt = min(xt, xj) if load > 0.0 else max(xt, xj)
        if load > 0.0:
            xl = hi
            xh = max(lo, xt)
        else:
            xh = lo
            xl = min(hi, xt)
        if not math.isfinite(guess) and xl < xt < xh:  # preloaded: try the tighter end first
            guess = xt
    if bounds[4] != 0.0:  # interfering tip/root contacts: make sure the bracket holds the root
        width = max(xh - xl, 1e-12)
        for _ in range(80):
            if set_load(xl, gaps, levers, law_a, b, n, scale, m, work, npos, nneg)[0] <= load:
                break
            xl -= width
            width *= 2.0
        width = max(xh - xl, 1e-12)
        for _ in range(80):
            if set_load(xh, gaps, levers, law_a, b, n, scale, m, work, npos, nneg)[0] >= load:
                break
            xh += width
            width *= 2.0
    if math.isfinite(guess) and xl < guess < xh:
        x = guess
        if slope is not None and load != 0.0 and slope[1] > 0.0:
            pred = guess + (load - slope[0]) / slope[1]
            if xl < pred < xh:
                x = pred
            elif (pred >= xh) if load > 0.0 else (pred <= xl):  # past the loaded end: that end is closer
                x = xh if load > 0.0 else xl
    else:
        x = xh if load > 0.0 else (xl if load < 0.0 else 0.5 * (xl + xh))
    tol = 1e-13 * (abs(xl) + abs(xh)) + 1e-300
    for _ in range(300):
        g, dg, err, gabs = set_load(x, gaps, levers, law_a, b, n, scale, m, work, npos, nneg)
        f = g - load
        ftol = rtol * max(abs(load), gabs)
        if err <= ftol and abs(f) <= ftol:
            if slope is not None and load != 0.0:
                slope[0], slope[1] = load, dg
            return x
        trusted = abs(f) > 2.0 * err  # the sign of f is right: the bracket may move
        if trusted:
            if f > 0.0:
                xh = x
            else:
                xl = x
        xn = x - f / dg if dg > 0.0 else xl - 1.0
        if not (xl < xn < xh):  # bisect on trusted loads; else settle the forces where we are
            xn = 0.5 * (xl + xh) if trusted else x
        if err <= ftol and abs(xn - x) <= tol:
            if slope is not None and load != 0.0:
                slope[0], slope[1] = load, dg
            return xn
        x = xn
    return x


# --- one unit ----------------------------------------------------------------------------------

BOUND_CONTACTS = 6  # pins assumed to share +-T_R when bounding the rotation (prepare_pins)


@njit(nogil=True, cache=True)
def pin_law_a(phi, c):
    """Coefficient a of pin j's contact law [um/N^n] at phase phi = psi_j - chi_d: Johnson's
    approach with the relative radius of the pin and the flank (``flank_radius_mm`` of
    ``pin_centre_curve_radius_mm``); the flank's body radius is its radius of curvature, at most
    r_p where the flank is nearly straight. Palmgren: the same for every pin."""
    if c.johnson == 0.0:
        return c.palmgren_a
    rho = cm.flank_radius_mm(cm.pin_centre_curve_radius_mm(phi, c.pin_circle_radius_mm, c.k1, c.pins),
                             c.generating_radius_mm)
    r_rel = cm.capped_relative_radius_mm(c.pin_radius_mm, rho, cm.RELATIVE_RADIUS_CAP * c.pin_radius_mm)
    body = min(abs(rho), c.pin_circle_radius_mm)
    return cm.johnson_law_a_um_per_n(c.contact_length_mm, c.pin_radius_mm, c.pin_e_gpa, c.pin_nu, body,
                                     c.disc_e_gpa, c.disc_nu, r_rel)


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
        fill_pin_law(2.0 * math.pi / zp * (s + 0.5) / steps, c, out[s].reshape((discs, zp)))
    return out


@njit(nogil=True, cache=True)
def unit_pin_laws(chi, c, zp, discs, table):
    """pin_law_a of every pin (flat) of a unit at crank angle chi: its row of ``pin_law_table``
    when chi is one of the table's angles (exactly), else computed."""
    if table is not None:
        steps = table.shape[0]
        s = int(math.floor(chi * zp * steps / (2.0 * math.pi)))
        if 0 <= s < steps and 2.0 * math.pi / zp * (s + 0.5) / steps == chi:
            return table[s]
    out = np.empty((discs, zp))
    fill_pin_law(chi, c, out)
    return out.ravel()


@njit(nogil=True, cache=True)
def _pins_bound(g, lev, laws, bounds, c, load):
    """A rotation beyond the one at which the pins carry ``load`` (+-T_R), in closed form: if the
    k pins with the largest levers L_j on the loaded side (k <= BOUND_CONTACTS) each carry an
    equal share, F_j = |load| / (k 1e-6 L_j), their closures delta(F_j) (the contact law as the
    solver reads it, ``law_approach_continued_um``: a tiny lever's huge share stays huge) are reached
    at x_k = max_j (g_j + delta(F_j)) / L_j, where they carry the load; the other pins on the
    loaded side add to it, and beyond the other side's last release nothing pulls back; so
    max(min_k x_k, lo) (load > 0) bounds the rotation (no solve)."""
    m = g.size
    k = min(BOUND_CONTACTS, m)
    idx = np.full(k, -1)
    for j in range(m):  # the k largest levers on the loaded side (insertion into a short list)
        v = lev[j] * load
        if v <= 0.0:
            continue
        pos = k
        while pos > 0 and (idx[pos - 1] < 0 or lev[idx[pos - 1]] * load < v):
            pos -= 1
        if pos < k:
            for q in range(k - 1, pos, -1):
                idx[q] = idx[q - 1]
            idx[pos] = j
    best = np.inf
    for kk in range(1, k + 1):
        if idx[kk - 1] < 0:
            break
        x = 0.0
        for q in range(kk):
            j = idx[q]
            lv = abs(lev[j])
            # in y = x sign(load): (g_j + delta) / |L_j| on either side
            xj = (g[j] + cm.law_approach_continued_um(abs(load) / (kk * 1e-6 * lv), laws[j], c.law_b, c.law_n)) / lv
            x = max(x, xj) if q > 0 else xj
        best = min(best, x)
    best += 1e-12 * abs(best)  # rounding
    if load > 0.0:
        return max(best, bounds[2])
    return min(-best, bounds[0])


@njit(nogil=True, cache=True)
def prepare_pins(gap_um, lever_um_per_rad, chi, c, every, table=None):
    """The unit's pin contacts referred to the output (levers / k), with their contact-law
    coefficients and bounds: (gaps, levers, law_a, count, bounds, work, radial, disc, yw, shifted
    gaps, shifted bounds, npos, nneg, jac, res).
    Reduced to the pins that close somewhere between the rotations at -T_R and +T_R (bounded by
    ``_pins_bound``) unless ``every`` (the discs translate: a translation can close a pin that no
    rotation closes, the tip and root pins); each with its closure per um of its disc's translation
    along the eccentric (``compliance.pin_radial_closure``; 0 when the discs do not translate), its
    disc, and scratch: yw (7, discs) holds the discs' translations [um] (row 0), sums (rows 1-4)
    and the last translations solved under a positive and a negative load (rows 5, 6: the next
    solve's start), then scratch for the gaps shifted by the translations and their bounds, and
    for the translations' Newton system (``solve_pins``). ``table``: the design's
    ``pin_law_table`` (None: each law computed).
    Without translation the kept contacts are in ``closure_order`` (npos, nneg: its runs; else
    -1, 0)."""
    discs, zp = gap_um.shape
    g = gap_um.ravel()
    lev = lever_um_per_rad.ravel() / c.lever_factor
    m = g.size
    bounds = np.empty(5)
    set_bounds(g, lev, m, bounds)
    laws = unit_pin_laws(chi, c, zp, discs, table)
    x_hi, x_lo = np.inf, -np.inf
    if not every:
        x_hi = _pins_bound(g, lev, laws, bounds, c, c.rated_torque_nm)
        x_lo = _pins_bound(g, lev, laws, bounds, c, -c.rated_torque_nm)
    keep = 0
    gk = np.empty(m)
    lk = np.empty(m)
    ak = np.empty(m)
    rk = np.zeros(m)
    dk = np.zeros(m, dtype=np.int64)
    for j in range(m):
        if every or lev[j] * x_hi - g[j] > 0.0 or lev[j] * x_lo - g[j] > 0.0:
            gk[keep] = g[j]
            lk[keep] = lev[j]
            ak[keep] = laws[j]
            if every:  # only translating discs read the radial closures (fixed: left 0)
                rk[keep] = cm.pin_radial_closure(pin_phase(j, chi, zp, discs), c.k1)
            dk[keep] = j // zp
            keep += 1
    npos, nneg = -1, 0
    if not every:  # fixed gaps: in closure order (set_load stops each run at its first open contact)
        order, npos, nneg = closure_order(gk, lk, keep)
        gk, lk, ak, rk, dk = gk[order], lk[order], ak[order], rk[order], dk[order]
    set_bounds(gk, lk, keep, bounds)
    return (gk, lk, ak, keep, bounds, np.zeros(keep), rk, dk, np.zeros((7, discs)), np.empty(keep), np.empty(5),
            npos, nneg, np.empty((discs, discs)), np.empty(discs))


@njit(nogil=True, cache=True)
def prepare_rollers(crank_clearance_um, roller_cos, c):
    """One crank bearing's rollers: gap G_r / 2 each, lever cos(psi_i): (gaps, levers, law_a, count,
    bounds, work)."""
    z = roller_cos.size
    g = np.full(z, 0.5 * crank_clearance_um)
    la = np.full(z, c.roller_a)
    bounds = np.empty(5)
    set_bounds(g, roller_cos, z, bounds)
    return g, roller_cos, la, z, bounds, np.zeros(z)


@njit(nogil=True, cache=True)
def prepare_support(c):
    """One crank support (tapered roller) bearing's rollers under a radial load, axially held (the
    two of a crank face each other and carry equal loads, so their induced axial forces cancel):
    roller i at psi_i = 2 pi i / Z closes, normal to its raceway, by (delta_r cos psi_i - G / 2)
    cos(alpha); its normal force Q_i bears cos(alpha) cos(psi_i) of itself radially. Levers
    cos(alpha) cos(psi_i), gaps G cos(alpha) / 2, Palmgren's law (Harris & Kotzalas, Rolling
    Bearing Analysis 5th ed., the load distribution of a radially loaded roller bearing with
    clearance; docs/elastic.md): (gaps, levers, law_a, count, bounds, work, memo). The support
    bearings' deflection is the same function of the chain's torque for every unit of a design:
    memo (3, SUPPORT_MEMO) keeps the torques, sides and deflections solved, so that repeated
    ``chain_angles`` calls on one set (a unit's loop table) solve each torque once (a batch of
    units reads the loop's ten from ``loop_points``)."""
    z = int(c.support_rollers)
    lv = np.empty(z)
    for i in range(z):
        lv[i] = c.support_cos_alpha * math.cos(2.0 * math.pi * i / z)
    g = np.full(z, 0.5 * c.support_clearance_um * c.support_cos_alpha)
    la = np.full(z, c.support_a)
    bounds = np.empty(5)
    set_bounds(g, lv, z, bounds)
    return g, lv, la, z, bounds, np.zeros(z), np.full((3, SUPPORT_MEMO), np.nan)


@njit(nogil=True, cache=True)
def _warm_solve(st, load, s, b, n, scale, state, i):
    """A roller set's deflection under ``load`` (side s at zero load), started from the last
    solution under a load of the same sign: state[i] (+) or state[i + 1] (-), updated."""
    g, lv, la, m, bounds, work, _ = st
    k = i if s > 0.0 else i + 1
    x = solve_set(g, lv, la, b, n, scale, m, bounds, work, load, s, state[k])
    if load != 0.0:
        state[k] = x
    return x


@njit(nogil=True, cache=True)
def solve_in_place(a, b):
    """b <- x solving a x = b (n x n, a overwritten): Gaussian elimination with partial pivoting
    (Golub & Van Loan, Matrix Computations, 4th ed., Algorithm 3.4.1). For the discs' translations
    (n = discs): no allocation, so that the loop's kernel runs without numba's runtime."""
    n = b.size
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(a[i, k]) > abs(a[p, k]):
                p = i
        if p != k:
            for j in range(n):
                a[k, j], a[p, j] = a[p, j], a[k, j]
            b[k], b[p] = b[p], b[k]
        for i in range(k + 1, n):
            f = a[i, k] / a[k, k]
            for j in range(k + 1, n):
                a[i, j] -= f * a[k, j]
            b[i] -= f * b[k]
    for k in range(n - 1, -1, -1):
        t = b[k]
        for j in range(k + 1, n):
            t -= a[k, j] * b[j]
        b[k] = t / a[k, k]


@njit(nogil=True, cache=True)
def solve_pins(pins, load, side, guess, c, slope=None):
    """The pins' output angle x [rad] at chain torque ``load`` (``solve_set``; at 0 the dead band's
    edge on ``side``). With the discs translating (docs/elastic.md): each disc q also moves by y_q
    [um] along its eccentric, which closes pin j by radial_j y_q, until its pins' radial resultant
    balances its bearings: r_q = sum_j F_j radial_j + K_y y_q = 0. Solved by turns: x exactly for
    the y's held (the pins' gaps shifted by radial_j y_q: the bracketed solver unchanged), then a
    Newton step on the y's with x re-solved (J = diag(K_yy,q + K_y) - K_xy K_xy^T / K_xx), from the
    last y's, until the residuals are below 1e-10 of the forces. The dead band's edge of a
    translating disc is read at TINY_TORQUE (its radial balance needs a direction). ``slope``:
    solve_set's predictor (fixed discs only)."""
    pg, pl, pa, pm, pb, pw, pr, pd, py, ge, gb, npos, nneg, jac, res = pins
    ky = c.radial_stiffness_n_per_um
    if not ky < np.inf:
        return solve_set(pg, pl, pa, c.law_b, c.law_n, 1e-6, pm, pb, pw, load, side, guess, 1e-11, npos, nneg,
                         slope)
    t = side * TINY_TORQUE * c.rated_torque_nm if load == 0.0 else load
    discs = py.shape[1]
    row = 5 if t > 0.0 else 6
    for q in range(discs):  # start from the last solution under a load of the same sign (loops: no temporary)
        py[0, q] = py[row, q]
    x = guess
    for _ in range(int(c.translation_rounds)):
        for j in range(pm):
            ge[j] = pg[j] - pr[j] * py[0, pd[j]]
        set_bounds(ge, pl, pm, gb)
        x = solve_set(ge, pl, pa, c.law_b, c.law_n, 1e-6, pm, gb, pw, t, side, x)
        for r in range(1, py.shape[0]):
            for q in range(discs):
                py[r, q] = 0.0
        kxx = 0.0
        for j in range(pm):
            if pw[j] > 0.0:
                d = pl[j] * x - ge[j]
                f, df, _e = law_step(d, pa[j], c.law_b, c.law_n, pw[j]) if d > 0.0 else (0.0, 0.0, 0.0)
                q = pd[j]
                py[1, q] += f * pr[j]
                py[2, q] += df * pr[j] * pr[j]
                py[3, q] += df * pr[j] * pl[j]
                py[4, q] += f * abs(pr[j])
                kxx += df * pl[j] * pl[j]
        done = True
        for q in range(discs):
            res[q] = py[1, q] + ky * py[0, q]
            if abs(res[q]) > 1e-9 * (py[4, q] + ky * abs(py[0, q])) + 1e-9:
                done = False
        if done:
            break
        for q in range(discs):
            for r in range(discs):
                jac[q, r] = -py[3, q] * py[3, r] / kxx if kxx > 0.0 else 0.0
            jac[q, q] += py[2, q] + ky
        solve_in_place(jac, res)  # res <- the Newton step
        small = True
        for q in range(discs):
            py[0, q] -= res[q]
            small = small and abs(res[q]) <= TRANSLATION_STEP_UM
        if small:  # a last step this small is taken without re-solving x (its effect is below the figures' digits)
            break
    for q in range(discs):
        py[row, q] = py[0, q]
    return x


@njit(nogil=True, cache=True)
def support_deflection_um(t_el, s, support, c, state):
    """Radial deflection of the support bearings [um] when the chain carries t_el [N m] (side s at
    0): from the support set's memo when this torque was solved before, else solved (a symmetric
    set's mirrored load from state[8], state[9]) and remembered."""
    memo = support[6]
    side = s if t_el == 0.0 else 0.0
    free = -1
    for i in range(memo.shape[1]):
        if memo[0, i] == t_el and memo[1, i] == side:
            return memo[2, i]
        if free < 0 and np.isnan(memo[0, i]):
            free = i
    sload = t_el * c.support_force_n_per_nm
    if c.support_symmetric != 0.0 and sload != 0.0 and abs(sload) == state[8]:
        ds = s * state[9]
    else:
        ds = _warm_solve(support, sload, s, 0.0, cm.PALMGREN_EXPONENT, 1.0, state, 6)
        state[8] = abs(sload)
        state[9] = abs(ds)
    if free >= 0:
        memo[0, free] = t_el
        memo[1, free] = side
        memo[2, free] = ds
    return ds


@njit(nogil=True, cache=True)
def chain_angles(t_el, side, pins, rollers, support, backlash1_rad, c, state, out):
    """Output angle of each element [rad] (ELEMENTS order) when the chain carries t_el [N m];
    at t_el = 0, ``side`` picks the edge of the dead bands (+1: positive). ``state`` (N_STATE,):
    the last pins and rollers solutions for positive and negative loads, starts for the next solve
    (NaN: none), then the last rollers' load and deflection (the roller layout is symmetric when
    their number is even: a mirrored load needs no solve), then the same for the support bearings,
    then the pins' last load and stiffness for positive and negative loads (solve_set's slope);
    updated. A translating disc's dead-band edge is read at TINY_TORQUE (its radial balance needs
    a load direction)."""
    s = side if t_el == 0.0 else (1.0 if t_el > 0.0 else -1.0)
    support_um = support_deflection_um(t_el, s, support, c, state) if c.support_rollers > 0.0 else 0.0
    _chain_angles(t_el, side, pins, rollers, support_um, backlash1_rad, c, state, out)


@njit(nogil=True, cache=True, inline="always")
def _chain_angles(t_el, side, pins, rollers, support_um, backlash1_rad, c, state, out):
    """``chain_angles`` with the support bearings' deflection given [um] (``loop_points``)."""
    s = side if t_el == 0.0 else (1.0 if t_el > 0.0 else -1.0)
    k = 0 if s > 0.0 else 2
    x = solve_pins(pins, t_el, s, state[k], c, state[10 + k:12 + k])
    rg, rl, ra, rm, rb, rw = rollers
    load = t_el * c.bearing_force_n_per_nm
    if c.rollers_symmetric != 0.0 and load != 0.0 and abs(load) == state[4]:
        dr = s * state[5]  # an even number of rollers, one on the load line: the mirror of the last solve
    else:
        dr = solve_set(rg, rl, ra, c.roller_b, c.law_n, 1.0, rm, rb, rw, load, s, state[k + 1])
        state[4] = abs(load)
        state[5] = abs(dr)
    if t_el != 0.0:
        state[k] = x
        state[k + 1] = dr
    out[0] = x
    if c.translation_factor != 1.0:  # the translation across the eccentric adds to the elastic part only
        edge = 0.0
        if rb[2] <= rb[0]:  # a clearance: the dead band's edge on this side
            edge = rb[0] if s > 0.0 else rb[2]
        dr = edge + (dr - edge) * c.translation_factor
    out[1] = dr * c.bearing_angle_rad_per_um
    out[2] = 0.5 * s * backlash1_rad + t_el / c.involute_stiffness_nm_per_rad
    out[3] = t_el / c.structure_stiffness_nm_per_rad
    out[4] = t_el * c.crank_compliance_rad_per_nm
    out[5] = support_um * c.bearing_angle_rad_per_um
    out[6] = t_el * c.carrier_compliance_rad_per_nm
    out[7] = t_el * c.main_bearing_compliance_rad_per_nm


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
def branch_angles(torque_nm, branch, pins, rollers, support, backlash1_rad, c, state, out):
    """Element angles [rad] on a branch at applied torque T (``branch_point``, ``chain_angles``)."""
    t_el, side = branch_point(torque_nm, branch, c)
    chain_angles(t_el, side, pins, rollers, support, backlash1_rad, c, state, out)


LOOP_POINTS = 10  # the loop's points that the figures read (loop_points)


@njit(nogil=True, cache=True)
def loop_points(support, c):
    """The points of the loop that ``loop_figures`` reads, in its order (from small to large
    torques, a torque and its mirror in turn, so that each solve starts from the previous one):
    (LOOP_POINTS, 4) rows [chain torque T_el [N m], side, the support bearings' deflection there
    [um], the point's weight in its figure]: zero torque on the falling and the rising branch (the
    backlash: +1, -1), +-x T_R on both branches (the lost motion: +-1/2), +-l T_R and +-h T_R
    loading (the rigidity's span: -+1, +-1). The same for every unit of a design: computed once
    per batch."""
    tr = c.rated_torque_nm
    xt = c.measuring_fraction * tr
    lo, hi = c.rigidity_low * tr, c.rigidity_high * tr
    out = np.empty((LOOP_POINTS, 4))
    state = new_state()
    for q, (torque, branch, weight) in enumerate(((0.0, FALL, 1.0), (0.0, RISE, -1.0), (xt, RISE, 0.5),
                                                  (-xt, FALL, -0.5), (xt, FALL, 0.5), (-xt, RISE, -0.5),
                                                  (lo, RISE, -1.0), (-lo, FALL, 1.0), (hi, RISE, 1.0),
                                                  (-hi, FALL, -1.0))):
        t_el, side = branch_point(torque, branch, c)
        s = side if t_el == 0.0 else (1.0 if t_el > 0.0 else -1.0)
        out[q, 0] = t_el
        out[q, 1] = side
        out[q, 2] = support_deflection_um(t_el, s, support, c, state) if c.support_rollers > 0.0 else 0.0
        out[q, 3] = weight
    return out


@njit_borrowing(nogil=True, cache=True)
def loop_figures(pins, rollers, points, backlash1_rad, c, state, out, a):
    """The test-bench figures of a prepared unit into out[0:N_FIGURES] (module docstring):

        lost motion = 1/2 [theta(+x T_R, load) + theta(+x T_R, unload)] - 1/2 [theta(-x T_R, load) + theta(-x T_R, unload)]
        backlash    = theta(0, unload+) - theta(0, unload-)           (the loop's width at zero torque)
        rigidity    = 2 (h - l) T_R / ([theta(h T_R) - theta(l T_R)]_load+ + [theta(-l T_R) - theta(-h T_R)]_load-)

    [arcmin, arcmin, N m/arcmin], then the lost motion of each element [arcmin], then each
    element's part of the rigidity's angle span [arcmin] (its compliance share times the span).
    ``points``: the design's ``loop_points``. ``state``: ``new_state()``; it holds the reach of the
    pins' solves afterwards. ``a``: scratch (N_ELEMENTS,). Allocates nothing: compiled without
    numba's runtime (``njit_borrowing``), it and the solvers it calls keep no reference counts."""
    width = 0.0
    for e in range(N_ELEMENTS):
        out[3 + e] = 0.0  # the elements' lost motion, then their span, accumulated in place [rad]
        out[SHARES + e] = 0.0
    for q in range(LOOP_POINTS):  # loop_points' rows: 2 for the backlash, 4 for the lost motion, 4 for the span
        _chain_angles(points[q, 0], points[q, 1], pins, rollers, points[q, 2], backlash1_rad, c, state, a)
        w = points[q, 3]
        if q < 2:
            total = 0.0
            for e in range(N_ELEMENTS):
                total += a[e]
            width += w * total
        for e in range(N_ELEMENTS):
            if 2 <= q < 6:
                out[3 + e] += w * a[e]
            elif q >= 6:
                out[SHARES + e] += w * a[e]
    lm = 0.0
    total = 0.0
    for e in range(N_ELEMENTS):
        lm += out[3 + e]
        total += out[SHARES + e]
    tr = c.rated_torque_nm
    out[LOST_MOTION] = lm * ARCMIN_PER_RAD
    out[BACKLASH] = width * ARCMIN_PER_RAD
    out[RIGIDITY] = 2.0 * (c.rigidity_high - c.rigidity_low) * tr / (total * ARCMIN_PER_RAD) if total > 0.0 else np.inf
    for e in range(N_ELEMENTS):
        out[3 + e] *= ARCMIN_PER_RAD
        out[SHARES + e] *= ARCMIN_PER_RAD


@njit(nogil=True, cache=True)
def unit_hysteresis(gap_um, lever_um_per_rad, chi_rad, involute_backlash_rad, crank_clearance_um, c, roller_cos, out,
                    points=None, table=None):
    """The test-bench figures of one unit (``loop_figures``) from its arrays:

    gap_um[d, j]: free gap of pin j to disc d at zero rotation, normal to the profile [um]
    (negative: interference); lever_um_per_rad[d, j]: signed lever, gap(beta) = gap - lever beta
    for a disc rotation beta about its centre [um/rad]; chi_rad: the unit's crank angle (pin j of
    disc d sits at phase 2 pi j / z_p - chi - 2 pi d / discs: it sets the flank curvature of each
    contact); involute_backlash_rad: the involute stage's backlash at the output [rad] (negative
    read as 0); crank_clearance_um: radial clearance G_r of the crank needle bearings [um]
    (negative: preloaded); c: the design's Chain; roller_cos: the rollers' cos(psi_i); points: the
    design's ``loop_points``, shared by a batch of units (None: computed); table: the design's
    ``pin_law_table`` (None: the laws computed)."""
    pins = prepare_pins(gap_um, lever_um_per_rad, chi_rad, c, c.radial_stiffness_n_per_um < np.inf, table)
    loop_figures(pins, prepare_rollers(crank_clearance_um, roller_cos, c),
                 loop_points(prepare_support(c), c) if points is None else points, max(involute_backlash_rad, 0.0), c,
                 new_state(), out, np.empty(N_ELEMENTS))


@njit(nogil=True, cache=True)
def new_state():
    """chain_angles' state before the first solve: no starts yet."""
    return np.full(N_STATE, np.nan)


@njit(nogil=True, cache=True)
def evaluate_units(gap_um, lever_um_per_rad, chi_rad, involute_backlash_rad, crank_clearance_um, c, roller_cos, out,
                   table=None):
    """``unit_hysteresis`` of n units: gap_um and lever_um_per_rad (n, discs, z_p), the rest (n,);
    out (3, n): lost motion [arcmin], backlash [arcmin], rigidity [N m/arcmin]; table: the
    design's ``pin_law_table`` (None: each unit's laws computed)."""
    fig = np.empty(N_FIGURES)
    points = loop_points(prepare_support(c), c)  # the same for every unit
    for i in range(gap_um.shape[0]):
        unit_hysteresis(gap_um[i], lever_um_per_rad[i], chi_rad[i], involute_backlash_rad[i], crank_clearance_um[i],
                        c, roller_cos, fig, points, table)
        out[0, i] = fig[LOST_MOTION]
        out[1, i] = fig[BACKLASH]
        out[2, i] = fig[RIGIDITY]


# --- Python side: one unit, its loop ------------------------------------------------------------

@dataclass(frozen=True)
class ElasticUnit:
    """One unit as the elastic model sees it (the arrays of ``unit_hysteresis``)."""

    gap_um: np.ndarray  # (discs, z_p)
    lever_um_per_rad: np.ndarray  # (discs, z_p)
    chi_rad: float
    involute_backlash_rad: float
    crank_clearance_um: float


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
    gap, lever = np.empty((g.discs, g.zp)), np.empty((g.discs, g.zp))
    unit_gaps(mesh_table(g, np.array([r.chi_rad]))[0], g.a_mm, g.rp_mm, g.zp, g.discs, g.pitch_radius_um,
              *(np.ascontiguousarray(x, dtype=float) for x in unit_arrays(r)), gap, lever,
              stage_work(g.discs, g.zp))
    return ElasticUnit(gap, lever, float(r.chi_rad), float(involute_backlash_rad), float(crank_clearance_um))


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
    """A unit prepared for repeated evaluation (loops, tables): the compiled functions' arrays."""

    def __init__(self, model: ElasticModel, unit: ElasticUnit):
        self.model, self.unit = model, unit
        c = model.chain
        law = np.empty(unit.gap_um.shape)
        fill_pin_law(unit.chi_rad, c, law)
        self.law_a = law
        self.rollers = prepare_rollers(unit.crank_clearance_um, model.roller_cos, c)
        self.support = prepare_support(c)
        self.b1 = max(unit.involute_backlash_rad, 0.0)
        self.pins = prepare_pins(unit.gap_um, unit.lever_um_per_rad, float(unit.chi_rad), c, model.translating)

    def figures(self) -> np.ndarray:
        out = np.empty(N_FIGURES)
        loop_figures(self.pins, self.rollers, loop_points(self.support, self.model.chain), self.b1, self.model.chain,
                     new_state(), out, np.empty(N_ELEMENTS))
        return out

    def branch(self, torque_nm: float, branch: int) -> np.ndarray:
        """Element angles [rad] on a branch (``branch_angles``)."""
        out = np.empty(N_ELEMENTS)
        branch_angles(float(torque_nm), branch, self.pins, self.rollers, self.support, self.b1, self.model.chain,
                      new_state(), out)
        return out

    def chain(self, elastic_torque_nm: float, side: float) -> np.ndarray:
        """Element angles [rad] at a chain torque (``chain_angles``), e.g. both edges of the dead bands."""
        out = np.empty(N_ELEMENTS)
        chain_angles(float(elastic_torque_nm), float(side), self.pins, self.rollers, self.support, self.b1,
                     self.model.chain, new_state(), out)
        return out

    def translation_um(self) -> np.ndarray:
        """Each disc's translation along its eccentric [um] at the last evaluation (0: none)."""
        if not self.model.translating:
            return np.zeros(self.unit.gap_um.shape[0])
        return self.pins[8][0].copy()

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
