"""The cycloid disc's body by finite elements (mechanics/disc_body.py, docs/rigidity-elements.md): the
plane-stress code against a closed form, the rv80e disc's mesh convergence, its invariants, and the
design's holes refused with the field named."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from helpers import example_text
from rvbacklash.design.loading import design_from_toml
from rvbacklash.errors import InputError
from rvbacklash.geometry.disc_holes import Hole
from rvbacklash.mechanics import fe_cache
from rvbacklash.mechanics import plane_stress as ps
from rvbacklash.design.structure import has_disc_fe
from rvbacklash.models import compliance as cm
from rvbacklash.mechanics.disc_body import (MeshSize, disc_body_compliance, ideal_pin_forces_n,
                                            pin_load)
from rvbacklash.mechanics.plane_mesh import circle_polyline, facets_on_circle, mesh_plate
from rvbacklash.problem import prepare

LEVER_FACTOR = 0.9686  # rv80e: output rotation per disc rotation (models/compliance.cycloid_lever_factor)
BEARING_N_PER_UM = 673.5  # rv80e: one needle bearing's secant at the rated torque's load (docs/rigidity-elements.md)
COARSE = MeshSize(12, 2.5, 6.0)  # the invariants do not need the default's accuracy


@pytest.fixture(autouse=True)
def _own_cache(tmp_path, monkeypatch):
    """Each test computes its own results (no disk cache from another run, none left behind)."""
    monkeypatch.setenv("RVBACKLASH_CACHE_DIR", str(tmp_path / "cache"))
    fe_cache.clear_memory()
    yield
    fe_cache.clear_memory()


@pytest.fixture(scope="module")
def forces(rv80e_problem):
    """The ideal load sharing of a perfect stage at the rated 784 N m (each disc k T / 2)."""
    return ideal_pin_forces_n(rv80e_problem, 0.0, LEVER_FACTOR * 784.0 / 2)


def _annulus_twist(r1: float, r2: float, t: float, e_mpa: float, nu: float, torque_nmm: float,
                   segment_mm: float) -> float:
    """FE twist of an annulus held at its inner edge, the torque as a uniform shear traction on
    the outer edge (applied and read as the disc's loads are: point forces along the boundary
    polyline, the rotation as their work over the torque)."""
    outer = circle_polyline(0.0, 0.0, r2, segment_mm)
    mesh = mesh_plate(outer, [circle_polyline(0.0, 0.0, r1, segment_mm)], 4 * segment_mm)
    basis = ps.scalar_basis(mesh)
    k = ps.stiffness_matrix(basis, e_mpa, nu, t)
    # 8 points per boundary segment, each carrying its share of the traction, tangential
    n = len(outer)
    s = (np.arange(8 * n) + 0.5) / 8
    i = np.floor(s).astype(int)
    a, b = outer[i % n], outer[(i + 1) % n]
    pts = a + (s - i)[:, None] * (b - a)
    seg = np.linalg.norm(b - a, axis=1)
    tangent = np.stack([-pts[:, 1], pts[:, 0]], axis=1) / np.hypot(pts[:, 0], pts[:, 1])[:, None]
    weight = seg / 8
    force = tangent * weight[:, None]
    force *= torque_nmm / np.sum(pts[:, 0] * force[:, 1] - pts[:, 1] * force[:, 0])  # moment exactly T
    op = ps.point_operator(basis, pts * (1 - 1e-9))
    f = ps.point_loads(op, force)
    held = ps.component_dofs(basis, facets_on_circle(mesh, 0.0, 0.0, r1, 0.01))
    free = np.setdiff1d(np.arange(2 * basis.N), held)
    u = np.zeros(2 * basis.N)
    u[free] = spsolve(k[free][:, free].tocsc(), f[free])
    return float(np.sum(force * ps.point_values(op, u))) / torque_nmm


def test_the_plane_stress_code_twists_an_annulus_as_lame():
    """Oracle: an annulus r1..r2 of thickness t, inner edge held, torque T as a uniform shear on the
    outer edge, twists by theta = T / (4 pi G t) (1 / r1^2 - 1 / r2^2) (Lame; Roark 7th ed.,
    Table 9.2 / Timoshenko & Goodier art. 29): the FE within 1 %."""
    r1, r2, t, e, nu, torque = 20.0, 60.0, 12.0, 208e3, 0.3, 380e3
    exact = cm.housing_ring_torsion_compliance_rad_per_nm(r1, r2, t, e * 1e-3, nu) * torque * 1e-3  # [rad]
    fe = _annulus_twist(r1, r2, t, e, nu, torque, 1.5)
    assert fe == pytest.approx(exact, rel=0.01)
    assert abs(fe / exact - 1) < 2e-3  # measured: 9.6e-4, second order in the segment (the polygons' area)


def test_plane_stress_lame_parameter():
    lam, mu = ps.plane_stress_lame_mpa(208e3, 0.3)
    assert lam == pytest.approx(208e3 * 0.3 / (1 - 0.09), rel=1e-12)
    assert mu == pytest.approx(80e3, rel=1e-12)


def test_the_rv80e_disc_converges_on_refinement(rv80e_problem, forces):
    """The compliance changes < 1 % when every size of the mesh is divided by 1.5."""
    base = disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0)
    fine = disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=MeshSize().refined(1.5))
    assert fine.elements > 1.5 * base.elements
    assert abs(fine.compliance_rad_per_nm / base.compliance_rad_per_nm - 1) < 0.01  # measured 0.3 %
    # the figure the notes report (docs/rigidity-elements.md): 3.24e-7 rad/(N m) for disc 0 at chi = 0
    assert base.compliance_rad_per_nm == pytest.approx(3.242e-7, rel=0.01)


def test_invariants_of_the_rv80e_disc(rv80e_problem, forces):
    r = disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=COARSE)
    assert r.compliance_rad_per_nm > 0 and r.flexible_rotation_rad > r.rigid_rotation_rad > 0
    assert r.disc_torque_nm == pytest.approx(LEVER_FACTOR * 784.0 / 2, rel=1e-3)  # the patches' moment
    # a rigid disc on three equal bearings shares the torque in equal thirds (up to the springs'
    # quadrature on three different meshes of the bores); the flexible one does not
    assert r.rigid_crank_torque_shares == pytest.approx((1 / 3,) * 3, abs=1e-3)
    assert sum(r.crank_torque_shares) == pytest.approx(1.0, abs=1e-9)
    assert max(r.crank_torque_shares) - min(r.crank_torque_shares) > 0.02
    # the rigid reading: three equal springs K at a0 turn the disc by T_d / (3 K a0^2) and move it by
    # R / (3 K) under the pins' resultant R, which does the work R^2 / (3 K) (docs/elastic.md, the
    # disc's sideways motion: its part across the eccentric is the chain's translation factor)
    load = pin_load(rv80e_problem, 0.0, 0, forces[0])
    resultant = load.force_n.sum(axis=0)
    k_n_per_mm, torque = BEARING_N_PER_UM * 1e3, load.torque_nmm
    rigid = torque / (3 * k_n_per_mm * 42.0 ** 2) + resultant @ resultant / (3 * k_n_per_mm * torque)
    assert r.rigid_rotation_rad == pytest.approx(rigid, rel=1e-3)
    assert r.spring_condition_number < 10


def test_the_result_does_not_depend_on_the_forces_scale(rv80e_problem, forces):
    one = disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=COARSE)
    scaled = disc_body_compliance(rv80e_problem, 0.0, 3.7 * forces, BEARING_N_PER_UM, disc=0, mesh=COARSE)
    assert scaled.compliance_rad_per_nm == pytest.approx(one.compliance_rad_per_nm, rel=1e-8)
    assert scaled.crank_torque_shares == pytest.approx(one.crank_torque_shares, rel=1e-8)
    assert scaled.flexible_rotation_rad == pytest.approx(3.7 * one.flexible_rotation_rad, rel=1e-8)


def test_both_discs_in_parallel(rv80e_problem, forces):
    """disc=None: every loaded disc, compliances in parallel (n / sum 1 / C_d), tuples disc after disc."""
    both = disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, mesh=COARSE)
    each = [disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=d, mesh=COARSE) for d in (0, 1)]
    assert both.discs == (0, 1) and len(both.crank_torque_shares) == 6
    assert both.compliance_rad_per_nm == pytest.approx(
        2 / sum(1 / e.compliance_rad_per_nm for e in each), rel=1e-12)
    assert both.disc_compliances_rad_per_nm == tuple(e.compliance_rad_per_nm for e in each)
    # a disc without load carries nothing: the stage's compliance is the loaded disc's, k^2 C_0
    alone = forces.copy()
    alone[1] = 0.0
    one = disc_body_compliance(rv80e_problem, 0.0, alone, BEARING_N_PER_UM, mesh=COARSE)
    assert one.discs == (0,) and one.compliance_rad_per_nm / 2 == pytest.approx(each[0].compliance_rad_per_nm)


def test_the_result_is_cached_in_memory_and_on_disk(rv80e_problem, forces):
    first = disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=COARSE)
    assert disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=COARSE) == first
    fe_cache.clear_memory()
    assert disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=COARSE) == first
    softer = disc_body_compliance(rv80e_problem, 0.0, forces, 0.5 * BEARING_N_PER_UM, disc=0, mesh=COARSE)
    assert softer.rigid_rotation_rad == pytest.approx(2 * first.rigid_rotation_rad, rel=1e-9)


def test_pin_loads_in_the_disc_frame(rv80e_problem):
    """Contact points on the profile, forces along the normal through the pitch point, the disc
    torque their moment."""
    g = rv80e_problem.cycloid
    load = pin_load(rv80e_problem, 0.3, 1, np.ones(g.zp))
    chi_d = 0.3 + math.pi
    pitch = g.a_mm * g.zc * np.array([math.cos(chi_d), math.sin(chi_d)])  # housing direction of the eccentric ...
    turn = chi_d / g.zc  # ... in the disc frame
    pitch = np.array([math.cos(turn) * pitch[0] - math.sin(turn) * pitch[1],
                      math.sin(turn) * pitch[0] + math.cos(turn) * pitch[1]])
    to_pitch = pitch - load.contact_mm
    cross = to_pitch[:, 0] * load.normal[:, 1] - to_pitch[:, 1] * load.normal[:, 0]
    assert np.max(np.abs(cross)) < 1e-9  # every normal passes through the pitch point
    centres = load.contact_mm + g.rrp_mm * load.normal
    housing = np.stack([g.rp_mm * np.cos(g.pin_angles), g.rp_mm * np.sin(g.pin_angles)], axis=1)
    back = centres @ np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])  # R(-turn)
    back += g.a_mm * np.array([math.cos(chi_d), math.sin(chi_d)])
    assert np.max(np.abs(back - housing)) < 1e-9  # the pins' centres, back in the housing frame
    with pytest.raises(InputError, match="pin_forces_n"):
        pin_load(rv80e_problem, 0.0, 0, np.full(g.zp, np.nan))
    # a change of load may unload a pin (a preloaded unit's opposite flank, models/elastic/bodies.py): signed
    pulled = pin_load(rv80e_problem, 0.3, 1, -np.ones(g.zp))
    assert np.allclose(pulled.force_n, -load.force_n) and pulled.torque_nmm == pytest.approx(-load.torque_nmm)


def _with(*edits: tuple[str, str]):
    text = example_text("rv80e")
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    return design_from_toml(text)


HOLE = "disc_pillar_hole_diameter_mm = 34.0"


@pytest.mark.parametrize("edits, field, fragment", [
    (((HOLE, "disc_pillar_hole_diameter_mm = 31.0"),), "structure.disc_pillar_hole_diameter_mm",
     "does not clear the hole"),
    (((HOLE, "disc_pillar_hole_diameter_mm = 47.0"),), "structure.disc_pillar_hole_diameter_mm", "overlap"),
    (((HOLE, "disc_pillar_hole_diameter_mm = 50.0\ndisc_pillar_hole_radius_mm = 45.0"),),
     "structure.disc_pillar_hole_diameter_mm", "cuts into the profile's band"),
    ((("disc_centre_hole_diameter_mm = 37.0", "disc_centre_hole_diameter_mm = 48.0"),),
     "structure.disc_centre_hole_diameter_mm", "overlap"),
    ((("bearing_bore_mm = 30.0", "bearing_bore_mm = 44.0"),), "crank_stage.bearing_bore_mm",
     "crank bore"),
    (((HOLE, "disc_pillar_hole_radius_mm = 42.0"), ("disc_centre_hole_diameter_mm = 37.0", "")),
     "structure.disc_pillar_hole_radius_mm", "allowed only with disc_pillar_hole_diameter_mm"),
])
def test_bad_holes_are_refused_naming_the_field(edits, field, fragment):
    with pytest.raises(InputError) as e:
        _with(*edits)
    assert e.value.field == field, str(e.value)
    assert fragment in str(e.value) and "allowed" in str(e.value) and "\n" not in str(e.value)


def test_the_rv80e_disc_fe_is_on_and_its_holes_fit(rv80e):
    assert has_disc_fe(rv80e.structure) and not has_disc_fe(None)
    assert rv80e.structure.disc_pillar_hole_diameter_mm == 34.0


def test_a_mesh_gmsh_cannot_build_names_the_fields(rv80e_problem, forces, monkeypatch):
    """A hole across the profile (the design's checks refuse it first; here forced past them): gmsh
    leaves no mesh, refused naming the holes' fields, no traceback."""
    import rvbacklash.mechanics.disc_body as db

    real = db.disc_inputs(rv80e_problem, 0)
    crossing = Hole(70.0, 0.0, 8.0, "pillar_hole", "structure.disc_pillar_hole_diameter_mm")
    monkeypatch.setattr(db, "disc_inputs", lambda problem, disc: real._replace(holes=real.holes + (crossing,)))
    with pytest.raises(InputError) as e:
        disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=0, mesh=COARSE)
    assert e.value.field == "structure.disc_pillar_hole_diameter_mm" and "gmsh could not mesh" in str(e.value)
    assert "elastic.crank_bearing_raceway_diameter_mm" in str(e.value) or "crank_stage.bearing_bore_mm" in str(e.value)


def test_bad_arguments_are_refused(rv80e_problem, forces):
    with pytest.raises(InputError, match="bearing_stiffness_n_per_um"):
        disc_body_compliance(rv80e_problem, 0.0, forces, 0.0)
    with pytest.raises(InputError, match="pin_forces_n"):
        disc_body_compliance(rv80e_problem, 0.0, forces[0], BEARING_N_PER_UM)
    with pytest.raises(InputError, match="disc"):
        disc_body_compliance(rv80e_problem, 0.0, forces, BEARING_N_PER_UM, disc=2)
    with pytest.raises(InputError, match="structure.disc_pillar_hole_diameter_mm"):
        st = rv80e_problem.design.structure.model_copy(update={"disc_pillar_hole_diameter_mm": None})
        disc_body_compliance(prepare(rv80e_problem.design.model_copy(update={"structure": st})), 0.0, forces,
                             BEARING_N_PER_UM)
