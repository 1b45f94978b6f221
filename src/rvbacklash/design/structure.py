"""Inputs of the whole torque path (docs/elastic.md, "The whole torque path"): the ``[structure]``
table of a design.

The elastic model derives the cycloid pins, the crank needle bearings and the involute mesh from
``[elastic]``; this table adds what carries the torque between them and the output flange, each
element from its dimensions:

- **crankshafts**: bending (with shear) between their two support bearings under the discs'
  forces, and torsion between the eccentrics and the planet gear;
- **crank support bearings**: tapered roller bearings, two per crankshaft (rollers, size,
  contact angle, clearance or preload, the rollers' profile: logarithmic by default, ISO/TS
  16281's profile for an unknown one, as tapered rollers of precision bearings are profiled);
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

With other than two discs the crankshafts, support bearings and carrier (derived for two discs
symmetric about the crank's mid-span) must be stated (``elastic.structure_stiffness_nm_per_arcmin``);
the table then still gives the disc bodies' FE and the discs' sideways motion across the eccentric
(``models/elastic/chain.py``, ``with_structure``; docs/elastic.md).

No field has a default that stands for a dimension: a design states its own (the rv80e example
says where each of its numbers comes from). Materials default to steel (handbook values).

**Validity.** Each dimension feeds a formula of ``models/compliance.py`` that means something
only for a part of the kind it describes; a 0.01 mm crankshaft or a 0.001 mm pillar gave a lost
motion of 4.5e11 arcmin. A design is refused (field, value, allowed range) outside:

- *beam length against section depth* (crankshaft span / diameter, pillar length / tangential
  width) from ``DEPTH_RATIO_MIN`` = 1: the beam formulas with Timoshenko's shear term stay
  within a few per cent of elasticity down to a length equal to the depth (Cowper, "On the
  accuracy of Timoshenko's beam theory", J. Eng. Mech. Div. ASCE 94 (1968) 1447: < 3.5 % at
  depth = length); shorter, the load goes straight into the support and no beam formula holds;
- *slenderness* up to ``SLENDERNESS_MAX`` = 20 (crankshaft span and twisting length over their
  diameters, pillar length over either side of its section): a plausibility limit, not a formula's
  (real RV parts are 1-3; rv80e: 1.8, 1.6, 1.35), past which a shaft or pillar is a wire whose
  deflection under the rated torque leaves the linear theory;
- *rollers* of the support bearings ``ROLLER_ASPECT`` = 0.5 to 4 lengths per diameter: Palmgren's
  line-contact law (``palmgren_line_approach_um``) is a fit to bearing rollers (tapered rollers are
  about 1-2.5 diameters long; rv80e: 2); a disc of a roller or a needle is outside it;
- *pillars that fit*: their tangential width below the chord between two neighbours on the
  pillar circle (2 R_p sin(pi / n_p)), their radial depth inside the circle (h < 2 R_p);
- *the FE carrier* (``CARRIER_FE_FIELDS``, all five or none: ``has_carrier_fe``; the body in
  mechanics/carrier_body.py): the plates hold the pillars (their outer corners inside the outline,
  their inner faces outside the central hole) and are no thinner than their diameter over
  ``SLENDERNESS_MAX``; the seats (bores of the support bearings' outer diameter on the crank
  circle) are larger than the crankshaft's journal and keep ``MIN_WALL_MM`` = 1 mm to the
  outline, the central hole, each other and the pillars (``check_structure``): thinner walls are
  not a carrier and are not meshed;
- against the rest of the design (``check_structure``, called by ``Design``): the crankshaft's
  diameters between half the eccentric's (the crank needle bearing's raceway D_e: a crank whose
  equivalent section is under half the eccentric it carries is not the part the formula
  describes; rv80e: 25 mm for 30 mm, 0.83) and the circle about the crank axis that encloses the
  eccentric (D_e + 2 a: no round section of the span is stiffer); the two discs' mid-planes at
  least a disc face width apart, and the supports' load centres outside the disc stack (span >=
  disc spacing + face width); the pillars inside the discs (R_p + h/2 below the disc's root
  radius r_p - r_rp - a).
- the discs' holes, when ``disc_pillar_hole_diameter_mm`` is given (the disc body's finite elements
  run then, mechanics/disc_body.py; layout in geometry/disc_holes.py): each hole and crank bore
  (the needle bearing's outer raceway, D_e + 2 D_w) ends at least ``DISC_WALL_PIN_RADII`` = 1.5 pin
  radii inside the profile's root radius r_p - r_rp - a (the disc's rotation is read one pin radius
  below each contact: that point must lie in the body, with material between it and the hole),
  holes at least ``DISC_LIGAMENT_MIN_MM`` = 1 mm apart (a thinner web is no part, and no mesh), and
  each pillar hole wide enough for its pillar's section swept by the eccentric orbit
  (sqrt(w^2 + h^2) + 2 a, plus twice any offset between the hole's and the pillar's circles).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from rvbacklash.design.elastic import check_profile
from rvbacklash.errors import InputError
from rvbacklash.geometry.carrier_layout import crank_angles_rad, pillar_angles_rad
from rvbacklash.geometry.reducer import centre_distance_mm
from rvbacklash.geometry.disc_holes import crank_bore_diameter_mm, disc_holes, pillar_hole_clearance_diameter_mm

DEPTH_RATIO_MIN = 1.0  # a beam at least as long as its section is deep (Cowper 1968)
SLENDERNESS_MAX = 20.0  # length over diameter or section side: a plausibility limit (real parts: 1-3)
ROLLER_ASPECT = (0.5, 4.0)  # support-bearing roller length over diameter (Palmgren's law: bearing rollers)
DISC_WALL_PIN_RADII = 1.5  # a disc hole ends this many pin radii inside the profile's root (module docstring)
DISC_LIGAMENT_MIN_MM = 1.0  # the thinnest web between two holes of a disc [mm]


CARRIER_FE_FIELDS = ("carrier_flange_thickness_mm", "carrier_end_plate_thickness_mm", "carrier_outer_diameter_mm",
                     "carrier_bore_diameter_mm", "support_bearing_seat_diameter_mm")
MIN_WALL_MM = 1.0  # the thinnest wall the FE carrier meshes (between seats, pillars, holes and outline)


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
    shaft_youngs_modulus_gpa: float = Field(206.0, ge=1, le=1000,
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
        0.0, ge=0, le=100, description="radial internal clearance of the mounted support bearings (diametral) [um]: "
                                       "a dead band; a preload is support_bearing_preload_um")
    support_bearing_preload_um: float = Field(
        0.0, ge=0, le=100, description="radial preload of the mounted support bearings: the negative radial internal "
                                       "clearance the shims set (diametral interference) [um]; raises the stiffness; "
                                       "exclusive with a clearance")
    support_bearing_roller_profile: Literal["logarithmic", "crowned", "straight"] = Field(
        "logarithmic", description="generatrix of the tapered rollers (docs/rigidity-elements.md): logarithmic (ISO/TS "
                                   "16281's profile for an unknown one), crowned (circular crown, "
                                   "support_bearing_roller_crown_drop_um at the ends), straight (Palmgren's law per "
                                   "roller, no tilt: the model before profiles). Profiled rollers are sliced and "
                                   "tilted by the crankshaft's slope at the bearing")
    support_bearing_roller_crown_drop_um: float | None = Field(
        None, gt=0, le=100, description="crowned tapered rollers: drop of the circular crown at the ends (radius) "
                                        "[um]; required with support_bearing_roller_profile = crowned")
    support_bearing_roller_log_scale_um: float | None = Field(
        None, gt=0, le=100, description="logarithmic tapered rollers: K in P(x) = K ln(1 / (1 - (2x/L)^2)) [um]; "
                                        "default ISO/TS 16281: 0.45 D_we (D_we in mm)")

    carrier_pillars: int = Field(ge=2, le=24, description="pillars tying the carrier's end plate to the output "
                                                          "flange [-]")
    pillar_radius_mm: float = Field(gt=0, le=5000, description="radius of the pillars' centres [mm]")
    pillar_length_mm: float = Field(gt=0, le=5000, description="free length of a pillar between the plates [mm]")
    pillar_width_mm: float = Field(gt=0, le=1000, description="pillar section, tangential width w [mm] (the "
                                                              "direction it bends in)")
    pillar_depth_mm: float = Field(gt=0, le=1000, description="pillar section, radial depth h [mm]")
    carrier_youngs_modulus_gpa: float = Field(206.0, ge=1, le=1000,
                                              description="Young's modulus of the carrier [GPa] (steel: 206; "
                                                          "ductile iron: ~170)")
    carrier_poisson_ratio: float = Field(0.3, ge=0, lt=0.5, description="Poisson's ratio of the carrier [-]")

    # the carrier as one 3-D body by finite elements (mechanics/carrier_body.py): all five or none;
    # given, they replace the pillars clamped in rigid plates (which stay the closed form)
    carrier_flange_thickness_mm: float | None = Field(
        None, gt=0, le=1000, description="carrier (FE): output flange's thickness, from its bolted outer face to the "
                                         "pillars [mm]")
    carrier_end_plate_thickness_mm: float | None = Field(
        None, gt=0, le=1000, description="carrier (FE): end plate's thickness [mm]")
    carrier_outer_diameter_mm: float | None = Field(
        None, gt=0, le=10000, description="carrier (FE): outer diameter of the flange and the end plate [mm]")
    carrier_bore_diameter_mm: float | None = Field(
        None, ge=0, le=10000, description="carrier (FE): central hole through both plates [mm]; 0: none")
    support_bearing_seat_diameter_mm: float | None = Field(
        None, gt=0, le=1000, description="carrier (FE): bore of the support bearings' seats in both plates, on the "
                                         "crank circle = the bearing's outer diameter [mm]")
    disc_pillar_hole_diameter_mm: float | None = Field(
        None, gt=0, le=5000, description="diameter of the discs' holes the carrier pillars pass through [mm]; given: "
                                         "the disc bodies are computed by finite elements (mechanics/disc_body.py); "
                                         "at least sqrt(w^2 + h^2) + 2 x eccentricity of the pillar section")
    disc_pillar_hole_radius_mm: float | None = Field(
        None, gt=0, le=5000, description="radius of the circle of the discs' pillar holes' centres [mm]; default "
                                         "pillar_radius_mm (holes at the pillars' angles, between the cranks)")
    disc_centre_hole_diameter_mm: float | None = Field(
        None, gt=0, le=5000, description="diameter of a hole in the discs' centre (the input shaft's passage) [mm]; "
                                         "default: none (a solid centre)")

    # Capacity and life (issue 37; docs/capacity.md): the support bearings' pitch diameter and stated ratings,
    # and the output's main bearings (an angular-contact ball pair, back to back). None: not given.
    support_bearing_pitch_diameter_mm: float | None = Field(
        None, gt=0, le=5000, description="pitch diameter D_pw of the support bearings' rollers [mm] (ISO 281's f_c); "
                                         "default: (crankshaft_diameter_mm + support_bearing_seat_diameter_mm) / 2")
    support_bearing_dynamic_load_rating_n: float | None = Field(
        None, gt=0, le=1e8, description="the support bearings' basic dynamic load rating C_r from the maker's "
                                        "catalogue [N]; default: ISO 281 from the rollers' geometry")
    support_bearing_static_load_rating_n: float | None = Field(
        None, gt=0, le=1e8, description="the support bearings' basic static load rating C_0r from the maker's "
                                        "catalogue [N]; default: ISO 76 from the rollers' geometry")
    main_bearing_balls: int | None = Field(None, ge=6, le=500, description="main bearings (angular-contact ball "
                                                                          "pair, back to back): balls per row [-]")
    main_bearing_ball_diameter_mm: float | None = Field(None, gt=0, le=100, description="main bearings: ball "
                                                                                        "diameter D_w [mm]")
    main_bearing_pitch_diameter_mm: float | None = Field(None, gt=0, le=5000, description="main bearings: pitch "
                                                                                          "diameter D_pw [mm]")
    main_bearing_contact_angle_deg: float | None = Field(None, gt=0, lt=90, description="main bearings: nominal "
                                                                                       "contact angle [deg]")
    main_bearing_row_spread_mm: float | None = Field(
        None, gt=0, le=5000, description="main bearings: axial distance between the two rows' ball centres [mm]")
    main_bearing_preload_n: float | None = Field(None, ge=0, le=1e7, description="main bearings: axial preload "
                                                                                 "between the rows [N]")
    main_bearing_groove_ratio_inner: float = Field(0.52, gt=0.5, le=0.6, description="main bearings: inner "
                                                   "groove radius / D_w [-] (ISO 281's assumption: <= 0.52)")
    main_bearing_groove_ratio_outer: float = Field(0.53, gt=0.5, le=0.6, description="main bearings: outer "
                                                   "groove radius / D_w [-] (ISO 281's assumption: <= 0.53)")

    disc_translation: Literal["across", "full", "none"] = Field(
        "across", description="each disc's sideways motion on its needle bearings: across (across the eccentric, the "
                              "pins' resultant's torque-carrying part: closed form, no cost), full (also along the "
                              "eccentric: the pins' radial resultant followed, solved with every pin; 2-3x slower, "
                              "about 1 % on the rv80e figures), none (the disc only turns about its centre)")

    @model_validator(mode="after")
    def _consistent(self) -> "StructureInputs":
        """The table's dimensions against each other (module docstring, "Validity")."""
        span, d = self.crankshaft_support_span_mm, self.crankshaft_diameter_mm
        if not self.disc_spacing_mm < span:
            raise InputError("disc_spacing_mm", self.disc_spacing_mm,
                             f"the discs must sit between the crankshaft's supports; allowed: disc_spacing_mm < "
                             f"crankshaft_support_span_mm = {span:g}")
        _ratio("crankshaft_diameter_mm", d, "crankshaft_support_span_mm", span, "crankshaft span / diameter")
        d_twist = self.crankshaft_torsion_diameter_mm or d
        _ratio("crankshaft_torsion_diameter_mm" if self.crankshaft_torsion_diameter_mm else "crankshaft_diameter_mm",
               d_twist, "crankshaft_torsion_length_mm", self.crankshaft_torsion_length_mm,
               "twisting length / diameter", lowest=0.0)
        _ratio("pillar_width_mm", self.pillar_width_mm, "pillar_length_mm", self.pillar_length_mm,
               "pillar length / width (the bending direction)")
        _ratio("pillar_depth_mm", self.pillar_depth_mm, "pillar_length_mm", self.pillar_length_mm,
               "pillar length / depth", lowest=0.0)
        chord = 2.0 * self.pillar_radius_mm * math.sin(math.pi / self.carrier_pillars)
        if not self.pillar_width_mm < chord:
            raise InputError("pillar_width_mm", self.pillar_width_mm,
                             f"{self.carrier_pillars} pillars this wide overlap on their circle; allowed: < "
                             f"2 pillar_radius_mm sin(pi / carrier_pillars) = {chord:.4g} mm")
        if not self.pillar_depth_mm < 2.0 * self.pillar_radius_mm:
            raise InputError("pillar_depth_mm", self.pillar_depth_mm,
                             f"the pillars would cross the axis; allowed: < 2 pillar_radius_mm = "
                             f"{2.0 * self.pillar_radius_mm:g} mm")
        if self.support_bearing_clearance_um > 0.0 and self.support_bearing_preload_um > 0.0:
            raise InputError("support_bearing_preload_um", self.support_bearing_preload_um,
                             f"a bearing has a clearance or a preload, not both (support_bearing_clearance_um = "
                             f"{self.support_bearing_clearance_um:g}); allowed: 0 when a clearance is given")
        check_profile("support_bearing_roller", self.support_bearing_roller_profile,
                      self.support_bearing_roller_crown_drop_um, self.support_bearing_roller_log_scale_um)
        if self.disc_pillar_hole_diameter_mm is None:
            for name in ("disc_pillar_hole_radius_mm", "disc_centre_hole_diameter_mm"):
                if getattr(self, name) is not None:
                    raise InputError(name, getattr(self, name), "allowed only with disc_pillar_hole_diameter_mm (the "
                                                                "disc bodies' finite elements read the holes together)")
        _check_main_bearings(self)
        lo, hi = ROLLER_ASPECT
        dw, lw = self.support_bearing_roller_diameter_mm, self.support_bearing_roller_length_mm
        if not lo * dw <= lw <= hi * dw:
            raise InputError("support_bearing_roller_length_mm", lw,
                             f"allowed: {lo:g} to {hi:g} roller diameters ({lo * dw:.4g} to {hi * dw:.4g} mm for "
                             f"support_bearing_roller_diameter_mm = {dw:g}): Palmgren's line-contact law is for "
                             f"bearing rollers")
        return self


MAIN_BEARING_FIELDS = ("main_bearing_balls", "main_bearing_ball_diameter_mm", "main_bearing_pitch_diameter_mm",
                       "main_bearing_contact_angle_deg", "main_bearing_row_spread_mm", "main_bearing_preload_n")


def has_main_bearings(structure: StructureInputs | None) -> bool:
    """Whether the design gives its main bearings (all of MAIN_BEARING_FIELDS; docs/capacity.md)."""
    return structure is not None and all(getattr(structure, name) is not None for name in MAIN_BEARING_FIELDS)


def _check_main_bearings(st: StructureInputs) -> None:
    """The main bearings' fields: all or none; balls that fit on their pitch circle (Z D_w < pi D_pw:
    a ball bearing, not overlapping balls) and a ball small against its pitch circle (D_w < D_pw / 3,
    the f_c table's range)."""
    given = [n for n in MAIN_BEARING_FIELDS if getattr(st, n) is not None]
    if not given:
        return
    missing = [n for n in MAIN_BEARING_FIELDS if getattr(st, n) is None]
    if missing:
        raise InputError(missing[0], None, f"the main bearings need all of {', '.join(MAIN_BEARING_FIELDS)} "
                                           f"(given: {', '.join(given)}); allowed: all or none")
    z, dw, dp = st.main_bearing_balls, st.main_bearing_ball_diameter_mm, st.main_bearing_pitch_diameter_mm
    if not z * dw < math.pi * dp:
        raise InputError("main_bearing_balls", z, f"{z} balls of {dw:g} mm do not fit on a {dp:g} mm pitch circle; "
                                                  f"allowed: < pi D_pw / D_w = {math.pi * dp / dw:.4g}")
    if not dw < dp / 3.0:
        raise InputError("main_bearing_ball_diameter_mm", dw, f"allowed: < main_bearing_pitch_diameter_mm / 3 = "
                                                              f"{dp / 3.0:.4g} mm (a ball bearing's proportions)")


def _ratio(field: str, size: float, length_field: str, length: float, what: str,
           lowest: float = DEPTH_RATIO_MIN) -> None:
    """A beam's length over its section's size within [lowest, SLENDERNESS_MAX] (module docstring);
    the error names the section field (``size``) with the sizes allowed for that length and, for a
    beam too slender, the lengths allowed for that size (either may be the one to change)."""
    if lowest * size <= length <= SLENDERNESS_MAX * size:
        return
    smallest = length / SLENDERNESS_MAX
    if length > SLENDERNESS_MAX * size:
        allowed = (f"{what} <= {SLENDERNESS_MAX:g}, i.e. {field} >= {smallest:.4g} or {length_field} <= "
                   f"{SLENDERNESS_MAX * size:.4g}")
    else:
        allowed = f"{lowest:g} <= {what}, i.e. {field} <= {length / lowest:.4g}"
    raise InputError(field, size, f"{what} = {length / size:.4g} ({length_field} = {length:g}); allowed: {allowed}")


def has_disc_fe(structure: StructureInputs | None) -> bool:
    """Whether the design's discs are FE bodies (``disc_pillar_hole_diameter_mm`` given) rather than
    rigid (mechanics/disc_body.py)."""
    return structure is not None and structure.disc_pillar_hole_diameter_mm is not None


def has_carrier_fe(structure: StructureInputs | None) -> bool:
    """Whether the design's carrier is the FE body (all of CARRIER_FE_FIELDS given) rather than the
    pillars clamped in rigid plates (mechanics/carrier_body.py, models/compliance.py)."""
    return structure is not None and all(getattr(structure, name) is not None for name in CARRIER_FE_FIELDS)


def _check_carrier_outline(st: StructureInputs) -> None:
    """The FE carrier's plates against its pillars (module docstring, "Validity"): all five fields or
    none, the pillars standing on the plates (inside the outline, outside the central hole, walls
    of MIN_WALL_MM), plates no thinner than their diameter over SLENDERNESS_MAX."""
    given = [name for name in CARRIER_FE_FIELDS if getattr(st, name) is not None]
    if not given:
        return
    missing = [name for name in CARRIER_FE_FIELDS if getattr(st, name) is None]
    if missing:
        raise InputError(f"structure.{missing[0]}",
                         allowed=f"missing: the FE carrier needs all of {', '.join(CARRIER_FE_FIELDS)} "
                                 f"({', '.join(given)} given); allowed: all five, or none (pillars clamped in rigid "
                                 f"plates)")
    outer = st.carrier_outer_diameter_mm
    corner = math.hypot(st.pillar_radius_mm + 0.5 * st.pillar_depth_mm, 0.5 * st.pillar_width_mm)
    if not corner + MIN_WALL_MM <= 0.5 * outer:
        raise InputError("structure.carrier_outer_diameter_mm", outer,
                         f"the plates do not hold the pillars (their outer corners reach {corner:.4g} mm from the "
                         f"axis); allowed: >= {2.0 * (corner + MIN_WALL_MM):.4g} mm (a {MIN_WALL_MM:g} mm wall)")
    bore, inner = st.carrier_bore_diameter_mm, st.pillar_radius_mm - 0.5 * st.pillar_depth_mm
    if bore > 0 and not 0.5 * bore + MIN_WALL_MM <= inner:
        raise InputError("structure.carrier_bore_diameter_mm", bore,
                         f"the central hole cuts the pillars (their inner faces at {inner:.4g} mm from the axis); "
                         f"allowed: 0 (none) or <= {2.0 * (inner - MIN_WALL_MM):.4g} mm (a {MIN_WALL_MM:g} mm wall)")
    for name in ("carrier_flange_thickness_mm", "carrier_end_plate_thickness_mm"):
        t = getattr(st, name)
        if not outer <= SLENDERNESS_MAX * t:
            raise InputError(f"structure.{name}", t,
                             f"a plate {outer:g} mm across this thin is a membrane, not a carrier plate; allowed: >= "
                             f"carrier_outer_diameter_mm / {SLENDERNESS_MAX:g} = {outer / SLENDERNESS_MAX:.4g} mm")


def _rectangle_distance_mm(x: float, y: float, angle_rad: float, radius_mm: float, depth_mm: float,
                           width_mm: float) -> float:
    """Distance from the point (x, y) to a pillar's section (radial depth x tangential width,
    centred at radius_mm, angle_rad) [mm]; 0 inside."""
    u = x * math.cos(angle_rad) + y * math.sin(angle_rad) - radius_mm
    v = -x * math.sin(angle_rad) + y * math.cos(angle_rad)
    return math.hypot(max(abs(u) - 0.5 * depth_mm, 0.0), max(abs(v) - 0.5 * width_mm, 0.0))


def _check_carrier_seats(design, st: StructureInputs) -> None:
    """The FE carrier's support-bearing seats (bores of support_bearing_seat_diameter_mm on the crank
    circle, one per crank in each plate; pillars where geometry/carrier_layout.py places them, as
    mechanics/carrier_mesh.py builds them) inside the plates with walls of MIN_WALL_MM to the
    outline, the central hole, each other and the pillars, and larger than the crankshaft's
    journal (the bearing's bore)."""
    s1, s3 = design.first_stage, design.crank_stage
    a0 = (s3.crank_circle_radius_mm if s3.crank_circle_radius_mm is not None
          else centre_distance_mm(s1.module_mm, s1.centre_gear_teeth, s1.planet_teeth))
    cranks, seat = s1.planets, st.support_bearing_seat_diameter_mm
    limits = {"the plates' outline": 2.0 * (0.5 * st.carrier_outer_diameter_mm - MIN_WALL_MM - a0)}
    if st.carrier_bore_diameter_mm > 0:
        limits["the central hole"] = 2.0 * (a0 - 0.5 * st.carrier_bore_diameter_mm - MIN_WALL_MM)
    if cranks > 1:
        limits["the next seat"] = 2.0 * a0 * math.sin(math.pi / cranks) - MIN_WALL_MM
    gaps = [_rectangle_distance_mm(a0 * math.cos(crank), a0 * math.sin(crank), pillar, st.pillar_radius_mm,
                                   st.pillar_depth_mm, st.pillar_width_mm)
            for crank in crank_angles_rad(cranks) for pillar in pillar_angles_rad(cranks, st.carrier_pillars)]
    limits["the pillars"] = 2.0 * (min(gaps) - MIN_WALL_MM)
    binding = min(limits, key=limits.get)
    journal = st.crankshaft_diameter_mm
    if not journal < seat <= limits[binding]:
        raise InputError("structure.support_bearing_seat_diameter_mm", seat,
                         f"the seats (bores on the {a0:g} mm crank circle) must hold a bearing on the "
                         f"{journal:g} mm journal and keep a {MIN_WALL_MM:g} mm wall to {binding}; allowed: > "
                         f"crankshaft_diameter_mm = {journal:g} and <= {limits[binding]:.4g} mm")


def check_structure(design) -> None:
    """The [structure] table of ``design`` (a ``Design``, whose validator calls this: design/schema.py
    imports this module, not the other way round) against the rest of the design (module
    docstring, "Validity"); an InputError names the field by its path in the design."""
    st = design.structure
    if st is None:
        return
    s2, e = design.second_stage, design.elastic
    raceway = (e.crank_bearing_raceway_diameter_mm if e is not None else None) or design.crank_stage.bearing_bore_mm
    if raceway is not None:
        lo, hi = 0.5 * raceway, raceway + 2.0 * s2.eccentricity_mm
        for name in ("crankshaft_diameter_mm", "crankshaft_torsion_diameter_mm"):
            d = getattr(st, name)
            if d is not None and not lo <= d <= hi:
                raise InputError(f"structure.{name}", d,
                                 f"allowed: {lo:.4g} to {hi:.4g} mm, from half the eccentric it carries (the crank "
                                 f"needle bearing's raceway {raceway:g} mm) to the circle about the crank axis that "
                                 f"encloses it (raceway + 2 x eccentricity {s2.eccentricity_mm:g} mm)")
    if e is not None and s2.discs >= 2:
        face = e.disc_face_width_mm
        if not st.disc_spacing_mm >= face:
            raise InputError("structure.disc_spacing_mm", st.disc_spacing_mm,
                             f"the two discs would overlap; allowed: >= elastic.disc_face_width_mm = {face:g}")
        if not st.crankshaft_support_span_mm >= st.disc_spacing_mm + face:
            raise InputError("structure.crankshaft_support_span_mm", st.crankshaft_support_span_mm,
                             f"the supports must sit outside the disc stack; allowed: >= disc_spacing_mm + "
                             f"elastic.disc_face_width_mm = {st.disc_spacing_mm + face:g}")
    root = s2.pin_circle_radius_mm - s2.pin_radius_mm - s2.eccentricity_mm
    if not st.pillar_radius_mm + 0.5 * st.pillar_depth_mm < root:
        raise InputError("structure.pillar_radius_mm", st.pillar_radius_mm,
                         f"the pillars pass through the discs; allowed: pillar_radius_mm + pillar_depth_mm / 2 < "
                         f"the discs' root radius r_p - r_rp - a = {root:.4g} mm")
    _check_carrier_outline(st)  # after the pillars' own limits: those name the part to change first
    if has_carrier_fe(st):
        _check_carrier_seats(design, st)
    check_disc_holes(design)


def check_disc_holes(design) -> None:
    """The discs' holes (module docstring, "Validity", the last item) when
    ``structure.disc_pillar_hole_diameter_mm`` is given; an InputError names the hole's field."""
    st, s2, e = design.structure, design.second_stage, design.elastic
    if st is None or st.disc_pillar_hole_diameter_mm is None:
        return
    if e is None:
        raise InputError("elastic", None, "allowed: an [elastic] table (disc face width, materials, the crank needle "
                                          "bearings) with structure.disc_pillar_hole_diameter_mm: the disc bodies' "
                                          "finite elements read it")
    bore_field = ("elastic.crank_bearing_raceway_diameter_mm" if e.crank_bearing_raceway_diameter_mm is not None
                  else "crank_stage.bearing_bore_mm")
    raceway = e.crank_bearing_raceway_diameter_mm or design.crank_stage.bearing_bore_mm
    if raceway is None:
        raise InputError("elastic.crank_bearing_raceway_diameter_mm", None,
                         "required with structure.disc_pillar_hole_diameter_mm (the crank bores); allowed: diameter [mm]")
    a0 = design.crank_stage.crank_circle_radius_mm
    if a0 is None:  # as problem.derive_geometry: the first stage's centre distance
        s1 = design.first_stage
        a0 = centre_distance_mm(s1.module_mm, s1.centre_gear_teeth, s1.planet_teeth)
    hole_radius = st.disc_pillar_hole_radius_mm or st.pillar_radius_mm
    offset = abs(hole_radius - st.pillar_radius_mm)
    needed = pillar_hole_clearance_diameter_mm(st.pillar_width_mm, st.pillar_depth_mm, s2.eccentricity_mm) + 2 * offset
    if not st.disc_pillar_hole_diameter_mm > needed:
        raise InputError("structure.disc_pillar_hole_diameter_mm", st.disc_pillar_hole_diameter_mm,
                         f"the pillar ({st.pillar_width_mm:g} x {st.pillar_depth_mm:g} mm) does not clear the hole as "
                         f"the disc orbits it by the eccentricity {s2.eccentricity_mm:g} mm; allowed: > sqrt(w^2 + "
                         f"h^2) + 2 a{' + 2 |hole radius - pillar radius|' if offset else ''} = {needed:.4g} mm")
    bore = crank_bore_diameter_mm(raceway, e.crank_bearing_roller_diameter_mm)
    holes = disc_holes(design.first_stage.planets, a0, bore, bore_field, st.carrier_pillars, hole_radius,
                       st.disc_pillar_hole_diameter_mm, st.disc_centre_hole_diameter_mm)
    root = s2.pin_circle_radius_mm - s2.pin_radius_mm - s2.eccentricity_mm
    edge_max = root - DISC_WALL_PIN_RADII * s2.pin_radius_mm
    for h in holes:
        edge = math.hypot(h.x_mm, h.y_mm) + h.radius_mm
        if edge > edge_max:
            what = (f"crank bore (raceway + 2 needle diameters = {2 * h.radius_mm:.4g} mm on the crank circle "
                    f"{a0:g} mm)" if h.kind == "crank_bore" else f"{h.kind.replace('_', ' ')}")
            raise InputError(h.field, _field_value(design, h.field),
                             f"the {what} cuts into the profile's band: its outer edge at {edge:.4g} mm from the "
                             f"disc centre; allowed: <= root radius r_p - r_rp - a - {DISC_WALL_PIN_RADII:g} r_rp = "
                             f"{edge_max:.4g} mm")
    for i, h in enumerate(holes):
        for g in holes[i + 1:]:
            web = math.hypot(h.x_mm - g.x_mm, h.y_mm - g.y_mm) - h.radius_mm - g.radius_mm
            if web < DISC_LIGAMENT_MIN_MM:
                blame = g if g.kind != "crank_bore" else h  # the hole that is not a bearing's (sized by its bearing)
                raise InputError(blame.field, _field_value(design, blame.field),
                                 f"the disc's {h.kind.replace('_', ' ')} and {g.kind.replace('_', ' ')} "
                                 f"{'overlap' if web < 0 else 'leave too thin a web'} ({web:.3g} mm); allowed: webs "
                                 f">= {DISC_LIGAMENT_MIN_MM:g} mm between the holes")


def _field_value(design, path: str):
    """The value of a design field by its path (``structure.disc_pillar_hole_diameter_mm``)."""
    table, name = path.split(".")
    return getattr(getattr(design, table), name)
