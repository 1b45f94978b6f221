"""Triangle meshes of a plate with holes (gmsh's Python API), as scikit-fem ``MeshTri``.

The plate's outline and its holes are closed polylines [mm]; gmsh's built-in kernel meshes the
surface between them (a plane surface with hole loops: no boolean operation is needed for round
holes that do not touch, and the checks of design/structure.py make sure they do not). Every
polyline vertex is a mesh node and every polyline segment one mesh edge (a transfinite line of
two nodes), so a load placed on the polyline lies on the mesh's boundary exactly; inside, the
size grows away from each loop by ``GROWTH`` mm per mm from its segment length to at most
``max_size_mm`` (one gmsh MathEval field: cheap to evaluate, unlike distance fields over ~1000
curves, which took 0.6 s of a 0.8 s mesh). A mesh whose triangles do not cover the area between
the loops (holes crossing each other or the outline: gmsh may then leave none, or a wrong one) is
a MeshError.
"""

from __future__ import annotations

import threading

import numpy as np
from skfem import MeshTri

from rvbacklash.errors import InputError

GROWTH = 0.3  # element size grows by this much per mm of distance from a boundary
_GMSH = threading.Lock()  # gmsh is one global model per process: one mesh at a time


class MeshError(RuntimeError):
    """gmsh could not mesh the outline (the caller names the design fields)."""


def _segment_sizes(points: np.ndarray) -> np.ndarray:
    """Mesh size at each vertex of a closed polyline: the mean length of its two segments."""
    seg = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
    return 0.5 * (seg + np.roll(seg, 1))


def _add_loop(geo, points: np.ndarray) -> tuple[int, np.ndarray, float]:
    """The loop's tag, its points and its mean segment length."""
    sizes = _segment_sizes(points)
    tags = [geo.addPoint(float(x), float(y), 0.0, float(h)) for (x, y), h in zip(points, sizes)]
    lines = [geo.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
    for line in lines:  # one mesh edge per segment (and no size field evaluated along them)
        geo.mesh.setTransfiniteCurve(line, 2)
    return geo.addCurveLoop(lines), points, float(sizes.mean())


def _grade(field, loops: list[tuple[int, np.ndarray, float]], max_size_mm: float) -> None:
    """Background size: the minimum over the loops of a size growing away from each by GROWTH,
    the distance from a loop taken as | |x - c| - R | with c its centroid and R its mean radius
    (exact for a circle, within the lobes' height for a cycloid disc: a size, not a geometry)."""
    terms = []
    for _, points, size in loops:
        cx, cy = (float(v) for v in points.mean(axis=0))
        radius = float(np.mean(np.hypot(points[:, 0] - cx, points[:, 1] - cy)))
        terms.append(f"{float(size)!r} + {GROWTH!r} * Abs(Sqrt((x - ({cx!r}))^2 + (y - ({cy!r}))^2) - {radius!r})")
    expression = f"{float(max_size_mm)!r}"
    for term in terms:
        expression = f"Min({term}, {expression})"
    size = field.add("MathEval")
    field.setString(size, "F", expression)
    field.setAsBackgroundMesh(size)


def mesh_plate(outline_mm: np.ndarray, holes_mm: list[np.ndarray], max_size_mm: float) -> MeshTri:
    """Linear triangles filling ``outline_mm`` (n, 2) minus the ``holes_mm`` polylines (each (m, 2)),
    counter-clockwise or not. Raises MeshError when gmsh fails or leaves no triangles."""
    import gmsh  # imported here: a design without FE never loads gmsh's library

    if max_size_mm <= 0:
        raise InputError("max_size_mm", max_size_mm, "allowed: > 0")
    with _GMSH:
        tags, coords, types, conn = _generate(gmsh, outline_mm, holes_mm, max_size_mm)
    if 2 not in list(types):
        raise MeshError("no triangles")
    tri = np.asarray(conn[list(types).index(2)], dtype=np.int64).reshape(-1, 3)
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    used = np.unique(tri)
    keep = np.full(len(tags), -1, dtype=np.int64)
    keep[index[used]] = np.arange(len(used))  # drop nodes that no triangle uses (gmsh keeps geometry points)
    p = coords.reshape(-1, 3)[index[used], :2].T
    t = keep[index[tri]].T
    a, b, c = p[:, t[0]], p[:, t[1]], p[:, t[2]]
    area = 0.5 * np.sum(np.abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])))
    expected = _polygon_area(outline_mm) - sum(_polygon_area(h) for h in holes_mm)
    if not abs(area - expected) <= 1e-6 * abs(expected):  # holes crossing or outside the outline
        raise MeshError(f"the triangles cover {area:.6g} mm^2 of the {expected:.6g} mm^2 between the loops")
    return MeshTri(np.ascontiguousarray(p), np.ascontiguousarray(t))


def _generate(gmsh, outline_mm, holes_mm, max_size_mm):
    """gmsh's nodes (tags, coordinates) and its 2-D elements (types, connectivity)."""
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.MeshSizeMax", float(max_size_mm))
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay: well-shaped triangles
        gmsh.model.add("plate")
        geo = gmsh.model.geo
        loops = [_add_loop(geo, np.asarray(outline_mm, float))]
        loops += [_add_loop(geo, np.asarray(h, float)) for h in holes_mm]
        geo.addPlaneSurface([tag for tag, _, _ in loops])
        geo.synchronize()
        _grade(gmsh.model.mesh.field, loops, max_size_mm)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        types, _, conn = gmsh.model.mesh.getElements(2)
        return tags, coords, types, conn
    except Exception as exc:  # gmsh raises plain Exceptions with its log's last line
        raise MeshError(str(exc)) from exc
    finally:
        gmsh.finalize()


def _polygon_area(points) -> float:
    """Area of a closed polyline (shoelace) [mm^2], either orientation."""
    x, y = np.asarray(points, float).T
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def circle_polyline(x_mm: float, y_mm: float, radius_mm: float, segment_mm: float) -> np.ndarray:
    """A circle as a closed polyline of equal segments about ``segment_mm`` long (at least 16),
    vertices on the circle."""
    n = max(16, int(np.ceil(2.0 * np.pi * radius_mm / segment_mm)))
    a = 2.0 * np.pi * np.arange(n) / n
    return np.stack([x_mm + radius_mm * np.cos(a), y_mm + radius_mm * np.sin(a)], axis=1)


def facets_on_circle(mesh: MeshTri, x_mm: float, y_mm: float, radius_mm: float, tolerance_mm: float) -> np.ndarray:
    """Boundary facets whose both ends lie on the circle (within ``tolerance_mm``)."""
    f = mesh.boundary_facets()
    ends = mesh.p[:, mesh.facets[:, f]]  # (2, 2, n)
    r = np.hypot(ends[0] - x_mm, ends[1] - y_mm)
    return f[np.all(np.abs(r - radius_mm) < tolerance_mm, axis=0)]
