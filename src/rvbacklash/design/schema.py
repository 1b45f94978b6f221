"""Design input schema (pydantic v2). Field names carry units; the TOML file mirrors it.

Validation rules that need several fields (z_p = z_c + 1, K1 < 1, pins must not overlap,
zone lower <= upper) live here too, so a Design that exists is a valid one.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, create_model, model_validator

from rvbacklash.design import geometry
from rvbacklash.factors.catalog import CATALOG


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class FirstStage(_Strict):
    """Involute stage: centre (input) gear and the planet gears on the crankshafts."""

    centre_gear_teeth: int = Field(ge=5, le=200, description="z1, centre (input) gear teeth [-]")
    planet_teeth: int = Field(ge=5, le=500, description="z2, planet gear teeth [-]")
    module_mm: float = Field(gt=0, le=50, description="module m [mm]")
    pressure_angle_deg: float = Field(gt=0, lt=45, description="pressure angle alpha [deg]")
    planets: int = Field(3, ge=1, le=12, description="planet gears = crankshafts [-]")


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
        return self


class CrankStage(_Strict):
    """Crankshafts carrying the planet gears and driving the discs."""

    crank_circle_radius_mm: float | None = Field(
        None, gt=0, le=2000,
        description="a0, radius of the circle of crank axes [mm]; default: first-stage centre distance")
    eccentricity_transfer_coefficient: float = Field(
        0.0, ge=0, le=1,
        description="k_n of Table 1 row 21 [-]; zero to first order (docs/model.md)")


class ToleranceZone(_Strict):
    """Tolerance zone of one factor's raw quantity [um], and its statistical reading.

    Give either ``lower_um`` and ``upper_um``, or ``plus_minus_um`` (symmetric about 0).
    Default reading (Sun et al. 2014 Eq. (4)-(5)): normal, mean = zone centre,
    sigma = zone width / 6 (3 sigma = half the zone).
    """

    lower_um: float | None = Field(None, ge=-10000, le=10000, description="lower limit [um]")
    upper_um: float | None = Field(None, ge=-10000, le=10000, description="upper limit [um]")
    plus_minus_um: float | None = Field(None, ge=0, le=10000, description="symmetric half-width [um]")
    distribution: Literal["normal"] = Field("normal", description="statistical reading of the zone")
    note: str = Field("", max_length=500, description="provenance of the numbers, free text")

    @model_validator(mode="after")
    def _one_form(self) -> "ToleranceZone":
        has_limits = self.lower_um is not None or self.upper_um is not None
        if has_limits and self.plus_minus_um is not None:
            raise ValueError("give either lower_um/upper_um or plus_minus_um, not both")
        if not has_limits and self.plus_minus_um is None:
            raise ValueError("missing zone: give lower_um and upper_um, or plus_minus_um")
        if has_limits and (self.lower_um is None or self.upper_um is None):
            raise ValueError("give both lower_um and upper_um")
        if has_limits and self.lower_um > self.upper_um:
            raise ValueError(f"lower_um = {self.lower_um} > upper_um = {self.upper_um}: allowed lower_um <= upper_um")
        return self

    @property
    def limits_um(self) -> tuple[float, float]:
        if self.plus_minus_um is not None:
            return (-self.plus_minus_um, self.plus_minus_um)
        return (self.lower_um, self.upper_um)  # type: ignore[return-value]


# Factors whose zone may be omitted: the nominal modification of the second stage is used
# as a fixed (zero-width) value; its manufacturing error is a separate factor (18, 19).
OPTIONAL_FACTORS = {"equidistance_modification", "moving_distance_modification"}

Factors = create_model(
    "Factors",
    __config__=ConfigDict(extra="forbid", frozen=True),
    __doc__="Tolerance zone of each of the 21 factors of Sun et al. 2014, Table 1.",
    **{
        f.key: (
            ToleranceZone | None if f.key in OPTIONAL_FACTORS else ToleranceZone,
            Field(None if f.key in OPTIONAL_FACTORS else ...,
                  description=f"[{f.id}] {f.name} ({f.symbol}): {f.raw_quantity}"),
        )
        for f in CATALOG
    },
)


class Design(_Strict):
    """A complete RV reducer design: geometry of the three stages and 21 tolerance zones."""

    name: str = Field(min_length=1, max_length=200, description="design name")
    description: str = Field("", max_length=5000)
    reference: str = Field("", max_length=5000, description="where the numbers come from")
    first_stage: FirstStage
    second_stage: SecondStage
    crank_stage: CrankStage = CrankStage()
    factors: Factors  # type: ignore[valid-type]
