"""The zones of the errors only the transmission-error model reads (factors.catalog.KINEMATIC_FACTORS,
design ``[transmission_error]``) and how a unit draws them (docs/transmission-error.md).

Each is a 2-D position error: an isotropic normal vector (sigma per component) whose length
stays within the zone's radius R for 99.73 % of the parts (the length is Rayleigh distributed:
P(|v| <= R) = 1 - exp(-R^2 / (2 sigma^2)) = 0.9973 gives sigma = R / 3.44). ASSUMPTION: isotropic
(no preferred direction), independent from part to part; a position tolerance t (zone
diameter) has R = t / 2, an eccentricity zone e has R = e.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rvbacklash.design.schema import Design
from rvbacklash.factors.catalog import FACTOR_KEYS, KINEMATIC_FACTORS
from rvbacklash.factors.distributions import ResolvedZone

WITHIN_ZONE = 0.9973  # share of parts whose error lies within the zone's radius
DEFAULT_HOLE_POSITION_UM = 10.0  # ASSUMPTION (factors.catalog.KINEMATIC_FACTORS)
SIGMA_PER_RADIUS = 1.0 / math.sqrt(-2.0 * math.log(1.0 - WITHIN_ZONE))  # 1 / 3.44


@dataclass(frozen=True)
class KinematicZone:
    """Zone radius [um] of one kinematic factor, the sigma per component it implies, its origin."""

    key: str
    radius_um: float
    sigma_um: float
    origin: str


def kinematic_zones(design: Design, zones: tuple[ResolvedZone, ...]) -> tuple[KinematicZone, ...]:
    """The zones of KINEMATIC_FACTORS in catalog order."""
    te = design.transmission_error
    runout = zones[FACTOR_KEYS.index("gear_runout")]
    fr = max(abs(runout.lower_um), abs(runout.upper_um))
    out = []
    for f in KINEMATIC_FACTORS:
        given = getattr(te, f.key + "_um")
        if f.key.endswith("eccentricity"):
            radius, origin = (given, "explicit") if given is not None else \
                (fr / 2.0, f"default: F_r / 2 of gear_runout ({runout.origin})")
        else:
            t = given if given is not None else DEFAULT_HOLE_POSITION_UM
            radius, origin = t / 2.0, "explicit" if given is not None else f"default: {f.default}"
        out.append(KinematicZone(f.key, float(radius), float(radius) * SIGMA_PER_RADIUS, origin))
    return tuple(out)
