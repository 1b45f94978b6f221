"""The 3-D elasticity helpers (mechanics/solid.py) against scikit-fem's own forms."""

from __future__ import annotations

import numpy as np
from skfem import MeshTet
from skfem.models.elasticity import lame_parameters, linear_elasticity

from rvbacklash.mechanics import solid


def test_the_stiffness_matrix_is_scikit_fems():
    mesh = MeshTet().refined(2)
    mesh = MeshTet(mesh.p * np.array([[2.0], [1.0], [0.5]]), mesh.t)  # not a cube: every term counts
    basis = solid.vector_p2_basis(mesh)
    ours = solid.stiffness_matrix(basis, 206e3, 0.3)
    theirs = linear_elasticity(*lame_parameters(206e3, 0.3)).assemble(basis)
    assert abs(ours - theirs).max() <= 1e-12 * abs(theirs).max()
    assert abs(ours - solid.stiffness_matrix(basis, 206e3, 0.2)).max() > 1e-3 * abs(theirs).max()


def test_rigid_body_modes_cost_no_energy():
    mesh = MeshTet().refined(1)
    basis = solid.vector_p2_basis(mesh)
    k = solid.stiffness_matrix(basis, 1e3, 0.3)
    modes = solid.rigid_body_modes(basis, np.arange(basis.N))
    assert np.abs(k @ modes).max() < 1e-9 * abs(k).max()
    assert np.linalg.matrix_rank(modes) == 6
