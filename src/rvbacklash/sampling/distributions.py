"""Statistical reading of a tolerance zone (Sun et al. 2014, Eq. (4)-(5)).

The paper reads every zone [lower, upper] as a normal variable whose 3-sigma range is the
zone: mean = (lower + upper) / 2, sigma = (upper - lower) / 6. A "fixed" zone is a
deterministic value (lower = upper, sigma = 0).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from rvbacklash.design.derived import ResolvedZone


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


def zone_moments(zones: Sequence[ResolvedZone]) -> tuple[np.ndarray, np.ndarray]:
    """(mean, sigma) arrays [um] of the raw quantities, in catalog order."""
    mean = np.array([zone_mean_um(z.lower_um, z.upper_um) for z in zones])
    sigma = np.array([0.0 if z.distribution == "fixed" else zone_sigma_um(z.lower_um, z.upper_um)
                      for z in zones])
    return mean, sigma
