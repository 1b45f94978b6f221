"""Statistical reading of a tolerance zone: the one registry of input distributions.

Every factor's raw quantity [um] is a random variable read from its tolerance zone. Each
entry of ``REGISTRY`` says, for one reading: the name a design file uses, a documentation line
(docs/distributions.md is checked against it), the optional zone fields it reads, the factor
kinds it applies to, its scipy.stats law (for the generic sampler, the exact distribution and
Sobol indices), its mean and standard deviation (closed form: the stack-up needs no scipy), and
how the compiled contact-model sampler draws it. Adding a distribution is one entry; an entry
without a compiled branch of its own is drawn from a tabulated inverse cdf (``KERNEL_TABLE``).

Default (Sun et al. 2014, Eq. (4)-(5)): normal, mean = zone centre, sigma = zone width / 6.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np

# 99.73 % of a normal lies within +-3 sigma; the zone covers the same share of every reading.
ZONE_COVERAGE = 0.9973002039367398  # = erf(3 / sqrt(2))

# Branches of the compiled sampler (sampling.unit_draw.draw). KERNEL_TABLE draws any law
# from its inverse cdf tabulated at TABLE_POINTS probabilities.
KERNEL_FIXED, KERNEL_NORMAL, KERNEL_UNIFORM, KERNEL_TRUNCNORM, KERNEL_RAYLEIGH, KERNEL_TABLE = range(6)
TABLE_POINTS = 4097


class KernelLaw(NamedTuple):
    """How the compiled sampler draws one factor [um]: its branch (KERNEL_*) and the parameters
    that branch reads: fixed: loc; normal: loc + scale z; uniform: lower + (upper - lower) u;
    truncated normal: loc + scale z redrawn until it lies in [lower, upper]; Rayleigh: loc + scale
    sqrt(-2 ln(1 - u)); table: none (the tabulated inverse cdf)."""

    code: int
    loc: float = 0.0
    scale: float = 0.0
    lower: float = 0.0
    upper: float = 0.0


@dataclass(frozen=True)
class ResolvedZone:
    """One factor's zone [um] and statistical reading, as the analyses and samplers use it.

    Distribution parameters left as None take their defaults from the zone.
    """

    lower_um: float
    upper_um: float
    distribution: str  # a REGISTRY name
    origin: str  # "explicit", or where a default came from (standard, grade, assumption)
    note: str = ""
    kind: str = "signed"  # catalog kind of the raw quantity
    mean_um: float | None = None
    sigma_um: float | None = None
    scale_um: float | None = None
    value_um: float | None = None


# --- formulas ------------------------------------------------------------------------------

def zone_mean_um(lower_um: float, upper_um: float) -> float:
    """Mean of a zone read as normal, mu = (upper + lower) / 2.

    Source: Sun et al. 2014, Eq. (4) (before the 1/cos(alpha) transfer).
    Parameters: lower_um, upper_um [um]. Returns [um].
    """
    return 0.5 * (lower_um + upper_um)


def zone_sigma_um(lower_um: float, upper_um: float, sigmas_in_half_zone: float = 3.0) -> float:
    """Standard deviation of a zone read as normal, sigma = (upper - lower) / 6.

    The half-zone is ``sigmas_in_half_zone`` (3) standard deviations: 99.73 % of parts
    inside the zone. Source: Sun et al. 2014, Eq. (5) (read with the difference of the
    limits; the paper prints a sum, see docs/paper-errata.md).
    Parameters: lower_um <= upper_um [um]. Returns [um] >= 0.
    """
    return (upper_um - lower_um) / (2.0 * sigmas_in_half_zone)


def rayleigh_scale_um(magnitude_limit_um: float, coverage: float = ZONE_COVERAGE) -> float:
    """Rayleigh scale s with P(R <= limit) = coverage: s = limit / sqrt(-2 ln(1 - coverage)).

    With the default coverage 0.9973 (the normal's +-3 sigma), s = limit / 3.4393.
    Source: Rayleigh cdf F(r) = 1 - exp(-r^2 / (2 s^2)).
    Parameters: magnitude_limit_um [um] > 0. Returns s [um].
    """
    return magnitude_limit_um / math.sqrt(-2.0 * math.log1p(-coverage))


def truncated_normal_moments(mean: float, sigma: float, lower: float, upper: float) -> tuple[float, float]:
    """Mean and standard deviation of N(mean, sigma) truncated to [lower, upper].

    With a = (lower - mean)/sigma, b = (upper - mean)/sigma, Z = Phi(b) - Phi(a):
    E = mean + sigma (phi(a) - phi(b)) / Z,
    Var = sigma^2 [1 + (a phi(a) - b phi(b)) / Z - ((phi(a) - phi(b)) / Z)^2].
    Source: Johnson, Kotz & Balakrishnan, Continuous Univariate Distributions vol. 1 (1994),
    ch. 13.10.1. Parameters in [um]; sigma > 0, lower < upper.
    """
    a, b = (lower - mean) / sigma, (upper - mean) / sigma
    pdf = lambda x: math.exp(-0.5 * x * x) / math.sqrt(2 * math.pi)  # noqa: E731
    cdf = lambda x: 0.5 * math.erfc(-x / math.sqrt(2))  # noqa: E731
    z = cdf(b) - cdf(a)
    d = (pdf(a) - pdf(b)) / z
    var = sigma ** 2 * (1.0 + (a * pdf(a) - b * pdf(b)) / z - d * d)
    return mean + sigma * d, math.sqrt(max(var, 0.0))


# --- the readings --------------------------------------------------------------------------

def _mean(z: ResolvedZone) -> float:
    return z.mean_um if z.mean_um is not None else zone_mean_um(z.lower_um, z.upper_um)


def _sigma(z: ResolvedZone) -> float:
    return z.sigma_um if z.sigma_um is not None else zone_sigma_um(z.lower_um, z.upper_um)


def fixed_value_um(z: ResolvedZone) -> float:
    """The value of a factor without variance (fixed, or a zero-width normal zone)."""
    if z.value_um is not None:
        return z.value_um
    return _mean(z)


def _rayleigh_scale(z: ResolvedZone) -> float:
    if z.scale_um is not None:
        return z.scale_um
    if z.kind == "phase":
        return rayleigh_scale_um(max(abs(z.lower_um), abs(z.upper_um)))
    return rayleigh_scale_um(z.upper_um - z.lower_um)


def _scipy_normal(z):
    from scipy import stats
    s = _sigma(z)
    return stats.norm(loc=_mean(z), scale=s) if s > 0 else None


def _scipy_uniform(z):
    from scipy import stats
    return stats.uniform(loc=z.lower_um, scale=z.upper_um - z.lower_um)


def _scipy_truncnorm(z):
    from scipy import stats
    m, s = _mean(z), _sigma(z)
    return stats.truncnorm((z.lower_um - m) / s, (z.upper_um - m) / s, loc=m, scale=s)


def _scipy_rayleigh(z):
    """A Rayleigh magnitude R; on a phase-weighted quantity x = R cos(theta) with a uniform phase
    x is exactly normal with sigma = the Rayleigh scale (the two components of an isotropic 2-D
    normal), and that is what is returned."""
    from scipy import stats
    if z.kind == "phase":
        return stats.norm(loc=0.0, scale=_rayleigh_scale(z))
    return stats.rayleigh(loc=z.lower_um, scale=_rayleigh_scale(z))


def _rayleigh_moments(z) -> tuple[float, float]:
    s = _rayleigh_scale(z)
    if z.kind == "phase":
        return 0.0, s
    return z.lower_um + s * math.sqrt(math.pi / 2), s * math.sqrt((4 - math.pi) / 2)


def _rayleigh_kernel(z):
    s = _rayleigh_scale(z)
    if z.kind == "phase":
        return KernelLaw(KERNEL_NORMAL, 0.0, s)
    return KernelLaw(KERNEL_RAYLEIGH, z.lower_um, s)


def _normal_kernel(z):
    s = _sigma(z)
    if s > 0:
        return KernelLaw(KERNEL_NORMAL, _mean(z), s)
    return KernelLaw(KERNEL_FIXED, fixed_value_um(z))


@dataclass(frozen=True)
class Distribution:
    """One reading of a tolerance zone (see the module docstring)."""

    name: str
    doc: str
    parameters: tuple[str, ...]  # optional zone fields it reads
    kinds: tuple[str, ...] | None  # catalog kinds it applies to; None: every kind
    needs_width: bool  # refuses a zone of zero width
    scipy: Callable[[ResolvedZone], Any]  # frozen scipy.stats law, None for a deterministic value
    moments: Callable[[ResolvedZone], tuple[float, float]]  # (mean, sigma) [um]
    kernel: Callable[[ResolvedZone], KernelLaw] | None = None
    normal: Callable[[ResolvedZone], bool] = lambda z: False  # the law is exactly normal (closed forms)


REGISTRY: dict[str, Distribution] = {d.name: d for d in (
    Distribution(
        "normal", "N(mean, sigma), mean = zone centre, sigma = zone width / 6 (Sun et al. 2014, Eq. (4)-(5)); "
                  "the default",
        ("mean_um", "sigma_um"), None, False, _scipy_normal, lambda z: (_mean(z), _sigma(z)), _normal_kernel,
        normal=lambda z: _sigma(z) > 0),
    Distribution(
        "uniform", "uniform over the zone", (), None, True, _scipy_uniform,
        lambda z: (zone_mean_um(z.lower_um, z.upper_um), (z.upper_um - z.lower_um) / math.sqrt(12.0)),
        lambda z: KernelLaw(KERNEL_UNIFORM, lower=z.lower_um, upper=z.upper_um)),
    Distribution(
        "truncated_normal", "the normal above (same mean_um / sigma_um), truncated to the zone",
        ("mean_um", "sigma_um"), None, True, _scipy_truncnorm,
        lambda z: truncated_normal_moments(_mean(z), _sigma(z), z.lower_um, z.upper_um),
        lambda z: KernelLaw(KERNEL_TRUNCNORM, _mean(z), _sigma(z), z.lower_um, z.upper_um)),
    Distribution(
        "rayleigh", "Rayleigh magnitude for magnitude-type errors, scale = limit / 3.4393 (99.73 % inside); on a "
                    "phase-weighted quantity R cos(theta) with a uniform phase, i.e. normal with sigma = scale",
        ("scale_um",), ("magnitude", "phase"), False, _scipy_rayleigh, _rayleigh_moments, _rayleigh_kernel,
        normal=lambda z: z.kind == "phase"),
    Distribution(
        "fixed", "a deterministic value: value_um, else the zone centre", ("value_um",), None, False,
        lambda z: None, lambda z: (fixed_value_um(z), 0.0),
        lambda z: KernelLaw(KERNEL_FIXED, fixed_value_um(z))),
)}

NAMES: tuple[str, ...] = tuple(REGISTRY)
PARAMETERS: tuple[str, ...] = ("mean_um", "sigma_um", "scale_um", "value_um")  # every optional parameter


def distribution(name: str) -> Distribution:
    return REGISTRY[name]


def marginal(z: ResolvedZone):
    """The scipy.stats frozen distribution of a factor's raw quantity [um], None if fixed."""
    return REGISTRY[z.distribution].scipy(z)


def moments_um(z: ResolvedZone) -> tuple[float, float]:
    """(mean, sigma) of a factor's raw quantity [um]."""
    return REGISTRY[z.distribution].moments(z)


def is_random(z: ResolvedZone) -> bool:
    return moments_um(z)[1] > 0


def is_normal(z: ResolvedZone) -> bool:
    """The raw quantity is exactly normal (and random)."""
    return REGISTRY[z.distribution].normal(z)


def kernel_draw(z: ResolvedZone) -> KernelLaw:
    """How the compiled sampler draws this zone; a law without a branch of its own is drawn from
    its tabulated inverse cdf."""
    entry = REGISTRY[z.distribution]
    if entry.kernel is None:
        return KernelLaw(KERNEL_TABLE)
    return entry.kernel(z)


def ppf_table(z: ResolvedZone, points: int = TABLE_POINTS) -> np.ndarray:
    """Inverse cdf at probabilities (k + 0.5) / points, k = 0..points-1 [um] (KERNEL_TABLE)."""
    d = marginal(z)
    if d is None:
        return np.full(points, fixed_value_um(z))
    return np.asarray(d.ppf((np.arange(points) + 0.5) / points), dtype=float)


def markdown_table() -> str:
    """The table of readings for docs/distributions.md (a test keeps the page in step)."""
    lines = ["| `distribution` | reading | parameters | applies to |", "|---|---|---|---|"]
    for d in REGISTRY.values():
        params = ", ".join(f"`{p}`" for p in d.parameters) or "—"
        kinds = ", ".join(d.kinds) if d.kinds else "every factor"
        lines.append(f"| `{d.name}` | {d.doc} | {params} | {kinds} |")
    return "\n".join(lines)
