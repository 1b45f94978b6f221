"""From standard normals to the 21 raw factor values (Gaussian copula), and the fast-path
plan of the linear model.

Every method first produces independent standard normals Z, one column per random factor.
A correlation matrix R (Gaussian copula) makes them Z L^T with L L^T = R. A normal factor is
then mu + sigma z; any other marginal F is F^-1(Phi(z)); a fixed factor is its value.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rvbacklash.problem import Problem

N_FACTORS = 21


def correlation_factor(r: np.ndarray) -> np.ndarray:
    """L with L L^T = R for a symmetric positive semi-definite R (eigen-decomposition, so a
    singular R, e.g. two fully correlated factors, is fine)."""
    vals, vecs = np.linalg.eigh(r)
    return vecs * np.sqrt(np.clip(vals, 0.0, None))


@dataclass(frozen=True, eq=False)
class InputTransform:
    """Maps (n, k) independent standard normals to (n, 21) raw values [um]."""

    random_columns: np.ndarray  # catalog indices of the k random factors
    fixed_values: np.ndarray  # (21,) value of every factor without variance (0 elsewhere)
    marginals: tuple  # (k,) scipy frozen distributions
    normal_mask: np.ndarray  # (k,) True where the marginal is normal
    means: np.ndarray  # (k,) normal means (0 elsewhere)
    sigmas: np.ndarray  # (k,) normal sigmas (0 elsewhere)
    chol: np.ndarray | None  # (k, k) correlation factor, None if independent

    @property
    def dimension(self) -> int:
        return int(self.random_columns.size)

    def correlate(self, z: np.ndarray) -> np.ndarray:
        return z if self.chol is None else z @ self.chol.T

    def __call__(self, z: np.ndarray) -> np.ndarray:
        z = self.correlate(z)
        x = np.broadcast_to(self.fixed_values, (z.shape[0], N_FACTORS)).copy()
        for col, (idx, dist) in enumerate(zip(self.random_columns, self.marginals)):
            if self.normal_mask[col]:
                x[:, idx] = self.means[col] + self.sigmas[col] * z[:, col]
            else:
                from scipy import special  # here: only a non-normal marginal needs it (a third of a second to import)

                x[:, idx] = dist.ppf(special.ndtr(z[:, col]))
        return x


def _is_normal(dist) -> bool:
    return dist is not None and dist.dist.name == "norm"


def build_input_transform(problem: Problem) -> InputTransform:
    """The copula transform of a problem's random factors (fixed ones keep their value)."""
    cols = np.flatnonzero(problem.random_mask)
    dists = tuple(problem.marginals[i] for i in cols)
    fixed = np.where(problem.random_mask, 0.0, problem.means_um)
    normal = np.array([_is_normal(d) for d in dists], dtype=bool)
    means = np.where(normal, problem.means_um[cols], 0.0)
    sigmas = np.where(normal, problem.sigmas_um[cols], 0.0)
    sub = problem.correlation[np.ix_(cols, cols)]
    chol = None if np.array_equal(sub, np.eye(cols.size)) else correlation_factor(sub)
    return InputTransform(cols, fixed, dists, normal, means, sigmas, chol)


def linear_fast_plan(transform: InputTransform, sensitivities: np.ndarray) -> tuple[np.ndarray, float] | None:
    """(weights, offset) such that y = offset + z . weights for the linear model, when every
    random factor is normal (correlated or not); None otherwise."""
    if not transform.normal_mask.all():
        return None
    s = sensitivities[transform.random_columns]
    v = s * transform.sigmas
    weights = v if transform.chol is None else transform.chol.T @ v
    offset = float(sensitivities @ transform.fixed_values + s @ transform.means)
    return np.ascontiguousarray(weights, dtype=float), offset
