"""Friction and lubrication formulas (docs/efficiency.md; issue 40): one function per formula, each
with its equation, source, units and validity. The losses work (``analysis/losses``) applies them to
the loads of the elastic solution over a revolution (``analysis/capacity/revolution.py``).

Units: forces [N], lengths [mm] unless the name says otherwise, speeds [m/s] or [r/min] as named,
moments [N mm] (Palmgren's units) or [N m] as named, viscosity kinematic [mm^2/s = cSt] or dynamic
[Pa s] as named, temperatures [degC] unless named [K].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from rvbacklash.problem import Problem

STEFAN_BOLTZMANN_W_PER_M2K4 = 5.670374419e-8  # CODATA 2018 (exact from the SI's 2019 definition)
KELVIN_OFFSET = 273.15


# --- the lubricant -------------------------------------------------------------------------------

def walther_constants(nu1_mm2_s: float, t1_c: float, nu2_mm2_s: float, t2_c: float) -> tuple[float, float]:
    """(A, B) of the Walther equation through two (viscosity, temperature) points:
    log10 log10(nu + 0.7) = A - B log10(T [K]).

    Source: ASTM D341-20, "Standard Practice for Viscosity-Temperature Equations and Charts for
    Liquid Petroleum or Hydrocarbon Products", Eq. (1) with Z = nu + 0.7 (the 0.7 holds for
    nu >= 2 mm^2/s; the standard's lower-viscosity correction terms are left out).
    Units: nu [mm^2/s], t [degC]. Validity: two distinct temperatures, nu >= 2 mm^2/s, mineral and
    synthetic hydrocarbon oils within about -20..150 degC (the chart's range)."""
    if t1_c == t2_c:
        raise ValueError("walther_constants: two distinct temperatures are needed")
    y1 = math.log10(math.log10(nu1_mm2_s + 0.7))
    y2 = math.log10(math.log10(nu2_mm2_s + 0.7))
    x1, x2 = math.log10(t1_c + KELVIN_OFFSET), math.log10(t2_c + KELVIN_OFFSET)
    b = (y1 - y2) / (x2 - x1)
    return y1 + b * x1, b


def kinematic_viscosity_mm2_s(temperature_c: float, nu40_mm2_s: float, nu100_mm2_s: float) -> float:
    """The oil's kinematic viscosity at a temperature from its grade's two points (40 and 100 degC),
    by the Walther equation (``walther_constants``; ASTM D341): nu = 10^10^(A - B log10 T) - 0.7 [mm^2/s].
    Validity: as ``walther_constants``."""
    a, b = walther_constants(nu40_mm2_s, 40.0, nu100_mm2_s, 100.0)
    return 10.0 ** (10.0 ** (a - b * math.log10(temperature_c + KELVIN_OFFSET))) - 0.7


def dynamic_viscosity_pa_s(kinematic_mm2_s: float, density_kg_m3: float) -> float:
    """eta = rho nu [Pa s] (nu [mm^2/s] = 1e-6 m^2/s). Definition."""
    return density_kg_m3 * kinematic_mm2_s * 1e-6


# --- EHL film and the friction coefficient --------------------------------------------------------

def line_contact_min_film_um(load_per_length_n_per_mm: float, entrainment_speed_m_s: float,
                             relative_radius_mm: float, e_prime_n_per_mm2: float, viscosity_pa_s: float,
                             pressure_viscosity_per_pa: float) -> float:
    """Minimum EHL film thickness of a line contact (Dowson-Higginson, as Hamrock gives it):
    h_min = 2.65 R U^0.70 G^0.54 W'^-0.13, U = eta0 u / (E' R), G = alpha E', W' = w' / (E' R)
    [um]; u the mean entrainment speed (u1 + u2) / 2, w' the load per unit length, E' the reduced
    modulus 2 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2) (= 2 E*).

    Source: Dowson & Higginson, "Elasto-hydrodynamic lubrication" (1966/1977), in Hamrock, Schmid &
    Jacobson, "Fundamentals of Machine Elements", 3rd ed., Ch. 8 (Eq. "h_min" of rectangular
    conjunctions); Hamrock, "Fundamentals of Fluid Film Lubrication" (1994), Ch. 21. Validity:
    isothermal, fully flooded, smooth surfaces, steel-like materials (G ~ 5000); 0 when the contact
    does not entrain oil (u = 0)."""
    speed = np.asarray(entrainment_speed_m_s, float)
    load = np.asarray(load_per_length_n_per_mm, float)
    r_m = np.asarray(relative_radius_mm, float) * 1e-3
    e_pa = e_prime_n_per_mm2 * 1e6
    live = (speed > 0.0) & (load > 0.0)
    u = viscosity_pa_s * np.where(live, speed, 1.0) / (e_pa * r_m)
    g = pressure_viscosity_per_pa * e_pa
    w = np.where(live, load, 1.0) * 1e3 / (e_pa * r_m)
    h = np.where(live, 2.65 * r_m * u ** 0.70 * g ** 0.54 * w ** -0.13 * 1e6, 0.0)
    return float(h) if h.ndim == 0 else h


def film_parameter(film_um: float, roughness1_um: float, roughness2_um: float) -> float:
    """Lambda = h_min / sqrt(Rq1^2 + Rq2^2) [-] (Tallian 1967; Hamrock, Schmid & Jacobson, Ch. 8:
    Lambda < 1 boundary, 1..3 mixed, > 3 full film). Roughness Rq [um]."""
    s = math.hypot(roughness1_um, roughness2_um)
    if s <= 0.0:
        return np.full(np.shape(film_um), math.inf) if np.ndim(film_um) else math.inf
    return np.asarray(film_um, float) / s if np.ndim(film_um) else film_um / s


def mixed_friction_coefficient(film_parameter_: float, boundary: float, full_film: float) -> float:
    """The friction coefficient of a lubricated contact from its film parameter (a stated
    mixed-lubrication law): mu = mu_EHL + (mu_bd - mu_EHL) phi(Lambda), phi = 1 for Lambda <= 1,
    (3 - Lambda) / 2 for 1 < Lambda < 3, 0 for Lambda >= 3 — the asperities' share falling linearly
    across Tallian's mixed regime (its bounds: Tallian 1967; the linear share is this model's
    assumption, not a standard). Units: [-]. Validity: steady sliding; mu_bd the boundary
    coefficient of the pair and lubricant, mu_EHL the full film's traction coefficient."""
    share = np.clip((3.0 - np.asarray(film_parameter_, float)) / 2.0, 0.0, 1.0)
    mu = full_film + (boundary - full_film) * share
    return float(mu) if mu.ndim == 0 else mu


# --- rolling bearings (Palmgren) -----------------------------------------------------------------

def palmgren_viscous_moment_nmm(f0: float, viscosity_mm2_s: float, speed_rpm: float, pitch_diameter_mm: float) -> float:
    """Load-independent (viscous) friction moment of a rolling bearing (Palmgren):
    M0 = 1e-7 f0 (nu n)^(2/3) dm^3 for nu n >= 2000, M0 = 160e-7 f0 dm^3 below [N mm].

    Source: Palmgren, "Ball and Roller Bearing Engineering" (3rd ed., 1959); Harris & Kotzalas,
    "Rolling Bearing Analysis" 5th ed. (2007), vol. 1, Sec. "Bearing friction torque", Eqs.
    M_v = 1e-7 f0 (nu0 n)^(2/3) d_m^3 and the low-speed limit 160e-7 f0 d_m^3. Units: nu [mm^2/s
    = cSt] of the oil (a grease: its base oil), n [r/min], dm [mm]. Validity: moderate speeds and
    loads, oil bath or grease (f0 by type and lubrication); 0 when the bearing does not turn."""
    if speed_rpm <= 0.0:
        return 0.0
    vn = viscosity_mm2_s * speed_rpm
    if vn >= 2000.0:
        return 1e-7 * f0 * vn ** (2.0 / 3.0) * pitch_diameter_mm ** 3
    return 160e-7 * f0 * pitch_diameter_mm ** 3


def palmgren_load_moment_nmm(f1: float, load_n: float, pitch_diameter_mm: float) -> float:
    """Load-dependent friction moment of a rolling bearing (Palmgren): M1 = f1 P1 dm [N mm].

    Source: Palmgren (1959); Harris & Kotzalas 5th ed., vol. 1, Eq. M_l = f1 F_beta d_m with f1 by
    bearing type (needle roller 0.0005, tapered roller 0.0004, radial cylindrical roller
    0.0002-0.0004; angular contact ball 0.001 (P0/C0)^0.33: ``angular_ball_f1``) and F_beta by
    load (radial roller: F_r; single-row angular contact ball: max(F_a - 0.1 F_r, F_r)). Units:
    P1 [N], dm [mm]. Validity: as ``palmgren_viscous_moment_nmm``; at standstill M1 is the
    breakaway moment (the load-dependent friction needs no speed)."""
    return f1 * max(load_n, 0.0) * pitch_diameter_mm


def makers_friction_moment_nmm(friction_coefficient: float, load_n: float, bore_mm: float) -> float:
    """A rolling bearing's friction moment by the makers' quick estimate M = mu P d / 2 [N mm] (d the
    bore [mm], P the load [N]), mu by type for "stable operation under normal operating conditions":
    needle roller and cage assembly 0.0020-0.0030, tapered roller 0.0017-0.0025, angular contact ball
    0.0012-0.0020. Source: JTEKT (Koyo), "Bearing knowledge" 8-4, Table 8-1 "Friction coefficient mu"
    (koyo.jtekt.co.jp/en/support/bearing-knowledge/8-4000.html, read 2026). Used as a published
    cross-check of the Palmgren terms (tests), not in the losses."""
    return friction_coefficient * load_n * bore_mm / 2.0


def angular_ball_f1(static_equivalent_n: float, static_rating_n: float) -> float:
    """f1 = 0.001 (P0 / C0)^0.33 of an angular contact ball bearing (Palmgren; Harris & Kotzalas
    5th ed., vol. 1, table of f1: z = 0.001, y = 0.33) [-]."""
    if static_rating_n <= 0.0 or static_equivalent_n <= 0.0:
        return 0.0
    return 0.001 * (static_equivalent_n / static_rating_n) ** 0.33


def angular_ball_load_n(axial_n: float, radial_n: float) -> float:
    """Palmgren's F_beta of a single-row angular contact ball bearing: max(F_a - 0.1 F_r, F_r) [N]
    (Harris & Kotzalas 5th ed., vol. 1)."""
    return max(axial_n - 0.1 * radial_n, radial_n)


def ball_static_rating_n(balls: int, ball_diameter_mm: float, contact_angle_deg: float, f0: float = 12.3) -> float:
    """Basic static radial load rating of a single-row radial (angular contact) ball bearing:
    C0r = f0 i Z D_w^2 cos(alpha) [N] (ISO 76:2006, cl. 5.1.1, Eq. (1)); f0 from the standard's
    table by D_w cos(alpha) / D_pw (12.3 at about 0.05-0.06: an RV main bearing's small balls on a
    large circle; value transcribed from the table's range, assumption). Validity: rings of hardened
    bearing steel, groove radius <= 0.52 D_w."""
    return f0 * balls * ball_diameter_mm ** 2 * math.cos(math.radians(contact_angle_deg))


MAIN_BEARING_STATIC_AXIAL_FACTOR = 0.26  # ISO 76 Y0 of a single-row angular contact ball bearing at 40 deg
#                                          (X0 = 0.5): P0 = 0.5 F_r + 0.26 F_a, at least F_r


def preloaded_pair_load_moment_nmm(balls: int, ball_diameter_mm: float, pitch_diameter_mm: float,
                                   contact_angle_deg: float, preload_n: float, f1_scale: float = 0.001) -> float:
    """The load-dependent (Palmgren) moment of ONE row of a preloaded angular contact ball pair under a
    pure torque (no external load: each row carries the axial preload) [N mm]: M1 = f1 F_beta dm with
    F_beta = ``angular_ball_load_n``(preload, 0), f1 = z (P0 / C0)^0.33 (``angular_ball_f1``, z =
    ``f1_scale``, Palmgren's 0.001), P0 = Y0 F_a (ISO 76: Y0 = 0.26 at 40 deg), C0 by ISO 76
    (``ball_static_rating_n``). At standstill it is the row's breakaway moment."""
    c0 = ball_static_rating_n(balls, ball_diameter_mm, contact_angle_deg)
    f1 = f1_scale / 0.001 * angular_ball_f1(MAIN_BEARING_STATIC_AXIAL_FACTOR * preload_n, c0)
    return palmgren_load_moment_nmm(f1, angular_ball_load_n(preload_n, 0.0), pitch_diameter_mm)


# --- the involute mesh (ISO/TR 14179-2) ----------------------------------------------------------

def gear_loss_factor(gear_ratio: float, pinion_teeth: float, base_helix_rad: float, contact_ratio: float,
                     addendum_ratio_1: float, addendum_ratio_2: float) -> float:
    """Ohlendorf's gear loss factor H_V = pi (u + 1) / (z1 u cos beta_b) (1 - eps_a + eps_1^2 +
    eps_2^2) [-]: the mean sliding of the mesh's path of contact per unit power.

    Source: ISO/TR 14179-2:2001, Eq. for H_V (after Ohlendorf 1958); Niemann & Winter,
    "Maschinenelemente" vol. II. Validity: eps_1, eps_2 (the addendum contact ratios of pinion and
    wheel) < 1, eps_a = eps_1 + eps_2 < 2 (spur or low-helix gears)."""
    u = gear_ratio
    return (math.pi * (u + 1.0) / (pinion_teeth * u * math.cos(base_helix_rad))
            * (1.0 - contact_ratio + addendum_ratio_1 ** 2 + addendum_ratio_2 ** 2))


def mesh_friction_coefficient(tangential_load_per_width_n_per_mm: float, sum_velocity_m_s: float,
                              relative_radius_mm: float, viscosity_mpa_s: float, roughness_ra_um: float,
                              lubricant_factor: float = 1.0) -> float:
    """Mean coefficient of friction of a gear mesh (ISO/TR 14179-2, after Schlenk):
    mu_mZ = 0.048 (F_bt / b / (v_sumC rho_redC))^0.2 eta_oil^-0.05 Ra^0.25 X_L [-].

    Source: ISO/TR 14179-2:2001, Eq. for mu_mZ. Units: F_bt/b [N/mm] the base tangential load per
    face width, v_sumC [m/s] the sum velocity at the pitch point (2 v_t sin alpha_wt), rho_redC [mm]
    the relative radius at the pitch point, eta_oil [mPa s] at the oil's temperature, Ra [um] the
    mean of the flanks' Ra, X_L the lubricant factor (1.0 mineral oil). Validity: v_sumC > 0;
    the standard quotes it for 0.2..~50 m/s and mu_mZ ~ 0.02..0.10 (capped there, the low-speed
    end stated as boundary friction)."""
    if sum_velocity_m_s <= 0.0 or tangential_load_per_width_n_per_mm <= 0.0:
        return 0.0
    mu = (0.048 * (tangential_load_per_width_n_per_mm / (sum_velocity_m_s * relative_radius_mm)) ** 0.2
          * viscosity_mpa_s ** -0.05 * roughness_ra_um ** 0.25 * lubricant_factor)
    return min(mu, 0.10)


def mesh_power_loss_w(mesh_power_w: float, friction_coefficient: float, loss_factor: float) -> float:
    """Load-dependent mesh power loss P_VZP = P mu_mZ H_V [W] (ISO/TR 14179-2:2001; P the power the
    mesh transmits in the frame where its axes stand still)."""
    return abs(mesh_power_w) * friction_coefficient * loss_factor


@dataclass(frozen=True)
class MeshGeometry:
    """The first stage's mesh as ISO/TR 14179-2 reads it."""

    loss_factor: float  # H_V
    pitch_radius_mm: float  # the centre gear's
    relative_radius_mm: float  # at the pitch point
    pressure_angle_rad: float
    face_width_mm: float


def mesh_geometry(problem: Problem) -> MeshGeometry:
    """H_V and the pitch point's radii of the centre gear / planet mesh (standard addendum m, no
    profile shift, spur: the design's first stage)."""
    s1 = problem.design.first_stage
    alpha = math.radians(s1.pressure_angle_deg)
    m = s1.module_mm
    r1, r2 = m * s1.centre_gear_teeth / 2.0, m * s1.planet_teeth / 2.0
    pb = math.pi * m * math.cos(alpha)

    def addendum_ratio(r: float) -> float:
        return (math.sqrt((r + m) ** 2 - (r * math.cos(alpha)) ** 2) - r * math.sin(alpha)) / pb

    e1, e2 = addendum_ratio(r1), addendum_ratio(r2)
    hv = gear_loss_factor(s1.planet_teeth / s1.centre_gear_teeth, s1.centre_gear_teeth, 0.0, e1 + e2, e1, e2)
    return MeshGeometry(hv, r1, r1 * r2 * math.sin(alpha) / (r1 + r2), alpha, s1.face_width_mm)


# --- the pins ------------------------------------------------------------------------------------

def pin_sliding_speed_m_s(pin_to_pitch_point_mm: float, pin_radius_mm: float, disc_speed_rad_s: float) -> float:
    """The disc's flank's speed past a pin at the contact [m/s]: the disc turns about the pitch
    point P (its instantaneous centre against the housing: every contact normal passes through it)
    at the output's speed, and the contact lies on the line pin centre - P at the pin's radius from
    the pin centre: v = |omega_d| (|Q_j P| - r_rp). Kinematics of the cycloid drive (Litvin & Fuentes,
    "Gear Geometry and Applied Theory" 2nd ed., Ch. 19; a test checks it by finite differences of the
    contact point's motion)."""
    return abs(disc_speed_rad_s) * abs(pin_to_pitch_point_mm - pin_radius_mm) * 1e-3


def pin_contact_loss_w(force_n: float, sliding_speed_m_s: float, flank_mu: float,
                       seat_mu: float) -> tuple[float, float]:
    """(flank loss, seat loss) [W] of one pin contact. The pin turns in its seat when the seat's
    friction is the smaller (it then rolls on the flank and the sliding happens in the seat, at the
    same speed: the seat's radius is the pin's), and stands still otherwise (it slides on the flank):
    the loss is min(mu_flank, mu_seat) F v in the contact that slips (Malhotra & Parameswaran, "Analysis
    of a cycloid speed reducer", Mech. Mach. Theory 18 (1983) 491-499: the rotating-pin case; the seat
    reaction taken equal to the flank force; rolling resistance left out)."""
    p = np.abs(np.asarray(force_n, float)) * sliding_speed_m_s
    seat = np.asarray(seat_mu < flank_mu)
    flank_w = np.where(seat, 0.0, flank_mu * p)
    seat_w = np.where(seat, seat_mu * p, 0.0)
    if flank_w.ndim == 0:
        return float(flank_w), float(seat_w)
    return flank_w, seat_w


# --- the thermal balance -------------------------------------------------------------------------

def housing_heat_flow_w(case_c: float, ambient_c: float, area_m2: float, convection_w_m2k: float,
                        emissivity: float, conductance_w_k: float = 0.0) -> float:
    """Heat the housing gives off [W]: Q = h A (T - Ta) + eps sigma A (T^4 - Ta^4) + G (T - Ta)
    (convection, grey-body radiation to surroundings at the ambient temperature, conduction into the
    mounting flange through a stated conductance G [W/K]). Source: Incropera & DeWitt, "Fundamentals
    of Heat and Mass Transfer" 6th ed., Eqs. (1.3a), (1.7), (3.19); the lumped form as ISO/TR 14179-1
    writes a gearbox's heat balance. Units: temperatures [degC], A [m^2], h [W/(m^2 K)]."""
    t, ta = case_c + KELVIN_OFFSET, ambient_c + KELVIN_OFFSET
    return ((convection_w_m2k * area_m2 + conductance_w_k) * (case_c - ambient_c)
            + emissivity * STEFAN_BOLTZMANN_W_PER_M2K4 * area_m2 * (t ** 4 - ta ** 4))


def lumped_time_constant_s(heat_capacity_j_k: float, conductance_w_k: float) -> float:
    """Time constant of a lumped thermal body tau = C / G_th [s] (C = m c [J/K], G_th = dQ/dT at the
    steady state [W/K]): the temperature rise reaches 1 - 1/e of its steady value after tau (Incropera
    & DeWitt 6th ed., Sec. 5.2, Eq. (5.7))."""
    return heat_capacity_j_k / conductance_w_k if conductance_w_k > 0.0 else math.inf


def thermal_growth_um(length_mm: float, expansion_per_k: float, delta_t_k: float) -> float:
    """Free thermal growth of a length dL = L alpha dT [um] (L [mm], alpha [1/K], dT [K]). Linear
    elasticity-free expansion (any handbook; Incropera & DeWitt, Table A.1 for alpha)."""
    return length_mm * expansion_per_k * delta_t_k * 1e3


def offset_clearance_um(clearance_um: float, radial_offset_um: float) -> float:
    """The tangential free travel of a journal in a bearing of diametral clearance G [um] whose centre
    is offset across the travel by d [um]: the chord of the clearance circle (radius G/2) at the offset,
    G_eff = sqrt(G^2 - 4 d^2) [um] (plane geometry); 0 when |d| >= G/2 (the rollers on the offset's side
    closed: a radial preload, not followed). G <= 0 (a preload already) is returned as it is. Rigid
    bodies; d = 0 gives G exactly."""
    if clearance_um <= 0.0:
        return float(clearance_um)
    squared = clearance_um * clearance_um - 4.0 * radial_offset_um * radial_offset_um
    return math.sqrt(squared) if squared > 0.0 else 0.0
