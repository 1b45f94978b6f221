"""Inputs of the capacity and life ratings (docs/capacity.md): the ``[capacity]`` table of a design.

Every field has a default, so a design with ``[elastic]`` (and, for the support and main
bearings, ``[structure]``) is rated without one:

- ``rated_life_h`` 6000 and ``rated_output_speed_rpm`` 15: the RV-E convention (the rated torque
  is the output torque at which the reducer reaches its rated life at the rated output speed;
  Nabtesco RV-E catalogue, "rated service life", as quoted for RV-20E/40E in public transcriptions
  of the maker's product pages; ../shared/reference/anchors.md);
- ``contact_stress_limit_mpa`` 4000: the static limit of the pins' and the flanks' Hertz pressure,
  ISO 76's reference stress for roller/raceway contacts of hardened bearing steel (the pins and
  discs are GCr15 / 100Cr6 through-hardened, as bearing rollers and rings): the stress at which
  the permanent deformation reaches about 1e-4 of the roller diameter;
- ``acceleration_torque_fraction`` 0.5: the allowable acceleration/deceleration torque as this
  share of the derived momentary maximum torque: the RV-E catalogue convention (acceleration
  2.5 T0, momentary 5 T0: RV-40E 1029 / 2058 N m, RV-20E 412 / 833 N m in Nabtesco's product
  figures as transcribed publicly), i.e. a static safety factor of 2 against the first static
  limit for the repeated start/stop peaks;
- ``main_bearing_static_safety`` 1.0: the main bearings' allowable moment's static safety s0 (ISO 76:
  the ball contact stress 4200 MPa at s0 = 1).
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field


class _Strict(BaseModel):
    # same rules as every design table (design/schema.py): no coercion, no unknown keys
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class CapacityInputs(_Strict):
    """Rated life and speed, static limits and the life method."""

    rated_life_h: float = Field(6000.0, gt=0, le=1e7, description="rated life K [h]: the rated torque is the output "
                                                                  "torque at which the reducer's L10 is K (RV-E: 6000)")
    rated_output_speed_rpm: float = Field(15.0, gt=0, le=1e4, description="rated output speed N0 [r/min] (RV-E: 15)")
    contact_stress_limit_mpa: float = Field(
        4000.0, gt=0, le=20000, description="static limit of the pins' and flanks' Hertz pressure [MPa] (ISO 76's "
                                            "4000 MPa for hardened bearing steel line contacts)")
    acceleration_torque_fraction: float = Field(
        0.5, gt=0, le=1, description="allowable acceleration/deceleration torque as a share of the momentary maximum "
                                     "(RV-E catalogue convention: 2.5 T0 / 5 T0 = 0.5)")
    main_bearing_static_safety: float = Field(1.0, ge=1, le=10, description="static safety s0 of the main bearings' "
                                                                            "allowable moment (ISO 76: 4200 MPa / s0)")
    life_method: Literal["iso16281", "iso281"] = Field(
        "iso16281", description="the needle bearings' life: iso16281 (from the rollers' internal load distribution "
                                "over the revolution, ISO/TS 16281) or iso281 (the cubic-mean load and C)")
