"""Compliance formulas of the elastic hysteresis model (docs/elastic.md), one function per formula.

Units: forces [N], lengths [mm], moduli [N/mm^2] (= MPa) unless a name says otherwise,
approaches [um], torques [N m], angles [rad]. The scalar formulas are compiled with numba
(``njit``) so that the Monte-Carlo kernel (``models/elastic.py``) runs exactly the functions the
tests check; they are callable from Python with plain floats.
"""

from __future__ import annotations

import math

from rvbacklash._numba import nb

PALMGREN_COEFFICIENT = 3.84e-5  # [mm N^-0.9 mm^0.8] of Palmgren's roller formula
PALMGREN_EXPONENT = 0.9
RELATIVE_RADIUS_CAP = 10.0  # near-conformal contacts: relative radius capped at 10 pin radii (validity)


# --- Hertz line contact (Johnson, Contact Mechanics, Cambridge University Press 1985, ch. 4) ----

@nb.njit(cache=True)
def contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2):
    """Contact modulus E* of two elastic bodies: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.

    Source: Johnson, Contact Mechanics (1985), ch. 4 (Hertz theory), the combined modulus of
    Eq. (4.22) [equation number as we read it; unverified].
    Parameters: e1_gpa, e2_gpa Young's moduli [GPa]; nu1, nu2 Poisson's ratios [-].
    Returns E* [N/mm^2]. Validity: linear elastic, isotropic bodies.
    """
    return 1.0 / ((1.0 - nu1 * nu1) / (e1_gpa * 1e3) + (1.0 - nu2 * nu2) / (e2_gpa * 1e3))


@nb.njit(cache=True)
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


@nb.njit(cache=True)
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


@nb.njit(cache=True)
def line_contact_half_width_mm(force_n, length_mm, radius_mm, e_star_n_per_mm2):
    """Half-width of a Hertz line contact: a = sqrt(4 P R / (pi E*)), P = F / L.

    Source: Johnson, Contact Mechanics (1985), ch. 4, Eq. (4.43) [numbering unverified]; the same
    as Roark's b = 1.60 sqrt(p K_D C_E) for the full width (Young & Budynas, Roark's Formulas for
    Stress and Strain, 7th ed., Table 14.1, cylinders).
    Parameters: force_n F [N], length_mm L [mm], radius_mm relative radius R [mm],
    e_star_n_per_mm2 E* [N/mm^2]. Returns a [mm]. Validity: a << R, uniform load along L.
    """
    return math.sqrt(4.0 * force_n * radius_mm / (math.pi * length_mm * e_star_n_per_mm2))


@nb.njit(cache=True)
def line_contact_peak_pressure_mpa(force_n, length_mm, half_width_mm):
    """Peak Hertz pressure of a line contact: p0 = 2 P / (pi a), P = F / L.

    Source: Johnson (1985), ch. 4, Eq. (4.44) [numbering unverified]; Roark's sigma_max =
    0.798 sqrt(p / (K_D C_E)) (7th ed., Table 14.1). Parameters: F [N], L [mm], a [mm].
    Returns p0 [MPa]."""
    return 2.0 * force_n / (math.pi * length_mm * half_width_mm)


@nb.njit(cache=True)
def johnson_line_approach_um(force_n, length_mm, body1_radius_mm, e1_gpa, nu1, body2_radius_mm, e2_gpa, nu2,
                             relative_radius):
    """Elastic approach of two cylinders in line contact (distance between their axes):

        delta = (2 P / pi) sum_k (1 - nu_k^2)/E_k (ln(4 R_k / a) - 1/2),  P = F / L,
        a = sqrt(4 P R / (pi E*))

    Source: Johnson, Contact Mechanics (1985), ch. 4, the compression of two cylinders in line
    contact (section 4.3, Eq. (4.45) [numbering unverified]); ../shared/reference/anchors.md.
    Parameters: force_n F [N]; length_mm L [mm]; body radii R_k [mm] (for a concave or non-circular
    body: the depth to which its displacement is referred, see docs/elastic.md); Young's moduli
    [GPa], Poisson's ratios [-]; relative_radius R [mm]. Returns delta [um].
    Validity: a << R_k (the log stays > 1/2), elastic, no edge effects along L.
    """
    e_star = contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2)
    a = line_contact_half_width_mm(force_n, length_mm, relative_radius, e_star)
    p = force_n / length_mm
    c1 = (1.0 - nu1 * nu1) / (e1_gpa * 1e3)
    c2 = (1.0 - nu2 * nu2) / (e2_gpa * 1e3)
    s = c1 * (math.log(4.0 * body1_radius_mm / a) - 0.5) + c2 * (math.log(4.0 * body2_radius_mm / a) - 0.5)
    return 2.0 * p / math.pi * s * 1e3


@nb.njit(cache=True)
def johnson_law_a_um_per_n(length_mm, body1_radius_mm, e1_gpa, nu1, body2_radius_mm, e2_gpa, nu2, relative_radius):
    """Coefficient a of Johnson's approach written as delta = F (a - b ln F) [um, N].

    Expanding ln(4 R_k / a) with a^2 = 4 F R / (pi L E*) in ``johnson_line_approach_um``:
        a = (2 / (pi L)) [sum_k c_k (ln(4 R_k) - 1/2) - ln(4 R / (pi L E*)) / (2 E*)],  c_k = (1 - nu_k^2)/E_k
    (the same formula, rearranged so that the kernel can invert it). Parameters as
    ``johnson_line_approach_um``. Returns a [um/N].
    """
    e_star = contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2)
    c1 = (1.0 - nu1 * nu1) / (e1_gpa * 1e3)
    c2 = (1.0 - nu2 * nu2) / (e2_gpa * 1e3)
    s = c1 * (math.log(4.0 * body1_radius_mm) - 0.5) + c2 * (math.log(4.0 * body2_radius_mm) - 0.5)
    s -= math.log(4.0 * relative_radius / (math.pi * length_mm * e_star)) / (2.0 * e_star)
    return 2.0 / (math.pi * length_mm) * s * 1e3


@nb.njit(cache=True)
def johnson_law_b_um_per_n(length_mm, e1_gpa, nu1, e2_gpa, nu2):
    """Coefficient b of Johnson's approach delta = F (a - b ln F): b = 1 / (pi L E*) [um/N].

    Source: ``johnson_line_approach_um`` rearranged. Parameters: L [mm], moduli [GPa], ratios [-]."""
    return 1e3 / (math.pi * length_mm * contact_modulus_n_per_mm2(e1_gpa, nu1, e2_gpa, nu2))


@nb.njit(cache=True)
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


@nb.njit(cache=True)
def palmgren_law_a(length_mm):
    """Coefficient a of Palmgren's approach written as delta = a Q^0.9 [um, N]: a = 3.84e-2 / L^0.8."""
    return PALMGREN_COEFFICIENT / length_mm ** 0.8 * 1e3


@nb.njit(cache=True)
def law_approach_um(force_n, a, b, n):
    """The contact law every contact of the kernel uses: delta = F^n (a - b ln F) [um].

    Johnson: n = 1 and (a, b) from ``johnson_law_a_um_per_n`` / ``johnson_law_b_um_per_n``;
    Palmgren: n = 0.9, b = 0, a = ``palmgren_law_a``. Two contacts in series (a roller between
    two raceways) add their a's and b's. F > 0 [N]; returns [um]."""
    return force_n ** n * (a - b * math.log(force_n))


# --- the pin-centre curve and the disc flank --------------------------------------------------

@nb.njit(cache=True)
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


@nb.njit(cache=True)
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

@nb.njit(cache=True)
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


@nb.njit(cache=True)
def applied_torque_nm(elastic_nm, increasing, friction_nm, friction_fraction):
    """Inverse of ``elastic_torque_nm``: the applied torque that holds T_el on a branch [N m]."""
    if increasing:
        return elastic_nm + friction_nm + friction_fraction * abs(elastic_nm)
    return elastic_nm - friction_nm - friction_fraction * abs(elastic_nm)
