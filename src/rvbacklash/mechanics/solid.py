"""Three-dimensional linear elasticity on gmsh meshes: what every 3-D body of the mechanics layer
shares (docs/rigidity-elements.md).

- ``gmsh_session``: a gmsh model for one mesh (no terminal output, Ctrl-C left to the caller);
- ``tet_mesh``: the model's linear tetrahedra as a scikit-fem ``MeshTet``;
- ``vector_p2_basis``: quadratic tetrahedra (``ElementVector(ElementTetP2())``), straight-sided;
- ``stiffness_matrix``: Hooke's law (as scikit-fem's ``linear_elasticity``, vectorised) in N and mm;
- ``solve_clamped``: K u = f with some degrees of freedom held at zero, by conjugate gradients
  preconditioned with smoothed-aggregation algebraic multigrid (pyamg) on the body's rigid-body
  modes: a sparse direct solver needed ~15 GiB for a carrier of ~20 000 quadratic nodes.

Units: lengths [mm], forces [N], moduli [N/mm^2 = MPa], displacements [mm].
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from typing import NamedTuple

import numpy as np
import pyamg
from threadpoolctl import threadpool_limits
import scipy.sparse as sp
from scipy.sparse.linalg import cg
from scipy.spatial import cKDTree
from skfem import Basis, ElementTetP2, ElementVector, MeshTet
from skfem.models.elasticity import lame_parameters

CG_RTOL = 1e-7  # relative residual: the compliance (an energy) converges like its square (rv80e: the same
                # to 10 digits at 1e-6 as at 1e-10)
CG_MAX_ITERATIONS = 2000
GMSH_TETRAHEDRON = 4  # gmsh's element type of a 4-node tetrahedron


class SolverError(RuntimeError):
    """The iterative solve did not converge (the caller names the input that made the body so)."""


@contextlib.contextmanager
def gmsh_session(name: str) -> Iterator[object]:
    """A fresh gmsh model named ``name`` (the ``gmsh`` module is yielded); gmsh is finalised on
    exit. ``interruptible=False``: gmsh would otherwise install its own Ctrl-C handler."""
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add(name)
        yield gmsh
    finally:
        gmsh.finalize()


def tet_mesh(gmsh) -> MeshTet:
    """The meshed gmsh model's 4-node tetrahedra as a ``MeshTet`` [mm] (nodes that no tetrahedron
    uses are dropped)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    _, element_nodes = gmsh.model.mesh.getElementsByType(GMSH_TETRAHEDRON)
    if element_nodes.size == 0:
        raise ValueError("the body has no volume to mesh")
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(tags.size)
    t = index[element_nodes.astype(np.int64)].reshape(-1, 4)
    used, t = np.unique(t, return_inverse=True)
    p = coords.reshape(-1, 3)[used]
    return MeshTet(np.ascontiguousarray(p.T), np.ascontiguousarray(t.reshape(-1, 4).T))


def vector_p2_basis(mesh: MeshTet, elements: np.ndarray | None = None) -> Basis:
    """Quadratic displacement basis on ``mesh`` (on ``elements`` only when given). Quadrature of
    order 2: the strains of quadratic straight-sided tetrahedra are linear, so the stiffness
    integrand is quadratic and order 2 integrates it exactly (scikit-fem's default, 4, is ~3x the
    cost for the same matrix)."""
    return Basis(mesh, ElementVector(ElementTetP2()), elements=elements, intorder=2)


def stiffness_matrix(basis: Basis, e_mpa: float, nu: float) -> sp.csr_matrix:
    """Stiffness matrix of an isotropic body [N/mm], Young's modulus E [MPa], Poisson's ratio nu [-]:

        K_ij = int (2 mu eps(phi_i) : eps(phi_j) + lambda tr eps(phi_i) tr eps(phi_j)) dV

    (Lame's lambda and mu from ``lame_parameters``; the same matrix as scikit-fem's
    ``linear_elasticity(...).assemble(basis)``, checked in the tests). Each element's matrix is one
    product F F^T, F the basis functions' strains scaled by the quadrature weights (stacked over
    the quadrature points): 2-3x faster than the form's pairwise loop."""
    lam, mu = lame_parameters(e_mpa, nu)
    grad = np.stack([phi[0].grad for phi in basis.basis])  # (functions, component, direction, element, point)
    eps = 0.5 * (grad + grad.transpose(0, 2, 1, 3, 4))
    nb, _, _, nel, nq = eps.shape
    shear = eps.reshape(nb, 9, nel, nq) * np.sqrt(2.0 * mu * basis.dx)
    volume = np.einsum("iaaeq->ieq", eps)[:, None] * np.sqrt(lam * basis.dx)
    factor = np.concatenate([shear, volume], axis=1).transpose(2, 0, 1, 3).reshape(nel, nb, 10 * nq)
    local = np.matmul(factor, factor.transpose(0, 2, 1))
    dofs = basis.element_dofs.T
    rows = np.broadcast_to(dofs[:, :, None], local.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], local.shape).ravel()
    return sp.csr_matrix((local.ravel(), (rows, cols)), shape=(basis.N, basis.N))


def dof_components(basis: Basis) -> np.ndarray:
    """Which displacement component (0 x, 1 y, 2 z) each degree of freedom of a vector basis is."""
    comp = np.empty(basis.N, dtype=np.int64)
    for name in ("nodal_dofs", "facet_dofs", "edge_dofs", "interior_dofs"):
        dofs = getattr(basis, name, None)
        if dofs is not None and dofs.size:
            comp[dofs] = np.arange(dofs.shape[0])[:, None]
    return comp


def rigid_body_modes(basis: Basis, dofs: np.ndarray) -> np.ndarray:
    """The six rigid-body motions (three translations, three rotations about the centroid) at
    ``dofs``: the near-null space smoothed aggregation needs for elasticity. Shape (len(dofs), 6)."""
    comp = dof_components(basis)[dofs]
    x = basis.doflocs[:, dofs]
    x = x - x.mean(axis=1, keepdims=True)
    modes = np.zeros((dofs.size, 6))
    for i in range(3):
        modes[comp == i, i] = 1.0
    for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):  # rotation in the (a, b) plane
        modes[comp == a, 3 + k] = -x[b, comp == a]
        modes[comp == b, 3 + k] = x[a, comp == b]
    return modes


def rotation_about_z(angle_rad: float) -> np.ndarray:
    """The 3 x 3 rotation by ``angle_rad`` about the z axis."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


class Tie(NamedTuple):
    """Degrees of freedom tied to others: u = matrix @ u_kept; kept: the dof of each column."""

    matrix: sp.csr_matrix
    kept: np.ndarray


def sector_tie(basis: Basis, sector_rad: float, tolerance_mm: float) -> tuple[Tie, np.ndarray]:
    """Rotational (cyclic) symmetry of a sector -sector/2 ... +sector/2 about z, meshed with matching
    faces (gmsh setPeriodic): u = T u_kept, the displacements on the face at +sector/2 those of
    their partners at -sector/2 turned by the sector, u_s = R u_m (a body of n equal sectors under
    n equal loads deforms alike in each). Returns T (N x kept) and the x, y degrees of freedom on
    the axis (on both faces: held at zero by the symmetry). Raises SolverError if a node of the
    face at +sector/2 has no partner."""
    x, comp = basis.doflocs, dof_components(basis)

    def on_face(angle):
        across = -np.sin(angle) * x[0] + np.cos(angle) * x[1]
        along = np.cos(angle) * x[0] + np.sin(angle) * x[1]
        return (np.abs(across) < tolerance_mm) & (along > tolerance_mm), np.hypot(x[0], x[1]) < tolerance_mm

    slave, axis = on_face(0.5 * sector_rad)
    master, _ = on_face(-0.5 * sector_rad)
    turn = rotation_about_z(sector_rad)
    s0, m0 = np.nonzero(slave & (comp == 0))[0], np.nonzero(master & (comp == 0))[0]
    distance, nearest = cKDTree((turn @ x[:, m0]).T).query(x[:, s0].T)
    if s0.size and distance.max() > tolerance_mm:
        raise SolverError(f"the sector's faces do not match (a node {distance.max():.3g} mm from its partner)")
    m0 = m0[nearest]
    # a vector basis numbers the three components of a node (or edge midpoint) consecutively
    if np.any(comp[np.r_[s0, m0] + 1] != 1) or np.any(comp[np.r_[s0, m0] + 2] != 2):
        raise SolverError("unexpected numbering of the vector basis' degrees of freedom")
    slaves = (s0[:, None] + np.arange(3)).ravel()
    kept = np.setdiff1d(np.arange(basis.N), slaves)
    column = np.full(basis.N, -1)
    column[kept] = np.arange(kept.size)
    rows = [kept]
    cols = [np.arange(kept.size)]
    vals = [np.ones(kept.size)]
    for i in range(3):
        for j in range(3):
            if turn[i, j] != 0.0:
                rows.append(s0 + i)
                cols.append(column[m0 + j])
                vals.append(np.full(s0.size, turn[i, j]))
    tie = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(basis.N, kept.size))
    return Tie(tie, kept), np.nonzero(axis & (comp < 2))[0]


def solve_clamped(basis: Basis, stiffness: sp.csr_matrix, load: np.ndarray, held: np.ndarray,
                  tie: Tie | None = None) -> tuple[np.ndarray, int]:
    """Displacements u [mm] of K u = f with the degrees of freedom ``held`` at zero (and u = T u_kept
    for a ``tie``, ``sector_tie``), and the number of conjugate-gradient iterations. Raises
    SolverError if CG does not reach CG_RTOL."""
    if tie is None:
        free = np.setdiff1d(np.arange(basis.N), held)
        t_free = sp.identity(basis.N, format="csr")[:, free]
        a, b, dofs = stiffness[free][:, free].tocsr(), load[free], free
    else:
        column = np.full(basis.N, -1)
        column[tie.kept] = np.arange(tie.kept.size)
        held_kept = column[held]
        free = np.setdiff1d(np.arange(tie.kept.size), held_kept[held_kept >= 0])
        t_free = tie.matrix[:, free]
        a, b, dofs = (t_free.T @ stiffness @ t_free).tocsr(), t_free.T @ load, tie.kept[free]
    with threadpool_limits(1, user_api="blas"):  # vector BLAS calls on 2 threads: slower, much slower when loaded
        return _solve_reduced(basis, a, b, dofs, t_free)


def _solve_reduced(basis: Basis, a: sp.csr_matrix, b: np.ndarray, dofs: np.ndarray,
                   t_free: sp.csr_matrix) -> tuple[np.ndarray, int]:
    # the prolongation smoother's weight from each row (``weighting="local"``), not from the matrix's spectral
    # radius: that estimate took 3.4 of a 10 s rv80e solve; the coarse level by sparse LU, not a pseudo-inverse
    ml = pyamg.smoothed_aggregation_solver(a, B=rigid_body_modes(basis, dofs), symmetry="hermitian",
                                           max_coarse=500, smooth=("jacobi", {"weighting": "local"}),
                                           coarse_solver="splu")
    iterations = 0

    def count(_):
        nonlocal iterations
        iterations += 1

    x, info = cg(a, b, rtol=CG_RTOL, atol=0.0, maxiter=CG_MAX_ITERATIONS, M=ml.aspreconditioner(), callback=count)
    if info != 0:
        raise SolverError(f"conjugate gradients did not converge in {iterations} iterations")
    return t_free @ x, iterations
