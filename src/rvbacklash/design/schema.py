"""Design input schema (pydantic v2). Field names carry units; the TOML file mirrors it.

Validation rules that need several fields (z_p = z_c + 1, K1 < 1, pins must not overlap,
zone lower <= upper) live here too, so a Design that exists is a valid one.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, create_model, model_validator

from rvbacklash.design.capacity import CapacityInputs
from rvbacklash.design.lubrication import LubricationInputs, ThermalInputs
from rvbacklash.design.wear import WearInputs
from rvbacklash.design.costs import Costs
from rvbacklash.design.elastic import ElasticInputs
from rvbacklash.design.structure import StructureInputs, check_structure
from rvbacklash.factors import distributions
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.geometry import reducer as geometry
from rvbacklash.geometry.cycloid import PinCentreCurve


class _Strict(BaseModel):
    # strict: no silent coercion (``planets = true`` is not 1 planet, "5" is not 5); an integer
    # is still accepted where a number is expected.
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class FirstStage(_Strict):
    """Involute stage: centre (input) gear and the planet gears on the crankshafts."""

    centre_gear_teeth: int = Field(ge=5, le=200, description="z1, centre (input) gear teeth [-]")
    planet_teeth: int = Field(ge=5, le=500, description="z2, planet gear teeth [-]")
    module_mm: float = Field(gt=0, le=50, description="module m [mm]")
    pressure_angle_deg: float = Field(gt=0, lt=45, description="pressure angle alpha [deg]")
    planets: int = Field(3, ge=1, le=12, description="planet gears = crankshafts [-]")
    face_width_mm: float | None = Field(None, gt=0, le=1000,
                                        description="face width b [mm]; needed for tolerances from a grade")


class SecondStage(_Strict):
    """Cycloid stage: discs on the crank eccentrics meshing with the pins of the housing."""

    cycloid_teeth: int = Field(ge=2, le=500, description="z_c, teeth of each cycloid disc [-]")
    pins: int = Field(ge=3, le=501, description="z_p, pins; must be z_c + 1 [-]")
    eccentricity_mm: float = Field(gt=0, le=100, description="eccentricity a [mm]")
    pin_circle_radius_mm: float = Field(gt=0, le=2000, description="pin-circle radius r_p [mm]")
    pin_radius_mm: float = Field(gt=0, le=200, description="pin radius r_rp [mm]")
    discs: int = Field(2, ge=1, le=4, description="cycloid discs [-]")
    equidistance_modification_um: float = Field(
        0.0, ge=-1000, le=1000,
        description="nominal equidistance modification dr_rp [um]; positive = thinner teeth, more backlash")
    moving_distance_modification_um: float = Field(
        0.0, ge=-1000, le=1000,
        description="nominal moving-distance modification dr_p [um]; positive = teeth moved out, less backlash")

    @model_validator(mode="after")
    def _consistent(self) -> "SecondStage":
        if self.pins != self.cycloid_teeth + 1:
            raise ValueError(
                f"pins = {self.pins} with cycloid_teeth = {self.cycloid_teeth}: "
                f"allowed pins = cycloid_teeth + 1 = {self.cycloid_teeth + 1}")
        k1 = geometry.short_amplitude_coefficient(self.eccentricity_mm, self.pins, self.pin_circle_radius_mm)
        if not k1 < 1.0:
            raise ValueError(
                f"K1 = a*z_p/r_p = {k1:.4g} (eccentricity_mm={self.eccentricity_mm}, pins={self.pins}, "
                f"pin_circle_radius_mm={self.pin_circle_radius_mm}): allowed 0 < K1 < 1")
        gap = geometry.pin_gap_mm(self.pin_circle_radius_mm, self.pin_radius_mm, self.pins)
        if not gap > 0:
            raise ValueError(
                f"pin_radius_mm = {self.pin_radius_mm}: pins overlap on the pin circle; allowed "
                f"pin_radius_mm < r_p sin(pi/z_p) = "
                f"{self.pin_circle_radius_mm * math.sin(math.pi / self.pins):.4g}")
        curve = PinCentreCurve(self.eccentricity_mm, self.pin_circle_radius_mm + self.moving_distance_modification_um * 1e-3,
                               self.cycloid_teeth)
        rho = curve.min_convex_radius_of_curvature()
        generating = self.pin_radius_mm + self.equidistance_modification_um * 1e-3
        if not generating < rho:
            raise ValueError(
                f"pin_radius_mm = {self.pin_radius_mm}: the profile is undercut (generating pin radius {generating:.4g} mm "
                f">= smallest radius of curvature {rho:.4g} mm of the pin-centre path); allowed: a smaller pin radius "
                f"or eccentricity")
        return self


class CrankStage(_Strict):
    """Crankshafts carrying the planet gears and driving the discs."""

    crank_circle_radius_mm: float | None = Field(
        None, gt=0, le=2000,
        description="a0, radius of the circle of crank axes [mm]; default: first-stage centre distance")
    eccentricity_transfer_coefficient: float = Field(
        0.0, ge=0, le=1,
        description="k_n of Table 1 row 21 [-]; zero to first order (docs/model.md)")
    bearing_bore_mm: float | None = Field(
        None, gt=0, le=500, description="crank bearing bore [mm]; needed for its clearance from a grade")


class ToleranceZone(_Strict):
    """Tolerance zone of one factor's raw quantity [um] and its statistical reading.

    Zone: ``lower_um`` and ``upper_um``, or ``plus_minus_um`` (symmetric about 0).
    Reading (``distribution``): one of the registry ``rvbacklash.factors.distributions``,
    each with its own named parameters (docs/distributions.md).
    """

    lower_um: float | None = Field(None, ge=-10000, le=10000, description="lower limit [um]")
    upper_um: float | None = Field(None, ge=-10000, le=10000, description="upper limit [um]")
    plus_minus_um: float | None = Field(None, ge=0, le=10000, description="symmetric half-width [um]")
    distribution: Literal[distributions.NAMES] = Field(  # type: ignore[valid-type]
        "normal", description="statistical reading of the zone: " + ", ".join(distributions.NAMES))
    mean_um: float | None = Field(None, ge=-10000, le=10000,
                                  description="normal / truncated_normal: mean [um]; default zone centre")
    sigma_um: float | None = Field(None, gt=0, le=10000,
                                   description="normal / truncated_normal: sigma [um]; default zone width / 6")
    scale_um: float | None = Field(None, gt=0, le=10000,
                                   description="rayleigh: scale [um]; default width / 3.4393 (99.73 % inside)")
    value_um: float | None = Field(None, ge=-10000, le=10000, description="fixed: the value [um]")
    note: str = Field("", max_length=500, description="provenance of the numbers, free text")

    @model_validator(mode="after")
    def _one_form(self) -> "ToleranceZone":
        has_limits = self.lower_um is not None or self.upper_um is not None
        if has_limits and self.plus_minus_um is not None:
            raise ValueError("give either lower_um/upper_um or plus_minus_um, not both")
        if has_limits and (self.lower_um is None or self.upper_um is None):
            raise ValueError("give both lower_um and upper_um")
        if has_limits and self.lower_um > self.upper_um:
            raise ValueError(f"lower_um = {self.lower_um} > upper_um = {self.upper_um}: allowed lower_um <= upper_um")
        reading = distributions.distribution(self.distribution)
        for name in distributions.PARAMETERS:
            if getattr(self, name) is not None and name not in reading.parameters:
                allowed = [d.name for d in distributions.REGISTRY.values() if name in d.parameters]
                raise ValueError(f"{name} = {getattr(self, name)} does not apply to distribution "
                                 f"'{self.distribution}'; allowed with: {', '.join(allowed)}")
        if self.limits_um is not None and reading.needs_width and self.limits_um[0] == self.limits_um[1]:
            raise ValueError(f"distribution '{self.distribution}' needs a zone of non-zero width; "
                             f"got [{self.limits_um[0]}, {self.limits_um[1]}]")
        if self.distribution == "truncated_normal" and self.mean_um is not None and self.limits_um is not None:
            lo, hi = self.limits_um
            if not lo <= self.mean_um <= hi:
                raise ValueError(f"mean_um = {self.mean_um} outside the zone [{lo}, {hi}] it is truncated to")
        return self

    @property
    def has_zone(self) -> bool:
        return self.plus_minus_um is not None or self.lower_um is not None or self.value_um is not None

    @property
    def limits_um(self) -> tuple[float, float] | None:
        """The zone given in the file, or None when it comes from a grade."""
        if self.plus_minus_um is not None:
            return (-self.plus_minus_um, self.plus_minus_um)
        if self.lower_um is not None:
            return (self.lower_um, self.upper_um)  # type: ignore[return-value]
        if self.value_um is not None:  # fixed with value_um only
            return (self.value_um, self.value_um)
        return None


class Correlation(_Strict):
    """Correlation between named factors, applied as a Gaussian copula."""

    factors: list[str] = Field(min_length=2, description="factor keys, in the order of the matrix")
    matrix: list[list[float]] = Field(description="symmetric positive semi-definite, unit diagonal")

    @model_validator(mode="after")
    def _valid(self) -> "Correlation":
        known = [f.key for f in CATALOG]
        for k in self.factors:
            if k not in known:
                raise ValueError(f"factors: unknown factor {k!r}; allowed: {', '.join(known)}")
        if len(set(self.factors)) != len(self.factors):
            raise ValueError("factors: a factor is listed twice")
        n = len(self.factors)
        if len(self.matrix) != n or any(len(row) != n for row in self.matrix):
            raise ValueError(f"matrix must be {n} x {n} (one row and column per listed factor)")
        m = np.array(self.matrix, dtype=float)
        if not np.all(np.isfinite(m)):
            raise ValueError("matrix: entries must be finite")
        if not np.allclose(np.diag(m), 1.0, atol=1e-12):
            raise ValueError(f"matrix: diagonal must be 1; got {np.diag(m).tolist()}")
        if np.any(np.abs(m) > 1.0):
            raise ValueError("matrix: entries must lie in [-1, 1]")
        if not np.allclose(m, m.T, atol=1e-12):
            raise ValueError("matrix: must be symmetric")
        smallest = float(np.linalg.eigvalsh(m).min())
        if smallest < -1e-10:
            raise ValueError(f"matrix: not positive semi-definite (smallest eigenvalue "
                             f"{smallest:.4g}); allowed: a valid correlation matrix")
        return self


# Factors whose zone may be omitted: the nominal modification of the second stage is used
# as a fixed (zero-width) value; its manufacturing error is a separate factor (18, 19).
OPTIONAL_FACTORS = {"equidistance_modification", "moving_distance_modification"}

Factors = create_model(
    "Factors",
    __config__=ConfigDict(extra="forbid", frozen=True),
    __doc__="Tolerance zone of each of the 21 factors of Sun et al. 2014, Table 1 (or only its "
            "distribution, the zone then coming from a grade).",
    **{
        f.key: (ToleranceZone | None, Field(None, description=f"[{f.id}] {f.name} ({f.symbol}): {f.raw_quantity}"))
        for f in CATALOG
    },
)


class Grades(_Strict):
    """Precision grades from which tolerance zones are derived (docs/standards.md).

    Precedence for each factor: an explicit zone in [factors.<key>], else grades.factors.<key>,
    else the grade of the factor's stage.
    """

    edition: Literal["1995", "2013"] = Field("1995", description="ISO 1328-1 edition for gear tolerances")
    involute: int | None = Field(None, ge=0, le=12, description="grade of the involute stage (ISO 1328-1)")
    cycloid: int | None = Field(None, ge=0, le=12,
                                description="grade of the cycloid stage (assumption: equivalent-module ISO 1328-1 + ISO 286)")
    crank: int | None = Field(None, ge=0, le=12, description="grade of the crank stage (ISO 286 IT grade)")
    factors: dict[str, int] = Field(default_factory=dict, description="grade of single factors, by key")

    @model_validator(mode="after")
    def _valid(self) -> "Grades":
        known = [f.key for f in CATALOG]
        lo, hi = (0, 12) if self.edition == "1995" else (1, 11)
        for key, grade in self.factors.items():
            if key not in known:
                raise ValueError(f"factors: unknown factor {key!r}; allowed: {', '.join(known)}")
            if key in OPTIONAL_FACTORS:
                raise ValueError(f"factors.{key}: a designed modification has no grade; set its nominal value "
                                 f"in second_stage and its error in {key}_error")
            if not lo <= grade <= hi:
                raise ValueError(f"factors.{key} = {grade}: allowed grades {lo} to {hi} (ISO 1328-1:{self.edition})")
        for stage in ("involute", "cycloid", "crank"):
            g = getattr(self, stage)
            if g is not None and not lo <= g <= hi:
                raise ValueError(f"{stage} = {g}: allowed grades {lo} to {hi} (ISO 1328-1:{self.edition})")
        return self

    def grade_for(self, factor) -> tuple[int, str] | None:
        """(grade, input field) that applies to a catalog factor, or None."""
        if factor.key in self.factors:
            return self.factors[factor.key], f"grades.factors.{factor.key}"
        stage = factor.stage.label
        g = getattr(self, stage)
        return (g, f"grades.{stage}") if g is not None else None


class ContactErrors(_Strict):
    """How the contact model reads the per-element errors of the cycloid stage (docs/contact.md)."""

    error_model: Literal["long_wave", "independent"] = Field(
        "long_wave", description="long_wave: each part's deviations are first and second harmonics (random "
                                 "amplitude and phase) plus a per-element part, conforming to its grade; "
                                 "independent: every element drawn on its own from the zone (the pessimistic bound)")
    disc_single_pitch_um: float | None = Field(
        None, gt=0, le=1000, description="single pitch tolerance f_pt of the disc teeth [um]; default: from the "
                                         "cycloid grade (ISO 1328-1, equivalent gear), else 0.3 F_p")
    pin_hole_single_pitch_um: float | None = Field(
        None, gt=0, le=1000, description="single pitch tolerance f_pt of the housing's pin holes [um]; default: from "
                                         "the cycloid grade (ISO 1328-1 at the pin circle), else 0.3 F_p")


class TransmissionErrorInputs(_Strict):
    """Zones of the errors only the transmission-error model reads (factors.catalog.KINEMATIC_FACTORS);
    a field left out takes the factor's documented default."""

    centre_gear_eccentricity_um: float | None = Field(
        None, ge=0, le=1000, description="largest eccentricity of the centre gear [um]; default: F_r / 2 of gear_runout")
    planet_eccentricity_um: float | None = Field(
        None, ge=0, le=1000, description="largest eccentricity of a planet gear [um]; default: F_r / 2 of gear_runout")
    disc_crank_hole_position_um: float | None = Field(
        None, ge=0, le=1000, description="position tolerance (zone diameter) of a disc's crank holes [um]; default 10")
    carrier_crank_hole_position_um: float | None = Field(
        None, ge=0, le=1000, description="position tolerance (zone diameter) of the carrier's crank seats [um]; "
                                         "default 10")


class Design(_Strict):
    """A complete RV reducer design: geometry of the three stages and 21 tolerance zones."""

    name: str = Field(min_length=1, max_length=200, description="design name")
    description: str = Field("", max_length=5000)
    reference: str = Field("", max_length=5000, description="where the numbers come from")
    first_stage: FirstStage
    second_stage: SecondStage
    crank_stage: CrankStage = CrankStage()
    factors: Factors = Factors()  # type: ignore[valid-type]
    grades: Grades | None = None
    correlation: Correlation | None = None
    costs: Costs | None = None  # cost model of `allocate` (design/costs.py); None: the defaults
    contact: ContactErrors = ContactErrors()
    transmission_error: TransmissionErrorInputs = TransmissionErrorInputs()  # docs/transmission-error.md
    elastic: ElasticInputs | None = None  # test-bench hysteresis model (design/elastic.py, docs/elastic.md)
    structure: StructureInputs | None = None  # the whole torque path (design/structure.py); None: rigid
    capacity: CapacityInputs = CapacityInputs()  # rated life and speed, static limits (design/capacity.py)
    lubrication: LubricationInputs = LubricationInputs()  # the losses' friction and lubricant (design/lubrication.py)
    thermal: ThermalInputs = ThermalInputs()  # heat balance and thermal expansion (design/lubrication.py)
    wear: WearInputs = WearInputs()  # wear coefficients, running-in (design/wear.py, docs/service-life.md)

    @model_validator(mode="after")
    def _every_factor_has_a_zone(self) -> "Design":
        for f in CATALOG:
            zone = getattr(self.factors, f.key)
            if f.key in OPTIONAL_FACTORS or (zone is not None and zone.has_zone):
                continue
            if self.grades is not None and self.grades.grade_for(f) is not None:
                continue
            raise ValueError(f"factors.{f.key}: no tolerance; allowed: a zone (lower_um/upper_um or plus_minus_um) "
                             f"or a grade (grades.{f.stage.label} or grades.factors.{f.key})")
        return self

    @model_validator(mode="after")
    def _structure_fits_the_design(self) -> "Design":
        check_structure(self)
        return self

    @model_validator(mode="after")
    def _distribution_fits_the_factor(self) -> "Design":
        for f in CATALOG:
            zone = getattr(self.factors, f.key)
            kinds = distributions.distribution(zone.distribution).kinds if zone is not None else None
            if kinds is not None and f.kind not in kinds:
                allowed = ", ".join(g.key for g in CATALOG if g.kind in kinds)
                raise ValueError(f"factors.{f.key}.distribution = '{zone.distribution}': a {zone.distribution} law "
                                 f"is for errors of kind {' or '.join(kinds)}; allowed for: {allowed}")
            if zone is not None and zone.distribution == "rayleigh" and f.kind == "magnitude" and \
                    zone.limits_um is not None and zone.limits_um[1] <= zone.limits_um[0]:
                raise ValueError(f"factors.{f.key}: rayleigh needs a zone [lower, upper] with upper > lower")
        return self
