"""The hysteresis loop's friction from the contacts (``[elastic] friction_model = "contacts"``;
docs/efficiency.md, "The loop's friction from the contacts"; issue 40 item 3).

The bench twists the output with the input locked, slowly: every element's friction opposes the
motion its own bodies make under the *elastic* twist, not the running reducer's kinematic motion
(which, with the input locked, is zero). Per output rotation d theta (the chain's element angles,
``chain_angles``, at the chain's torque T):

- **pins** (flank or seat, whichever slips easier; at standstill both take the static coefficient
  mu_s): the disc turns against the housing by d beta = (d theta_pins + d theta_seats) / k about its
  own centre (the chain's lever model, docs/elastic.md, "Kinematics"), which moves each loaded
  contact along its tangent by s_j d beta (``tangential_lever_mm``); Coulomb friction mu_s F_j there:
  T_pins = mu_s sum_j F_j s_j (d theta_pins+seats / d theta) / k;
- **crank needle and support bearings**: the cranks turn (z1/z2) d theta against the carrier and the
  discs: Palmgren's load moment M1 = f1 P dm of each (the bearing makers' breakaway moment), P from
  the chain's bearing force per torque (the needle bearings: T k / (n a0) each; the support bearings:
  a crank's two eccentric loads over its two supports, the gear's force left out);
- **involute mesh**: the centre gear turns d theta against the carrier carrying T / R: mu_s H_V T / R
  (ISO/TR 14179-2's loss factor H_V, ``friction.mesh_geometry``);
- **main bearings and the output seal**: the carrier turns d theta in the housing: the preloaded
  pair's two rows' M1 (``friction.preloaded_pair_load_moment_nmm``) and the stated seal torque — the
  load-independent part T_0.

*Why Coulomb, and not a micro-slip law.* Mindlin's partial slip (Johnson, "Contact Mechanics", 1985,
Sec. 7.2, Eq. (7.42)) dissipates less than Coulomb sliding only while the tangential displacement
stays below the full-slip one, delta_t* = 3 mu P (2 - nu) / (16 G a) = mu (2 - nu) / (4 (1 - nu))
delta_n for a Hertz contact of like materials (delta_n its normal approach): 0.07 delta_n at mu = 0.12,
nu = 0.3. Under the twist a pin's tangential motion s_j beta and its normal closure L_j beta are of
the same order (s_j / L_j ~ 0.3-3 here, tested), so every loaded pin slides fully once its closure
passes a few % of its own: the micro-slip part of each branch is its first few % of torque, and
Coulomb sliding is the model (an upper bound there). The point-contact ratio is used for the line
contact as an order of magnitude (a 2-D contact's tangential compliance, like its approach, has no
closed form without the bodies' size).

The result T_f(T) = T_0 + (mu_s a + b) |T| is what the chain's Coulomb element reads
(``friction_torque_nm`` = T_0, ``friction_load_fraction`` = mu_s a + b, the least-squares slope over
x T_R..T_R; its own curve is kept in ``TwistFriction.curve_nm``): linear in mu_s, which ``calibrate``
fits. A value stated in ``[elastic]`` (``friction_torque_nm``, ``friction_load_fraction``) wins over
the model's. Derived on the nominal unit at crank angle 0, once per design; every unit of a run uses
it (as it uses the stated constant). The discs' translation along their eccentrics and the disc
bodies' deformation do not move the flanks against the pins here (the flank's motion against the
pin is the contacts' and seats' approach alone).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.models import friction as fr
from rvbacklash.models.elastic.chain import PIN_SEATING, PINS, ElasticModel
from rvbacklash.models.elastic.unit import PreparedUnit, nominal_unit
from rvbacklash.problem import Problem

CURVE_FRACTIONS = tuple(float(x) for x in np.linspace(0.05, 1.0, 20))  # of T_R: where T_f(T) is evaluated
DERIVATIVE_STEP = 1e-3  # of T_R: the central difference of the element angles


def tangential_lever_mm(pin_circle_radius_mm: float, pin_radius_mm: float, eccentricity_mm: float, pins: int,
                        discs: int, chi_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """(s, L) [mm per rad] of every pin of every disc (discs, z_p): the tangential (s) and normal (L)
    displacement of the flank at the contact for a unit rotation of the disc about its own centre O_d.
    Pin j at Q_j = r_p e^{i psi_j}, disc d's centre O_d = a e^{i chi_d} and pitch point P = a z_p e^{i chi_d}
    (chi_d = chi + 2 pi d / discs); the contact normal n_j runs from Q_j through P and the contact C_j lies
    on it at r_rp from Q_j. A rotation beta about O_d moves C_j by beta z x (C_j - O_d): along the normal
    beta (C_j - O_d) x n_j (the lever, = the contact model's), along the tangent beta (C_j - O_d) . n_j.
    Rigid-body kinematics (Litvin & Fuentes, "Gear Geometry and Applied Theory" 2nd ed., Ch. 19 for the
    normal through P); absolute values."""
    psi = 2.0 * math.pi * np.arange(pins) / pins
    qx, qy = pin_circle_radius_mm * np.cos(psi), pin_circle_radius_mm * np.sin(psi)
    s = np.empty((discs, pins))
    lever = np.empty((discs, pins))
    for d in range(discs):
        chi_d = chi_rad + 2.0 * math.pi * d / discs
        ox, oy = eccentricity_mm * math.cos(chi_d), eccentricity_mm * math.sin(chi_d)
        px, py = pins * ox, pins * oy
        nx, ny = px - qx, py - qy
        norm = np.hypot(nx, ny)
        nx, ny = nx / norm, ny / norm
        cx, cy = qx + pin_radius_mm * nx - ox, qy + pin_radius_mm * ny - oy
        s[d] = np.abs(cx * nx + cy * ny)
        lever[d] = np.abs(cx * ny - cy * nx)
    return s, lever


@dataclass(frozen=True)
class TwistFriction:
    """The loop's friction from the contacts (module docstring) at the design's coefficients."""

    coefficient: float  # mu_s: the static coefficient on the pins and the mesh ([lubrication])
    constant_nm: float  # T_0: main bearings' preload moments and the output seal
    load_fraction_per_coefficient: float  # a: d lambda / d mu_s (pins and mesh)
    load_fraction_bearings: float  # b: the needle and support bearings' M1
    torque_nm: tuple[float, ...]  # the chain torques the curve is evaluated at
    curve_nm: tuple[float, ...]  # T_f(T) of the model at those torques (before the linear fit)
    terms_at_rated_nm: dict  # each term at T_R [N m at the output]
    pins_share_at_rated: float  # d theta_pins+seats / d theta at T_R

    @property
    def load_fraction(self) -> float:
        """lambda = mu_s a + b (the chain's friction_load_fraction)."""
        return self.load_fraction_for(self.coefficient)

    def load_fraction_for(self, coefficient: float) -> float:
        return coefficient * self.load_fraction_per_coefficient + self.load_fraction_bearings

    def torque_at_nm(self, torque_nm: float, coefficient: float | None = None) -> float:
        """The linear law T_0 + lambda |T| [N m] (the chain's Coulomb element)."""
        mu = self.coefficient if coefficient is None else coefficient
        return self.constant_nm + self.load_fraction_for(mu) * abs(torque_nm)


def twist_friction(problem: Problem, model: ElasticModel, coefficient: float | None = None) -> TwistFriction:
    """The TwistFriction of a design's elastic model (module docstring); ``coefficient`` overrides the
    design's [lubrication] static_friction_coefficient."""
    lube = problem.design.lubrication
    mu = lube.static_friction_coefficient if coefficient is None else float(coefficient)
    c = model.chain._replace(friction_nm=0.0, friction_fraction=0.0)
    frictionless = replace(model, chain=c)
    unit = nominal_unit(problem)
    pu = PreparedUnit(frictionless, unit)
    g = model.geometry
    s_mm, _ = tangential_lever_mm(g.rp_mm, g.rrp_mm, g.a_mm, g.zp, g.discs, float(unit.chi_rad))
    s1 = problem.design.first_stage
    crank_turn = s1.centre_gear_teeth / s1.planet_teeth  # the cranks against the carrier per output rotation
    ratio = problem.geometry.ratio
    hv = fr.mesh_geometry(problem).loss_factor
    needle_dm = model.raceway_diameter_mm + model.inputs.crank_bearing_roller_diameter_mm
    per_torque_n = c.bearing_force_n_per_nm  # each crank needle bearing's load per chain torque [N / N m]
    bearings_nm_per_nm = (fr.palmgren_load_moment_nmm(lube.needle_bearing_f1, per_torque_n, needle_dm)
                          * model.bearings * crank_turn * 1e-3)
    st = model.structure
    support_dm = None
    if st is not None:
        support_dm = st.support_bearing_pitch_diameter_mm or (
            0.5 * (st.crankshaft_diameter_mm + st.support_bearing_seat_diameter_mm)
            if st.support_bearing_seat_diameter_mm is not None else None)
    support_nm_per_nm = 0.0
    if support_dm is not None:  # 2 supports per crank share its discs' eccentric loads: n bearings' load in all
        support_nm_per_nm = (fr.palmgren_load_moment_nmm(lube.support_bearing_f1, per_torque_n, support_dm)
                             * model.bearings * crank_turn * 1e-3)
    main_nm = 0.0
    if st is not None and st.main_bearing_balls is not None and st.main_bearing_pitch_diameter_mm is not None:
        main_nm = 2.0 * fr.preloaded_pair_load_moment_nmm(
            st.main_bearing_balls, st.main_bearing_ball_diameter_mm, st.main_bearing_pitch_diameter_mm,
            st.main_bearing_contact_angle_deg, st.main_bearing_preload_n or 0.0, lube.main_bearing_f1_scale) * 1e-3
    t0 = main_nm + lube.output_seal_torque_nm
    tr = c.rated_torque_nm
    h = DERIVATIVE_STEP * tr
    torques, pins_per_mu, shares = [], [], []
    for f in CURVE_FRACTIONS:
        t = f * tr
        a = pu.chain(t, -1.0)
        forces = pu.pin_forces_n(float(a[PINS] + a[PIN_SEATING]))
        hi, lo = pu.chain(t + h, -1.0), pu.chain(t - h, -1.0)
        total = float(hi.sum() - lo.sum())
        share = float(hi[PINS] + hi[PIN_SEATING] - lo[PINS] - lo[PIN_SEATING]) / total if total > 0 else 0.0
        torques.append(t)
        shares.append(share)
        pins_per_mu.append(float(np.sum(forces * s_mm)) * 1e-3 * share / c.lever_factor)
    t_arr = np.array(torques)
    per_mu = np.array(pins_per_mu) + hv * t_arr / ratio  # pins and mesh, per unit coefficient
    bearing = (bearings_nm_per_nm + support_nm_per_nm) * t_arr
    fit = t_arr >= c.measuring_fraction * tr  # the slope over x T_R .. T_R (least squares through T_0)
    a_fit = float(per_mu[fit] @ t_arr[fit] / (t_arr[fit] @ t_arr[fit]))
    b_fit = float(bearing[fit] @ t_arr[fit] / (t_arr[fit] @ t_arr[fit]))
    curve = t0 + mu * per_mu + bearing
    terms = {"pins (flanks or seats)": mu * pins_per_mu[-1], "crank needle bearings": bearings_nm_per_nm * tr,
             "crank support bearings": support_nm_per_nm * tr, "involute mesh": mu * hv * tr / ratio,
             "main bearings": main_nm, "output seal": lube.output_seal_torque_nm}
    return TwistFriction(mu, t0, a_fit, b_fit, tuple(torques), tuple(float(v) for v in curve),
                         {k: float(v) for k, v in terms.items()}, shares[-1])


def with_twist_friction(problem: Problem, model: ElasticModel) -> ElasticModel:
    """The model with its chain's Coulomb friction from ``twist_friction`` (a value stated in
    [elastic] wins: friction_torque_nm for T_0, friction_load_fraction for lambda)."""
    e = model.inputs
    tf = twist_friction(problem, model)
    t0 = e.friction_torque_nm if e.friction_torque_nm is not None else tf.constant_nm
    lam = e.friction_load_fraction if e.friction_load_fraction is not None else tf.load_fraction
    tr = model.chain.rated_torque_nm
    if not (0.0 <= lam < 0.5 and t0 < tr * (1.0 - lam)):
        raise InputError("elastic.friction_model", "contacts",
                         f"the contacts' friction T_f = {t0:.4g} N m + {lam:.4g} |T| never lets the output move "
                         f"(allowed: friction_load_fraction < 0.5 and T_0 < T_R (1 - lambda)); check "
                         f"[lubrication] static_friction_coefficient, or state the friction")
    return replace(model, chain=model.chain._replace(friction_nm=float(t0), friction_fraction=float(lam)),
                   twist_friction=tf)
