"""Every factor's tolerance zone, resolved once: explicit zone, factor grade or stage grade
(standards), or the nominal value of a designed modification; each with its origin."""

from __future__ import annotations

from rvbacklash.design.schema import Design
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.factors.distributions import ResolvedZone
from rvbacklash.standards.factor_tolerances import graded_zone

NOMINAL_MODIFICATION = {
    "equidistance_modification": "equidistance_modification_um",
    "moving_distance_modification": "moving_distance_modification_um",
}


def resolve_zones(design: Design) -> tuple[ResolvedZone, ...]:
    """Zones in catalog order. Precedence: explicit zone, factor grade, stage grade; an omitted
    modification zone is the stage's nominal value (fixed)."""
    zones = []
    for f in CATALOG:
        zone = getattr(design.factors, f.key)
        if zone is not None and zone.has_zone:
            lo, hi = zone.limits_um
            origin = "explicit"
        elif f.key in NOMINAL_MODIFICATION:
            field = NOMINAL_MODIFICATION[f.key]
            v = float(getattr(design.second_stage, field))
            zones.append(ResolvedZone(v, v, "fixed", f"second_stage.{field} (nominal, fixed)", kind=f.kind,
                                      value_um=v))
            continue
        else:
            grade, field = design.grades.grade_for(f)
            g = graded_zone(f, grade, design, design.grades.edition, field)
            lo, hi, origin = g.lower_um, g.upper_um, g.origin
        dist = zone.distribution if zone is not None else "normal"
        if dist == "fixed":  # deterministic: its "zone" is the value itself
            lo = hi = zone.value_um if zone.value_um is not None else 0.5 * (lo + hi)
        params = (zone.mean_um, zone.sigma_um, zone.scale_um, zone.value_um) if zone is not None else (None,) * 4
        zones.append(ResolvedZone(float(lo), float(hi), dist, origin, zone.note if zone else "", f.kind, *params))
    return tuple(zones)
