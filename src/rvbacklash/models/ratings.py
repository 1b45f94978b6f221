"""Load ratings, rating lives and contact stresses of the reducer's bearings and contacts
(docs/capacity.md), one function per formula, beside ``compliance.py``.

Units: forces [N], lengths [mm], stresses [MPa], speeds [r/min], lives in millions of revolutions
[Mrev] or hours [h] as the names say. The scalar formulas that the production run's kernel
evaluates per unit are compiled with numba (``njit``) and callable from Python with plain floats.

Sources: ISO 281:2007 (dynamic load ratings and rating life; its tables as data in
``standards/data``), ISO 76:2006 (static load ratings), ISO/TS 16281:2008 (rating life from the
internal load distribution; the equations as transcribed in public implementations of the
standard, its text not read here: equation numbers are theirs), Harris & Kotzalas, *Rolling
Bearing Analysis* 5th ed. (2007) (Hertz point contact, system life), Lundberg & Palmgren (1947,
1952) (the Weibull slopes of a system of bearings).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.errors import InputError

ROLLER_LIFE_EXPONENT = 10.0 / 3.0  # ISO 281: L10 = (C/P)^p, roller bearings
BALL_LIFE_EXPONENT = 3.0  # ball bearings
ROLLER_WEIBULL_SLOPE = 9.0 / 8.0  # Lundberg-Palmgren: line contact
BALL_WEIBULL_SLOPE = 10.0 / 9.0  # point contact
B_M_RADIAL_ROLLER = 1.1  # ISO 281:2007 Table 1: cylindrical, tapered and (machined-ring) needle roller bearings
B_M_ANGULAR_BALL = 1.3  # ISO 281:2007 Table 1: radial and angular contact groove ball bearings
ISO76_ROLLER_STRESS_MPA = 4000.0  # ISO 76: the static load rating's contact stress, roller bearings
ISO76_BALL_STRESS_MPA = 4200.0  # ISO 76: radial ball bearings (not self-aligning)
ISO16281_LAMBDA_NU = 0.83  # ISO/TS 16281: the reduction factor lambda*nu of radial roller bearings
LN_RELIABILITY_90 = math.log(0.9)


# --- ISO 281:2007: the tables of f_c -------------------------------------------------------------

@functools.cache
def fc_table(kind: str) -> tuple[np.ndarray, np.ndarray]:
    """(gamma, f_c) of ISO 281:2007's f_c table for ``kind`` "roller" (Table 7, radial roller
    bearings) or "ball" (Table 2, first column) from ``standards/data`` (provenance in each file)."""
    from rvbacklash.standards.tables import read_table

    rows = read_table(f"iso281_fc_radial_{kind}.csv")
    return np.array([float(r["gamma"]) for r in rows]), np.array([float(r["f_c"]) for r in rows])


def fc_radial_roller(gamma: float) -> float:
    """f_c of a radial roller bearing at gamma = D_we cos(alpha) / D_pw, linearly interpolated in
    ISO 281:2007 Table 7 (as ISO 281 prescribes). Validity: 0.01 <= gamma <= 0.28 (the rows stored;
    beyond, refused)."""
    return _interpolate("roller", gamma)


def fc_radial_ball(gamma: float) -> float:
    """f_c of a radial or angular-contact groove ball bearing at gamma = D_w cos(alpha) / D_pw,
    linearly interpolated in ISO 281:2007 Table 2 (first column). Validity: 0.01 <= gamma <= 0.40."""
    return _interpolate("ball", gamma)


def _interpolate(kind: str, gamma: float) -> float:
    g, f = fc_table(kind)
    if not (g[0] <= gamma <= g[-1]):
        raise InputError("bearing geometry", round(gamma, 4),
                         f"allowed: D_w cos(alpha) / D_pw between {g[0]:g} and {g[-1]:g} (ISO 281 f_c table of radial "
                         f"{kind} bearings as stored)")
    return float(np.interp(gamma, g, f))


def fc_radial_roller_closed_form(gamma: float, lambda_nu: float = ISO16281_LAMBDA_NU) -> float:
    """The closed form behind ISO 281's Table 7 (Lundberg-Palmgren for line contact):

        f_c = 207.9 lambda nu [1 + (1.04 ((1 - g)/(1 + g))^(143/108))^(9/2)]^(-2/9) g^(2/9) (1 - g)^(29/27) / (1 + g)^(1/4)

    Source: ISO/TR 1281-1:2008 (the explanatory notes on ISO 281), the roller bearing's rating
    factor; lambda nu = 0.83 for radial roller bearings. Used here to check the stored table (it
    agrees to +-0.05 over 0.01-0.28); the table is what the ratings read. Parameters: gamma [-].
    Returns f_c [-]."""
    t = (1.04 * ((1.0 - gamma) / (1.0 + gamma)) ** (143.0 / 108.0)) ** 4.5
    return (207.9 * lambda_nu * (1.0 + t) ** (-2.0 / 9.0) * gamma ** (2.0 / 9.0) * (1.0 - gamma) ** (29.0 / 27.0)
            / (1.0 + gamma) ** 0.25)


# --- ISO 281 / ISO 76: load ratings from the geometry ---------------------------------------------

def dynamic_load_rating_radial_roller_n(rows: int, length_mm: float, contact_angle_deg: float, rollers: int,
                                        diameter_mm: float, pitch_diameter_mm: float,
                                        b_m: float = B_M_RADIAL_ROLLER) -> float:
    """Basic dynamic radial load rating of a radial roller bearing:

        C_r = b_m f_c (i L_we cos(alpha))^(7/9) Z^(3/4) D_we^(29/27)

    Source: ISO 281:2007, clause 7.1.1, Eq. (7); f_c from Table 7 (``fc_radial_roller``), b_m from
    Table 1 (1.1: cylindrical, tapered, needle roller bearings with machined rings). Parameters:
    rows i [-], effective roller length L_we [mm], contact angle alpha [deg], rollers per row Z
    [-], roller diameter D_we [mm], pitch diameter D_pw [mm]. Returns C_r [N]. Validity: the
    standard's (a hardened bearing steel of modern quality, the roller's contact without edge
    stresses; gamma within the table)."""
    cos_a = math.cos(math.radians(contact_angle_deg))
    fc = fc_radial_roller(diameter_mm * cos_a / pitch_diameter_mm)
    return b_m * fc * (rows * length_mm * cos_a) ** (7.0 / 9.0) * rollers ** 0.75 * diameter_mm ** (29.0 / 27.0)


def dynamic_load_rating_radial_ball_n(rows: int, contact_angle_deg: float, balls: int, diameter_mm: float,
                                      pitch_diameter_mm: float, b_m: float = B_M_ANGULAR_BALL) -> float:
    """Basic dynamic radial load rating of a radial or angular-contact ball bearing:

        C_r = b_m f_c (i cos(alpha))^0.7 Z^(2/3) D_w^1.8          (D_w <= 25.4 mm)
        C_r = 3.647 b_m f_c (i cos(alpha))^0.7 Z^(2/3) D_w^1.4    (D_w > 25.4 mm)

    Source: ISO 281:2007, clause 6.1.1, Eqs. (1) and (2); f_c from Table 2 (``fc_radial_ball``),
    b_m = 1.3 (Table 1). Parameters: rows i, contact angle [deg], balls per row Z, ball diameter
    D_w [mm], pitch diameter D_pw [mm]. Returns C_r [N]. Validity: groove radii <= 0.52 D_w
    (inner) and 0.53 D_w (outer), the standard's."""
    cos_a = math.cos(math.radians(contact_angle_deg))
    fc = fc_radial_ball(diameter_mm * cos_a / pitch_diameter_mm)
    base = b_m * fc * (rows * cos_a) ** 0.7 * balls ** (2.0 / 3.0)
    return base * diameter_mm ** 1.8 if diameter_mm <= 25.4 else 3.647 * base * diameter_mm ** 1.4


def static_load_rating_radial_roller_n(rows: int, length_mm: float, contact_angle_deg: float, rollers: int,
                                       diameter_mm: float, pitch_diameter_mm: float) -> float:
    """Basic static radial load rating of a radial roller bearing:

        C_0r = 44 (1 - D_we cos(alpha) / D_pw) i Z L_we D_we cos(alpha)

    the load that gives 4000 MPa at the centre of the most heavily loaded roller/raceway contact
    (a permanent deformation of ~1e-4 D_we). Source: ISO 76:2006, clause 6.1.1, Eq. (3).
    Parameters as ``dynamic_load_rating_radial_roller_n``. Returns C_0r [N]."""
    cos_a = math.cos(math.radians(contact_angle_deg))
    return 44.0 * (1.0 - diameter_mm * cos_a / pitch_diameter_mm) * rows * rollers * length_mm * diameter_mm * cos_a


# --- ISO 281: life -------------------------------------------------------------------------------

@njit(cache=True)
def basic_rating_life_mrev(rating_n, load_n, exponent):
    """Basic rating life (90 % reliability): L10 = (C / P)^p [10^6 revolutions].

    Source: ISO 281:2007, clause 6.2 (balls, p = 3) and 7.2 (rollers, p = 10/3), Eqs. (3), (8).
    Parameters: C [N], P [N] (0: an unloaded bearing, infinite life), p [-]. Returns L10 [Mrev].
    Validity: P < C_0 and P <~ C / 2 (the standard's range of validity of the basic formula)."""
    if load_n <= 0.0:
        return np.inf
    return (rating_n / load_n) ** exponent


@njit(cache=True)
def life_hours(life_mrev, speed_rpm):
    """A life in revolutions as hours at a constant speed: L_h = 10^6 L / (60 n).

    Source: ISO 281:2007, clause 6.2 (the rating life in hours). Parameters: L [Mrev], n [r/min]
    (> 0). Returns L_h [h]."""
    return life_mrev * 1e6 / (60.0 * speed_rpm)


def equivalent_load_variable_n(loads_n, revolutions, exponent: float) -> float:
    """The constant load that gives the same life as a load varying in steps:

        P = (sum_i P_i^p N_i / sum_i N_i)^(1/p)

    (P_i acting for N_i revolutions; over a revolution at equal angle steps, the p-power mean).
    Source: ISO 281:2007, clause 7.4 / Annex (variable load: the equivalent mean load); Harris &
    Kotzalas 5th ed., the mean effective load. Parameters: loads P_i [N], revolutions N_i (any
    unit, weights), p = 10/3 rollers, 3 balls. Returns P [N]."""
    p = np.asarray(loads_n, float)
    w = np.broadcast_to(np.asarray(revolutions, float), p.shape)
    return float((np.sum(w * p ** exponent) / np.sum(w)) ** (1.0 / exponent))


def system_life(lives, slopes) -> float:
    """L10 of a system of bearings that fails with its first bearing (reliabilities multiply; each
    bearing's survival a two-parameter Weibull law through S = 0.9 at its L10):

        sum_i (L / L_i)^(e_i) = 1;   with one slope e:  L = (sum_i L_i^(-e))^(-1/e)

    Source: Lundberg & Palmgren, Acta Polytechnica Mech. Eng. Series 1(3) (1947) and 2(4) (1952):
    e = 10/9 for point contact (balls), 9/8 for line contact (rollers); Harris & Kotzalas, Rolling
    Bearing Analysis 5th ed. (2007), the life of a system of bearings. Parameters: L10 of each
    bearing (any unit; inf: never fails), its Weibull slope e_i. Returns the system's L10 (same
    unit; inf when every bearing is unloaded)."""
    life = np.asarray(lives, float)
    e = np.broadcast_to(np.asarray(slopes, float), life.shape)
    finite = np.isfinite(life)
    if not finite.any():
        return math.inf
    life, e = life[finite], e[finite]
    if np.all(e == e[0]):
        return float(np.sum(life ** -e[0]) ** (-1.0 / e[0]))
    from scipy.optimize import brentq

    hi = float(life.min())  # the system cannot outlive its weakest bearing; the root lies in (0, hi]
    return float(brentq(lambda x: float(np.sum((x / life) ** e)) - 1.0, hi * 1e-9, hi, xtol=1e-14 * hi,
                        rtol=1e-14))


@njit(cache=True)
def tapered_equivalent_load_n(radial_n, axial_n, contact_angle_deg):
    """Dynamic equivalent radial load of a single-row tapered roller bearing:

        P = F_r                    (F_a / F_r <= e),   e = 1.5 tan(alpha)
        P = 0.4 F_r + Y F_a        (F_a / F_r > e),    Y = 0.4 cot(alpha)

    Source: ISO 281:2007, clause 7.3.1, Table 8 (single-row radial roller bearings, alpha != 0).
    Parameters: F_r [N], F_a [N], alpha [deg]. Returns P [N]."""
    t = math.tan(math.radians(contact_angle_deg))
    if radial_n <= 0.0 or axial_n <= 1.5 * t * radial_n:
        return radial_n if radial_n > 0.0 else 0.4 * axial_n / t
    return 0.4 * radial_n + 0.4 / t * axial_n


@njit(cache=True)
def tapered_pair_axial_loads_n(radial_a_n, radial_b_n, contact_angle_deg, external_axial_n):
    """(F_a,A, F_a,B) of two tapered roller bearings mounted face to face (or back to back) and
    set line to line: each radial load induces an axial force 0.5 F_r / Y (Y = 0.4 cot(alpha));
    the external axial load K_a acts towards bearing B. If 0.5 F_rA / Y + K_a >= 0.5 F_rB / Y:
    F_aB = 0.5 F_rA / Y + K_a, F_aA = 0.5 F_rA / Y; else F_aA = 0.5 F_rB / Y - K_a, F_aB =
    0.5 F_rB / Y.

    Source: the makers' rule for adjusted tapered roller pairs (Timken, SKF and NTN catalogues:
    "axial load factors of paired tapered roller bearings"), with ISO 281's Y = 0.4 cot(alpha);
    Harris & Kotzalas 5th ed., induced thrust of tapered bearings. Parameters: F_rA, F_rB [N],
    alpha [deg], K_a [N]. Returns (F_aA, F_aB) [N]. Validity: zero end play, no preload."""
    y = 0.4 / math.tan(math.radians(contact_angle_deg))
    ia, ib = 0.5 * radial_a_n / y, 0.5 * radial_b_n / y
    if ia + external_axial_n >= ib:
        return ia, ia + external_axial_n
    return ib - external_axial_n, ib


def makers_reducer_life_h(rated_life_h: float, rated_speed_rpm: float, speed_rpm: float, rated_torque_nm: float,
                          torque_nm: float) -> float:
    """The reducer makers' life formula: L_h = K (N_0 / N_m) (T_0 / T_m)^(10/3), the rated life K
    at the rated torque T_0 and rated output speed N_0 scaled to a mean torque T_m and speed N_m
    (the roller bearings' L10 = (C/P)^(10/3) with P proportional to the torque).

    Source: the RV reducers' selection procedure (Nabtesco RV-E catalogue, "life"; as quoted in
    ../shared/reference/anchors.md, unverified against the catalogue's text). Parameters: K [h],
    N_0 [r/min], N_m [r/min], T_0 [N m], T_m [N m]. Returns L_h [h]."""
    return rated_life_h * rated_speed_rpm / speed_rpm * (rated_torque_nm / torque_nm) ** ROLLER_LIFE_EXPONENT


# --- ISO/TS 16281: rating life from the internal load distribution (roller bearings) -------------

def iso16281_raceway_ratings_n(rating_n: float, rollers: int, gamma: float, rows: int = 1,
                               contact_angle_deg: float = 0.0,
                               lambda_nu: float = ISO16281_LAMBDA_NU) -> tuple[float, float]:
    """(Q_ci, Q_ce): the roller load for the basic dynamic load rating of the inner and of the outer
    raceway of a radial roller bearing:

        Q_ci = C / (lambda nu 0.378 Z cos(alpha) i^(7/9)) [1 + (1.038 ((1 - g)/(1 + g))^(143/108))^(9/2)]^(2/9)
        Q_ce = C / (lambda nu 0.364 Z cos(alpha) i^(7/9)) [1 + (1.038 ((1 - g)/(1 + g))^(143/108))^(-9/2)]^(2/9)

    Source: ISO/TS 16281:2008, Eqs. (47)-(50) as numbered in a public implementation (lambda nu =
    0.83 for radial roller bearings). Parameters: C [N] (ISO 281's rating of the bearing), Z, gamma
    = D_we cos(alpha) / D_pw, rows i, alpha [deg]. Returns (Q_ci, Q_ce) [N]."""
    ratio = (1.038 * ((1.0 - gamma) / (1.0 + gamma)) ** (143.0 / 108.0)) ** 4.5
    base = rating_n / (lambda_nu * rollers * math.cos(math.radians(contact_angle_deg)) * rows ** (7.0 / 9.0))
    return (base / 0.378 * (1.0 + ratio) ** (2.0 / 9.0), base / 0.364 * (1.0 + 1.0 / ratio) ** (2.0 / 9.0))


@njit(cache=True)
def iso16281_lamina_rating_n(raceway_rating_n, slices):
    """Basic dynamic load rating of one lamina (slice) of a raceway: q_c = Q_c (1 / n_s)^(7/9).

    Source: ISO/TS 16281:2008, Eqs. (51)-(52) (public implementation's numbering). Parameters: Q_c
    [N] (``iso16281_raceway_ratings_n``), n_s [-]. Returns q_c [N]."""
    return raceway_rating_n * (1.0 / slices) ** (7.0 / 9.0)


@njit(cache=True)
def iso16281_equivalent_lamina_load_n(lamina_loads_n, rotating):
    """Dynamic equivalent load of a lamina of a raceway over the Z rollers that pass it:

        q_e = (sum_j q_j^4 / Z)^(1/4)        raceway rotating relative to the load
        q_e = (sum_j q_j^4.5 / Z)^(1/4.5)    raceway stationary relative to the load

    Source: ISO/TS 16281:2008, Eqs. (61)-(64) (public implementation's numbering). Parameters:
    the lamina's load on each roller q_j [N], rotating. Returns q_e [N]."""
    p = 4.0 if rotating else 4.5
    s = 0.0
    for q in lamina_loads_n:
        if q > 0.0:
            s += q ** p
    return (s / lamina_loads_n.size) ** (1.0 / p)


@njit(cache=True)
def iso16281_reference_life_mrev(inner_equivalent_n, outer_equivalent_n, inner_lamina_rating_n,
                                 outer_lamina_rating_n):
    """Basic reference rating life of a roller bearing from its laminae:

        L_10r = (sum_k [(q_ei,k / q_ci)^(9/2) + (q_ee,k / q_ce)^(9/2)])^(-8/9)

    Source: ISO/TS 16281:2008, Eq. (65) (public implementation's numbering). Parameters: each
    lamina's equivalent load on the inner and the outer raceway [N] (arrays over the laminae),
    the laminae's ratings q_ci, q_ce [N]. Returns L_10r [Mrev] (inf: unloaded)."""
    s = 0.0
    for k in range(inner_equivalent_n.size):
        s += (inner_equivalent_n[k] / inner_lamina_rating_n) ** 4.5 + (outer_equivalent_n[k] / outer_lamina_rating_n) ** 4.5
    if s <= 0.0:
        return np.inf
    return s ** (-8.0 / 9.0)


@njit(cache=True)
def iso16281_lamina_load_n(approach_um, stiffness_n_per_mm, slices):
    """Load of one lamina of a roller closed by delta [um] (ISO/TS 16281's roller-raceway constant:
    both contacts in series): q = (c_l / n_s) delta^(10/9), delta [mm]; 0 when open.

    Source: ISO/TS 16281:2008, the lamina's load-deflection relation (c_l = 35948 L_we^(8/9),
    ``compliance.iso_roller_constant_n_per_mm``). Parameters: delta [um], c_l [N/mm^(10/9)],
    n_s. Returns q [N]."""
    if approach_um <= 0.0:
        return 0.0
    return stiffness_n_per_mm / slices * (approach_um * 1e-3) ** (10.0 / 9.0)


# --- Hertz contact ---------------------------------------------------------------------------------

@njit(cache=True)
def line_contact_peak_pressure_from_load_mpa(force_n, length_mm, relative_radius_mm, e_star_n_per_mm2):
    """Peak Hertz pressure of a line contact: p0 = sqrt(P E* / (pi R)), P = F / L.

    Source: Johnson, Contact Mechanics (1985), ch. 4 (p0 = 2P/(pi a), a = sqrt(4 P R / (pi E*))),
    ``compliance.line_contact_peak_pressure_mpa`` with its half-width. Parameters: F [N], L [mm],
    relative radius R [mm], E* [MPa]. Returns p0 [MPa]. Validity: a << R, uniform along L."""
    if force_n <= 0.0:
        return 0.0
    return math.sqrt(force_n / length_mm * e_star_n_per_mm2 / (math.pi * relative_radius_mm))


def hertz_point_contact(force_n: float, curvature_sum_per_mm: float, curvature_difference: float,
                        e_star_n_per_mm2: float) -> tuple[float, float, float, float]:
    """(a, b, p0, delta): semi-axes [mm], peak pressure [MPa] and approach [mm] of a Hertz point
    (elliptical) contact:

        F(rho) = ((kappa^2 + 1) E(e) - 2 K(e)) / ((kappa^2 - 1) E(e)),  e^2 = 1 - 1/kappa^2   (solved for kappa)
        a = (6 kappa^2 E Q / (pi sum(rho) E'))^(1/3),   b = a / kappa,   p0 = 3 Q / (2 pi a b)
        delta = K (9 / (2 E)) ... = (2 K / pi) (9 sum(rho) / (2 E)) ^(1/3) (Q / (pi kappa E'))^(2/3)

    with E' = 2 E* (E* the contact modulus ``compliance.contact_modulus_n_per_mm2``), K, E the
    complete elliptic integrals of the first and second kind. Source: Harris & Kotzalas, Rolling
    Bearing Analysis 5th ed. (2007), vol. 1, ch. 6 (point contact: Eqs. 6.26-6.40 as we read them;
    Hamrock & Brewe's form); Johnson (1985), ch. 4. Parameters: Q [N], sum(rho) [1/mm], F(rho) [-]
    (0: a circle), E* [MPa]. Validity: elastic, the contact small against the radii."""
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    if curvature_difference <= 1e-12:
        kappa, kk, ee = 1.0, math.pi / 2, math.pi / 2
    else:
        def f(k):
            m = 1.0 - 1.0 / (k * k)
            return ((k * k + 1.0) * ellipe(m) - 2.0 * ellipk(m)) / ((k * k - 1.0) * ellipe(m)) - curvature_difference

        kappa = brentq(f, 1.0 + 1e-9, 1e4, xtol=1e-14)
        m = 1.0 - 1.0 / (kappa * kappa)
        kk, ee = float(ellipk(m)), float(ellipe(m))
    e_prime = 2.0 * e_star_n_per_mm2
    a = (6.0 * kappa * kappa * ee * force_n / (math.pi * curvature_sum_per_mm * e_prime)) ** (1.0 / 3.0)
    b = a / kappa
    p0 = 3.0 * force_n / (2.0 * math.pi * a * b)
    delta = kk * (9.0 / (2.0 * ee * (1.0 / curvature_sum_per_mm)) * (force_n / (math.pi * kappa * e_prime)) ** 2) \
        ** (1.0 / 3.0)
    return float(a), float(b), float(p0), float(delta)


def ball_raceway_curvatures(ball_diameter_mm: float, groove_ratio: float, gamma: float,
                            inner: bool) -> tuple[float, float]:
    """(sum(rho) [1/mm], F(rho) [-]) of a ball on the inner or the outer raceway of a groove:

        inner: sum(rho) = (1/D) (4 - 1/f_i + 2 g/(1 - g)),   F(rho) = (1/f_i + 2 g/(1 - g)) / (4 - 1/f_i + 2 g/(1 - g))
        outer: sum(rho) = (1/D) (4 - 1/f_e - 2 g/(1 + g)),   F(rho) = (1/f_e - 2 g/(1 + g)) / (4 - 1/f_e - 2 g/(1 + g))

    (f = groove radius / D, g = D cos(alpha) / D_pw). Source: Harris & Kotzalas 5th ed., vol. 1,
    ch. 2 (curvature sum and difference of ball bearings, Eqs. 2.27-2.32 as we read them).
    Parameters: D [mm], f [-], g [-], inner. Returns (sum(rho), F(rho))."""
    if inner:
        s = 4.0 - 1.0 / groove_ratio + 2.0 * gamma / (1.0 - gamma)
        return s / ball_diameter_mm, (1.0 / groove_ratio + 2.0 * gamma / (1.0 - gamma)) / s
    s = 4.0 - 1.0 / groove_ratio - 2.0 * gamma / (1.0 + gamma)
    return s / ball_diameter_mm, (1.0 / groove_ratio - 2.0 * gamma / (1.0 + gamma)) / s
