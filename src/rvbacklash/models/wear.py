"""Wear formulas (docs/service-life.md), one function per formula, beside ``compliance.py`` and
``ratings.py``: Archard's law in its volume, depth and single-pass forms, the running-in
coefficient, and the sliding kinematics of the cycloid stage's contacts (pin on flank, pin in its
seat) and of the crank needle bearings.

Units: forces [N], lengths [mm], wear depths [um], wear coefficients k [mm^3/(N m)] (the
dimensional coefficient: wear volume per newton of load and metre of sliding), hardness [HV],
angles [rad], times [h]. The phase of a pin phi = psi_j - chi_d (models/elastic/chain.pin_phase)
places its contact on the tooth: every tooth point is met at one phase.

Sources: Archard, J.F. (1953) "Contact and rubbing of flat surfaces", J. Appl. Phys. 24(8),
981-988 (V = K F s / H); the single-point-observation form of the wear depth per pass
(h = k int p ds over the contact's passage) as in Flodin, A. & Andersson, S. (1997) "Simulation of
mild wear in spur gears", Wear 207, 16-23; running-in: Blau, P.J. (2005) "On the nature of
running-in", Tribology International 38, 1007-1012 (the wear rate falls from a higher running-in
value to a steady one); hardness conversion ASTM E140 (60 HRC ~ 697 HV); the geometry of the pin
centre curve C: ``compliance.pin_centre_curve_radius_mm``.
"""

from __future__ import annotations

import math

import numpy as np

HV_TO_N_PER_MM2 = 9.80665  # Vickers hardness number -> N/mm^2 (HV is kgf/mm^2)


def dimensional_wear_coefficient(k_dimensionless: float, hardness_hv: float) -> float:
    """The dimensional wear coefficient k = K / H [mm^3/(N m)] of Archard's dimensionless K and the
    softer body's hardness H.

    Source: Archard (1953): V = K F s / H. With H [N/mm^2] = 9.80665 HV and s in metres (1e3 mm):
    k = 1e3 K / (9.80665 HV). Parameters: K [-], hardness [HV]. Returns k [mm^3/(N m)].
    Validity: mild (oxidative, lubricated) wear, K < 1e-4; H of the softer surface."""
    return 1e3 * k_dimensionless / (HV_TO_N_PER_MM2 * hardness_hv)


def archard_volume_mm3(k_mm3_per_nm: float, load_n: float, sliding_m: float) -> float:
    """Archard's wear volume V = k F s.

    Source: Archard (1953). Parameters: k [mm^3/(N m)], F normal load [N], s sliding distance [m].
    Returns V [mm^3]. Validity: k constant (steady mild wear), F and s >= 0."""
    return k_mm3_per_nm * load_n * sliding_m


def archard_depth_um(k_mm3_per_nm, pressure_mpa, sliding_mm):
    """Archard's wear depth of a surface under a contact pressure p sliding a distance s:
    w = k p s (the local form of V = k F s: dV = dA dw, dF = p dA).

    Source: Archard (1953); the local form as used in every wear-depth model (Flodin & Andersson
    1997, Eq. (1)). Parameters: k [mm^3/(N m)], p [MPa = N/mm^2], s [mm] (arrays allowed).
    Returns w [um] = k [mm^3/(N mm)] p s 1e3 with k/1e3 per mm of sliding."""
    return np.asarray(k_mm3_per_nm) * 1e-3 * np.asarray(pressure_mpa) * np.asarray(sliding_mm) * 1e3


def pass_depth_um(k_mm3_per_nm, load_per_length_n_per_mm, sliding_per_surface_length):
    """Wear depth of a surface point as a line contact passes over it once:
    h = k int p v_s dt = k (F / L) (v_s / v_t) (the contact's pressure integrates to F / L over its
    width, crossed in 2b / v_t while sliding at v_s: the single point observation).

    Source: Flodin & Andersson (1997), Eq. (3) (h = k p s_p with s_p = 2 b |v_1 - v_2| / v_i the
    sliding distance of a point while in contact; for a Hertzian contact p_mean 2 b = F / L).
    Parameters: k [mm^3/(N m)], F / L load per unit length [N/mm], v_s / v_t the sliding distance per
    unit of surface the contact crosses [-]. Returns h [um]. Validity: the contact moves over the
    surface (v_t > 0); near a dwell spread the load over the contact's width instead (deposit)."""
    return np.asarray(k_mm3_per_nm) * 1e-3 * np.asarray(load_per_length_n_per_mm) \
        * np.asarray(sliding_per_surface_length) * 1e3


def running_in_hours(t0_h: float, t1_h: float, factor: float, time_constant_h: float) -> float:
    """The integral of the running-in multiplier of the wear coefficient from t0 to t1:
    int f dt, f(t) = 1 + (m - 1) exp(-t / tau) (k(t) = k_steady f(t)): a coefficient m times the
    steady one on first running, falling to it as the surfaces conform.
    = (t1 - t0) + (m - 1) tau (exp(-t0/tau) - exp(-t1/tau)).

    Source: the two-phase shape of Blau (2005) (running-in wear rate above the steady rate, decaying);
    the exponential form is our assumption (docs/service-life.md). Parameters: t0, t1 [h], m [-]
    (1: no running-in), tau [h] (> 0). Returns the equivalent steady hours [h]."""
    if factor == 1.0 or time_constant_h <= 0.0:
        return t1_h - t0_h
    return (t1_h - t0_h) + (factor - 1.0) * time_constant_h * (math.exp(-t0_h / time_constant_h)
                                                              - math.exp(-t1_h / time_constant_h))


# --- the cycloid stage's sliding ----------------------------------------------------------------

def pitch_distance_mm(phi_rad, pin_circle_radius_mm, k1):
    """Distance from pin j's centre Q to the pitch point P at phase phi: |Q - P| = r_p sqrt(S),
    S = 1 + K1^2 - 2 K1 cos phi (P = a z_p e^{i chi_d}, Q = r_p e^{i psi_j}, K1 = a z_p / r_p).

    Source: the geometry of models/elastic/loads.py (every contact normal passes through P);
    ``compliance.pin_centre_curve_radius_mm``'s S. Returns [mm]."""
    s = 1.0 + k1 * k1 - 2.0 * k1 * np.cos(phi_rad)
    return pin_circle_radius_mm * np.sqrt(s)


def flank_sliding_per_phase_mm(phi_rad, pin_circle_radius_mm, k1, pin_radius_mm, cycloid_teeth):
    """Relative sliding of the flank on a non-rotating pin per radian of phase:
    |v_s| / |d phi/dt| = (|Q - P| - r_rp) / z_c.

    Derivation: relative to the pins the disc turns about the pitch point P (its instantaneous
    centre: the eccentric's translation plus the disc's rotation -chi / z_c) at |omega| = |chi'| / z_c;
    the contact point lies on QP at r_rp from Q, so the disc's material there slides past the pin at
    |omega| |P P_c| along the common tangent; |phi'| = |chi'|. Litvin & Fuentes, Gear Geometry and
    Applied Theory, 2nd ed. (2004), ch. on cycloidal gearing (the same instantaneous centre).
    Parameters [mm], K1 [-], z_c [-]. Returns [mm/rad]. Tested against finite differences of the
    disc's rigid motion."""
    return (pitch_distance_mm(phi_rad, pin_circle_radius_mm, k1) - pin_radius_mm) / cycloid_teeth


def flank_arc_per_phase_mm(phi_rad, pin_circle_radius_mm, k1, pins, cycloid_teeth, generating_radius_mm):
    """Arc length of the disc's flank that the contact crosses per radian of phase:
    ds/dphi = (r_p sqrt(S) / z_c) (1 - r_g / rho_C).

    Derivation: the pin-centre curve C(t) has |C'| = r_p sqrt(S) / z_c (compliance.
    pin_centre_curve_radius_mm), a pin at phase phi sits at t = -phi, and the flank is C offset
    inwards by r_g: its arc is |C'| (1 - r_g / rho_C) (an offset curve's arc element). Parameters:
    r_p [mm], K1 [-], z_p, z_c [-], r_g [mm]. Returns [mm/rad] (> 0 without undercut). Tested against the
    disc-frame contact points' arc length."""
    from rvbacklash.models import compliance as cm

    phi = np.asarray(phi_rad, float)
    speed = pitch_distance_mm(phi, pin_circle_radius_mm, k1) / cycloid_teeth
    rho_c = np.vectorize(lambda p: cm.pin_centre_curve_radius_mm(float(p), pin_circle_radius_mm, k1, pins))(phi)
    return speed * (1.0 - generating_radius_mm / rho_c)


def contact_direction_rad(phi_rad, k1):
    """Direction of the contact normal at pin j, from the pitch point through the pin's centre,
    against the pin's outward radial direction: theta = arg(1 - K1 e^{-i phi}), |theta| <= asin K1.
    The pin's flank contact sits at theta + pi on the pin, its seat contact at theta (the pin is
    pushed into its seat along the normal). Returns [rad]."""
    phi = np.asarray(phi_rad, float)
    return np.arctan2(k1 * np.sin(phi), 1.0 - k1 * np.cos(phi))


# --- the crank needle bearings -------------------------------------------------------------------

def needle_rolling_per_revolution_mm(raceway_diameter_mm: float, roller_diameter_mm: float) -> float:
    """Rolling distance of a needle on either raceway per revolution of the rings against each
    other: pi d_m (1 - gamma^2) / 2, d_m = d_i + D, gamma = D / d_m (the cage turns at
    (1 - gamma) / 2 of the inner ring's speed against the outer ring; each raceway's contact rolls
    pi d_i (1 + gamma) / 2 = pi d_o (1 - gamma) / 2).

    Source: Harris & Kotzalas, Rolling Bearing Analysis 5th ed. (2007), vol. 1, ch. 8 (cage and
    roller speeds, outer ring fixed). Parameters: d_i inner raceway diameter [mm], D [mm].
    Returns [mm]."""
    dm = raceway_diameter_mm + roller_diameter_mm
    gamma = roller_diameter_mm / dm
    return math.pi * dm * (1.0 - gamma * gamma) / 2.0


def clearance_growth_um(inner_depth_um, outer_depth_um, roller_depth_um):
    """Growth of a roller bearing's radial internal clearance G_r = d_o - d_i - 2 D by raceway and
    roller wear: dG_r = 2 w_i + 2 w_o + 4 w_r (each ring's diameter and each of the two rollers
    across the bore change by twice their depths). Returns [um]."""
    return 2.0 * inner_depth_um + 2.0 * outer_depth_um + 4.0 * roller_depth_um
