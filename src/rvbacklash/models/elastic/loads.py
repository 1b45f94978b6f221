"""The loads the elastic chain carries, element by element, at one crank angle (docs/capacity.md,
"Loads over a revolution"): what a unit's pins, crank needle bearings, crankshafts and support
bearings carry when the chain holds a torque. The capacity work reads them over a revolution (life,
static limits); the wear and losses work read the same contacts' forces.

Frames and signs. Everything is in the housing frame at the instant of crank angle chi (pin j at
psi_j = 2 pi j / z_p; disc d's eccentric along chi_d = chi + 2 pi d / discs; the carrier, and
with it every disc's crank bores, turned by -chi / z_c: crank c at 2 pi c / P - chi / z_c,
geometry/disc_holes.py). Forces [N], lengths [mm], moments [N mm].

- **pins**: pin j's force on disc d acts along the line from the pin's centre through the pitch
  point P = a z_p e^{i chi_d} (every contact normal of the cycloid passes through it; the
  elastic chain's lever arms are the moments of these lines about the disc centre: a test checks
  sum F_j L_j against the moment of the forces below);
- **crank needle bearings**: a rigid disc on its P equal bearings (the chain's model of the disc's
  translation, docs/elastic.md): bearing c of disc d carries F_d / P + M_d / (P a0^2) z x r_c (F_d,
  M_d the pins' resultant and moment on the disc, r_c the bore's centre from the disc centre);
  the disc FE's unequal shares are not fed back (docs/capacity.md says how much they would move);
- **crankshafts**: each crank's torque is its eccentrics' loads' moment about its axis; its planet
  gear reacts it with a tooth force F_t = T_c / r_2 (and F_t tan(alpha) separating) at the gear's
  plane (``crankshaft_torsion_length_mm`` from mid-span);
- **support bearings**: the crankshaft as a beam on two simple supports at +-L/2 carrying its two
  eccentrics' loads at +-s/2 (disc 0 at -s/2, nearer support A) and the gear force: statics.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.models import compliance as cm


class LoadGeometry(NamedTuple):
    """What the load kernels read of a design (``load_geometry``)."""

    eccentricity_mm: float
    cycloid_teeth: float
    pins: float
    pin_circle_radius_mm: float
    pin_radius_mm: float
    generating_radius_mm: float
    k1: float
    discs: int
    cranks: int
    crank_circle_radius_mm: float
    contact_length_mm: float  # of one pin on one disc
    e_star_n_per_mm2: float  # pin on disc
    support_span_mm: float  # 0: no support bearings (no [structure])
    disc_spacing_mm: float
    gear_offset_mm: float  # the planet gear's plane from the crankshaft's mid-span (beyond support B)
    planet_pitch_radius_mm: float
    pressure_angle_rad: float


@njit(cache=True)
def pitch_point(chi_d, g):
    """The pitch point of disc d at eccentric angle chi_d: a z_p e^{i chi_d} [mm] (housing frame)."""
    r = g.eccentricity_mm * g.pins
    return r * math.cos(chi_d), r * math.sin(chi_d)


@njit(cache=True)
def disc_resultants(forces_n, chi, g, out):
    """Each disc's resultant of its pins' forces and their moment about its centre (housing frame)
    into out (discs, 3): F_x, F_y [N], M [N mm]. ``forces_n`` (discs, z_p): every pin's normal
    force on the disc [N] (0: open), each along the line from the pin's centre through the pitch
    point (module docstring)."""
    discs, zp = forces_n.shape
    for d in range(discs):
        chi_d = chi + 2.0 * math.pi * d / discs
        px, py = pitch_point(chi_d, g)
        ox, oy = g.eccentricity_mm * math.cos(chi_d), g.eccentricity_mm * math.sin(chi_d)
        fx = fy = m = 0.0
        for j in range(zp):
            f = forces_n[d, j]
            if f <= 0.0:
                continue
            psi = 2.0 * math.pi * j / zp
            qx, qy = g.pin_circle_radius_mm * math.cos(psi), g.pin_circle_radius_mm * math.sin(psi)
            ux, uy = px - qx, py - qy
            norm = math.sqrt(ux * ux + uy * uy)
            ux, uy = f * ux / norm, f * uy / norm
            fx += ux
            fy += uy
            m += (px - ox) * uy - (py - oy) * ux  # the line passes through P: its moment about O_d
        out[d, 0] = fx
        out[d, 1] = fy
        out[d, 2] = m


@njit(cache=True)
def crank_angle_in_housing(c, chi, g):
    """Where crank c sits around the reducer's axis at crank angle chi: 2 pi c / P - chi / z_c [rad]."""
    return 2.0 * math.pi * c / g.cranks - chi / g.cycloid_teeth


@njit(cache=True)
def crank_bearing_loads(resultants, chi, g, out):
    """The load each crank needle bearing carries (the disc's force on the crank's eccentric,
    housing frame) into out (discs, cranks, 2) [N]: F_d / P + M_d / (P a0^2) z x r_c (a rigid disc
    on P equal bearings)."""
    discs = resultants.shape[0]
    p = g.cranks
    a0 = g.crank_circle_radius_mm
    for d in range(discs):
        fx, fy, m = resultants[d, 0], resultants[d, 1], resultants[d, 2]
        t = m / (p * a0 * a0)
        for c in range(p):
            theta = crank_angle_in_housing(c, chi, g)
            rx, ry = a0 * math.cos(theta), a0 * math.sin(theta)
            out[d, c, 0] = fx / p - t * ry
            out[d, c, 1] = fy / p + t * rx


@njit(cache=True)
def crank_torques_nmm(bearing_loads, chi, g, out):
    """Each crank's torque from its eccentrics' loads [N mm] into out (cranks,): sum over discs of
    (a e^{i chi_d}) x load."""
    discs, cranks = bearing_loads.shape[0], bearing_loads.shape[1]
    for c in range(cranks):
        t = 0.0
        for d in range(discs):
            chi_d = chi + 2.0 * math.pi * d / discs
            ex, ey = g.eccentricity_mm * math.cos(chi_d), g.eccentricity_mm * math.sin(chi_d)
            t += ex * bearing_loads[d, c, 1] - ey * bearing_loads[d, c, 0]
        out[c] = t


@njit(cache=True)
def support_bearing_loads(bearing_loads, torques_nmm, chi, g, out):
    """The loads on each crank's two support bearings (housing frame) into out (cranks, 2, 2) [N]:
    [c, 0] support A (at -L/2, disc 0's side), [c, 1] support B (at +L/2, the planet gear's side).
    The crank carries its eccentrics' loads (disc 0 at -s/2, disc 1 at +s/2; one disc: mid-span)
    and its planet gear's tooth force (the crank's torque reacted at the gear's pitch point towards
    the centre gear, plus its separating part F_t tan(alpha)) at gear_offset_mm; simple supports."""
    discs, cranks = bearing_loads.shape[0], bearing_loads.shape[1]
    span = g.support_span_mm
    for c in range(cranks):
        theta = crank_angle_in_housing(c, chi, g)
        er_x, er_y = math.cos(theta), math.sin(theta)
        ft = torques_nmm[c] / g.planet_pitch_radius_mm
        # the tooth force on the planet: along z x e_r (its moment about the crank axis is -T_c), the
        # separating part outwards
        gx = -ft * er_y + abs(ft) * math.tan(g.pressure_angle_rad) * er_x
        gy = ft * er_x + abs(ft) * math.tan(g.pressure_angle_rad) * er_y
        tx, ty = gx, gy
        mx = gx * (g.gear_offset_mm + 0.5 * span)
        my = gy * (g.gear_offset_mm + 0.5 * span)
        for d in range(discs):
            z = 0.0 if discs == 1 else (-0.5 if d == 0 else 0.5) * g.disc_spacing_mm
            tx += bearing_loads[d, c, 0]
            ty += bearing_loads[d, c, 1]
            mx += bearing_loads[d, c, 0] * (z + 0.5 * span)
            my += bearing_loads[d, c, 1] * (z + 0.5 * span)
        out[c, 1, 0] = mx / span
        out[c, 1, 1] = my / span
        out[c, 0, 0] = tx - out[c, 1, 0]
        out[c, 0, 1] = ty - out[c, 1, 1]


@njit(cache=True)
def pin_relative_radius_mm(phi, g):
    """Relative radius of pin j's contact with the flank at phase phi (the chain's: the flank's
    radius of curvature from ``compliance.pin_centre_curve_radius_mm``, capped where near-conformal
    at ``RELATIVE_RADIUS_CAP`` pin radii, which overstates the stress there) [mm]."""
    rho = cm.flank_radius_mm(cm.pin_centre_curve_radius_mm(phi, g.pin_circle_radius_mm, g.k1, g.pins),
                             g.generating_radius_mm)
    return cm.capped_relative_radius_mm(g.pin_radius_mm, rho, cm.RELATIVE_RADIUS_CAP * g.pin_radius_mm)


@njit(cache=True)
def pin_stresses_mpa(forces_n, chi, g, out):
    """Peak Hertz pressure of every pin-flank contact [MPa] into out (discs, z_p): p0 =
    sqrt(F E* / (pi L R)) (``compliance.line_contact_half_width_mm``, ``line_contact_peak_pressure_mpa``)
    with the contact's relative radius (``pin_relative_radius_mm``); 0 where open."""
    discs, zp = forces_n.shape
    for d in range(discs):
        for j in range(zp):
            f = forces_n[d, j]
            if f <= 0.0:
                out[d, j] = 0.0
                continue
            phi = 2.0 * math.pi * j / zp - (chi + 2.0 * math.pi * d / discs)
            r = pin_relative_radius_mm(phi, g)
            a = cm.line_contact_half_width_mm(f, g.contact_length_mm, r, g.e_star_n_per_mm2)
            out[d, j] = cm.line_contact_peak_pressure_mpa(f, g.contact_length_mm, a)


# --- a bearing's rollers under a radial load (ISO/TS 16281's slices) ---------------------------------

class RollerSet(NamedTuple):
    """A radial roller bearing's rollers by ISO/TS 16281's slices: cos of each roller's angle from
    the load line (one roller on it), each slice's profile drop [um] (per side), the roller's
    constant c_l [N/mm^(10/9)] (``compliance.iso_roller_constant_n_per_mm``)."""

    roller_cos: np.ndarray
    drop_um: np.ndarray
    stiffness_n_per_mm: float


@njit(cache=True)
def roller_load_n(approach_um, drop_um, stiffness_n_per_mm):
    """A roller's load [N] when its middle closes by delta [um]: sum over its slices of
    (c_l / n_s) (delta - 2 P_k)^(10/9) (``ratings.iso16281_lamina_load_n``)."""
    n_s = drop_um.size
    q = 0.0
    for k in range(n_s):
        d = approach_um - 2.0 * drop_um[k]
        if d > 0.0:
            q += stiffness_n_per_mm / n_s * (d * 1e-3) ** (10.0 / 9.0)
    return q


@njit(cache=True)
def roller_set_load_n(approach_um, clearance_um, rollers):
    """The radial load [N] a bearing's rollers carry at the rings' approach delta_r [um]: sum_i Q_i
    cos(psi_i), roller i closed by delta_r cos(psi_i) - G/2 (a preload, G < 0, closes the rollers
    on the far side too: they push back)."""
    total = 0.0
    for i in range(rollers.roller_cos.size):
        c = rollers.roller_cos[i]
        total += c * roller_load_n(approach_um * c - 0.5 * clearance_um, rollers.drop_um, rollers.stiffness_n_per_mm)
    return total


@njit(cache=True)
def roller_set_approach_um(load_n, clearance_um, rollers):
    """The radial approach delta_r [um] of a bearing's rings under the radial load ``load_n`` [N] with
    the diametral clearance ``clearance_um`` (negative: preload): roller i closes by delta_r cos(psi_i)
    - G/2, sum_i Q_i cos(psi_i) = F_r (Harris & Kotzalas 5th ed., the load distribution with
    clearance; ISO/TS 16281's slices). Illinois regula falsi on the monotone load
    (``compliance.illinois_point``), bracketed by +-(|G|/2 + the profile's largest drop + the
    approach at which the roller on the load line alone would carry the load)."""
    top = 0.0
    for k in range(rollers.drop_um.size):
        top = max(top, 2.0 * rollers.drop_um[k])
    lone = (max(load_n, 0.0) / rollers.stiffness_n_per_mm) ** 0.9 * 1e3
    reach = 0.5 * abs(clearance_um) + top + lone + 1e-9
    lo, hi = -reach, reach
    flo = roller_set_load_n(lo, clearance_um, rollers) - load_n
    fhi = roller_set_load_n(hi, clearance_um, rollers) - load_n
    if flo >= 0.0:
        return lo
    side = 0
    x = hi
    for _ in range(300):
        x = cm.illinois_point(lo, flo, hi, fhi)
        fx = roller_set_load_n(x, clearance_um, rollers) - load_n
        if fx == 0.0 or hi - lo <= 1e-13 * (abs(hi) + abs(lo)):
            return x
        lo, flo, hi, fhi, side = cm.illinois_bracket(x, fx, lo, flo, hi, fhi, side)
    return x


@njit(cache=True)
def roller_loads_n(approach_um, clearance_um, rollers, out):
    """Each roller's load [N] at the rings' approach delta_r (``roller_set_approach_um``) into out."""
    for i in range(rollers.roller_cos.size):
        out[i] = roller_load_n(approach_um * rollers.roller_cos[i] - 0.5 * clearance_um, rollers.drop_um,
                               rollers.stiffness_n_per_mm)


@njit(cache=True)
def cycle_equivalent_lamina_loads(approach_um, load_angle_rad, clearance_um, rollers, points, out):
    """Each lamina's dynamic equivalent load on one raceway over a load cycle [N] into out (n_s,):
    state s loads the bearing with the rings' approach delta_r,s along the direction phi_s in that
    raceway's frame. A raceway point at theta sees, in state s, the lamina load of a roller at
    theta - phi_s from the load line, q_k = (c_l/n_s) (delta_r,s cos(theta - phi_s) - G/2 - 2 P_k)^(10/9);
    over the cycle its equivalent is (mean_s q^4)^(1/4) (a point's stress cycles, Miner's rule
    with the line contact's exponent 4); over the raceway's ``points`` points the lamina's
    equivalent is (mean_theta q_theta^4.5)^(1/4.5). For a raceway stationary relative to a constant
    load this is ISO/TS 16281's stationary-ring formula (exponent 4.5 over the roller positions); for
    one rotating relative to it, the rotating-ring formula (4 over the positions): the two cases the
    standard gives (tests), and every mixture of them that a crank bearing sees in between (its load
    turns against both rings: docs/capacity.md). Source: ISO/TS 16281:2008, Eqs. (61)-(64)
    (public implementation's numbering) and Lundberg-Palmgren's survival of a raceway (Harris &
    Kotzalas 5th ed., vol. 2, ch. 8); the generalisation over states is ours."""
    n_s = rollers.drop_um.size
    states = approach_um.size
    for k in range(n_s):
        total = 0.0
        for i in range(points):
            theta = 2.0 * math.pi * i / points
            s4 = 0.0
            for s in range(states):
                d = approach_um[s] * math.cos(theta - load_angle_rad[s]) - 0.5 * clearance_um - 2.0 * rollers.drop_um[k]
                if d > 0.0:
                    q = rollers.stiffness_n_per_mm / n_s * (d * 1e-3) ** (10.0 / 9.0)
                    s4 += q ** 4
            if s4 > 0.0:
                total += (s4 / states) ** (4.5 / 4.0)
        out[k] = (total / points) ** (1.0 / 4.5)
