"""The linear backlash model of Sun et al. 2014 (Table 1 transfers + Eq. (2)).

    dphi [arcmin] = sum_i  C_stage(i) * gain_i * x_i

x_i is the raw value of factor i [um] (catalog order = Table 2 numbering), gain_i its
transfer to circumferential backlash [um/um], C_stage the Eq. (1) coefficient [arcmin/um].
The model is a plain vectorised map (n, 21) -> (n,): ``model(x)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from rvbacklash.factors.catalog import CATALOG, Stage
from rvbacklash.geometry.reducer import DerivedGeometry
from rvbacklash.problem import Problem

N_FACTORS = len(CATALOG)


@dataclass(frozen=True, eq=False)
class LinearModel:
    geometry: DerivedGeometry
    gains_um_per_um: np.ndarray  # (21,) transfer gains
    stage_coefficients_arcmin_per_um: np.ndarray  # (21,) Eq. (1) coefficient of each factor's stage
    stages: np.ndarray  # (21,) Stage values 1..3

    @property
    def sensitivities_arcmin_per_um(self) -> np.ndarray:
        """S_i = d(dphi)/dx_i [arcmin per um of raw quantity] (Eq. 6); constant for a linear model."""
        return self.gains_um_per_um * self.stage_coefficients_arcmin_per_um

    def _check(self, x: ArrayLike) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape[-1:] != (N_FACTORS,):
            raise ValueError(f"factor values must have shape (n, {N_FACTORS}); got {x.shape}")
        return x

    def backlash_um(self, x: ArrayLike) -> np.ndarray:
        """Circumferential backlash of each factor [um], same shape as x."""
        return self._check(x) * self.gains_um_per_um

    def stage_backlash_um(self, x: ArrayLike) -> np.ndarray:
        """Stage sums dj_1, dj_2, dj_3 of Eq. (1) [um], shape (..., 3)."""
        j = self.backlash_um(x)
        return np.stack([j[..., self.stages == s].sum(axis=-1) for s in Stage], axis=-1)

    def __call__(self, x: ArrayLike) -> np.ndarray:
        """Output backlash dphi [arcmin], shape x.shape[:-1]."""
        return self._check(x) @ self.sensitivities_arcmin_per_um


def linear_model(problem: Problem) -> LinearModel:
    return LinearModel(problem.geometry, problem.gains_um_per_um, problem.stage_coefficients_arcmin_per_um,
                       problem.stages)
