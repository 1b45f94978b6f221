"""Inputs of the whole torque path (docs/elastic.md, "The whole torque path"): the ``[structure]``
table of a design.

The elastic model derives the cycloid pins, the crank needle bearings and the involute mesh from
``[elastic]``; this table adds what carries the torque between them and the output flange, each
element from its dimensions:

- **crankshafts**: bending (with shear) between their two support bearings under the discs'
  forces, and torsion between the eccentrics and the planet gear;
- **crank support bearings**: tapered roller bearings, two per crankshaft (rollers, size,
  contact angle, clearance or preload);
- **carrier**: the pillars that tie the end plate to the output flange;
- **the discs' sideways motion** on their needle bearings (``disc_translation``): across the
  eccentric by default (the part that carries torque: +51 % on the needle bearings' elastic
  compliance for the RV-80E class), optionally also along it (the pins' radial resultant).

The main bearings carry no load in a pure-torque test (the two discs' radial resultants, 180
degrees apart, cancel; their couple tilts the carrier, which does not turn the output): they are
left out of the torsional chain, derivation in docs/elastic.md. ``[elastic]
main_bearing_stiffness_nm_per_arcmin`` and ``structure_stiffness_nm_per_arcmin`` remain: a
measured value wins over the derivation (``structure_stiffness_nm_per_arcmin`` replaces the
crankshafts, support bearings and carrier).

No field has a default that stands for a dimension: a design states its own (the rv80e example
says where each of its numbers comes from). Materials default to steel (handbook values).
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator


class _Strict(BaseModel):
    # same rules as every design table (design/schema.py): no coercion, no unknown keys
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class StructureInputs(_Strict):
    """Dimensions of the crankshafts, their support bearings and the carrier."""

    crankshaft_support_span_mm: float = Field(
        gt=0, le=5000, description="crankshaft: distance between the load centres of its two support bearings [mm]")
    disc_spacing_mm: float = Field(
        gt=0, le=5000, description="axial distance between the two discs' mid-planes (the eccentrics' load points) "
                                   "[mm]; < crankshaft_support_span_mm")
    crankshaft_diameter_mm: float = Field(
        gt=0, le=1000, description="crankshaft: diameter of the equivalent solid round section between the supports "
                                   "(bending) [mm]")
    crankshaft_torsion_length_mm: float = Field(
        gt=0, le=5000, description="crankshaft: length that twists between the eccentrics' centre and the planet "
                                   "gear [mm]")
    crankshaft_torsion_diameter_mm: float | None = Field(
        None, gt=0, le=1000, description="crankshaft: diameter of the section that twists [mm]; default "
                                         "crankshaft_diameter_mm")
    shaft_youngs_modulus_gpa: float = Field(206.0, gt=0, le=1000,
                                            description="Young's modulus of the crankshafts [GPa] (steel: 206)")
    shaft_poisson_ratio: float = Field(0.3, ge=0, lt=0.5, description="Poisson's ratio of the crankshafts [-]")

    support_bearing_rollers: int = Field(ge=6, le=200, description="rollers per crank support (tapered roller) "
                                                                   "bearing [-]")
    support_bearing_roller_diameter_mm: float = Field(gt=0, le=200, description="mean roller diameter D_w [mm]")
    support_bearing_roller_length_mm: float = Field(gt=0, le=500, description="effective roller length L_we [mm]")
    support_bearing_contact_angle_deg: float = Field(
        ge=0, lt=45, description="contact angle alpha of the outer raceway [deg] (tan alpha = e / 1.5 from the "
                                 "catalogue's e factor)")
    support_bearing_clearance_um: float = Field(
        0.0, ge=-100, le=100, description="radial internal clearance of the mounted support bearings [um]; negative: "
                                          "preload (shims set it); a clearance is a dead band, a preload raises the "
                                          "stiffness")

    carrier_pillars: int = Field(ge=2, le=24, description="pillars tying the carrier's end plate to the output "
                                                          "flange [-]")
    pillar_radius_mm: float = Field(gt=0, le=5000, description="radius of the pillars' centres [mm]")
    pillar_length_mm: float = Field(gt=0, le=5000, description="free length of a pillar between the plates [mm]")
    pillar_width_mm: float = Field(gt=0, le=1000, description="pillar section, tangential width w [mm] (the "
                                                              "direction it bends in)")
    pillar_depth_mm: float = Field(gt=0, le=1000, description="pillar section, radial depth h [mm]")
    carrier_youngs_modulus_gpa: float = Field(206.0, gt=0, le=1000,
                                              description="Young's modulus of the carrier [GPa] (steel: 206; "
                                                          "ductile iron: ~170)")
    carrier_poisson_ratio: float = Field(0.3, ge=0, lt=0.5, description="Poisson's ratio of the carrier [-]")

    disc_translation: Literal["across", "full", "none"] = Field(
        "across", description="each disc's sideways motion on its needle bearings: across (across the eccentric, the "
                              "pins' resultant's torque-carrying part: closed form, no cost), full (also along the "
                              "eccentric: the pins' radial resultant followed, solved with every pin; 2-3x slower, "
                              "about 1 % on the rv80e figures), none (the disc only turns about its centre)")

    @model_validator(mode="after")
    def _consistent(self) -> "StructureInputs":
        if not self.disc_spacing_mm < self.crankshaft_support_span_mm:
            raise ValueError(f"disc_spacing_mm = {self.disc_spacing_mm}: the discs must sit between the crankshaft's "
                             f"supports; allowed: disc_spacing_mm < crankshaft_support_span_mm = "
                             f"{self.crankshaft_support_span_mm}")
        return self
