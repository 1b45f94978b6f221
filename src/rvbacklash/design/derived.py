"""Quantities derived from a validated Design: geometry and resolved tolerance zones."""

from __future__ import annotations

from dataclasses import asdict, dataclass

from rvbacklash.design import geometry
from rvbacklash.design.schema import Design
from rvbacklash.factors.catalog import CATALOG


@dataclass(frozen=True)
class DerivedGeometry:
    """Everything the transfers and Eq. (1) need, in the units of the field names."""

    ratio: float
    K1: float
    centre_gear_pitch_radius_mm: float
    planet_pitch_radius_mm: float
    centre_distance_mm: float
    cycloid_pitch_radius_mm: float
    crank_circle_radius_mm: float
    crank_circle_radius_is_default: bool
    pressure_angle_deg: float
    crank_eccentricity_coefficient: float

    @property
    def k1(self) -> float:
        return self.K1

    def to_dict(self) -> dict:
        return asdict(self)


def derive_geometry(design: Design) -> DerivedGeometry:
    s1, s2, s3 = design.first_stage, design.second_stage, design.crank_stage
    a = geometry.centre_distance_mm(s1.module_mm, s1.centre_gear_teeth, s1.planet_teeth)
    return DerivedGeometry(
        ratio=geometry.reduction_ratio(s1.centre_gear_teeth, s1.planet_teeth, s2.pins),
        K1=geometry.short_amplitude_coefficient(s2.eccentricity_mm, s2.pins, s2.pin_circle_radius_mm),
        centre_gear_pitch_radius_mm=geometry.pitch_radius_mm(s1.module_mm, s1.centre_gear_teeth),
        planet_pitch_radius_mm=geometry.pitch_radius_mm(s1.module_mm, s1.planet_teeth),
        centre_distance_mm=a,
        cycloid_pitch_radius_mm=geometry.cycloid_pitch_radius_mm(s2.eccentricity_mm, s2.cycloid_teeth),
        crank_circle_radius_mm=s3.crank_circle_radius_mm if s3.crank_circle_radius_mm is not None else a,
        crank_circle_radius_is_default=s3.crank_circle_radius_mm is None,
        pressure_angle_deg=s1.pressure_angle_deg,
        crank_eccentricity_coefficient=s3.eccentricity_transfer_coefficient,
    )


@dataclass(frozen=True)
class ResolvedZone:
    """One factor's zone [um] and statistical reading, as used by the analysis and sampling.

    Distribution parameters left as None take their defaults from the zone
    (``rvbacklash.sampling.distributions``).
    """

    lower_um: float
    upper_um: float
    distribution: str  # normal | uniform | truncated_normal | rayleigh | fixed
    origin: str  # "explicit", or where a default came from
    note: str = ""
    kind: str = "signed"  # catalog kind of the raw quantity
    mean_um: float | None = None
    sigma_um: float | None = None
    scale_um: float | None = None
    value_um: float | None = None


_NOMINAL_MODIFICATION = {
    "equidistance_modification": "equidistance_modification_um",
    "moving_distance_modification": "moving_distance_modification_um",
}


def resolve_zones(design: Design) -> tuple[ResolvedZone, ...]:
    """Zones in catalog order. Precedence: explicit zone, factor grade, stage grade; an omitted
    modification zone is the stage's nominal value (fixed)."""
    from rvbacklash.standards.factor_tolerances import graded_zone  # standards depend on design

    zones = []
    for f in CATALOG:
        zone = getattr(design.factors, f.key)
        if zone is not None and zone.has_zone:
            lo, hi = zone.limits_um
            origin = "explicit"
        elif f.key in _NOMINAL_MODIFICATION:
            field = _NOMINAL_MODIFICATION[f.key]
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
