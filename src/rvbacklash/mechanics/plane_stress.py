"""Plane-stress linear elasticity on a triangle mesh, quadratic elements (scikit-fem): the
stiffness of a plate of thickness t, loads and readings at points, rigid-body modes, and the
radial springs (a Winkler foundation) that hold a bore. Units: mm, N, MPa (N/mm^2).

Plane stress (a thin plate loaded in its plane, sigma_zz = 0): the plane-strain law with the
first Lame parameter replaced by lambda* = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2)
(Timoshenko & Goodier, Theory of Elasticity, 3rd ed., section 8 / 16).

The displacement vector is stacked by component, u = [u_x; u_y], each a quadratic (P2) field of
one scalar basis: the 2 x 2 blocks are assembled from the scalar basis's derivative matrices
(four small forms instead of one 12 x 12 vector form: ~5x faster in scikit-fem).
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from skfem import Basis, BilinearForm, ElementTriP2, FacetBasis, MeshTri, asm


def plane_stress_lame_mpa(youngs_modulus_mpa: float, poisson_ratio: float) -> tuple[float, float]:
    """(lambda*, mu) [MPa] of plane stress: lambda* = 2 lambda mu / (lambda + 2 mu) = E nu / (1 - nu^2),
    mu = E / (2 (1 + nu)). Source: Timoshenko & Goodier, Theory of Elasticity (3rd ed.), plane
    stress vs plane strain. Validity: isotropic, linear, a plate thin against its in-plane size."""
    lam = youngs_modulus_mpa * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio))
    mu = youngs_modulus_mpa / (2.0 * (1.0 + poisson_ratio))
    return 2.0 * lam * mu / (lam + 2.0 * mu), mu


def scalar_basis(mesh: MeshTri) -> Basis:
    """Quadratic scalar field on ``mesh``: each displacement component is one."""
    return Basis(mesh, ElementTriP2())


@BilinearForm
def _dxdx(u, v, w):
    return u.grad[0] * v.grad[0]


@BilinearForm
def _dydy(u, v, w):
    return u.grad[1] * v.grad[1]


@BilinearForm
def _dydx(u, v, w):  # row (test) derivative x, column (trial) derivative y: entry (i, j) = int dx phi_i dy phi_j
    return u.grad[1] * v.grad[0]


def stiffness_matrix(basis: Basis, youngs_modulus_mpa: float, poisson_ratio: float,
                     thickness_mm: float) -> sparse.csr_matrix:
    """K [N/mm] of a plate of thickness t, u = [u_x; u_y]: t int sigma(u) : eps(v) with
    sigma = lambda* tr(eps) I + 2 mu eps, as blocks of D_ab = int d_a phi_i d_b phi_j:
    K_xx = (lambda* + 2 mu) D_xx + mu D_yy, K_yy = (lambda* + 2 mu) D_yy + mu D_xx,
    K_xy = lambda* D_xy + mu D_yx, K_yx = K_xy^T."""
    lam, mu = plane_stress_lame_mpa(youngs_modulus_mpa, poisson_ratio)
    dxx, dyy, dxy = asm(_dxdx, basis), asm(_dydy, basis), asm(_dydx, basis)
    kxx = (lam + 2 * mu) * dxx + mu * dyy
    kyy = (lam + 2 * mu) * dyy + mu * dxx
    kxy = lam * dxy + mu * dxy.T
    return (thickness_mm * sparse.bmat([[kxx, kxy], [kxy.T, kyy]])).tocsr()


def point_operator(basis: Basis, points_mm: np.ndarray) -> sparse.csr_matrix:
    """P (2 n, 2 N): P @ u is the displacement at the n points (n, 2) [mm], rows u_x of every point
    then u_y; P.T @ [f_x; f_y] is the consistent load of point forces there (virtual work)."""
    p = basis.probes(np.ascontiguousarray(np.asarray(points_mm, float).T)).tocsr()
    return sparse.block_diag([p, p], format="csr")


def point_loads(operator: sparse.csr_matrix, forces_n: np.ndarray) -> np.ndarray:
    """Load vector [N] of forces (n, 2) at the points of ``operator`` (``point_operator``)."""
    f = np.asarray(forces_n, float)
    return operator.T @ np.concatenate([f[:, 0], f[:, 1]])


def point_values(operator: sparse.csr_matrix, u: np.ndarray) -> np.ndarray:
    """Displacements (n, 2) [mm] at the points of ``operator``."""
    return (operator @ u).reshape(2, -1).T


def rigid_modes(basis: Basis) -> np.ndarray:
    """G (2 N, 3): the nodal values of the rigid motions u = (1, 0), (0, 1) and the unit rotation
    about the origin (-y, x). Exact: quadratic elements interpolate linear fields at their nodes.
    G.T @ f is a load's resultant (F_x, F_y) and its moment about the origin [N mm]."""
    x, y = basis.doflocs
    n = basis.N
    g = np.zeros((2 * n, 3))
    g[:n, 0] = 1.0
    g[n:, 1] = 1.0
    g[:n, 2] = -y
    g[n:, 2] = x
    return g


def component_dofs(basis: Basis, facets: np.ndarray) -> np.ndarray:
    """The indices in u = [u_x; u_y] of both components at the nodes of ``facets``."""
    dofs = basis.get_dofs(facets).flatten()
    return np.concatenate([dofs, dofs + basis.N])


class RadialSprings:
    """Radial springs on a bore's boundary ``facets`` (a Winkler foundation): k (u . e_r)(v . e_r) per
    length of boundary, k [N/mm per mm], e_r the unit radius from the bore's centre, acting only on
    the half whose e_r . zone_direction > 0 (the half pressed against what the bore holds). A bore of
    radius R moved by delta as a rigid body feels k R (pi / 2) delta in any direction: k = 2 K /
    (pi R) gives it the stiffness K (``winkler_line_stiffness``).

    The radial displacement at the boundary's quadrature points, B u, is built once; a zone's
    stiffness is then B^T diag(k w active) B (w the quadrature weights), cheap to rebuild as the
    zone turns."""

    def __init__(self, mesh: MeshTri, basis: Basis, facets: np.ndarray, centre_mm: tuple[float, float],
                 line_stiffness_n_per_mm2: float):
        fb = FacetBasis(mesh, basis.elem, facets=facets, intorder=6)
        x = np.asarray(fb.global_coordinates())  # (2, facets, points)
        rx, ry = x[0] - centre_mm[0], x[1] - centre_mm[1]
        r = np.sqrt(rx * rx + ry * ry)
        self.er = np.stack([(rx / r).ravel(), (ry / r).ravel()])  # (2, q)
        nq, nb = x.shape[1] * x.shape[2], fb.Nbfun
        rows = np.repeat(np.arange(nq).reshape(x.shape[1], x.shape[2])[None], nb, axis=0)  # (basis fn, facet, point)
        cols = np.broadcast_to(fb.element_dofs[:, :, None], rows.shape)
        vals = np.stack([np.asarray(fb.basis[i][0]) for i in range(nb)])
        phi = sparse.coo_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(nq, basis.N)).tocsr()
        self.radial = sparse.hstack([sparse.diags(self.er[0]) @ phi, sparse.diags(self.er[1]) @ phi]).tocsr()
        self.weight = line_stiffness_n_per_mm2 * fb.dx.ravel()

    def active(self, zone_direction) -> np.ndarray:
        """Which quadrature points carry springs: those of the half facing ``zone_direction``."""
        return (self.er[0] * zone_direction[0] + self.er[1] * zone_direction[1]) > 0.0

    def stiffness(self, zone_direction) -> sparse.csr_matrix:
        """[N/mm] of the springs on the half facing ``zone_direction``."""
        return (self.radial.T @ sparse.diags(self.weight * self.active(zone_direction)) @ self.radial).tocsr()


def winkler_line_stiffness(radial_stiffness_n_per_mm: float, radius_mm: float) -> float:
    """k = 2 K / (pi R) [N/mm per mm of boundary]: radial springs on half a bore of radius R whose
    rigid translation meets the stiffness K [N/mm] (integral of k cos^2 over a half circle =
    k R pi / 2). Source: ours (integration). Validity: the half-circle zone of ``radial_springs``."""
    return 2.0 * radial_stiffness_n_per_mm / (np.pi * radius_mm)
