"""Compliance formulas of the elastic hysteresis model (docs/elastic.md), one function per formula.

Units: forces [N], lengths [mm], moduli [N/mm^2] (= MPa) unless a name says otherwise,
approaches [um], torques [N m], angles [rad]. The scalar formulas are compiled with numba
(``njit``) so that the Monte-Carlo kernel (``models/elastic/``) runs exactly the functions the
tests check; they are callable from Python with plain floats.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit

PALMGREN_COEFFICIENT = 3.84e-5  # [mm N^-0.9 mm^0.8] of Palmgren's roller formula
PALMGREN_EXPONENT = 0.9
RELATIVE_RADIUS_CAP = 10.0  # near-conformal contacts: relative radius capped at 10 pin radii (validity)


# --- Hertz line contact (Johnson, Contact Mechanics, Cambridge University Press 1985, ch. 4) ----

class Body(NamedTuple):
    """One of two cylinders in line contact: its radius R [mm] (for a concave or non-circular body:
    the depth to which its displacement is referred, see docs/elastic.md), Young's modulus [GPa],
    Poisson's ratio [-]."""

    radius_mm: float
    youngs_modulus_gpa: float
    poisson_ratio: float


@njit(cache=True)
def contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2):
    """Contact modulus E* of two elastic bodies: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.

    Source: Johnson, Contact Mechanics (1985), ch. 4 (Hertz theory), the combined modulus of
    Eq. (4.22) [equation number as we read it; unverified].
    Parameters: e1_gpa, e2_gpa Young's moduli [GPa]; nu1, nu2 Poisson's ratios [-].
    Returns E* [N/mm^2]. Validity: linear elastic, isotropic bodies.
    """
    return 1.0 / ((1.0 - nu1 * nu1) / (e1_gpa * 1e3) + (1.0 - nu2 * nu2) / (e2_gpa * 1e3))


@njit(cache=True)
def relative_radius_mm(r1_mm, r2_mm):
    """Relative radius of curvature of two cylinders in line contact: 1/R = 1/R1 + 1/R2.

    Signed radii: convex > 0, concave < 0 (a pin in a concave flank or a roller in a bore).
    Source: Johnson (1985), ch. 4, two-dimensional contact of cylindrical bodies.
    Parameters: r1_mm, r2_mm [mm] (either may be inf: a flat). Returns R [mm]; inf (or a negative
    value) when the curvatures cancel or cross: conformal contact, outside Hertz theory. Callers
    cap it (``capped_relative_radius_mm``).
    """
    c = 1.0 / r1_mm + 1.0 / r2_mm
    return 1.0 / c if c != 0.0 else math.inf


@njit(cache=True)
def capped_relative_radius_mm(r1_mm, r2_mm, cap_mm):
    """The relative radius, limited to ``cap_mm`` where the contact is near-conformal or worse.

    Hertz theory needs the contact half-width small against the radii; a concave flank that
    nearly fits the pin breaks that. Pins there carry little torque (small lever arm), so the cap
    only bounds their stiffness. Parameters [mm]. Returns [mm].
    """
    r = relative_radius_mm(r1_mm, r2_mm)
    if not (r > 0.0) or r > cap_mm:
        return cap_mm
    return r


@njit(cache=True)
def line_contact_half_width_mm(force_n, length_mm, radius_mm, e_star_n_per_mm2):
    """Half-width of a Hertz line contact: a = sqrt(4 P R / (pi E*)), P = F / L.

    Source: Johnson, Contact Mechanics (1985), ch. 4, Eq. (4.43) [numbering unverified]; the same
    as Roark's b = 1.60 sqrt(p K_D C_E) for the full width (Young & Budynas, Roark's Formulas for
    Stress and Strain, 7th ed., Table 14.1, cylinders).
    Parameters: force_n F [N], length_mm L [mm], radius_mm relative radius R [mm],
    e_star_n_per_mm2 E* [N/mm^2]. Returns a [mm]. Validity: a << R, uniform load along L.
    """
    return math.sqrt(4.0 * force_n * radius_mm / (math.pi * length_mm * e_star_n_per_mm2))


@njit(cache=True)
def line_contact_peak_pressure_mpa(force_n, length_mm, half_width_mm):
    """Peak Hertz pressure of a line contact: p0 = 2 P / (pi a), P = F / L.

    Source: Johnson (1985), ch. 4, Eq. (4.44) [numbering unverified]; Roark's sigma_max =
    0.798 sqrt(p / (K_D C_E)) (7th ed., Table 14.1). Parameters: F [N], L [mm], a [mm].
    Returns p0 [MPa]."""
    return 2.0 * force_n / (math.pi * length_mm * half_width_mm)


@njit(cache=True)
def johnson_line_approach_um(force_n, length_mm, body1, body2, relative_radius):
    """Elastic approach of two cylinders in line contact (distance between their axes):

        delta = (2 P / pi) sum_k (1 - nu_k^2)/E_k (ln(4 R_k / a) - 1/2),  P = F / L,
        a = sqrt(4 P R / (pi E*))

    Source: Johnson, Contact Mechanics (1985), ch. 4, the compression of two cylinders in line
    contact (section 4.3, Eq. (4.45) [numbering unverified]); ../shared/reference/anchors.md.
    Parameters: force_n F [N]; length_mm L [mm]; the two bodies (``Body``: R_k [mm], Young's modulus
    [GPa], Poisson's ratio [-]); relative_radius R [mm]. Returns delta [um].
    Validity: a << R_k (the log stays > 1/2), elastic, no edge effects along L.
    """
    body1_radius_mm, e1_gpa, nu1 = body1.radius_mm, body1.youngs_modulus_gpa, body1.poisson_ratio
    body2_radius_mm, e2_gpa, nu2 = body2.radius_mm, body2.youngs_modulus_gpa, body2.poisson_ratio
    e_star = contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2)
    a = line_contact_half_width_mm(force_n, length_mm, relative_radius, e_star)
    p = force_n / length_mm
    c1 = (1.0 - nu1 * nu1) / (e1_gpa * 1e3)
    c2 = (1.0 - nu2 * nu2) / (e2_gpa * 1e3)
    s = c1 * (math.log(4.0 * body1_radius_mm / a) - 0.5) + c2 * (math.log(4.0 * body2_radius_mm / a) - 0.5)
    return 2.0 * p / math.pi * s * 1e3


@njit(cache=True)
def johnson_law_a_um_per_n(length_mm, body1, body2, relative_radius):
    """Coefficient a of Johnson's approach written as delta = F (a - b ln F) [um, N].

    Expanding ln(4 R_k / a) with a^2 = 4 F R / (pi L E*) in ``johnson_line_approach_um``:
        a = (2 / (pi L)) [sum_k c_k (ln(4 R_k) - 1/2) - ln(4 R / (pi L E*)) / (2 E*)],  c_k = (1 - nu_k^2)/E_k
    (the same formula, rearranged so that the kernel can invert it). Parameters as
    ``johnson_line_approach_um``. Returns a [um/N].
    """
    body1_radius_mm, e1_gpa, nu1 = body1.radius_mm, body1.youngs_modulus_gpa, body1.poisson_ratio
    body2_radius_mm, e2_gpa, nu2 = body2.radius_mm, body2.youngs_modulus_gpa, body2.poisson_ratio
    e_star = contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2)
    c1 = (1.0 - nu1 * nu1) / (e1_gpa * 1e3)
    c2 = (1.0 - nu2 * nu2) / (e2_gpa * 1e3)
    s = c1 * (math.log(4.0 * body1_radius_mm) - 0.5) + c2 * (math.log(4.0 * body2_radius_mm) - 0.5)
    s -= math.log(4.0 * relative_radius / (math.pi * length_mm * e_star)) / (2.0 * e_star)
    return 2.0 / (math.pi * length_mm) * s * 1e3


@njit(cache=True)
def johnson_law_b_um_per_n(length_mm, e1_gpa, nu1, e2_gpa, nu2):
    """Coefficient b of Johnson's approach delta = F (a - b ln F): b = 1 / (pi L E*) [um/N].

    Source: ``johnson_line_approach_um`` rearranged. Parameters: L [mm], moduli [GPa], ratios [-]."""
    return 1e3 / (math.pi * length_mm * contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2))


@njit(cache=True)
def pin_seat_law_a_um_per_n(length_mm, pin, housing):
    """Coefficient a of the pin's seat in its housing groove, written as delta = F (a - b ln F) [um, N]
    (b: ``johnson_law_b_um_per_n`` of the pin's and the housing's materials).

    A pin pressed into the semicircular groove that holds it is a conforming line contact (a
    cylinder in a cylindrical seat of nearly its own radius: Johnson, Contact Mechanics (1985),
    ch. 4 and §5.3 on conforming contacts; Persson's pin-in-hole solution). Hertz's approach
    (``johnson_law_a_um_per_n``) needs the contact small against the radii; in a seat of the pin's
    own radius the relative radius R = r_pin r_seat / (r_seat - r_pin) is unbounded, so it is capped at
    RELATIVE_RADIUS_CAP pin radii as for near-conformal flanks (for rv80e's 4 mm pins: R = 40 mm,
    half-width 0.27 mm at 2 kN over 12 mm, a / r_pin = 0.07). A truly conforming seat spreads the
    load wider than that, so this approach errs on the soft side (logarithmically). The bodies'
    radii in the log: the pin's and the groove's (= the pin's).
    Parameters: length_mm L [mm] (the seat behind one disc: the flank's contact length); pin, housing
    (``Body``: radius [mm], E [GPa], nu). Returns a [um/N].
    Validity: a << r_pin (holds to ~10 kN per 12 mm for 4 mm pins); a clearance in the groove wider
    than the cap's conformity (c > 2 r_pin / (RELATIVE_RADIUS_CAP + 1)) is not modelled.
    """
    return johnson_law_a_um_per_n(length_mm, pin, housing, RELATIVE_RADIUS_CAP * pin.radius_mm)


@njit(cache=True)
def palmgren_line_approach_um(force_n, length_mm):
    """Palmgren's approach of a steel roller on a steel raceway: delta = 3.84e-5 Q^0.9 / L^0.8 [mm].

    Source: Palmgren, Ball and Roller Bearing Engineering (SKF, 3rd ed. 1959), as given by Harris &
    Kotzalas, Rolling Bearing Analysis (5th ed., 2007), the roller-raceway line contact
    [equation number unverified]; ../shared/reference/anchors.md.
    Parameters: force_n Q [N], length_mm effective length L [mm]. Returns delta [um] for ONE
    contact. Validity: steel on steel (E ~ 207 GPa), ignores the radii; agrees with Johnson's
    approach within tens of per cent for bearing geometries (tests/models/test_elastic.py).
    """
    return PALMGREN_COEFFICIENT * force_n ** PALMGREN_EXPONENT / length_mm ** 0.8 * 1e3


@njit(cache=True)
def palmgren_law_a(length_mm):
    """Coefficient a of Palmgren's approach written as delta = a Q^0.9 [um, N]: a = 3.84e-2 / L^0.8."""
    return PALMGREN_COEFFICIENT / length_mm ** 0.8 * 1e3


@njit(cache=True)
def law_approach_um(force_n, a, b, n):
    """The contact law every contact of the kernel uses: delta = F^n (a - b ln F) [um].

    Johnson: n = 1 and (a, b) from ``johnson_law_a_um_per_n`` / ``johnson_law_b_um_per_n``;
    Palmgren: n = 0.9, b = 0, a = ``palmgren_law_a``. Two contacts in series (a roller between
    two raceways) add their a's and b's. F > 0 [N]; returns [um]."""
    scale = force_n if n == 1.0 else force_n ** n  # the same number; the power is a libm call
    return scale * (a - b * math.log(force_n))


@njit(cache=True)
def law_approach_continued_um(force_n, a, b, n):
    """``law_approach_um`` as the elastic solver reads it (``models.elastic.law_step``): Johnson's
    formula stops increasing at ln F = a/b - 1, so beyond F_lim = exp(a/b - 2), where
    d(delta)/dF = b, it is continued by that tangent, delta = 2 b F_lim + b (F - F_lim); increasing
    in F for every F > 0 (a bound built on it stays a bound). Palmgren (b = 0): the law itself.
    F > 0 [N]; returns [um]."""
    ln_f = math.log(force_n)
    if b > 0.0 and ln_f > a / b - 2.0:
        f_lim = math.exp(a / b - 2.0)
        return 2.0 * b * f_lim + b * (force_n - f_lim)
    scale = force_n if n == 1.0 else force_n ** n
    return scale * (a - b * ln_f)  # law_approach_um with the logarithm taken once


# --- the pin-centre curve and the disc flank --------------------------------------------------

@njit(cache=True)
def pin_centre_curve_radius_mm(phi_rad, pin_circle_radius_mm, k1, pins):
    """Signed radius of curvature of the pin-centre curve C at the pin with phase phi:

        rho_C = r_p S^(3/2) / (1 + z_p K1^2 - (z_p + 1) K1 cos phi),   S = 1 + K1^2 - 2 K1 cos phi

    positive where C bends around the disc centre (convex flank). Derivation: C(t) = r_p e^(i t/z_c)
    - a e^(i t (1 + 1/z_c)) (geometry/cycloid.py) gives |C'| z_c = r_p sqrt(S) and
    (C' x C'') z_c^3 = r_p^2 (1 + z_p K1^2 - (z_p + 1) K1 cos t); a pin at phase phi sits at
    t = -phi. The same curvature as standard cycloid-drive theory (e.g. Litvin & Fuentes, Gear
    Geometry and Applied Theory, 2nd ed. 2004, ch. on cycloidal gearing), sign convention ours.
    Parameters: phi [rad], r_p [mm], K1 [-], z_p [-]. Returns rho_C [mm] (inf at an inflection).
    """
    c = math.cos(phi_rad)
    s = 1.0 + k1 * k1 - 2.0 * k1 * c
    den = 1.0 + pins * k1 * k1 - (pins + 1.0) * k1 * c
    if den == 0.0:
        return math.inf
    return pin_circle_radius_mm * s ** 1.5 / den


@njit(cache=True)
def flank_radius_mm(curve_radius_mm, generating_radius_mm):
    """Signed radius of curvature of the disc flank: rho = rho_C - r_g.

    The flank is C offset towards the disc by the generating pin radius r_g = r_rp + dr_rp
    (geometry/cycloid.py). An inward offset shortens a convex radius and lengthens a concave
    one by r_g: in signed form both are rho_C - r_g. Parameters [mm]. Returns [mm] (convex > 0).
    Validity: no undercut (rho_C > r_g where C is convex; the design schema checks it)."""
    return curve_radius_mm - generating_radius_mm


# --- the involute stage, kinematics, stiffness algebra ----------------------------------------

def mesh_torsional_stiffness_nm_per_rad(c_gamma_n_per_mm_um: float, face_width_mm: float, centre_gear_radius_mm: float,
                                        ratio: float, planets: int, pressure_angle_deg: float) -> float:
    """Stiffness of the involute stage referred to the output, input locked:

        K_1 = i^2 r_1^2 n b c_gamma cos^2(alpha)

    The mesh stiffness c_gamma (ISO 6336-1:2019, 9 / DIN 3990-1: load per face width along the
    line of action per um of deflection there) gives a circumferential deflection at the pitch
    circle F_t / (b c_gamma cos^2 alpha); each of the n planets carries F_t = T / (i r_1 n); the
    output turns by that deflection over i r_1 (Eq. (1)'s stage-1 lever arm, exact: docs/model.md).
    Parameters: c_gamma [N/(mm um)], face width b [mm], centre-gear pitch radius r_1 [mm], ratio i
    [-], planets n [-], pressure angle [deg]. Returns K_1 [N m/rad]. Validity: spur gears, load
    shared equally by the planets, constant mesh stiffness (no contact-ratio ripple).
    """
    c = c_gamma_n_per_mm_um * 1e3  # N/mm^2
    cos_a = math.cos(math.radians(pressure_angle_deg))
    return ratio ** 2 * centre_gear_radius_mm ** 2 * planets * face_width_mm * c * cos_a ** 2 * 1e-3


def cycloid_lever_factor(cycloid_teeth: int, pins: int, centre_gear_teeth: int, planet_teeth: int,
                         kinematic: bool = True) -> float:
    """Output rotation per disc rotation about its own centre, input locked:

        k = z_c / (z_p + z1/z2)   (kinematic),   k = 1 (Eq. (1): the lever arm a z_c)

    With the centre gear locked the cranks turn (z1/z2) theta relative to the carrier when the
    output turns theta; the normal displacement at pin j is then a (z_p + z1/z2) theta sin(phi) /
    sqrt(S) against a z_c beta sin(phi)/sqrt(S) for a disc rotation beta (docs/model.md, "Stage
    2"). So a disc-rotation play or deflection beta shows at the output as k beta, and the pins'
    lever arms referred to the output are L_j / k. The same factor refers the crank-bearing
    rotation of the disc relative to the carrier. Parameters: tooth counts [-]. Returns k [-].
    Example: RV-80E class 39 / (40 + 10/38) = 0.9687.
    """
    if not kinematic:
        return 1.0
    return cycloid_teeth / (pins + centre_gear_teeth / planet_teeth)


def series_stiffness(*stiffnesses: float) -> float:
    """Springs in series: 1/K = sum 1/K_i (inf = rigid, ignored). Any consistent unit."""
    inv = sum(1.0 / k for k in stiffnesses if math.isfinite(k))
    return 1.0 / inv if inv > 0 else math.inf


def parallel_stiffness(*stiffnesses: float) -> float:
    """Springs in parallel: K = sum K_i. Any consistent unit."""
    return float(sum(stiffnesses))


# --- friction: the branches of the loop -------------------------------------------------------

@njit(cache=True)
def elastic_torque_nm(torque_nm, increasing, friction_nm, friction_fraction):
    """Torque carried by the elastic chain on a branch of the loop, Coulomb friction at the output:

        theta increasing:  T = T_el + T_f0 + mu |T_el|,   theta decreasing:  T = T_el - T_f0 - mu |T_el|

    (friction opposes the motion; a friction element in parallel with the whole chain, referred to
    the output). Solved for T_el piecewise (it is monotone in T_el for mu < 1).
    Source: the Coulomb friction model (e.g. Armstrong-Helouvry, Dupont & Canudas de Wit,
    Automatica 30 (1994) 1083, static + Coulomb terms); its application here is ours (docs/elastic.md).
    Parameters: torque_nm T [N m], increasing (theta increasing on this branch), friction_nm T_f0
    [N m], friction_fraction mu [-]. Returns T_el [N m]. With T_f0 = mu = 0, T_el = T: the
    branches coincide.
    """
    if increasing:
        if torque_nm >= friction_nm:
            return (torque_nm - friction_nm) / (1.0 + friction_fraction)
        return (torque_nm - friction_nm) / (1.0 - friction_fraction)
    if torque_nm <= -friction_nm:
        return (torque_nm + friction_nm) / (1.0 + friction_fraction)
    return (torque_nm + friction_nm) / (1.0 - friction_fraction)


@njit(cache=True)
def applied_torque_nm(elastic_nm, increasing, friction_nm, friction_fraction):
    """Inverse of ``elastic_torque_nm``: the applied torque that holds T_el on a branch [N m]."""
    if increasing:
        return elastic_nm + friction_nm + friction_fraction * abs(elastic_nm)
    return elastic_nm - friction_nm - friction_fraction * abs(elastic_nm)


# --- the rest of the torque path: crankshafts, support bearings, carrier, disc translation ------
# (docs/elastic.md, "The whole torque path"). Lengths [mm], forces [N], moduli [GPa] as named,
# compliances [um/N] unless a name says otherwise.

def shear_modulus_gpa(e_gpa: float, nu: float) -> float:
    """Shear modulus of an isotropic material: G = E / (2 (1 + nu)).

    Source: any strength-of-materials text (e.g. Timoshenko & Goodier, Theory of Elasticity, 3rd
    ed. 1970, Eq. (6)). Parameters: e_gpa E [GPa], nu Poisson's ratio [-]. Returns G [GPa]."""
    return e_gpa / (2.0 * (1.0 + nu))


def circular_shear_coefficient(nu: float) -> float:
    """Timoshenko's shear coefficient of a solid circular section: kappa = 6 (1 + nu) / (7 + 6 nu).

    Source: Cowper, "The shear coefficient in Timoshenko's beam theory", J. Appl. Mech. 33 (1966)
    335, Table 1 (solid circle). Parameters: nu [-]. Returns kappa [-] (0.886 for nu = 0.3)."""
    return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)


def rectangular_shear_coefficient(nu: float) -> float:
    """Timoshenko's shear coefficient of a rectangular section: kappa = 10 (1 + nu) / (12 + 11 nu).

    Source: Cowper (1966), Table 1 (rectangle). Parameters: nu [-]. Returns kappa [-] (0.850 for
    nu = 0.3)."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


def crank_symmetric_deflection_um_per_n(span_mm: float, load_offset_mm: float, diameter_mm: float,
                                        e_gpa: float, nu: float) -> float:
    """Deflection under either load of a simply supported crankshaft carrying two equal loads in the
    same direction, symmetric about mid-span (the two discs' torque forces on one crank):

        delta / P = c^2 (3 L - 4 c) / (6 E I) + c / (kappa G A),   I = pi d^4 / 64,  A = pi d^2 / 4

    Source: Young & Budynas, Roark's Formulas for Stress and Strain, 7th ed. (2002), Table 8.1 case
    1e (simple supports, load at a; two loads superposed), shear term of Timoshenko beam theory
    (Timoshenko & Gere, Mechanics of Materials; Cowper's kappa). Parameters: span_mm L between the
    support bearings' load centres [mm]; load_offset_mm c from each support to the load [mm];
    diameter_mm d of an equivalent solid round section [mm]; e_gpa [GPa]; nu [-]. Returns [um/N].
    Validity: 0 < c <= L/2, slender enough for beam theory (L/d > ~1; the shear term covers stubby
    shafts approximately), supports radially rigid (their compliance is the support bearings'), no
    journal or eccentric steps (d is an equivalent diameter)."""
    e = e_gpa * 1e3
    inertia = math.pi * diameter_mm ** 4 / 64.0
    area = math.pi * diameter_mm ** 2 / 4.0
    g = shear_modulus_gpa(e_gpa, nu) * 1e3
    c, span = load_offset_mm, span_mm
    return (c * c * (3.0 * span - 4.0 * c) / (6.0 * e * inertia) + c / (circular_shear_coefficient(nu) * g * area)) * 1e3


def crank_antisymmetric_deflection_um_per_n(span_mm: float, load_offset_mm: float, diameter_mm: float,
                                            e_gpa: float, nu: float) -> float:
    """Deflection under either load of a simply supported crankshaft carrying two equal, opposite
    loads symmetric about mid-span (the two discs' radial forces, 180 degrees apart):

        delta / P = c^2 (L - 2 c)^2 / (6 E I L) + c (L - 2 c) / (kappa G A L)

    Source: Roark (7th ed.), Table 8.1 case 1e superposed (deflection at x = c of a load at c minus
    that of a load at L - c: c^2 (L-c)^2 / (3 E I L) - c^2 (L^2 - 2 c^2) / (6 E I L)); the shear
    term from the shear force P (L - 2 c) / L between support and load. Parameters and validity as
    ``crank_symmetric_deflection_um_per_n``. Returns [um/N]."""
    e = e_gpa * 1e3
    inertia = math.pi * diameter_mm ** 4 / 64.0
    area = math.pi * diameter_mm ** 2 / 4.0
    g = shear_modulus_gpa(e_gpa, nu) * 1e3
    c, span = load_offset_mm, span_mm
    bend = c * c * (span - 2.0 * c) ** 2 / (6.0 * e * inertia * span)
    shear = c * (span - 2.0 * c) / (circular_shear_coefficient(nu) * g * area * span)
    return (bend + shear) * 1e3


def shaft_torsion_compliance_rad_per_nm(length_mm: float, diameter_mm: float, e_gpa: float, nu: float) -> float:
    """Twist of a solid round shaft per unit torque: phi / T = L / (G J),  J = pi d^4 / 32.

    Source: Roark (7th ed.), Table 10.1 case 1 (solid circular section). Parameters: length_mm L
    [mm], diameter_mm d [mm], e_gpa [GPa], nu [-]. Returns [rad/(N m)]. Validity: uniform
    section, free warping (exact for a circle), elastic."""
    g = shear_modulus_gpa(e_gpa, nu) * 1e3  # N/mm^2
    return length_mm / (g * math.pi * diameter_mm ** 4 / 32.0) * 1e3


def crank_torsion_output_compliance_rad_per_nm(twist_rad_per_nm: float, planet_radius_mm: float,
                                               centre_gear_radius_mm: float, ratio: float, planets: int) -> float:
    """Output compliance of the cranks' torsion, input locked:

        C = (r_2 / (i r_1))^2 (L / (G J)) / n

    Each of the n planets carries F_t = T / (i r_1 n) (``mesh_torsional_stiffness_nm_per_rad``), so
    each crank carries the torque F_t r_2 between its planet gear and its eccentrics; a twist phi of
    a crank turns the output by phi r_2 / (i r_1) (virtual work: n F_t r_2 phi = T theta). Source:
    ours (the lever arms of Eq. (1), docs/model.md); the twist from
    ``shaft_torsion_compliance_rad_per_nm``. Parameters: twist per torque [rad/(N m)], pitch radii
    r_2 (planet), r_1 (centre gear) [mm], ratio i [-], planets n [-]. Returns [rad/(N m)] at the
    output. Validity: equal load sharing of the planets."""
    lever = planet_radius_mm / (ratio * centre_gear_radius_mm)
    return lever * lever * twist_rad_per_nm / planets


def tangential_output_compliance_rad_per_nm(deflection_um_per_n: float, lever_factor: float, bearings: int,
                                            crank_circle_radius_mm: float) -> float:
    """Output compliance of an element that yields tangentially at the cranks, loaded like the crank
    needle bearings (each of the n_b = discs x cranks load points carries F = T k / (n_b a0)):

        C = k^2 c / (n_b a0^2)

    A tangential deflection delta = c F at every crank turns the discs by delta / a0 against the
    carrier, the output by k delta / a0 (``cycloid_lever_factor``); virtual work gives the same.
    Source: ours (docs/elastic.md). Parameters: deflection_um_per_n c [um/N], lever_factor k [-],
    bearings n_b [-], crank_circle_radius_mm a0 [mm]. Returns [rad/(N m)]."""
    a0_m = crank_circle_radius_mm * 1e-3
    return lever_factor ** 2 * deflection_um_per_n * 1e-6 / (bearings * a0_m * a0_m)


def pillar_deflection_um_per_n(length_mm: float, width_mm: float, depth_mm: float, e_gpa: float, nu: float) -> float:
    """Sideways deflection of a carrier pillar clamped in both plates (fixed-guided beam) per unit
    shear force, with shear:

        delta / V = L^3 / (12 E I) + L / (kappa G A),   I = h w^3 / 12,  A = w h

    Source: Roark (7th ed.), Table 8.1 case 1d (left end fixed, right end guided: y = -W l^3 /
    (12 E I)), Cowper's shear coefficient of a rectangle. Parameters: length_mm L free length
    between the plates [mm]; width_mm w tangential (in the direction of the deflection) [mm];
    depth_mm h radial [mm]; e_gpa [GPa]; nu [-]. Returns [um/N]. Validity: plates rigid in their
    plane and the pillar ends fully clamped (bolted joints and plate bending neglected: a lower
    bound on the carrier's compliance); rectangular section standing for the real wedge-shaped
    pillar."""
    e = e_gpa * 1e3
    g = shear_modulus_gpa(e_gpa, nu) * 1e3
    inertia = depth_mm * width_mm ** 3 / 12.0
    area = width_mm * depth_mm
    return (length_mm ** 3 / (12.0 * e * inertia) + length_mm / (rectangular_shear_coefficient(nu) * g * area)) * 1e3


def crank_torque_nm(output_torque_nm: float, planet_radius_mm: float, centre_gear_radius_mm: float, ratio: float,
                    planets: int) -> float:
    """Torque each crankshaft carries between its planet gear and its eccentrics, input locked:

        T_c = r_2 T / (i r_1 n)

    Each of the n planets carries F_t = T / (i r_1 n) (``mesh_torsional_stiffness_nm_per_rad``), its
    crank the torque F_t r_2 (``crank_torsion_output_compliance_rad_per_nm``). Source: ours (the
    lever arms of Eq. (1), docs/model.md). Parameters: output torque T [N m], pitch radii r_2
    (planet), r_1 (centre gear) [mm], ratio i [-], planets n [-]. Returns [N m]. Validity: equal
    load sharing of the planets."""
    return planet_radius_mm * output_torque_nm / (ratio * centre_gear_radius_mm * planets)


def pillar_shear_force_n(output_torque_nm: float, lever_factor: float, pillars: int, pillar_radius_mm: float) -> float:
    """Shear force in each carrier pillar: V = k T / (2 n_p R_p) (``carrier_output_compliance_rad_per_nm``:
    the pillars carry half the cranks' torque k T from the end plate to the flange). Source: ours
    (docs/elastic.md). Parameters: output torque T [N m], lever_factor k [-], pillars n_p [-], their
    pitch radius R_p [mm]. Returns [N]."""
    return lever_factor * output_torque_nm / (2.0 * pillars * pillar_radius_mm * 1e-3)


def carrier_output_compliance_rad_per_nm(pillar_um_per_n: float, pillars: int, pillar_radius_mm: float,
                                         lever_factor: float) -> float:
    """Output compliance of the carrier's wind-up (end plate against output flange):

        C = k^2 c_p / (4 n_p R_p^2)

    The cranks bear on the flange and on the end plate through one support bearing each; with the
    discs symmetric about mid-span each end takes half the crank forces, so the pillars carry the
    torque k T / 2 from the end plate to the flange, a shear V = k T / (2 n_p R_p) each; the end
    plate turns phi = c_p V / R_p; the cranks' end-plate ends move a0 phi, the discs (mid-span on
    average) a0 phi / 2, the output k phi / 2. Source: ours (docs/elastic.md), a simplified model.
    Parameters: pillar_um_per_n c_p [um/N] (``pillar_deflection_um_per_n``), pillars n_p [-],
    pillar_radius_mm R_p (pitch radius of the pillars' centres) [mm], lever_factor k [-].
    Returns [rad/(N m)]. Validity: plates rigid, pillars equal and equally spaced."""
    rp_m = pillar_radius_mm * 1e-3
    return lever_factor ** 2 * pillar_um_per_n * 1e-6 / (4.0 * pillars * rp_m * rp_m)


def disc_translation_factor(crank_circle_radius_mm: float, disc_pitch_radius_mm: float) -> float:
    """How much the disc's sideways motion on its needle bearings adds to their torsional compliance:

        f = 1 + (a0 / rho)^2,   rho = a z_c (the disc's pitch radius)

    Every pin's contact normal passes through the pitch point P at rho from the disc centre, so the
    pins' resultant on a disc carrying torque T_d acts at P: a force T_d / rho across the eccentric
    (and a radial part along it). Three needle bearings at a0 from the disc centre, 120 degrees
    apart, of equal isotropic stiffness k_b: the moment turns the disc by T_d / (3 k_b a0^2), the
    force translates it by T_d / (3 k_b rho) (sum c_i = 0 decouples the two); the point P, which
    the pins hold, moves by T_d (1/rho + rho/a0^2) / (3 k_b) against T_d rho / (3 k_b a0^2) with the
    disc centre held: the ratio f. Source: ours (docs/elastic.md; equilibrium of a rigid disc on
    three springs, a closed form checked against a numeric 3-DOF solve in the tests).
    Parameters: a0 [mm], rho [mm]. Returns f [-] (RV-80E class: 1 + (42 / 58.5)^2 = 1.515).
    Validity: two or more equally spaced equal bearings (n of them: n k_b in every direction, n k_b
    a0^2 in rotation, the same ratio), linear about the loaded state; the dead band of the clearance
    is not widened by the translation."""
    return 1.0 + (crank_circle_radius_mm / disc_pitch_radius_mm) ** 2


@njit(cache=True)
def pin_radial_closure(phi_rad, k1):
    """Closure of the pin at phase phi per unit translation of the disc along its eccentric [um/um]:

        M = (cos phi - K1) / sqrt(1 + K1^2 - 2 K1 cos phi)

    The contact normal runs from the pitch point P (at a z_p from the housing centre along the
    eccentric) to the pin centre (r_p at angle phi): M is its component along the eccentric. Its
    component across, sin(phi) / sqrt(S), times a z_c is the pin's lever (``cycloid_lever_factor``).
    Source: ours, from the cycloid's pitch-point property (Litvin & Fuentes 2004, ch. on cycloidal
    gearing); checked against the exact geometry's gaps under a disc translation (tests).
    Parameters: phi [rad], K1 [-]. Returns M [-] (> 0: a translation along the eccentric closes it)."""
    c = math.cos(phi_rad)
    return (c - k1) / math.sqrt(1.0 + k1 * k1 - 2.0 * k1 * c)


def disc_body_output_compliance_rad_per_nm(disc_compliance_rad_per_nm: float, lever_factor: float,
                                           discs: int) -> float:
    """The discs' bodies referred to the output: C = k^2 C_disc / n_d [rad/(N m)].

    Each of the n_d discs carries k T / n_d (virtual work: the pins' generalised force, docs/elastic.md
    "Kinematics"), and its rotation beta reaches the output as k beta; C_disc is one disc's
    body rotation per N m of its torque (mechanics.disc_body, FE). Parameters: C_disc [rad/(N m)],
    k [-], n_d [-]."""
    return lever_factor ** 2 * disc_compliance_rad_per_nm / discs


def housing_ring_torsion_compliance_rad_per_nm(inner_radius_mm: float, outer_radius_mm: float,
                                               thickness_mm: float, e_gpa: float, nu: float) -> float:
    """Twist of a solid annulus r1..r2, thickness t, under a torque between its edges:
    theta / T = (1/r1^2 - 1/r2^2) / (4 pi G t) [rad/(N m)]. Derivation (Lame's annulus in pure
    shear; Timoshenko & Goodier, Theory of Elasticity, 3rd ed., the annulus under a torque): the
    shear stress tau = T / (2 pi r^2 t), the twist d(theta)/dr = tau / (G r); integrated from r1 to r2.
    The FE disc's oracle (tests/mechanics). Used to size the housing
    ring between the pins' grooves and its flange (docs/elastic.md, "The pins' seating").
    Parameters [mm, GPa, -]. Validity: plane stress, a full annulus (no bolt holes)."""
    g = shear_modulus_gpa(e_gpa, nu) * 1e3  # N/mm^2
    return (1.0 / inner_radius_mm ** 2 - 1.0 / outer_radius_mm ** 2) / (4.0 * math.pi * g * thickness_mm) * 1e3


# --- rolling elements by slices (ISO/TS 16281:2008; docs/rigidity-elements.md) --------------------
# A roller is cut into n_s slices of width L / n_s along its effective length L; slice k at x_k
# (from the roller's middle) closes by delta_k = delta + tilt x_k - 2 P_k, P_k the roller's
# profile drop there (it opens both of the roller's contacts, hence 2 P_k: ISO/TS 16281's
# delta_jk = delta_j - x_k tan(psi_j) - 2 P_k, as transcribed in public implementations; the
# standard's text was not read here). Approaches [um], x [mm], drops [um] per side, forces [N].

ISO_ROLLER_CONSTANT = 35948.0  # ISO/TS 16281: c_l = 35948 L^(8/9) [N mm^(-10/9)], a roller between two steel raceways
# ISO/TS 16281's profile for rollers whose profile is not known (log scale [um per mm of D_we]):
ISO_LOG_SCALE_SHORT = 0.35  # cylindrical and needle rollers, L <= 2.5 D_we: 0.00035 D_we [mm]
ISO_LOG_SCALE_LONG = 0.5  # cylindrical and needle rollers, L > 2.5 D_we: 0.0005 D_we over the end 1.25 D_we each
ISO_LOG_SCALE_TAPERED = 0.45  # tapered rollers: 0.00045 D_we
ISO_LOG_RELIEF_DIAMETERS = 2.5  # long rollers: the profile spans 2.5 D_we (1.25 D_we at each end)


def iso_roller_constant_n_per_mm(length_mm: float) -> float:
    """ISO/TS 16281's normal stiffness constant of a roller between two steel raceways:

        Q = c_l delta^(10/9),   c_l = 35948 L^(8/9)   [N, mm]

    Source: ISO/TS 16281:2008 (roller contact, the slice model: a slice of width L/n_s carries
    c_l / n_s delta_k^(10/9)); ../shared/reference/anchors.md; the constant as DIN 26281 and
    public implementations of both use it [the standard's text not read here]. Parameters:
    length_mm effective roller length L [mm]. Returns c_l [N/mm^(10/9)]. Validity: steel on
    steel, line contact (L >> contact width). Against Palmgren's two contacts in series
    (``palmgren_roller_constant_n_per_mm``, 37 310 L^(8/9)) it is 3.8 % softer in load at a given
    approach, 3.4 % larger in approach at a given load."""
    return ISO_ROLLER_CONSTANT * length_mm ** (8.0 / 9.0)


def palmgren_roller_constant_n_per_mm(length_mm: float) -> float:
    """Palmgren's roller between two raceways written as Q = c delta^(10/9) [N, mm]: its two contacts
    in series (delta = 2 x 3.84e-5 Q^0.9 / L^0.8, ``palmgren_line_approach_um``) give

        c = (2 x 3.84e-5)^(-10/9) L^(8/9) = 37 310 L^(8/9)

    Source: Palmgren (1959) as given by Harris & Kotzalas, Rolling Bearing Analysis 5th ed.
    (2007), the roller-raceway line contact; rearranged. Parameters: L [mm]. Returns c
    [N/mm^(10/9)]. Validity: as ``palmgren_line_approach_um``."""
    return (2.0 * PALMGREN_COEFFICIENT) ** (-1.0 / PALMGREN_EXPONENT) * length_mm ** (0.8 / PALMGREN_EXPONENT)


def roller_slice_positions_mm(length_mm: float, slices: int) -> np.ndarray:
    """Centres x_k of n_s equal slices of a roller of effective length L, from its middle:

        x_k = (k + 1/2) L / n_s - L / 2,   k = 0 .. n_s - 1

    Source: ISO/TS 16281:2008, the slice (lamina) model. Parameters: L [mm], n_s [-].
    Returns x_k [mm] (symmetric about 0)."""
    return ((np.arange(slices) + 0.5) / slices - 0.5) * length_mm


def crowned_profile_drop_um(x_mm: float, length_mm: float, crown_drop_um: float) -> float:
    """Drop of a circular crown at x from the roller's middle, the crown's arc through the drop
    ``crown_drop_um`` at both ends of the effective length L:

        P(x) = R - sqrt(R^2 - x^2),   R = ((L/2)^2 + P_e^2) / (2 P_e)   (P(x) ~ P_e (2x/L)^2)

    Source: the circular crowning of Harris & Kotzalas, Rolling Bearing Analysis 5th ed. (2007),
    roller profiles (crowned rollers); the arc's geometry. Parameters: x [mm], L [mm], P_e the
    drop at the ends [um] (> 0). Returns P(x) [um] per side (the roller's radius is smaller by it).
    Validity: |x| <= L/2."""
    half = 0.5 * length_mm
    drop_mm = crown_drop_um * 1e-3
    radius = (half * half + drop_mm * drop_mm) / (2.0 * drop_mm)
    return (radius - math.sqrt(radius * radius - x_mm * x_mm)) * 1e3


def logarithmic_profile_drop_um(x_mm: float, length_mm: float, scale_um: float, relief_mm: float) -> float:
    """Drop of a logarithmic (Lundberg) profile at x from the roller's middle:

        P(x) = K ln(1 / (1 - t^2)),   t = (2|x| - (L - l_r)) / l_r   where |x| > (L - l_r)/2, else 0

    l_r = L: the whole roller profiled (Lundberg's profile, the uniform-pressure profile of a
    line contact, Lundberg 1939; Johns & Gohar, Tribology International 14 (1981) 131, add a
    finite end drop to it); l_r < L: a straight middle and logarithmic ends of l_r / 2 each.
    ISO/TS 16281:2008 uses this profile for rollers whose profile is not known
    (``iso_logarithmic_profile``: K = 0.35 D_we um per mm, l_r = L for cylindrical and needle
    rollers up to L = 2.5 D_we; K = 0.5 D_we, l_r = 2.5 D_we for longer ones; K = 0.45 D_we, l_r = L
    for tapered rollers; as transcribed in public implementations of the standard, its text not
    read here). Parameters: x [mm], L [mm], K [um], l_r [mm] (0 < l_r <= L). Returns P(x) [um]
    per side; infinite at the ends (read it at the slices' centres). Validity: |x| < L/2."""
    straight = 0.5 * (length_mm - relief_mm)
    if abs(x_mm) <= straight:
        return 0.0
    t = (2.0 * abs(x_mm) - (length_mm - relief_mm)) / relief_mm
    return scale_um * math.log(1.0 / (1.0 - t * t))


def iso_logarithmic_profile(roller_diameter_mm: float, length_mm: float, tapered: bool) -> tuple[float, float]:
    """(K [um], l_r [mm]) of ISO/TS 16281:2008's logarithmic profile for a roller whose profile is not
    known (``logarithmic_profile_drop_um``): cylindrical and needle rollers K = 0.35 D_we, l_r = L
    when L <= 2.5 D_we, else K = 0.5 D_we, l_r = 2.5 D_we; tapered rollers K = 0.45 D_we, l_r = L
    (D_we in mm, K in um: the standard's 0.00035 D_we mm etc.). Source: ISO/TS 16281:2008, the
    roller profile equations (numbered (42)-(44) in a public implementation; the standard's text
    not read here). Parameters: D_we [mm], L [mm], tapered. Returns (K, l_r)."""
    if tapered:
        return ISO_LOG_SCALE_TAPERED * roller_diameter_mm, length_mm
    if length_mm <= ISO_LOG_RELIEF_DIAMETERS * roller_diameter_mm:
        return ISO_LOG_SCALE_SHORT * roller_diameter_mm, length_mm
    return ISO_LOG_SCALE_LONG * roller_diameter_mm, ISO_LOG_RELIEF_DIAMETERS * roller_diameter_mm


@njit(cache=True)
def law_force_n(delta_um, a, b, n):
    """Inverse of the contact law as the solver reads it (``law_approach_continued_um``): the force F
    [N] that closes a contact by delta [um] > 0 (0 for delta <= 0).

    Palmgren (b = 0): F = (delta / a)^(1/n). Johnson (n = 1, b > 0): Newton on the concave,
    increasing F (a - b ln F) - delta, safeguarded by bisection in ln F between 0 and F_lim =
    exp(a/b - 2), beyond which the law is its tangent (``law_approach_continued_um``). Source:
    the law's own formula; the same root as ``models.elastic.solver.law_force``, converged to 1e-15
    relative. Parameters: delta [um], a, b, n as ``law_approach_um``. Returns F [N]."""
    if delta_um <= 0.0:
        return 0.0
    if b == 0.0:
        return (delta_um / a) ** (1.0 / n)
    f_lim = math.exp(a / b - 2.0)
    d_lim = 2.0 * b * f_lim
    if delta_um >= d_lim:
        return f_lim + (delta_um - d_lim) / b
    lo, hi = 0.0, f_lim
    f = min(delta_um / a, 0.5 * f_lim)
    for _ in range(200):
        g = f * (a - b * math.log(f)) - delta_um
        if g < 0.0:
            lo = f
        else:
            hi = f
        fn = f - g / (a - b * math.log(f) - b)
        if not (lo < fn < hi):
            fn = math.sqrt(lo * hi) if lo > 0.0 else 0.5 * hi
        if abs(fn - f) <= 1e-15 * f:
            return fn
        f = fn
    return f


@njit(cache=True)
def sliced_roller_load_n(approach_um, tilt_rad, x_mm, drop_um, a, b, n):
    """Normal load of a roller by slices at an approach delta of its middle and a tilt:

        Q = sum_k F(max(0, delta + tilt x_k - 2 P_k) ) / n_s

    F: the roller's straight law inverted (``law_force_n``: delta = F^n (a - b ln F) for the whole
    roller, its two contacts in series). A slice of width L / n_s carries the line load of the
    whole roller at its own approach (for Palmgren's law that is Q_k = c_l / n_s delta_k^(10/9),
    c_l = a^(-10/9) [N um^(-10/9)], ISO/TS 16281's form with Palmgren's constant,
    ``palmgren_roller_constant_n_per_mm``; for Johnson's, the line load at which the approach of a
    line contact is delta_k), so that a straight roller without tilt is the straight law itself.
    Source: ISO/TS 16281:2008, the slice model (delta_jk = delta_j - x_k tan psi_j - 2 P_k);
    Harris & Kotzalas, Rolling Bearing Analysis 5th ed. (2007), roller-raceway contact with a
    profile and misalignment. Parameters: approach delta [um]; tilt [rad] (the raceways'
    misalignment in the roller's plane); x_mm slice centres [mm] (``roller_slice_positions_mm``);
    drop_um the profile's drop P_k at each [um] (per side); a, b, n the roller's straight law.
    Returns Q [N]. Validity: slices independent (no shear between them: ISO's simplification),
    tilt small (tan psi = psi)."""
    m = x_mm.size
    q = 0.0
    for k in range(m):
        d = approach_um + tilt_rad * x_mm[k] * 1e3 - 2.0 * drop_um[k]
        if d > 0.0:
            q += law_force_n(d, a, b, n)
    return q / m


@njit(cache=True)
def sliced_roller_approach_um(load_n, tilt_rad, x_mm, drop_um, a, b, n):
    """Inverse of ``sliced_roller_load_n``: the approach delta [um] at which the sliced roller carries
    Q = load_n > 0 (monotone: Q rises with delta once a slice touches). Bracketed: at
    delta_0 = min_k (2 P_k - tilt x_k) no slice touches; at delta_0 + spread + delta_straight(Q)
    every slice is closed by at least the straight roller's approach. Illinois regula falsi
    with bisection, to 1e-14 of the bracket. Parameters as ``sliced_roller_load_n``; load [N].
    Returns delta [um]."""
    m = x_mm.size
    lo = math.inf
    top = -math.inf
    for k in range(m):
        v = 2.0 * drop_um[k] - tilt_rad * x_mm[k] * 1e3
        lo = min(lo, v)
        top = max(top, v)
    hi = top + law_approach_continued_um(load_n, a, b, n)
    flo = -load_n
    fhi = sliced_roller_load_n(hi, tilt_rad, x_mm, drop_um, a, b, n) - load_n
    side = 0
    x = hi
    for _ in range(300):
        x = illinois_point(lo, flo, hi, fhi)
        fx = sliced_roller_load_n(x, tilt_rad, x_mm, drop_um, a, b, n) - load_n
        if fx == 0.0 or hi - lo <= 1e-14 * (abs(lo) + abs(hi)):
            return x
        lo, flo, hi, fhi, side = illinois_bracket(x, fx, lo, flo, hi, fhi, side)
    return x


@njit(cache=True)
def illinois_point(lo, flo, hi, fhi):
    """The next point of the Illinois regula falsi on the bracket [lo, hi] of an increasing f
    (flo <= 0 <= fhi): the secant's root, or the middle when the secant leaves the bracket or is
    flat. Source: Dowell & Jarratt, BIT 11 (1971) 168-174 (the Illinois method)."""
    x = hi - fhi * (hi - lo) / (fhi - flo) if fhi != flo else 0.5 * (lo + hi)
    if not (lo < x < hi):
        x = 0.5 * (lo + hi)
    return x


@njit(cache=True)
def illinois_bracket(x, fx, lo, flo, hi, fhi, side):
    """(lo, flo, hi, fhi, side): the bracket after f(x) = fx (``illinois_point``): x replaces the end
    of its sign; when the same end moves twice running (``side``: +1 hi, -1 lo, 0 none yet), the
    other end's value is halved, so that the secant cannot stall against it (Illinois)."""
    if fx > 0.0:
        if side == 1:
            flo *= 0.5
        return lo, flo, x, fx, 1
    if side == -1:
        fhi *= 0.5
    return x, fx, hi, fhi, -1


def crank_support_slope_rad_per_n(span_mm: float, load_offset_mm: float, diameter_mm: float, e_gpa: float) -> float:
    """Slope (cross-section rotation) at either support of a simply supported crankshaft carrying two
    equal loads P in the same direction, symmetric about mid-span at c from the supports (the case
    of ``crank_symmetric_deflection_um_per_n``), per unit load:

        phi / P = c (L - c) / (2 E I),   I = pi d^4 / 64

    Source: Young & Budynas, Roark's Formulas for Stress and Strain, 7th ed. (2002), Table 8.1 case
    1e (theta_A = W b (l^2 - b^2) / (6 E I l) for a load at a = l - b), the two loads superposed:
    c (L-c)(2L-c)/(6 E I L) + c (L-c)(L+c)/(6 E I L). Bending only: Timoshenko's shear term moves
    the centre line, not the section, and the bearing's inner ring turns with the section.
    Parameters: span L [mm], offset c [mm], diameter d [mm] (equivalent solid round section),
    E [GPa]. Returns [rad/N]. Validity: as ``crank_symmetric_deflection_um_per_n``; the bearing
    is taken as a simple support, so its own resistance to the tilt is not fed back (the slope is
    an upper bound)."""
    inertia = math.pi * diameter_mm ** 4 / 64.0
    return load_offset_mm * (span_mm - load_offset_mm) / (2.0 * e_gpa * 1e3 * inertia)
