"""Inputs of the wear model over the service life (docs/service-life.md): the optional ``[wear]``
table of a design. Every field has a default, so a design with ``[elastic]`` runs ``service-life``
without one. The defaults are ASSUMPTIONS from published ranges, to be replaced by a calibration
(``analysis.service_life.calibrate_wear``) on units measured over time:

- ``flank_wear_coefficient``, ``seat_wear_coefficient``, ``needle_wear_coefficient`` 1e-8: Archard's
  dimensionless K of each contact pair. Lubricated hardened steel wears in the mild range, K from
  about 1e-9 (elastohydrodynamic films, few asperity contacts) to 1e-6 (boundary lubrication)
  (../shared/reference/anchors.md; Hutchings & Shipway, Tribology 2nd ed. (2017), ch. 5: mild
  wear of lubricated steels); no value is standardised for GCr15 cycloid/pin pairs. We take 1e-8,
  the mixed-lubrication part of the band: a grease-lubricated reducer's flanks slide at ~0.01-0.1
  m/s under ~1-2 GPa, where films are thin but not absent. With ``hardness_hv`` the dimensional
  k = K / H = 1.46e-9 mm^3/(N m).
- ``hardness_hv`` 700: the softer surface of each pair; through-hardened bearing steel GCr15 /
  100Cr6 at 60-62 HRC (ASTM E140: 60 HRC = 697 HV), the pins', discs' and needles' material
  (examples/rv80e.toml).
- ``pin_rolling_fraction`` 0.5: the share of the flank's relative sliding that the pin's own
  rotation in its groove takes up (it then slides in its seat instead). The pin turns when the
  flank's friction torque exceeds the seat's; with the same steel and lubricant on both, neither
  wins outright: 0.5 is our assumption (0: the pin never turns, 1: it rolls on the flank).
- ``needle_slip_fraction`` 0.01: sliding of the needles on their raceways as a share of rolling
  (gross slip of loaded roller bearings is of the order of 1 %: Harris & Kotzalas, Rolling
  Bearing Analysis 5th ed. (2007), vol. 2, ch. on cage and roller skidding; an assumption).
- ``running_in_factor`` 5 and ``running_in_hours`` 100: the two-phase coefficient k(t) =
  k (1 + (m - 1) exp(-t / tau)): running-in wear rates are several times the steady ones and fall
  over the first hours to hundreds of hours (Blau, Tribology International 38 (2005) 1007); our
  assumption within that description.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class _Strict(BaseModel):
    # same rules as every design table (design/schema.py): no coercion, no unknown keys
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class WearInputs(_Strict):
    """Wear coefficients, hardness, sliding splits and running-in (module docstring)."""

    flank_wear_coefficient: float = Field(1e-8, ge=0, le=1e-3, description="Archard's dimensionless K, pin on "
                                                                          "cycloid flank [-]")
    seat_wear_coefficient: float = Field(1e-8, ge=0, le=1e-3, description="Archard's K, pin in its housing groove [-]")
    needle_wear_coefficient: float = Field(1e-8, ge=0, le=1e-3, description="Archard's K, crank needles on their "
                                                                           "raceways [-]")
    hardness_hv: float = Field(700.0, ge=100, le=2000, description="hardness of the softer surface of each pair [HV]")
    pin_rolling_fraction: float = Field(0.5, ge=0, le=1, description="share of the flank's relative sliding taken "
                                                                     "up by the pin turning in its seat [-]")
    needle_slip_fraction: float = Field(0.01, ge=0, le=0.5, description="needles' sliding as a share of their "
                                                                        "rolling [-]")
    running_in_factor: float = Field(5.0, ge=1, le=100, description="wear coefficient on first running, as a "
                                                                    "multiple of the steady one [-]")
    running_in_hours: float = Field(100.0, gt=0, le=1e5, description="time constant tau of the running-in [h]")
