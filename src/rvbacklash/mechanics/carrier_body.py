"""The carrier (output flange, pillars, end plate) as one 3-D body by finite elements, once per
design (docs/rigidity-elements.md).

**Body** (``carrier_mesh``): the output flange, the pillars and the end plate fused into one
solid with the support bearings' seats bored in both plates; quadratic tetrahedra in scikit-fem
(``solid``), one cyclic sector when the pillars repeat with the cranks (``carrier_mesh.sectors``),
else the whole body.

**Supports.** The flange's outer face z = 0, where the load is bolted on the bench, is held
(all displacements zero).

**Loads.** Each crank bears on the flange and on the end plate through one support bearing; with
the two discs symmetric about mid-span each bearing carries half of both discs' forces on its
crank, tangential to the crank circle: F_s = k T / (2 n_c a0) per seat (``seat_force_n_per_nm``).
The bearing's outer ring presses the loaded half of the seat's bore with a cosine pressure
p(psi) = p0 cos(psi), |psi| < 90 deg from the force's direction, over the bore's depth; p0 is
set so that the pressure's resultant is F_s.

**Output compliance.** The work-conjugate rotation C = sum_s F_s . u_s / T, u_s the seat's
pressure-weighted mean displacement (= f . u / T^2 with the load vector f of the torque T). By
virtual work this is the output's turn: the discs sit at the cranks' mid-span, so their crank
points move by the mean of the crank's two seats, (u_flange + u_end) / 2, tangentially; the
discs turn that over a0 against the held flange face, the output k times that (``lever_factor``,
``models.compliance.cycloid_lever_factor``). With rigid plates and pillars clamped in them, the
flange seats stand still and the end plate turns phi = c_p V / R_p (V = k T / (2 n_p R_p)): C =
k phi / 2 = k^2 c_p / (4 n_p R_p^2), the closed form ``carrier_output_compliance_rad_per_nm``
(the test of the slender limit). The FE adds what the closed form leaves out: the plates'
bending and shear, the pillars' roots turning in the plates, and the seats' bores ovalising under
the bearings (the seats' share; the bearing rings themselves are the support bearings' element).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import numpy as np
from skfem import FacetBasis, Functional, LinearForm
from skfem.helpers import dot

from rvbacklash.design.structure import CARRIER_FE_FIELDS, has_carrier_fe
from rvbacklash.errors import InputError
from rvbacklash.mechanics import solid
from rvbacklash.mechanics.carrier_mesh import ON_SURFACE_MM, CarrierGeometry, build_mesh, sectors
from rvbacklash.mechanics.fe_cache import cached
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD

# 2: the pillars placed by geometry/carrier_layout.py, sectors for two cranks and for pillars a multiple of the
# cranks (issue 36): a result of version 1 is another body or another mesh
MODEL_VERSION = 2


@dataclass(frozen=True)
class CarrierBodyResult:
    """The FE carrier of one design (per N m of output torque)."""

    output_compliance_rad_per_nm: float  # C = sum F_s . u_s / T (module docstring)
    stiffness_nm_per_arcmin: float  # 1 / C in N m/arcmin
    flange_seat_share: float  # part of C done at the flange's seats (the rest: the end plate's) [-]
    seat_force_n_per_nm: float  # F_s: each support bearing's tangential force per N m of output torque
    lever_factor: float  # k the loads and the compliance were referred to the output with [-]
    refinement: float  # element sizes over their defaults (``_mesh_sizes``) [-]
    nodes: int  # quadratic nodes (vertices and edge midpoints)
    elements: int  # tetrahedra
    dofs: int
    cg_iterations: int
    wall_time_s: float  # meshing + assembly + solve (of the computation, not of a cache hit)

    def to_dict(self) -> dict[str, float | int]:
        return asdict(self)


def seat_force_n_per_nm(lever_factor: float, cranks: int, crank_circle_radius_mm: float) -> float:
    """Tangential force of each crank support bearing on its seat per N m of output torque:

        F_s = k T / (2 n_c a0)   (T = 1 N m; a0 in m)

    The discs' pins carry the output torque; referred to the discs it is k T (the lever factor),
    carried by the n_c cranks at a0 as tangential forces k T / (n_c a0), each split equally between
    the crank's two support bearings (the two discs symmetric about the crank's mid-span). Source:
    ours (docs/elastic.md, "The whole torque path": the crank needle bearings' force k T / (n_b a0)
    with n_b = 2 n_c, two discs' worth per crank, half to each end). Parameters: lever_factor k
    [-], cranks n_c [-], crank_circle_radius_mm a0 [mm]. Returns [N/(N m)]. Validity: two discs
    symmetric about the cranks' mid-span, equal load sharing among the cranks."""
    return lever_factor / (2.0 * cranks * crank_circle_radius_mm * 1e-3)


def _seat_facets(mesh, centre_xy: tuple[float, float], radius_mm: float, z_range: tuple[float, float]) -> np.ndarray:
    """Boundary facets of the seat bore (all three vertices on its cylinder, within the plate)."""
    facets = mesh.boundary_facets()
    p = mesh.p[:, mesh.facets[:, facets]]  # (3, 3 vertices, n)
    r = np.hypot(p[0] - centre_xy[0], p[1] - centre_xy[1])
    on = np.all(np.abs(r - radius_mm) < ON_SURFACE_MM * max(1.0, radius_mm), axis=0)
    inside = np.all((p[2] >= z_range[0] - ON_SURFACE_MM) & (p[2] <= z_range[1] + ON_SURFACE_MM), axis=0)
    return facets[on & inside]


def _seat_load(basis, mesh, facets: np.ndarray, centre_xy: tuple[float, float], direction: np.ndarray,
               force_n: float) -> np.ndarray:
    """Load vector of a bearing pressing its seat's bore with p0 cos(psi) on the loaded half
    (module docstring), scaled so that the resultant along ``direction`` is ``force_n``."""
    fb = FacetBasis(mesh, basis.elem, facets=facets)
    cx, cy = centre_xy
    dx, dy = float(direction[0]), float(direction[1])

    def pressure(x):
        # unit radial direction from the bore's axis and the cosine pressure on the loaded half
        rx, ry = x[0] - cx, x[1] - cy
        r = np.sqrt(rx * rx + ry * ry)
        rx, ry = rx / r, ry / r
        return np.maximum(rx * dx + ry * dy, 0.0), rx, ry

    @LinearForm
    def traction(v, w):
        p, rx, ry = pressure(w.x)
        return dot(np.array([p * rx, p * ry, 0.0 * p]), v)

    @Functional
    def resultant(w):
        p, rx, ry = pressure(w.x)
        return p * (rx * dx + ry * dy)

    return traction.assemble(fb) * (force_n / resultant.assemble(fb))


def solve_carrier_body(geometry: CarrierGeometry, e_gpa: float, nu: float, lever_factor: float,
                       refinement: float = 1.0, plate_stiffening: float = 1.0,
                       whole: bool = False) -> CarrierBodyResult:
    """The carrier's output compliance by FE (module docstring), computed (not cached: see
    ``carrier_body_compliance``). Young's modulus e_gpa [GPa], Poisson's ratio nu [-], lever factor
    k [-]; refinement: element sizes over their defaults (``_mesh_sizes``);
    plate_stiffening: the plates' modulus times this (a diagnostic: > 1 separates the pillars'
    share from the plates' and seats'); whole: mesh the whole body, not one sector (a check of the
    sector's symmetry)."""
    start = time.perf_counter()
    g = geometry
    n = 1 if whole else sectors(g)
    mesh = build_mesh(g, refinement, n)
    basis = solid.vector_p2_basis(mesh)
    e_mpa = e_gpa * 1e3
    if plate_stiffening == 1.0:
        stiffness = solid.stiffness_matrix(basis, e_mpa, nu)
    else:
        z = mesh.p[2, mesh.t].mean(axis=0)
        in_pillars = (z > g.flange_thickness_mm) & (z < g.flange_thickness_mm + g.pillar_length_mm)
        stiffness = (solid.stiffness_matrix(solid.vector_p2_basis(mesh, np.nonzero(in_pillars)[0]), e_mpa, nu)
                     + solid.stiffness_matrix(solid.vector_p2_basis(mesh, np.nonzero(~in_pillars)[0]),
                                              e_mpa * plate_stiffening, nu))
    force = seat_force_n_per_nm(lever_factor, g.cranks, g.crank_circle_radius_mm)
    plates = {"flange": (0.0, g.flange_thickness_mm),
              "end_plate": (g.flange_thickness_mm + g.pillar_length_mm, g.height_mm)}
    loads = {}
    for plate, z_range in plates.items():
        f = np.zeros(basis.N)
        for angle in g.crank_angles_rad[:1] if n > 1 else g.crank_angles_rad:
            centre = (g.crank_circle_radius_mm * math.cos(angle), g.crank_circle_radius_mm * math.sin(angle))
            facets = _seat_facets(mesh, centre, 0.5 * g.seat_diameter_mm, z_range)
            if facets.size == 0:
                raise InputError("structure.support_bearing_seat_diameter_mm", g.seat_diameter_mm,
                                 "the seat's bore was not found in the carrier's mesh; allowed: seats inside the "
                                 "plates")
            f += _seat_load(basis, mesh, facets, centre, np.array([-math.sin(angle), math.cos(angle)]), force)
        loads[plate] = f
    held = basis.get_dofs(lambda x: np.abs(x[2]) < ON_SURFACE_MM).all()
    load = loads["flange"] + loads["end_plate"]
    try:
        tie = None
        if n > 1:
            tie, axis = solid.sector_tie(basis, 2 * math.pi / n, ON_SURFACE_MM * max(1.0, g.outer_diameter_mm))
            held = np.union1d(held, axis)
        u, iterations = solid.solve_clamped(basis, stiffness, load, held, tie)
    except solid.SolverError as exc:
        raise InputError("structure", allowed=f"the carrier's FE solve failed ({exc}); allowed: a carrier whose "
                                              f"plates and pillars are not orders of magnitude apart") from None
    # N mm of work per (N m)^2: 1e-3 rad/(N m); n sectors do the same work
    work = {plate: n * float(f @ u) for plate, f in loads.items()}
    compliance = (work["flange"] + work["end_plate"]) * 1e-3
    return CarrierBodyResult(
        output_compliance_rad_per_nm=compliance, stiffness_nm_per_arcmin=1.0 / (compliance * ARCMIN_PER_RAD),
        flange_seat_share=work["flange"] * 1e-3 / compliance, seat_force_n_per_nm=force, lever_factor=lever_factor,
        refinement=refinement, nodes=int(mesh.nvertices + mesh.nedges), elements=int(mesh.nelements), dofs=int(basis.N),
        cg_iterations=iterations, wall_time_s=time.perf_counter() - start)


def carrier_geometry(problem: Problem) -> CarrierGeometry:
    """The carrier's dimensions from a design's [structure] table (``has_carrier_fe``) and its
    crank circle; cranks = the first stage's planets."""
    st = problem.design.structure
    if problem.cycloid.discs != 2:
        raise InputError("second_stage.discs", problem.cycloid.discs,
                         "the FE carrier's loads are two discs' forces, symmetric about the cranks' mid-span; "
                         "allowed: discs = 2")
    if not has_carrier_fe(st):
        raise InputError("structure.carrier_flange_thickness_mm",
                         allowed=f"missing: the FE carrier needs all of {', '.join(CARRIER_FE_FIELDS)}")
    return CarrierGeometry(
        flange_thickness_mm=st.carrier_flange_thickness_mm, end_plate_thickness_mm=st.carrier_end_plate_thickness_mm,
        outer_diameter_mm=st.carrier_outer_diameter_mm, bore_diameter_mm=st.carrier_bore_diameter_mm,
        seat_diameter_mm=st.support_bearing_seat_diameter_mm,
        crank_circle_radius_mm=problem.geometry.crank_circle_radius_mm, cranks=problem.design.first_stage.planets,
        pillars=st.carrier_pillars, pillar_radius_mm=st.pillar_radius_mm, pillar_length_mm=st.pillar_length_mm,
        pillar_width_mm=st.pillar_width_mm, pillar_depth_mm=st.pillar_depth_mm)


def cached_carrier_body(geometry: CarrierGeometry, e_gpa: float, nu: float, lever_factor: float,
                        refinement: float = 1.0, disk: bool = True) -> CarrierBodyResult:
    """``solve_carrier_body`` through the FE cache (``fe_cache.cached``: in process and on disk,
    keyed by every input and MODEL_VERSION)."""
    inputs = {"geometry": asdict(geometry), "e_gpa": e_gpa, "nu": nu, "lever_factor": lever_factor,
              "refinement": refinement}
    data = cached("carrier_body", MODEL_VERSION, inputs,
                  lambda: solve_carrier_body(geometry, e_gpa, nu, lever_factor, refinement).to_dict(), disk=disk)
    return CarrierBodyResult(**data)


def carrier_body_compliance(problem: Problem, lever_factor: float) -> CarrierBodyResult:
    """The design's FE carrier (its [structure] carrier fields, ``has_carrier_fe``), once per design:
    output compliance [rad/(N m)] with the support bearings' forces of a unit output torque referred
    to the output by ``lever_factor`` k (module docstring; the lead's chain passes the k it uses)."""
    st = problem.design.structure
    return cached_carrier_body(carrier_geometry(problem), st.carrier_youngs_modulus_gpa, st.carrier_poisson_ratio,
                               lever_factor)
