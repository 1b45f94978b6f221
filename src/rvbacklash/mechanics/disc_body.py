"""The cycloid disc's body by finite elements (plane stress): its compliance between the pins'
contacts and the crank needle bearings, and how it shares the torque among the cranks
(docs/rigidity-elements.md). Computed once per design and load, cached (mechanics/fe_cache.py).

Frame: the disc frame of geometry/cycloid.py. Pin j sits at psi_j = 2 pi j / z_p on the pin
circle r_p of the housing; disc d is on its eccentric at chi_d = chi + 2 pi d / discs (centre
a (cos chi_d, sin chi_d)), turned by -chi_d / z_c. A point x of the housing is
R(chi_d / z_c) (x - a (cos chi_d, sin chi_d)) in the disc frame: origin at the disc's centre, axes
turned with the disc. The disc's crank bores and pillar holes are fixed in it
(geometry/disc_holes.py). In that frame pin j's centre lies on the pin-centre curve C at
t_j = chi_d - psi_j + 2 pi j; its contact point is p_j = C(t_j) - r_rp n_j with n_j C's outward unit
normal there, and the pin pushes the disc along -n_j (the normal passes through the pitch point).

The model:

- mesh: the nominal profile (``PinCentreCurve`` offset by the pin radius, the micrometre
  modifications left out) as a polyline of ``points_per_tooth`` vertices per tooth, minus the
  holes (gmsh, ``plane_mesh``); quadratic triangles, plane stress, thickness the disc's face width;
- loads: each pin's normal force as a uniform traction over a patch of the profile of half-width
  ``PATCH_HALF_WIDTH_PIN_RADII`` r_rp (0.5 mm for a 4 mm pin; the Hertz half-width at the rated
  load is ~0.1-0.2 mm: the patch only spreads the load over a few elements, its width does not
  reach the reading points one pin radius deeper, St Venant), applied as the consistent load of
  ``PATCH_SAMPLES`` equal point forces spread along it;
- supports: each crank bore on radial springs over the half of its boundary pressed against the
  rollers (a Winkler foundation, ``plane_stress.RadialSprings``), total stiffness the bearing's
  secant K in every direction; the half faces the bore's reaction, found by iteration (the
  cranks rigid);
- reading: the disc's rotation as the pins see it, theta = sum_j F_j . u(q_j) / T_d at q_j =
  p_j - r_rp n_j (one pin radius inside the contact: the local compression above it is the
  Hertz/Johnson law already in the chain; exact for a rigid motion since q_j lies on F_j's line),
  T_d = sum_j p_j x F_j; the same on a rigid disc on the same springs (the rigid-body modes of
  the same mesh: identical springs and loads); C_disc = (theta_flexible - theta_rigid) / T_d.

Linear: the springs are linear and the zones depend on the reactions' directions only, so the
result does not depend on the forces' scale.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass
from typing import NamedTuple

import numpy as np
from scipy.sparse.linalg import LinearOperator, cg, splu
from threadpoolctl import threadpool_limits

from rvbacklash.errors import InputError
from rvbacklash.geometry.cycloid import PinCentreCurve
from rvbacklash.geometry.disc_holes import Hole, crank_bore_diameter_mm, disc_holes
from rvbacklash.mechanics import plane_stress as ps
from rvbacklash.mechanics.fe_cache import cached
from rvbacklash.mechanics.plane_mesh import MeshError, circle_polyline, facets_on_circle, mesh_plate
from rvbacklash.problem import Problem

MODEL_VERSION = 1  # raise when the model computes something else (older cache files are then never read)
PATCH_HALF_WIDTH_PIN_RADII = 0.125  # a pin's load spread over +-r_rp / 8 of the profile (module docstring)
READING_DEPTH_PIN_RADII = 1.0  # the rotation is read this many pin radii below each contact (module docstring)
PATCH_SAMPLES = 12  # point forces per patch (their consistent load: a uniform traction within ~1e-3)
ZONE_PASSES = 8  # the bores' load zones follow their reactions (until no spring changes) in at most this many solves
CG_RTOL = 1e-10  # the zones' re-solves: residual / load (far below the mesh's error)
SPRING_CONDITION_MAX = 1e8  # the rigid disc on its springs: a larger condition number is a loose disc


@dataclass(frozen=True)
class MeshSize:
    """The disc's mesh: polyline vertices per tooth on the profile, segment length on the holes and
    the largest element inside [mm]. ``refined(f)``: every size divided by f."""

    points_per_tooth: int = 24
    hole_segment_mm: float = 1.6
    max_size_mm: float = 4.0

    def refined(self, factor: float) -> "MeshSize":
        return MeshSize(int(round(self.points_per_tooth * factor)), self.hole_segment_mm / factor,
                        self.max_size_mm / factor)


class PinLoad(NamedTuple):
    """The pins' forces on one disc in its frame (module docstring), the loaded pins only:
    their index j, contact points p_j [mm], outward normals n_j, forces F_j = -|F_j| n_j [N], reading
    points q_j [mm], curve parameters t_j, and the disc torque T_d = sum p_j x F_j [N mm]."""

    pins: np.ndarray
    contact_mm: np.ndarray
    normal: np.ndarray
    force_n: np.ndarray
    reading_mm: np.ndarray
    curve_t: np.ndarray
    torque_nmm: float


@dataclass(frozen=True)
class DiscBodyResult:
    """The disc bodies by FE (module docstring), one disc or several in parallel
    (``disc_body_compliance``). Rotations at the given pin forces (the discs' mean); shares: each
    crank's reaction's moment about the disc centre beyond an equal third of the resultant, over
    T_d (they sum to 1 per disc; a rigid disc on equal bearings gives equal thirds); reactions:
    each crank bore's force magnitude [N]; sizes of one disc's mesh; wall time of all."""

    compliance_rad_per_nm: float  # C_disc = (theta_flexible - theta_rigid) / T_d
    disc_torque_nm: float  # T_d: the pins' moment about the disc centre [N m] (signed: < 0 clockwise)
    flexible_rotation_rad: float
    rigid_rotation_rad: float
    crank_torque_shares: tuple[float, ...]
    rigid_crank_torque_shares: tuple[float, ...]
    crank_reactions_n: tuple[float, ...]
    rigid_crank_reactions_n: tuple[float, ...]
    disc_compliances_rad_per_nm: tuple[float, ...]  # each disc's C_d
    discs: tuple[int, ...]  # which discs (the tuples above list them one after the other)
    chi_rad: float
    loaded_pins: int
    nodes: int
    elements: int
    dofs: int
    zone_passes: int
    spring_condition_number: float
    wall_time_s: float  # of the computation (a cache hit returns the first one's)

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> "DiscBodyResult":
        return cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in d.items()})


# --- loads -------------------------------------------------------------------------------------

def pin_load(problem: Problem, chi_rad: float, disc: int, force_n: np.ndarray) -> PinLoad:
    """The pins' normal forces on ``disc`` at crank angle ``chi_rad`` as contact points and force
    vectors in the disc's frame (module docstring). ``force_n``: (z_p,) the chain's per-pin normal
    forces [N] (0 for an open pin), signed along the pin's push: a change of load may unload a pin
    (< 0; ``models.elastic.bodies.disc_load_n``: a preloaded unit's opposite pins)."""
    g = problem.cycloid
    force = np.asarray(force_n, float)
    if force.shape != (g.zp,) or not np.all(np.isfinite(force)):
        raise InputError("pin_forces_n", force.shape if force.shape != (g.zp,) else "not finite",
                         f"allowed: {g.zp} finite forces [N] per disc (one per pin)")
    chi_d = g.disc_crank_angle(chi_rad, disc)
    j = np.flatnonzero(force != 0)
    t = chi_d - g.pin_angles[j] + 2 * math.pi * j
    curve = PinCentreCurve(g.a_mm, g.rp_mm, g.zc)
    n = curve.outward_normal(t)
    p = curve.point(t) - g.rrp_mm * n
    f = -force[j, None] * n
    torque = float(np.sum(p[:, 0] * f[:, 1] - p[:, 1] * f[:, 0]))
    return PinLoad(j, p, n, f, p - READING_DEPTH_PIN_RADII * g.rrp_mm * n, t, torque)


def ideal_pin_forces_n(problem: Problem, chi_rad: float, disc_torque_nm: float) -> np.ndarray:
    """(discs, z_p) normal forces [N] of a perfect stage with zero clearance and equal linear contacts:
    every pin whose lever h_j = (p_j x -n_j) is positive closes by h_j beta, so F_j = T_d h_j /
    sum h_k^2 (each disc carrying T_d [N m], counter-clockwise). Source: ours (equal springs:
    closure proportional to the lever, sum F_j h_j = T_d). For the FE check of a nominal design."""
    g = problem.cycloid
    out = np.zeros((g.discs, g.zp))
    for d in range(g.discs):
        load = pin_load(problem, chi_rad, d, np.ones(g.zp))
        lever = load.contact_mm[:, 0] * load.force_n[:, 1] - load.contact_mm[:, 1] * load.force_n[:, 0]
        lever = np.maximum(lever, 0.0)
        out[d, load.pins] = disc_torque_nm * 1e3 * lever / np.sum(lever * lever)
    return out


def _profile(problem: Problem, points_per_tooth: int) -> tuple[np.ndarray, np.ndarray]:
    """The nominal profile polyline (n, 2) [mm] at t_k = 2 pi z_c k / n, and its cumulative arc
    length (n + 1) [mm]."""
    g = problem.cycloid
    curve = PinCentreCurve(g.a_mm, g.rp_mm, g.zc)
    t = np.linspace(0.0, 2 * math.pi * g.zc, points_per_tooth * g.zc, endpoint=False)
    pts = curve.point(t) - g.rrp_mm * curve.outward_normal(t)
    seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    return pts, np.concatenate([[0.0], np.cumsum(seg)])


def _patch_points(profile: np.ndarray, arc: np.ndarray, t: np.ndarray, contact: np.ndarray, zc: int,
                  half_width_mm: float, normal: np.ndarray) -> np.ndarray:
    """(pins, PATCH_SAMPLES, 2): points spread evenly along the profile polyline over +-half_width
    about each contact point (its foot on the polyline, found near the vertex of its parameter t),
    moved 1e-6 mm inside (the point finder's side of the edge)."""
    n = len(profile)
    k0 = np.floor(np.mod(t, 2 * math.pi * zc) / (2 * math.pi * zc) * n).astype(int)
    best = np.full(len(t), np.inf)
    centre = np.zeros(len(t))
    for shift in (-2, -1, 0, 1, 2):  # the foot lies on the segment of t or a neighbour
        k = (k0 + shift) % n
        a, b = profile[k], profile[(k + 1) % n]
        ab = b - a
        along = np.clip(np.sum((contact - a) * ab, axis=1) / np.sum(ab * ab, axis=1), 0.0, 1.0)
        gap = np.linalg.norm(a + along[:, None] * ab - contact, axis=1)
        closer = gap < best
        best = np.where(closer, gap, best)
        centre = np.where(closer, arc[k] + along * (arc[k + 1] - arc[k]), centre)
    offsets = half_width_mm * ((np.arange(PATCH_SAMPLES) + 0.5) / PATCH_SAMPLES * 2.0 - 1.0)
    where = np.mod(centre[:, None] + offsets[None, :], arc[-1])
    closed = np.vstack([profile, profile[:1]])
    x = np.interp(where, arc, closed[:, 0])
    y = np.interp(where, arc, closed[:, 1])
    return np.stack([x, y], axis=-1) - 1e-6 * normal[:, None, :]


# --- the model ---------------------------------------------------------------------------------

class DiscInputs(NamedTuple):
    """What the disc's FE reads of a design (``disc_inputs``)."""

    holes: tuple[Hole, ...]
    youngs_modulus_mpa: float
    poisson_ratio: float
    thickness_mm: float


def disc_inputs(problem: Problem, disc: int) -> DiscInputs:
    """The holes of ``disc`` in its frame, its material and thickness, from the design's [elastic]
    and [structure] tables (design/structure.py checks them)."""
    design = problem.design
    st, e = design.structure, design.elastic
    if st is None or st.disc_pillar_hole_diameter_mm is None or e is None:
        raise InputError("structure.disc_pillar_hole_diameter_mm", None,
                         "required for the disc bodies' finite elements, with an [elastic] table; allowed: the "
                         "pillar holes' diameter [mm]")
    raceway = e.crank_bearing_raceway_diameter_mm or design.crank_stage.bearing_bore_mm
    bore_field = ("elastic.crank_bearing_raceway_diameter_mm" if e.crank_bearing_raceway_diameter_mm is not None
                  else "crank_stage.bearing_bore_mm")
    g = problem.cycloid
    holes = disc_holes(design.first_stage.planets, problem.geometry.crank_circle_radius_mm,
                       crank_bore_diameter_mm(raceway, e.crank_bearing_roller_diameter_mm), bore_field,
                       st.carrier_pillars, st.disc_pillar_hole_radius_mm or st.pillar_radius_mm,
                       st.disc_pillar_hole_diameter_mm, st.disc_centre_hole_diameter_mm,
                       turn_rad=2 * math.pi * disc / (g.discs * g.zc))
    return DiscInputs(holes, e.disc_youngs_modulus_gpa * 1e3, e.disc_poisson_ratio, e.disc_face_width_mm)


def disc_body_compliance(problem: Problem, chi_rad: float, pin_forces_n: np.ndarray,
                         bearing_stiffness_n_per_um: float, *, disc: int | None = None,
                         mesh: MeshSize = MeshSize()) -> DiscBodyResult:
    """The disc bodies' compliance C_disc [rad/(N m)] and the cranks' load shares at crank angle
    ``chi_rad``, loaded by ``pin_forces_n`` ((discs, z_p) normal forces [N], 0 for open pins; signed:
    a load's change may unload a pin, ``pin_load``) and held by needle bearings of secant stiffness
    ``bearing_stiffness_n_per_um`` [N/um] each.

    ``disc``: None (default) computes every loaded disc and combines them as the chain has them, in
    parallel: C_disc = n / sum_d (1 / C_d) (n the design's discs, the sum over the loaded ones), so
    that the chain's k^2 C_disc / n is exactly the discs' parallel compliance k^2 / sum_d (1 / C_d)
    (rv80e: the two discs differ by up to ~15 % at a crank angle, each seeing the pins' zone at
    another place against its bores); the tuples list the discs one after the other. An int
    computes that disc alone. Each disc is computed once per input
    (memory and disk cache)."""
    forces = np.asarray(pin_forces_n, float)
    g = problem.cycloid
    if forces.ndim != 2 or forces.shape != (g.discs, g.zp):
        raise InputError("pin_forces_n", forces.shape, f"allowed: shape ({g.discs}, {g.zp}) (discs, pins) [N]")
    if not (math.isfinite(bearing_stiffness_n_per_um) and bearing_stiffness_n_per_um > 0):
        raise InputError("bearing_stiffness_n_per_um", bearing_stiffness_n_per_um, "allowed: > 0 [N/um]")
    if disc is not None and not (isinstance(disc, int) and 0 <= disc < g.discs):
        raise InputError("disc", disc, f"allowed: None (every disc) or 0 to {g.discs - 1}")
    chosen = [disc] if disc is not None else [d for d in range(g.discs) if np.any(forces[d] != 0)]
    if not chosen or not all(np.any(forces[d] != 0) for d in chosen):
        raise InputError("pin_forces_n", 0.0, "allowed: at least one loaded pin on the disc(s) computed")
    results = [_one_disc(problem, float(chi_rad), d, forces[d], float(bearing_stiffness_n_per_um), mesh)
               for d in chosen]
    return results[0] if disc is not None else _in_parallel(results, g.discs)


def _one_disc(problem: Problem, chi_rad: float, disc: int, force_n: np.ndarray, bearing_n_per_um: float,
              mesh: MeshSize) -> DiscBodyResult:
    """One disc, through the cache (keyed by everything the model reads)."""
    g = problem.cycloid
    d = disc_inputs(problem, disc)
    inputs = {"zc": g.zc, "zp": g.zp, "a_mm": g.a_mm, "rp_mm": g.rp_mm, "rrp_mm": g.rrp_mm, "discs": g.discs,
              "holes": [list(h) for h in d.holes], "e_mpa": d.youngs_modulus_mpa, "nu": d.poisson_ratio,
              "thickness_mm": d.thickness_mm, "chi_rad": chi_rad, "disc": disc,
              "forces_n": [float(x) for x in force_n], "bearing_n_per_um": bearing_n_per_um,
              "mesh": asdict(mesh), "patch": [PATCH_HALF_WIDTH_PIN_RADII, PATCH_SAMPLES],
              "reading_depth": READING_DEPTH_PIN_RADII, "zones": ZONE_PASSES}
    def compute() -> dict:
        with threadpool_limits(1, user_api="blas"):  # as the carrier's solve (mechanics/solid.py)
            return _solve(problem, chi_rad, disc, force_n, bearing_n_per_um, d, mesh).to_dict()

    result = cached("disc_body", MODEL_VERSION, inputs, compute)
    return DiscBodyResult.from_dict(result)


def _in_parallel(results: list[DiscBodyResult], discs: int) -> DiscBodyResult:
    """Discs tied by the cranks (one rotation): compliances in parallel, per disc n / sum_d 1 / C_d over
    the loaded discs (a disc without load carries nothing: k^2 C_disc / n is still the stage's)."""
    return DiscBodyResult(
        compliance_rad_per_nm=discs / sum(1.0 / r.compliance_rad_per_nm for r in results),
        disc_torque_nm=float(np.mean([r.disc_torque_nm for r in results])),
        flexible_rotation_rad=float(np.mean([r.flexible_rotation_rad for r in results])),
        rigid_rotation_rad=float(np.mean([r.rigid_rotation_rad for r in results])),
        crank_torque_shares=sum((r.crank_torque_shares for r in results), ()),
        rigid_crank_torque_shares=sum((r.rigid_crank_torque_shares for r in results), ()),
        crank_reactions_n=sum((r.crank_reactions_n for r in results), ()),
        rigid_crank_reactions_n=sum((r.rigid_crank_reactions_n for r in results), ()),
        disc_compliances_rad_per_nm=sum((r.disc_compliances_rad_per_nm for r in results), ()),
        discs=sum((r.discs for r in results), ()), chi_rad=results[0].chi_rad,
        loaded_pins=sum(r.loaded_pins for r in results), nodes=max(r.nodes for r in results),
        elements=max(r.elements for r in results), dofs=max(r.dofs for r in results),
        zone_passes=sum(r.zone_passes for r in results),
        spring_condition_number=max(r.spring_condition_number for r in results),
        wall_time_s=sum(r.wall_time_s for r in results))


def _mesh_disc(problem: Problem, holes: tuple[Hole, ...], mesh: MeshSize):
    profile, arc = _profile(problem, mesh.points_per_tooth)
    loops = [circle_polyline(h.x_mm, h.y_mm, h.radius_mm, mesh.hole_segment_mm) for h in holes]
    try:
        m = mesh_plate(profile, loops, mesh.max_size_mm)
    except MeshError as exc:
        fields = sorted({h.field for h in holes})
        raise InputError("structure.disc_pillar_hole_diameter_mm",
                         allowed=f"gmsh could not mesh the disc with these holes ({exc}); allowed: holes apart from "
                                 f"each other and inside the profile ({', '.join(fields)})")
    return m, profile, arc


class _Disc(NamedTuple):
    """One disc's assembled model: its mesh's rigid modes G, elastic stiffness, the pins' load
    vector and their reading, the crank bores and their springs."""

    modes: np.ndarray
    stiffness: object  # sparse [N/mm]
    load: np.ndarray  # f [N]
    reading: object  # point operator at the reading points q_j
    forces_n: np.ndarray  # F_j (pins, 2)
    torque_nmm: float  # the load's moment about the centre
    bores: list
    supports: list  # plane_stress.RadialSprings, one per bore

    def springs(self, zones):
        return [s.stiffness(z) for s, z in zip(self.supports, zones)]

    def reactions(self, mats, u) -> np.ndarray:
        """Each bore's reaction on the disc: (F_x, F_y, moment about the centre) [N, N mm]."""
        return np.array([self.modes.T @ -(s @ u) for s in mats])

    def rotation(self, u) -> float:
        """theta = sum_j F_j . u(q_j) / T_d [rad] (module docstring)."""
        return float(np.sum(self.forces_n * ps.point_values(self.reading, u))) / self.torque_nmm


def _assemble(problem: Problem, chi_rad: float, disc: int, force_n: np.ndarray, bearing_n_per_um: float,
              d: DiscInputs, mesh: MeshSize) -> tuple[_Disc, object]:
    g = problem.cycloid
    pins = pin_load(problem, chi_rad, disc, force_n)
    m, profile, arc = _mesh_disc(problem, d.holes, mesh)
    basis = ps.scalar_basis(m)
    modes = ps.rigid_modes(basis)
    patches = _patch_points(profile, arc, pins.curve_t, pins.contact_mm, g.zc, PATCH_HALF_WIDTH_PIN_RADII * g.rrp_mm,
                            pins.normal)
    f = ps.point_loads(ps.point_operator(basis, patches.reshape(-1, 2)),
                       np.repeat(pins.force_n / PATCH_SAMPLES, PATCH_SAMPLES, axis=0))
    bores = [h for h in d.holes if h.kind == "crank_bore"]
    k_line = ps.winkler_line_stiffness(bearing_n_per_um * 1e3, bores[0].radius_mm)
    supports = [ps.RadialSprings(m, basis, facets_on_circle(m, h.x_mm, h.y_mm, h.radius_mm,
                                                            0.05 * mesh.hole_segment_mm), (h.x_mm, h.y_mm), k_line)
                for h in bores]
    model = _Disc(modes, ps.stiffness_matrix(basis, d.youngs_modulus_mpa, d.poisson_ratio, d.thickness_mm), f,
                  ps.point_operator(basis, pins.reading_mm), pins.force_n,
                  float((modes.T @ f)[2]),  # the patches' moment: T_d to ~1e-4 (the polyline), in equilibrium exactly
                  bores, supports)
    return model, m


def _rigid(model: _Disc, bearing_n_per_um: float):
    """The rigid disc on the springs: (displacement, zones, passes, the condition number of its 3 x 3
    spring matrix, rotation scaled by the crank circle). First zones: each bore a third of the
    resultant and of the torque."""
    resultant = model.forces_n.sum(axis=0)
    zones = [-resultant / 3 - model.torque_nmm / (3 * (h.x_mm ** 2 + h.y_mm ** 2)) * np.array([-h.y_mm, h.x_mm])
             for h in model.bores]
    scale = np.array([1.0, 1.0, 1.0 / math.hypot(model.bores[0].x_mm, model.bores[0].y_mm)])
    for passes in range(1, ZONE_PASSES + 1):
        mats = model.springs(zones)
        k3 = model.modes.T @ (sum(mats) @ model.modes)
        cond = float(np.linalg.cond(k3 * scale[:, None] * scale[None, :]))
        if not cond < SPRING_CONDITION_MAX:
            raise InputError("bearing_stiffness_n_per_um", bearing_n_per_um,
                             f"the disc is not held by its bearings (condition number {cond:.3g}); allowed: > 0 with "
                             f"at least two crank bores")
        u = model.modes @ np.linalg.solve(k3, model.modes.T @ model.load)
        zones, settled = _follow(model.supports, zones, model.reactions(mats, u))
        if settled:
            break
    return u, zones, passes, cond


def _flexible(model: _Disc, zones):
    """The elastic disc on the springs, from the rigid disc's zones: (displacement, zones, passes).
    Factored once; the zones' small changes are solved by CG preconditioned with that factor."""
    first = u = None
    for passes in range(1, ZONE_PASSES + 1):
        mats = model.springs(zones)
        matrix = (model.stiffness + sum(mats)).tocsc()
        if first is None:
            first = _factor(matrix)
            u = first.solve(model.load)
        else:
            u = _refine(matrix, model.load, first, u)
        zones, settled = _follow(model.supports, zones, model.reactions(mats, u))
        if settled:
            break
    return u, zones, passes


def _solve(problem: Problem, chi_rad: float, disc: int, force_n: np.ndarray, bearing_n_per_um: float,
           d: DiscInputs, mesh: MeshSize) -> DiscBodyResult:
    start = time.perf_counter()
    model, m = _assemble(problem, chi_rad, disc, force_n, bearing_n_per_um, d, mesh)
    rigid, zones, passes_rigid, cond = _rigid(model, bearing_n_per_um)
    rigid_reactions = model.reactions(model.springs(zones), rigid)
    flexible, zones, passes = _flexible(model, zones)
    flexible_reactions = model.reactions(model.springs(zones), flexible)
    theta_f, theta_r = model.rotation(flexible), model.rotation(rigid)
    torque_nm = model.torque_nmm * 1e-3
    compliance = (theta_f - theta_r) / torque_nm
    return DiscBodyResult(
        compliance_rad_per_nm=compliance, disc_torque_nm=torque_nm,
        flexible_rotation_rad=theta_f, rigid_rotation_rad=theta_r,
        crank_torque_shares=_shares(flexible_reactions, model.bores, model.torque_nmm),
        rigid_crank_torque_shares=_shares(rigid_reactions, model.bores, model.torque_nmm),
        crank_reactions_n=tuple(float(x) for x in np.hypot(flexible_reactions[:, 0], flexible_reactions[:, 1])),
        rigid_crank_reactions_n=tuple(float(x) for x in np.hypot(rigid_reactions[:, 0], rigid_reactions[:, 1])),
        disc_compliances_rad_per_nm=(compliance,), discs=(disc,), chi_rad=float(chi_rad),
        loaded_pins=int(np.count_nonzero(np.asarray(force_n))), nodes=int(m.p.shape[1] + m.facets.shape[1]),
        elements=int(m.t.shape[1]), dofs=int(model.stiffness.shape[0]), zone_passes=passes_rigid + passes,
        spring_condition_number=cond, wall_time_s=time.perf_counter() - start)


def _refine(matrix, f, factor, start):
    """Solve matrix u = f by conjugate gradients preconditioned with the factors of a nearby matrix
    (the previous zones'): a few iterations, each one triangular solve."""
    precondition = LinearOperator(matrix.shape, matvec=factor.solve, dtype=float)
    u, info = cg(matrix, f, x0=start, M=precondition, rtol=CG_RTOL, maxiter=200)
    if info != 0:  # not converged (never seen): solve directly
        u = _factor(matrix).solve(f)
    return u


def _factor(matrix):
    """Sparse LU of a symmetric matrix: minimum-degree ordering of A^T + A and symmetric pivoting
    (half the fill and time of SuperLU's default COLAMD on the disc)."""
    return splu(matrix, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})


def _follow(supports, zones, reaction):
    """The zones turned to face each bore's reaction, and whether that leaves every spring as it was
    (then the solution that gave the reactions is the converged one)."""
    new = [r[:2] / np.hypot(r[0], r[1]) for r in reaction]
    settled = all(np.array_equal(s.active(z), s.active(n)) for s, z, n in zip(supports, zones, new))
    return new, settled


def _shares(reaction: np.ndarray, bores: list[Hole], torque_nmm: float) -> tuple[float, ...]:
    """Each crank's share of the torque: the moment about the disc centre of its reaction beyond an
    equal share of the resultant, -(h_c x (R_c - R / n)) / T_d (the equal share's moments cancel:
    sum h_c = 0). They sum to 1."""
    mean = reaction[:, :2].mean(axis=0)
    out = []
    for h, r in zip(bores, reaction):
        rx, ry = r[0] - mean[0], r[1] - mean[1]
        out.append(float(-(h.x_mm * ry - h.y_mm * rx) / torque_nmm))
    return tuple(out)
