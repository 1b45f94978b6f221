"""The carrier's body for the finite elements (mechanics/carrier_body.py, docs/rigidity-elements.md):
its dimensions (``CarrierGeometry``) and its gmsh mesh (``build_mesh``).

z along the reducer's axis. The output flange is a plate z = 0 ... t_f (outer diameter D,
central hole d_b); the pillars (n_p, tangential width w, radial depth h, free length L, centred
on the radius R_p between the cranks, geometry/carrier_layout.py) stand on it up to the end plate, z = t_f +
L ... t_f + L + t_e (same outline). Both plates have a through bore of the support bearings'
outer diameter D_s at each crank, on the crank circle a0: the seats. One fused OCC solid; when the
pillars repeat with the cranks only one sector of it is meshed (``sectors``), its two cut faces
alike so that the solver can tie them (``solid.sector_tie``), else the whole body.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.geometry import carrier_layout as layout
from rvbacklash.mechanics import solid

MESH_ELEMENTS_PER_SECTION = 1.6  # quadratic tetrahedra across the thinner plate, and the pillars' thinner side
ROOT_SIZE_FRACTION = 0.3  # elements along the pillars' roots, relative to the smaller of those sizes
BORE_SIZE_FRACTION = 0.5  # elements on the seats' and the central hole's bores, relative to the plates'
REFINED_DEPTH = 2.0  # ... growing back to the plates' size within this many of their own sizes
ON_SURFACE_MM = 1e-6  # a mesh vertex this close to a surface lies on it (gmsh puts them on it)


@dataclass(frozen=True)
class CarrierGeometry:
    """Dimensions of the carrier [mm] (module docstring). Cranks and pillars where
    geometry/carrier_layout.py places them (the discs' holes read the same placement): cranks at
    2 pi j / cranks, pillars at pi / lcm(cranks, pillars) + 2 pi i / pillars (between the cranks)."""

    flange_thickness_mm: float
    end_plate_thickness_mm: float
    outer_diameter_mm: float
    bore_diameter_mm: float  # central hole of both plates
    seat_diameter_mm: float  # support bearing's outer diameter: the seats' bores
    crank_circle_radius_mm: float
    cranks: int
    pillars: int
    pillar_radius_mm: float
    pillar_length_mm: float
    pillar_width_mm: float  # tangential
    pillar_depth_mm: float  # radial

    @property
    def crank_angles_rad(self) -> np.ndarray:
        return np.array(layout.crank_angles_rad(self.cranks))

    @property
    def pillar_angles_rad(self) -> np.ndarray:
        return np.array(layout.pillar_angles_rad(self.cranks, self.pillars))

    @property
    def height_mm(self) -> float:
        return self.flange_thickness_mm + self.pillar_length_mm + self.end_plate_thickness_mm

    def plate_mesh_size_mm(self, refinement: float = 1.0) -> float:
        """Element size in the plates: MESH_ELEMENTS_PER_SECTION quadratic tetrahedra across the
        thinner plate, over ``refinement`` [mm]."""
        return min(self.flange_thickness_mm, self.end_plate_thickness_mm) / MESH_ELEMENTS_PER_SECTION / refinement

    def pillar_mesh_size_mm(self, refinement: float = 1.0) -> float:
        """Element size in the pillars: MESH_ELEMENTS_PER_SECTION across their thinner side (or
        length), over ``refinement`` [mm]."""
        return min(self.pillar_width_mm, self.pillar_depth_mm, self.pillar_length_mm) / MESH_ELEMENTS_PER_SECTION \
            / refinement


def sectors(geometry: CarrierGeometry) -> int:
    """How many equal sectors the carrier is made of: n_c when the pillars repeat with the cranks
    (n_p a multiple of n_c, placed by geometry/carrier_layout.py: each sector holds one crank's
    seats and the pillars, or pillar halves, about it; rv80e: 3), two cranks included (the two cut
    faces then lie in one plane, on either side of the axis: ``_periodic_faces``); else 1 (the
    whole body is meshed, e.g. 3 cranks and 4 pillars)."""
    g = geometry
    return g.cranks if g.cranks > 1 and g.pillars % g.cranks == 0 else 1


def build_mesh(geometry: CarrierGeometry, refinement: float, n: int):
    """The carrier as one fused OCC solid, cut to one of ``n`` sectors (``sectors``; n = 1: whole):
    -pi/n ... pi/n about the crank at angle 0, through the middle of the pillars, its two cut faces
    meshed alike (gmsh setPeriodic); meshed in linear tetrahedra (``solid.tet_mesh``). Raises
    InputError (field ``structure``) if gmsh cannot mesh it."""
    g = geometry
    tf, te, length = g.flange_thickness_mm, g.end_plate_thickness_mm, g.pillar_length_mm
    radius, top = 0.5 * g.outer_diameter_mm, g.height_mm
    try:
        with solid.gmsh_session("carrier") as gmsh:
            occ = gmsh.model.occ
            flange = occ.addCylinder(0, 0, 0, 0, 0, tf, radius)
            end_plate = occ.addCylinder(0, 0, tf + length, 0, 0, te, radius)
            pillars = []
            for angle in g.pillar_angles_rad:
                # reaching half-way into both plates: the fuse then leaves no face between them
                box = occ.addBox(g.pillar_radius_mm - 0.5 * g.pillar_depth_mm, -0.5 * g.pillar_width_mm, 0.5 * tf,
                                 g.pillar_depth_mm, g.pillar_width_mm, length + 0.5 * (tf + te))
                occ.rotate([(3, box)], 0, 0, 0, 0, 0, 1, float(angle))
                pillars.append((3, box))
            body, _ = occ.fuse([(3, flange)], [(3, end_plate)] + pillars)
            holes = [] if g.bore_diameter_mm == 0 else [
                (3, occ.addCylinder(0, 0, -1, 0, 0, top + 2, 0.5 * g.bore_diameter_mm))]
            for angle in g.crank_angles_rad:
                a0 = g.crank_circle_radius_mm
                holes.append((3, occ.addCylinder(a0 * math.cos(angle), a0 * math.sin(angle), -1, 0, 0, top + 2,
                                                 0.5 * g.seat_diameter_mm)))
            body, _ = occ.cut(body, holes)
            if not body:
                raise ValueError("the holes leave nothing of the carrier")
            if n > 1:
                wedge = occ.addCylinder(0, 0, -1, 0, 0, top + 2, 2 * radius, angle=2 * math.pi / n)
                occ.rotate([(3, wedge)], 0, 0, 0, 0, 0, 1, -math.pi / n)
                occ.intersect(body, [(3, wedge)])
            occ.synchronize()
            if n > 1:
                _periodic_faces(gmsh, n)
            _mesh_sizes(gmsh, g, refinement)
            gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay: robust, deterministic
            gmsh.model.mesh.generate(3)
            return solid.tet_mesh(gmsh)
    except Exception as exc:  # gmsh raises plain Exceptions with its log line
        raise InputError("structure", allowed=f"the carrier ([structure] carrier_*, pillar_*, "
                                              f"support_bearing_seat_diameter_mm) cannot be meshed ({exc}); allowed: "
                                              f"plates, pillars and seats with walls of at least 1 mm") from None


def _periodic_faces(gmsh, n: int) -> None:
    """Mesh the sector's face at +pi/n as the copy of the one at -pi/n turned by 2 pi/n. A cut face
    lies in the plane through the axis at its angle, on the side its angle points to: for n = 2 both
    cut faces lie in one plane (the halves y < 0 and y > 0 of x = 0), told apart by that side alone."""
    def faces(angle):
        normal = (-math.sin(angle), math.cos(angle))
        along = (math.cos(angle), math.sin(angle))
        found = {}
        for _, tag in gmsh.model.getEntities(2):
            low, high = gmsh.model.getParametrizationBounds(2, tag)
            nx, ny, _ = gmsh.model.getNormal(tag, [0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1])])
            cx, cy, cz = gmsh.model.occ.getCenterOfMass(2, tag)
            if abs(abs(nx * normal[0] + ny * normal[1]) - 1.0) < 1e-9 and abs(cx * normal[0] + cy * normal[1]) < 1e-6 \
                    and cx * along[0] + cy * along[1] > 0.0:
                found[tag] = (cx, cy, cz)
        return found

    masters, slaves = faces(-math.pi / n), faces(math.pi / n)
    turn = solid.rotation_about_z(2 * math.pi / n)
    pairs = []
    for m, centre in masters.items():
        target = turn @ np.array(centre)
        s = min(slaves, key=lambda t: float(np.linalg.norm(np.array(slaves[t]) - target)))
        pairs.append((s, m))
    affine = np.eye(4)
    affine[:3, :3] = turn
    gmsh.model.mesh.setPeriodic(2, [s for s, _ in pairs], [m for _, m in pairs], affine.ravel().tolist())


def _mesh_sizes(gmsh, g: CarrierGeometry, refinement: float) -> None:
    """Element sizes, all over ``refinement`` (a larger one refines everywhere alike): the plates'
    and the pillars' own (``CarrierGeometry.plate_mesh_size_mm``, ``pillar_mesh_size_mm``);
    ROOT_SIZE_FRACTION of the smaller along the edges where the pillars meet the plates (a
    re-entrant right-angle edge: singular stresses, strain energy converging like h^1.1 on a
    uniform mesh, Williams' exponent 0.54); BORE_SIZE_FRACTION of the plates' on the seats' and the
    central hole's bores (the thin walls between them and the rim bend in their plane under the
    bearings); each growing to the plates' size over REFINED_DEPTH of its own."""
    plate, pillar = g.plate_mesh_size_mm(refinement), g.pillar_mesh_size_mm(refinement)
    planes = (g.flange_thickness_mm, g.flange_thickness_mm + g.pillar_length_mm)
    reach = 0.5 * math.hypot(g.pillar_width_mm, g.pillar_depth_mm) + ON_SURFACE_MM
    centres = [(g.pillar_radius_mm * math.cos(a), g.pillar_radius_mm * math.sin(a)) for a in g.pillar_angles_rad]
    seats = [(g.crank_circle_radius_mm * math.cos(a), g.crank_circle_radius_mm * math.sin(a), 0.5 * g.seat_diameter_mm)
             for a in g.crank_angles_rad] + [(0.0, 0.0, 0.5 * g.bore_diameter_mm)]

    def within(box, x, y, r):  # a bounding box inside the circle's square
        x0, y0, _, x1, y1, _ = box
        return x - r - ON_SURFACE_MM <= x0 and x1 <= x + r + ON_SURFACE_MM and \
            y - r - ON_SURFACE_MM <= y0 and y1 <= y + r + ON_SURFACE_MM

    def at_pillar(box):
        return any(within(box, cx, cy, reach) for cx, cy in centres)

    roots = [tag for _, tag in gmsh.model.getEntities(1)
             if any(abs(gmsh.model.getBoundingBox(1, tag)[2] - z) < ON_SURFACE_MM
                    and abs(gmsh.model.getBoundingBox(1, tag)[5] - z) < ON_SURFACE_MM for z in planes)
             and at_pillar(gmsh.model.getBoundingBox(1, tag))]
    sides = [tag for _, tag in gmsh.model.getEntities(2)
             if abs(gmsh.model.getBoundingBox(2, tag)[2] - planes[0]) < ON_SURFACE_MM
             and abs(gmsh.model.getBoundingBox(2, tag)[5] - planes[1]) < ON_SURFACE_MM
             and at_pillar(gmsh.model.getBoundingBox(2, tag))]
    bores = [tag for _, tag in gmsh.model.getEntities(2)
             if any(within(gmsh.model.getBoundingBox(2, tag), x, y, r) for x, y, r in seats if r > 0)]
    field = gmsh.model.mesh.field
    thresholds = []
    small = min(plate, pillar)
    core = 0.5 * min(g.pillar_width_mm, g.pillar_depth_mm)  # the pillar's inside is this close to its sides
    for kind, tags, size, near, far in (
            ("CurvesList", roots, ROOT_SIZE_FRACTION * small, 0.0, REFINED_DEPTH * small),
            ("SurfacesList", sides, pillar, core, core + REFINED_DEPTH * pillar),
            ("SurfacesList", bores, BORE_SIZE_FRACTION * plate, 0.0, REFINED_DEPTH * plate)):
        if not tags or size >= plate:
            continue
        distance = field.add("Distance")
        field.setNumbers(distance, kind, tags)
        field.setNumber(distance, "Sampling", 40)
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", size)
        field.setNumber(threshold, "SizeMax", plate)
        field.setNumber(threshold, "DistMin", near)
        field.setNumber(threshold, "DistMax", far)
        thresholds.append(threshold)
    if thresholds:
        smallest = field.add("Min")
        field.setNumbers(smallest, "FieldsList", thresholds)
        field.setAsBackgroundMesh(smallest)
    gmsh.option.setNumber("Mesh.MeshSizeMax", plate)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.1 * small)
