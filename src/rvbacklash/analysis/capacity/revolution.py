"""Loads over a revolution (docs/capacity.md): one unit's elements' loads at a set of crank angles
over one crank revolution against the carrier, at a given output torque, from the elastic
solution. The typed result (``RevolutionLoads``) is what the ratings read, and what the wear and
losses work read (each contact's force at each angle; its geometry through ``LoadGeometry``).

One crank revolution against the carrier is Delta chi = 2 pi z_c / z_p of the eccentric's angle
chi (the output turns 1 / z_p of a revolution): every crank bore sweeps once round its disc's
eccentric, the pins' pattern repeats z_c times (once per pin pitch of chi). ``CrankAngles`` takes
K angles that sweep it evenly and lie in as many places of an output revolution (``crank_angles``):
the nominal unit sees one crank revolution, a unit with errors also meets its pins and teeth at K
places of its output revolution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.models import compliance as cm
from rvbacklash.models.elastic import ElasticModel, PreparedUnit, unit_from_realization
from rvbacklash.models.elastic.chain import PIN_SEATING, PINS
from rvbacklash.models.elastic.loads import (LoadGeometry, RollerSet, crank_bearing_loads, crank_torques_nmm,
                                             disc_resultants, pin_stresses_mpa, roller_loads_n,
                                             roller_set_approach_um, support_bearing_loads)
from rvbacklash.models.elastic.rollers import ROLLER_SLICES, sliced_roller
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result

DEFAULT_ANGLES = 24  # crank angles per revolution: the rv80e life converged to < 0.2 % (tests; docs/capacity.md)
MAX_ANGLES = 4096


def load_geometry(problem: Problem, model: ElasticModel) -> LoadGeometry:
    """The LoadGeometry of a design's elastic model (the crankshafts' statics from [structure]; none:
    support span 0)."""
    g, c, geo = model.geometry, model.chain, problem.geometry
    st = model.structure
    s1 = problem.design.first_stage
    return LoadGeometry(
        eccentricity_mm=g.a_mm, cycloid_teeth=float(g.zc), pins=float(g.zp), pin_circle_radius_mm=g.rp_mm,
        pin_radius_mm=g.rrp_mm, generating_radius_mm=c.generating_radius_mm, k1=g.K1, discs=int(g.discs),
        cranks=int(s1.planets), crank_circle_radius_mm=model.crank_circle_radius_mm,
        contact_length_mm=c.contact_length_mm,
        e_star_n_per_mm2=cm.contact_modulus_n_per_mm2(c.pin_e_gpa, c.pin_nu, c.disc_e_gpa, c.disc_nu),
        support_span_mm=st.crankshaft_support_span_mm if st is not None else 0.0,
        disc_spacing_mm=st.disc_spacing_mm if st is not None else 0.0,
        gear_offset_mm=st.crankshaft_torsion_length_mm if st is not None else 0.0,
        planet_pitch_radius_mm=geo.planet_pitch_radius_mm, pressure_angle_rad=math.radians(geo.pressure_angle_deg))


def needle_rollers(model: ElasticModel) -> RollerSet:
    """The crank needle bearing's rollers as ISO/TS 16281 slices them: the design's profile
    (``rollers.sliced_roller``; straight: ROLLER_SLICES slices without drop), ISO's roller constant."""
    e = model.inputs
    roller = sliced_roller(e.crank_bearing_roller_profile, e.crank_bearing_roller_length_mm,
                           e.crank_bearing_roller_diameter_mm, False, e.crank_bearing_roller_crown_drop_um,
                           e.crank_bearing_roller_log_scale_um)
    drop = roller.drop_um if roller.drop_um.size else np.zeros(ROLLER_SLICES)
    z = e.crank_bearing_rollers
    return RollerSet(np.cos(2.0 * math.pi * np.arange(z) / z), np.ascontiguousarray(drop, float),
                     float(cm.iso_roller_constant_n_per_mm(e.crank_bearing_roller_length_mm)))


def crank_angles(chi0_rad: float, zc: int, zp: int, angles: int) -> np.ndarray:
    """K crank angles from chi0 that sweep one crank revolution against the carrier evenly and spread
    over one output revolution: chi_k = chi0 + 2 pi (z_c / z_p) (k / K + floor(k z_p / K)) [rad]. A
    whole crank revolution (2 pi z_c / z_p of chi) brings every crank bore back to the same place
    against its eccentric and the pins' nominal pattern back to itself (z_c pin pitches), so the
    nominal unit's states are those of one crank revolution; a unit's pins and teeth meet each other
    at K places of its output revolution."""
    if not (isinstance(angles, int) and 1 <= angles <= MAX_ANGLES):
        raise InputError("angles", angles, f"allowed: an integer from 1 to {MAX_ANGLES} (crank angles per revolution)")
    k = np.arange(angles)
    return chi0_rad + 2.0 * math.pi * zc / zp * (k / angles + np.floor(k * zp / angles))


class CrankAngles:
    """One unit prepared at each of K crank angles (``models.elastic.PreparedUnit``), solved at any
    output torque: the pins' forces at each angle (``pin_forces_n``). Built once per unit; each
    torque costs K solves of the chain."""

    def __init__(self, problem: Problem, model: ElasticModel, realization: Realization, involute_backlash_rad: float,
                 crank_clearance_um: float, angles: int = DEFAULT_ANGLES):
        self.problem, self.model = problem, model
        self.crank_clearance_um = float(crank_clearance_um)
        g = model.geometry
        self.chi_rad = crank_angles(float(realization.chi_rad), g.zc, g.zp, angles)
        self.units = [PreparedUnit(model, unit_from_realization(problem, realization.with_(chi_rad=float(chi)),
                                                                 involute_backlash_rad, crank_clearance_um))
                      for chi in self.chi_rad]
        self._cache: dict[float, np.ndarray] = {}

    def pin_forces_n(self, output_torque_nm: float) -> np.ndarray:
        """(K, discs, z_p): every pin's force at each angle when the chain carries the output torque
        [N] (the chain's torque = the output torque: the output's friction, a few N m, is left out)."""
        t = float(output_torque_nm)
        if t not in self._cache:
            out = []
            for pu in self.units:
                a = pu.chain(t, 1.0 if t >= 0.0 else -1.0)
                out.append(pu.pin_forces_n(float(a[PINS] + a[PIN_SEATING])))
            self._cache[t] = np.array(out)
        return self._cache[t]


@dataclass(frozen=True, repr=False)
class RevolutionLoads(Result):
    """Every element's load of one unit at K crank angles over one crank revolution against the
    carrier, at one output torque (housing frame at each instant; docs/capacity.md). Arrays:
    K first, then discs, cranks, pins or rollers; vectors (x, y) last. Rollers are numbered from
    the load line (roller 0 on it)."""

    output_torque_nm: float
    crank_angle_rad: np.ndarray  # (K,) the eccentric's angle chi of each state
    pin_force_n: np.ndarray  # (K, discs, z_p) each pin's normal force on its disc [N]
    pin_stress_mpa: np.ndarray  # (K, discs, z_p) peak Hertz pressure of each pin-flank contact [MPa]
    disc_force_n: np.ndarray  # (K, discs, 2) the pins' resultant on each disc [N]
    disc_moment_nm: np.ndarray  # (K, discs) the pins' moment about each disc's centre [N m]
    crank_bearing_load_n: np.ndarray  # (K, discs, cranks, 2) the load each needle bearing carries [N]
    crank_bearing_inner_angle_rad: np.ndarray  # (K, discs, cranks) the load's direction on the eccentric (inner ring)
    crank_bearing_outer_angle_rad: np.ndarray  # (K, discs, cranks) ... on the disc's bore (outer ring)
    crank_bearing_approach_um: np.ndarray  # (K, discs, cranks) the rings' radial approach (ISO/TS 16281 slices)
    crank_bearing_roller_load_n: np.ndarray  # (K, discs, cranks, Z) each needle's load, from the load line
    crank_torque_nm: np.ndarray  # (K, cranks) each crank's torque from its eccentrics [N m]
    support_bearing_load_n: np.ndarray  # (K, cranks, 2, 2) the load on each crank's support A and B [N]
    crank_clearance_um: float = field(default=0.0)
    geometry: LoadGeometry | None = field(default=None, metadata={EXPORT: False})

    @property
    def crank_bearing_load_magnitude_n(self) -> np.ndarray:
        return np.hypot(self.crank_bearing_load_n[..., 0], self.crank_bearing_load_n[..., 1])

    @property
    def support_bearing_load_magnitude_n(self) -> np.ndarray:
        return np.hypot(self.support_bearing_load_n[..., 0], self.support_bearing_load_n[..., 1])

    @property
    def crank_torque_shares(self) -> np.ndarray:
        """(K, cranks): each crank's share of the cranks' torque."""
        total = self.crank_torque_nm.sum(axis=1, keepdims=True)
        return np.divide(self.crank_torque_nm, total, out=np.zeros_like(self.crank_torque_nm), where=total != 0)

    def summary(self) -> list[str]:
        return [f"output torque {self.output_torque_nm:g} N m, {self.crank_angle_rad.size} crank angles",
                f"largest pin force {self.pin_force_n.max():.0f} N, pin stress {self.pin_stress_mpa.max():.0f} MPa",
                f"largest needle bearing load {self.crank_bearing_load_magnitude_n.max():.0f} N"]

    def rows(self) -> list[dict]:
        """One row per crank angle: the largest pin force and stress, each needle bearing's and
        support bearing's load magnitude, each crank's torque share."""
        out = []
        nb = self.crank_bearing_load_magnitude_n
        sb = self.support_bearing_load_magnitude_n
        shares = self.crank_torque_shares
        for k, chi in enumerate(self.crank_angle_rad):
            row = {"crank_angle_deg": math.degrees(chi), "max_pin_force_n": float(self.pin_force_n[k].max()),
                   "max_pin_stress_mpa": float(self.pin_stress_mpa[k].max())}
            for d in range(nb.shape[1]):
                for c in range(nb.shape[2]):
                    row[f"needle_d{d}_c{c}_n"] = float(nb[k, d, c])
            for c in range(sb.shape[1]):
                row[f"support_c{c}_a_n"] = float(sb[k, c, 0])
                row[f"support_c{c}_b_n"] = float(sb[k, c, 1])
                row[f"crank_c{c}_torque_share"] = float(shares[k, c])
            out.append(row)
        return out


def revolution_loads(angles: CrankAngles, output_torque_nm: float, geometry: LoadGeometry,
                     needles: RollerSet) -> RevolutionLoads:
    """The RevolutionLoads of a unit prepared at its crank angles (``CrankAngles``) at an output
    torque [N m]."""
    forces = angles.pin_forces_n(output_torque_nm)
    k_n, discs, zp = forces.shape
    p = geometry.cranks
    z = needles.roller_cos.size
    stress = np.empty_like(forces)
    res = np.empty((k_n, discs, 3))
    bl = np.empty((k_n, discs, p, 2))
    torques = np.empty((k_n, p))
    support = np.zeros((k_n, p, 2, 2))
    approach = np.empty((k_n, discs, p))
    rollers = np.empty((k_n, discs, p, z))
    inner = np.empty((k_n, discs, p))
    outer = np.empty((k_n, discs, p))
    clearance = angles.crank_clearance_um
    for k, chi in enumerate(angles.chi_rad):
        chi = float(chi)
        pin_stresses_mpa(forces[k], chi, geometry, stress[k])
        disc_resultants(forces[k], chi, geometry, res[k])
        crank_bearing_loads(res[k], chi, geometry, bl[k])
        crank_torques_nmm(bl[k], chi, geometry, torques[k])
        if geometry.support_span_mm > 0.0:
            support_bearing_loads(bl[k], torques[k], chi, geometry, support[k])
        for d in range(discs):
            chi_d = chi + 2.0 * math.pi * d / discs
            for c in range(p):
                load = float(math.hypot(bl[k, d, c, 0], bl[k, d, c, 1]))
                phi = math.atan2(bl[k, d, c, 1], bl[k, d, c, 0])
                inner[k, d, c] = phi - chi_d  # the eccentric turns with chi_d
                outer[k, d, c] = phi + chi / geometry.cycloid_teeth  # the discs (and the carrier) turn by -chi / z_c
                approach[k, d, c] = roller_set_approach_um(load, clearance, needles)
                roller_loads_n(approach[k, d, c], clearance, needles, rollers[k, d, c])
    return RevolutionLoads(float(output_torque_nm), angles.chi_rad.copy(), forces, stress, res[..., :2].copy(),
                           res[..., 2] * 1e-3, bl, inner, outer, approach, rollers, torques * 1e-3, support,
                           clearance, geometry)
