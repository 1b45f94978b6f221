"""Each element's power loss over a crank revolution (docs/efficiency.md): the formulas of
``models/friction.py`` applied to the loads of the elastic solution (``analysis/capacity``'s
``RevolutionLoads``: every pin's force, every needle and support bearing's load at K crank angles)
and to the reducer's kinematics.

Speeds (housing fixed, output on the carrier; ``speeds``): the output (carrier) at omega_o; the
input (centre gear) at R omega_o, R = 1 + z_p z2 / z1; the cranks against the carrier at z_p omega_o
(their needle and support bearings' relative speed); the discs at omega_o against the housing about
their pitch point P (the pins' sliding, ``friction.pin_sliding_speed_m_s``); the centre gear against
the carrier at (R - 1) omega_o (the mesh's power in the carrier's frame). Each loss is a mean over the
K states of the revolution [W]; the mean input torque follows from the power balance
(``LossBreakdown.input_torque_nm``), and each element's loss referred to the input is P / omega_in.

Modes: ``running`` (the lubricated friction at the speed: the pins' coefficient from their film
parameter, the bearings' load and viscous terms, the mesh by ISO/TR 14179-2) and ``static``
(breakaway at standstill: no viscous terms, the static coefficient for the pins and the mesh, the
bearings' load terms, the seals), both evaluated per unit of output speed and read as torques.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.analysis.capacity.revolution import RevolutionLoads
from rvbacklash.design.lubrication import LubricationInputs
from rvbacklash.models import friction as fr
from rvbacklash.models.elastic.loads import pin_relative_radius_mm
from rvbacklash.problem import Problem

ELEMENTS = ("pins on flanks", "pins in seats", "crank needle bearings", "crank support bearings", "main bearings",
            "involute mesh", "output seal", "input seal and churning")
MAIN_BEARING_STATIC_AXIAL_FACTOR = 0.26  # ISO 76 Y0 of a single-row angular contact ball bearing at 40 deg
#                                          (X0 = 0.5): P0 = 0.5 F_r + 0.26 F_a, at least F_r


@dataclass(frozen=True)
class Speeds:
    """The reducer's speeds at an output speed [rad/s] (module docstring)."""

    output_rad_s: float
    input_rad_s: float
    crank_rad_s: float  # against the carrier
    centre_gear_rad_s: float  # against the carrier


def speeds(problem: Problem, output_speed_rpm: float) -> Speeds:
    """The Speeds of the reducer at an output speed [r/min]."""
    s1, s2 = problem.design.first_stage, problem.design.second_stage
    w = abs(output_speed_rpm) * 2.0 * math.pi / 60.0
    ratio = problem.geometry.ratio
    return Speeds(w, ratio * w, s2.pins * w, s2.pins * s1.planet_teeth / s1.centre_gear_teeth * w)


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
    hv = fr.gear_loss_factor(s1.planet_teeth / s1.centre_gear_teeth, s1.centre_gear_teeth, 0.0, e1 + e2, e1, e2)
    return MeshGeometry(hv, r1, r1 * r2 * math.sin(alpha) / (r1 + r2), alpha, s1.face_width_mm)


@dataclass(frozen=True)
class LossContext:
    """What the losses read of a design besides the loads (``loss_context``)."""

    problem: Problem
    lube: LubricationInputs
    mesh: MeshGeometry
    pin_relative_radius_mm: np.ndarray  # (K, discs, z_p) at the loads' crank angles
    pin_to_pitch_point_mm: np.ndarray  # (K, discs, z_p)
    e_prime_n_per_mm2: float
    contact_length_mm: float
    pin_radius_mm: float
    needle_pitch_diameter_mm: float
    support_pitch_diameter_mm: float | None
    main: tuple[int, float, float, float, float] | None  # balls, D_w, D_pw, alpha [deg], preload [N]


def loss_context(problem: Problem, model, loads: RevolutionLoads, lube: LubricationInputs | None = None) -> LossContext:
    """The LossContext of a design's elastic model at the crank angles of ``loads``."""
    g = loads.geometry
    chi = loads.crank_angle_rad
    k_n, discs, zp = loads.pin_force_n.shape
    rel = np.empty((k_n, discs, zp))
    dist = np.empty((k_n, discs, zp))
    psi = 2.0 * math.pi * np.arange(zp) / zp
    qx, qy = g.pin_circle_radius_mm * np.cos(psi), g.pin_circle_radius_mm * np.sin(psi)
    for k in range(k_n):
        for d in range(discs):
            chi_d = float(chi[k]) + 2.0 * math.pi * d / discs
            px, py = g.eccentricity_mm * g.pins * math.cos(chi_d), g.eccentricity_mm * g.pins * math.sin(chi_d)
            dist[k, d] = np.hypot(px - qx, py - qy)
            for j in range(zp):
                rel[k, d, j] = pin_relative_radius_mm(float(psi[j] - chi_d), g)
    st = model.structure
    support = None
    main = None
    if st is not None:
        support = st.support_bearing_pitch_diameter_mm or (
            0.5 * (st.crankshaft_diameter_mm + st.support_bearing_seat_diameter_mm)
            if st.support_bearing_seat_diameter_mm is not None else None)
        if st.main_bearing_balls is not None and st.main_bearing_pitch_diameter_mm is not None:
            main = (st.main_bearing_balls, st.main_bearing_ball_diameter_mm, st.main_bearing_pitch_diameter_mm,
                    st.main_bearing_contact_angle_deg, st.main_bearing_preload_n or 0.0)
    e = model.inputs
    return LossContext(problem, lube or problem.design.lubrication, mesh_geometry(problem), rel, dist,
                       2.0 * g.e_star_n_per_mm2, g.contact_length_mm, g.pin_radius_mm,
                       model.raceway_diameter_mm + e.crank_bearing_roller_diameter_mm, support, main)


@dataclass(frozen=True)
class LossBreakdown:
    """Each element's mean power loss over the revolution at one operating point [W] (``ELEMENTS``
    order), and the point. ``input_torque_nm`` closes the power balance."""

    output_torque_nm: float
    output_speed_rpm: float
    temperature_c: float
    mode: str
    ratio: float
    loss_w: tuple[float, ...]
    load_dependent_w: tuple[float, ...]  # the part of each that scales with the load (pins, bearings' M1, mesh)
    pin_film_parameter: float  # the pins' mean film parameter over the loaded contacts (running mode)
    pin_friction_coefficient: float  # the pins' load-weighted mean coefficient
    mesh_friction_coefficient: float

    @property
    def total_loss_w(self) -> float:
        return float(sum(self.loss_w))

    @property
    def output_power_w(self) -> float:
        return abs(self.output_torque_nm) * abs(self.output_speed_rpm) * 2.0 * math.pi / 60.0

    @property
    def input_power_w(self) -> float:
        return self.output_power_w + self.total_loss_w

    @property
    def input_torque_nm(self) -> float:
        """The mean input torque [N m]: P_in / omega_in (forward drive)."""
        w_in = self.ratio * abs(self.output_speed_rpm) * 2.0 * math.pi / 60.0
        return self.input_power_w / w_in if w_in > 0.0 else math.nan

    @property
    def efficiency(self) -> float:
        p = self.input_power_w
        return self.output_power_w / p if p > 0.0 else math.nan

    def element_input_torque_nm(self) -> tuple[float, ...]:
        """Each element's loss as a torque at the input [N m]."""
        w_in = self.ratio * abs(self.output_speed_rpm) * 2.0 * math.pi / 60.0
        return tuple(p / w_in for p in self.loss_w)


def element_losses(ctx: LossContext, loads: RevolutionLoads, output_speed_rpm: float, temperature_c: float,
                   mode: str = "running") -> LossBreakdown:
    """Every element's mean power loss over the revolution (module docstring) at the loads' output
    torque, an output speed [r/min] and the oil's temperature [degC]; ``mode`` running or static."""
    lube, problem = ctx.lube, ctx.problem
    static = mode == "static"
    n_out = abs(output_speed_rpm)
    sp = speeds(problem, n_out)
    nu = fr.kinematic_viscosity_mm2_s(temperature_c, lube.viscosity_40c_mm2_s, lube.viscosity_100c_mm2_s)
    eta = fr.dynamic_viscosity_pa_s(nu, lube.density_kg_m3)
    crank_rpm = problem.design.second_stage.pins * n_out

    # pins: sliding at the flank or in the seat (the smaller friction), coefficient from the film parameter
    f = loads.pin_force_n
    v = fr.pin_sliding_speed_m_s(ctx.pin_to_pitch_point_mm, ctx.pin_radius_mm, sp.output_rad_s)
    loaded = f > 0.0
    if static:
        mu_flank = np.full(f.shape, lube.static_friction_coefficient)
        mu_seat = lube.static_friction_coefficient
        lam_mean = 0.0
    else:
        # the pin standing in its seat: the disc's surface alone entrains the oil (u = v / 2)
        h = fr.line_contact_min_film_um(f / ctx.contact_length_mm, 0.5 * v, ctx.pin_relative_radius_mm,
                                        ctx.e_prime_n_per_mm2, eta, lube.pressure_viscosity_per_gpa * 1e-9)
        lam = fr.film_parameter(h, lube.pin_roughness_rq_um, lube.disc_roughness_rq_um)
        mu_flank = np.asarray(fr.mixed_friction_coefficient(lam, lube.boundary_friction_coefficient,
                                                            lube.full_film_friction_coefficient))
        mu_seat = lube.pin_seat_friction_coefficient
        lam_mean = float(np.mean(lam[loaded])) if loaded.any() else math.nan
    flank, seat = fr.pin_contact_loss_w(f, v, mu_flank, mu_seat)
    flank_w = float(np.sum(flank)) / f.shape[0]
    seat_w = float(np.sum(seat)) / f.shape[0]
    weight = float(np.sum(f[loaded]))
    mu_pins = float(np.sum(np.minimum(mu_flank, mu_seat)[loaded] * f[loaded]) / weight) if weight > 0 else math.nan

    # crank needle bearings: Palmgren, P1 = the radial load at each state
    needle_load = loads.crank_bearing_load_magnitude_n
    dm = ctx.needle_pitch_diameter_mm
    m1 = fr.palmgren_load_moment_nmm(lube.needle_bearing_f1, 1.0, dm) * needle_load
    m0 = 0.0 if static else fr.palmgren_viscous_moment_nmm(lube.needle_bearing_f0, nu, crank_rpm, dm)
    count = needle_load.shape[1] * needle_load.shape[2]
    needle_w1 = float(np.sum(m1)) / needle_load.shape[0] * 1e-3 * sp.crank_rad_s
    needle_w = needle_w1 + count * m0 * 1e-3 * sp.crank_rad_s

    # support bearings (tapered pairs: Palmgren's F_beta = 2 Y F_a = F_r for the pair's induced thrust)
    support_w = support_w1 = 0.0
    if ctx.support_pitch_diameter_mm is not None and loads.geometry.support_span_mm > 0.0:
        sl = loads.support_bearing_load_magnitude_n
        dm = ctx.support_pitch_diameter_mm
        m1 = fr.palmgren_load_moment_nmm(lube.support_bearing_f1, 1.0, dm) * sl
        m0 = 0.0 if static else fr.palmgren_viscous_moment_nmm(lube.support_bearing_f0, nu, crank_rpm, dm)
        support_w1 = float(np.sum(m1)) / sl.shape[0] * 1e-3 * sp.crank_rad_s
        support_w = support_w1 + sl.shape[1] * sl.shape[2] * m0 * 1e-3 * sp.crank_rad_s

    # main bearings: the preloaded angular contact pair at the output's speed (pure torque: no external load)
    main_w = main_w1 = 0.0
    if ctx.main is not None:
        balls, dw, dpw, alpha, preload = ctx.main
        c0 = fr.ball_static_rating_n(balls, dw, alpha)
        f1 = lube.main_bearing_f1_scale / 0.001 * fr.angular_ball_f1(MAIN_BEARING_STATIC_AXIAL_FACTOR * preload, c0)
        m1 = fr.palmgren_load_moment_nmm(f1, fr.angular_ball_load_n(preload, 0.0), dpw)
        m0 = 0.0 if static else fr.palmgren_viscous_moment_nmm(lube.main_bearing_f0, nu, n_out, dpw)
        main_w1 = 2.0 * m1 * 1e-3 * sp.output_rad_s
        main_w = main_w1 + 2.0 * m0 * 1e-3 * sp.output_rad_s

    # the involute mesh (ISO/TR 14179-2) in the carrier's frame: each crank's torque through its planet
    mg = ctx.mesh
    r2 = problem.geometry.planet_pitch_radius_mm
    ft = np.abs(loads.crank_torque_nm) * 1e3 / r2  # (K, cranks) tooth force at the pitch circle [N]
    mesh_power = float(np.mean(np.sum(ft * r2 * 1e-3 * sp.crank_rad_s, axis=1)))
    if static:
        mu_mesh = lube.static_friction_coefficient
    else:
        vt = mg.pitch_radius_mm * 1e-3 * sp.centre_gear_rad_s
        fbt_b = float(np.mean(ft)) / math.cos(mg.pressure_angle_rad) / mg.face_width_mm
        mu_mesh = fr.mesh_friction_coefficient(fbt_b, 2.0 * vt * math.sin(mg.pressure_angle_rad),
                                               mg.relative_radius_mm, eta * 1e3, lube.gear_roughness_ra_um,
                                               lube.mesh_lubricant_factor)
    mesh_w = fr.mesh_power_loss_w(mesh_power, mu_mesh, mg.loss_factor)

    seal_w = lube.output_seal_torque_nm * sp.output_rad_s
    input_w = (lube.input_seal_torque_nm + lube.churning_torque_nm) * sp.input_rad_s
    losses = (flank_w, seat_w, needle_w, support_w, main_w, mesh_w, seal_w, input_w)
    load_dep = (flank_w, seat_w, needle_w1, support_w1, 0.0, mesh_w, 0.0, 0.0)
    return LossBreakdown(float(loads.output_torque_nm), n_out, float(temperature_c), mode, problem.geometry.ratio,
                         losses, load_dep, lam_mean, mu_pins, float(mu_mesh))
