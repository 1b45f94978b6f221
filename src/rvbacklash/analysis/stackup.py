"""Tolerance stack-up of the linear model: statistical (mean, sigma, mean +- 3 sigma),
worst case and RSS side by side, per factor, per stage and in total."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rvbacklash.analysis.sensitivity import normalised_weights, rank_descending, variance_shares
from rvbacklash.factors.catalog import CATALOG, Stage
from rvbacklash.geometry.reducer import DerivedGeometry
from rvbacklash.problem import Problem
from rvbacklash.results import Result


# --- formulas ---------------------------------------------------------------------------

def linear_mean(coefficients: np.ndarray, means: np.ndarray) -> float:
    """E[sum c_i x_i] = sum c_i mu_i. Units: [out/in] x [in] -> [out]."""
    return float(np.dot(coefficients, means))


def linear_sigma(coefficients: np.ndarray, sigmas: np.ndarray, correlation: np.ndarray | None = None) -> float:
    """Standard deviation of sum c_i x_i: sqrt(sum c_i^2 sigma_i^2) for independent x_i,
    sqrt(v^T R v) with v = c * sigma for a correlation matrix R (statistical stack-up)."""
    v = np.asarray(coefficients) * np.asarray(sigmas)
    if correlation is None:
        return float(np.sqrt(np.sum(v ** 2)))
    return float(np.sqrt(max(v @ correlation @ v, 0.0)))


def worst_case_extremes(coefficients: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> tuple[float, float]:
    """(smallest, largest) value of sum c_i x_i with every x_i anywhere in [lower_i, upper_i]:
    each factor at the zone limit that narrows, resp. widens, the result (arithmetic stack-up)."""
    a, b = np.asarray(coefficients) * lower, np.asarray(coefficients) * upper
    return float(np.minimum(a, b).sum()), float(np.maximum(a, b).sum())


def rss_half_width(coefficients: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float:
    """Root-sum-square of the half-zones, sqrt(sum (c_i (upper_i - lower_i) / 2)^2)
    (the classical RSS stack-up around the zone centres)."""
    return float(np.sqrt(np.sum((np.asarray(coefficients) * (upper - lower) / 2.0) ** 2)))


# --- results ------------------------------------------------------------------------------

@dataclass(frozen=True, repr=False)
class FactorResult(Result):
    id: int
    key: str
    name: str
    stage: str
    symbol: str
    raw_quantity: str
    zone_lower_um: float
    zone_upper_um: float
    distribution: str
    zone_origin: str
    raw_mean_um: float
    raw_sigma_um: float
    gain_um_per_um: float
    mean_um: float  # circumferential backlash at the stage's pitch circle (Table 2 "mu")
    sigma_um: float  # (Table 2 "sigma")
    sensitivity_arcmin_per_um: float  # Eq. (6), per um of raw quantity
    weight: float  # Eq. (7)
    variance_share: float  # S^2 sigma^2 / sigma_total^2
    rank: int  # by variance share, 1 = largest
    mean_arcmin: float
    sigma_arcmin: float
    worst_case_arcmin: float  # contribution at the zone limit that widens backlash
    note: str = ""

    def summary(self) -> list[str]:
        return [f"[{self.id}] {self.key}: mean {self.mean_arcmin:.4f} arcmin, sigma {self.sigma_arcmin:.4f}, "
                f"variance share {self.variance_share:.1%} (rank {self.rank})"]


@dataclass(frozen=True, repr=False)
class StageResult(Result):
    stage: str
    coefficient_arcmin_per_um: float
    mean_um: float
    sigma_um: float
    mean_arcmin: float
    sigma_arcmin: float
    worst_case_arcmin: float
    variance_share: float

    def summary(self) -> list[str]:
        return [f"{self.stage}: mean {self.mean_arcmin:.4f} arcmin, sigma {self.sigma_arcmin:.4f}"]


@dataclass(frozen=True, repr=False)
class TotalResult(Result):
    mean_arcmin: float
    sigma_arcmin: float
    minus3sigma_arcmin: float
    plus3sigma_arcmin: float
    worst_case_arcmin: float  # every factor at the limit that widens backlash
    worst_case_min_arcmin: float  # every factor at the limit that narrows it
    rss_arcmin: float  # zone centres + RSS of half-zones (upper RSS limit)
    rss_half_width_arcmin: float

    def summary(self) -> list[str]:
        return [f"mean {self.mean_arcmin:.4f} arcmin, sigma {self.sigma_arcmin:.4f}, mean + 3 sigma "
                f"{self.plus3sigma_arcmin:.4f}, worst case {self.worst_case_arcmin:.4f}, RSS {self.rss_arcmin:.4f}"]


@dataclass(frozen=True, repr=False)
class StackupResult(Result):
    """Stack-up and sensitivities of the linear model; ``rows()`` / ``to_frame()`` give the factor
    table (the paper's Table 2, extended), indexed by the Table 2 id."""

    design_name: str
    geometry: DerivedGeometry
    factors: tuple[FactorResult, ...]
    stages: dict[str, StageResult]
    total: TotalResult
    notes: dict[str, str] = field(default_factory=dict)
    _frame_index = "id"

    def to_dict(self) -> dict:
        return {
            "design": {"name": self.design_name, **self.geometry.to_dict()},
            "factors": [f.to_dict() for f in self.factors],
            "stages": {k: v.to_dict() for k, v in self.stages.items()},
            "total": self.total.to_dict(),
            "notes": dict(self.notes),
        }

    def rows(self) -> list[dict]:
        return [f.to_dict() for f in self.factors]

    def summary(self) -> list[str]:
        top = sorted(self.factors, key=lambda f: f.rank)[:3]
        return [f"{self.design_name}: " + self.total.summary()[0],
                "largest variance shares: " + ", ".join(f"{f.key} {f.variance_share:.1%}" for f in top)]


NOTES = {
    "mean_um, sigma_um": "circumferential backlash of the factor at its stage's pitch circle (paper Table 2)",
    "sensitivity_arcmin_per_um": "Eq. (6): output backlash per um of the factor's raw quantity",
    "weight": "Eq. (7): |S_i| / sum |S_j|; ranks cost per um, ignores tolerance size",
    "variance_share": "S_i^2 sigma_i^2 / sigma^2; share of the output variance, sums to 1: what to tighten",
    "worst_case_arcmin": "every factor at the zone limit that widens backlash",
    "rss_arcmin": "zone centres plus root-sum-square of the half-zones",
}


def analyze(problem: Problem) -> StackupResult:
    """Deterministic analysis of a prepared design: stack-up and sensitivities of the linear model."""
    zones = problem.zones
    mu_x, sd_x = problem.means_um, problem.sigmas_um
    corr = problem.correlation
    lo = np.array([z.lower_um for z in zones])
    hi = np.array([z.upper_um for z in zones])
    gains = problem.gains_um_per_um
    coef = problem.stage_coefficients_arcmin_per_um
    sens = problem.sensitivities_arcmin_per_um
    weights = normalised_weights(sens)
    shares = variance_shares(sens, sd_x)
    ranks = rank_descending(shares, np.abs(sens))
    widening = np.maximum(sens * lo, sens * hi)

    factors = tuple(
        FactorResult(
            id=f.id, key=f.key, name=f.name, stage=f.stage.label, symbol=f.symbol,
            raw_quantity=f.raw_quantity, zone_lower_um=float(lo[k]), zone_upper_um=float(hi[k]),
            distribution=zones[k].distribution, zone_origin=zones[k].origin,
            raw_mean_um=float(mu_x[k]), raw_sigma_um=float(sd_x[k]), gain_um_per_um=float(gains[k]),
            mean_um=float(gains[k] * mu_x[k]) + 0.0, sigma_um=float(abs(gains[k]) * sd_x[k]),
            sensitivity_arcmin_per_um=float(sens[k]), weight=float(weights[k]),
            variance_share=float(shares[k]), rank=int(ranks[k]),
            mean_arcmin=float(sens[k] * mu_x[k]) + 0.0, sigma_arcmin=float(abs(sens[k]) * sd_x[k]),
            worst_case_arcmin=float(widening[k]), note=zones[k].note,
        )
        for k, f in enumerate(CATALOG)
    )

    stages = {}
    for s in Stage:
        m = problem.stage_mask(s)
        stages[s.label] = StageResult(
            stage=s.label,
            coefficient_arcmin_per_um=float(coef[m][0]),
            mean_um=linear_mean(gains[m], mu_x[m]),
            sigma_um=linear_sigma(gains[m], sd_x[m], corr[np.ix_(m, m)]),
            mean_arcmin=linear_mean(sens[m], mu_x[m]),
            sigma_arcmin=linear_sigma(sens[m], sd_x[m], corr[np.ix_(m, m)]),
            worst_case_arcmin=float(widening[m].sum()),
            variance_share=float(shares[m].sum()),
        )

    mean = linear_mean(sens, mu_x)
    sigma = linear_sigma(sens, sd_x, corr)
    wc_min, wc_max = worst_case_extremes(sens, lo, hi)
    rss_hw = rss_half_width(sens, lo, hi)
    total = TotalResult(
        mean_arcmin=mean, sigma_arcmin=sigma,
        minus3sigma_arcmin=mean - 3 * sigma, plus3sigma_arcmin=mean + 3 * sigma,
        worst_case_arcmin=wc_max, worst_case_min_arcmin=wc_min,
        rss_arcmin=linear_mean(sens, (lo + hi) / 2) + rss_hw, rss_half_width_arcmin=rss_hw,
    )
    notes = dict(NOTES)
    if problem.design.correlation is not None:
        notes["correlation"] = (f"correlated factors {', '.join(problem.design.correlation.factors)}: sigma "
                                "includes the covariances; variance_share is the share of the independent part")
    return StackupResult(problem.name, problem.geometry, factors, stages, total, notes)
