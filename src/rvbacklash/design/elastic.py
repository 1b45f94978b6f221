"""Inputs of the elastic hysteresis model (docs/elastic.md): the ``[elastic]`` table of a design.

What the test bench needs to turn a unit's clearances into its torque-angle loop: the rated
torque and the measuring points (lost motion at +-x % of it, rigidity over an interval of it),
the materials and lengths of the line contacts (cycloid-pin, crank needle bearings), the mesh
stiffness of the involute stage, stated stiffnesses that replace or add to what the model derives
(main bearings; the structure that ``[structure]`` otherwise derives) and a friction model.

Defaults and their basis (every one can be overridden):

- ``measuring_torque_fraction`` 0.03: Nabtesco's lost motion is read at +-3 % of the rated
  torque (catalogue wording; other makers use 2-5 %).
- ``rigidity_interval_fraction`` [0.5, 1.0]: our choice. Nabtesco calls the rigidity "b/a" on its
  hysteresis figure; we read it as the secant of the loading branches over the upper half of the
  rated torque, beyond the dead bands (the exact torque points of the catalogue figure are
  unverified, see docs/elastic.md).
- Young's modulus 206 GPa and Poisson's ratio 0.3: handbook values for hardened steel (the housing
  too: a design with a cast-iron housing states its modulus).
- ``pin_seating`` "groove": every RV housing holds its pins in semicircular grooves; the seat is a
  second line contact in series with the flank's (issue 28).
- ``mesh_stiffness_n_per_mm_um`` 20: c_gamma of solid steel spur pairs (DIN 3990-1 / ISO 6336-1
  approximation, c' ~ 14 N/(mm um) times (0.75 eps_alpha + 0.25) for eps_alpha ~ 1.6).
- structure stiffness: None = not stated: the crankshafts, support bearings and carrier are derived
  from the design's ``[structure]`` table (design/structure.py); a design without that table has a
  rigid structure, and its predicted rigidity is an upper bound. A stated value (FE, a bench) wins.
- main-bearing stiffness: None = no element: a pure-torque test does not load the main bearings
  (docs/elastic.md, "The whole torque path"); a stated value adds one.
- friction: 0 (the loading and unloading branches coincide); an assumption, not a measurement.
- ``crank_bearing_roller_profile`` "logarithmic": precision needle rollers are profiled, not
  straight (needle roller and cage assemblies of the major makers have profiled rollers, a
  logarithmic or crowned generatrix [makers' catalogues, from memory]); with the actual profile
  unknown, ISO/TS 16281:2008 prescribes its logarithmic profile, K = 0.35 D_we um per mm of roller
  diameter for L <= 2.5 D_we (models/compliance.py, ``iso_logarithmic_profile``). "straight" is the
  model before profiles (Johnson's or Palmgren's law per roller, unchanged to the bit).
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from rvbacklash.errors import InputError


class _Strict(BaseModel):
    # same rules as every design table (design/schema.py): no coercion, no unknown keys
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class ElasticInputs(_Strict):
    """The elastic model's inputs: test-bench torques, contact geometry, stiffnesses, friction."""

    rated_torque_nm: float = Field(gt=0, le=1e6, description="rated output torque T_R [N m] (catalogue)")
    measuring_torque_fraction: float = Field(
        0.03, gt=0, lt=0.5, description="x: lost motion is read at +-x T_R [-] (Nabtesco: 0.03)")
    rigidity_interval_fraction: list[float] = Field(
        [0.5, 1.0], min_length=2, max_length=2,
        description="[low, high] of T_R: torsional rigidity is the secant of the loading branches over it [-]")

    disc_youngs_modulus_gpa: float = Field(206.0, gt=0, le=1000, description="Young's modulus of the discs [GPa]")
    disc_poisson_ratio: float = Field(0.3, ge=0, lt=0.5, description="Poisson's ratio of the discs [-]")
    pin_youngs_modulus_gpa: float = Field(206.0, gt=0, le=1000,
                                          description="Young's modulus of the pins and needle rollers [GPa]")
    pin_poisson_ratio: float = Field(0.3, ge=0, lt=0.5, description="Poisson's ratio of the pins and rollers [-]")
    disc_face_width_mm: float = Field(gt=0, le=1000, description="face width of one cycloid disc [mm]")
    pin_length_mm: float | None = Field(
        None, gt=0, le=5000, description="pin length [mm]; each disc bears on min(face width, pin length / discs); "
                                         "default: long enough")
    contact_law: Literal["johnson", "palmgren"] = Field(
        "johnson", description="line-contact approach: johnson (Hertz, Johnson's Contact Mechanics ch. 4, with the "
                               "local radii of curvature) or palmgren (roller formula 3.84e-5 Q^0.9 / L^0.8)")
    lever_arms: Literal["kinematic", "eq1"] = Field(
        "kinematic", description="how the disc and crank-bearing deflections refer to the output: kinematic "
                                 "(input locked: factor z_c / (z_p + z1/z2), docs/model.md) or eq1 (Eq. (1): a z_c, "
                                 "as the linear and contact models)")

    pin_seating: Literal["groove", "none"] = Field(
        "groove", description="the pins' seats in the housing: groove (each loaded pin presses into its semicircular "
                              "groove, a conforming line contact in series with the pin-flank contact; docs/elastic.md) "
                              "or none (the housing holds the pins rigidly)")
    housing_youngs_modulus_gpa: float = Field(
        206.0, gt=0, le=1000, description="Young's modulus of the housing's pin grooves [GPa] (steel: 206; ductile "
                                          "iron: ~170)")
    housing_poisson_ratio: float = Field(0.3, ge=0, lt=0.5, description="Poisson's ratio of the housing [-]")

    crank_bearing_rollers: int = Field(ge=3, le=200, description="needle rollers per crank (swivel-arm) bearing [-]")
    crank_bearing_roller_diameter_mm: float = Field(gt=0, le=100, description="needle roller diameter D_w [mm]")
    crank_bearing_roller_length_mm: float = Field(gt=0, le=500,
                                                  description="effective needle roller length L_w [mm]")
    crank_bearing_raceway_diameter_mm: float | None = Field(
        None, gt=0, le=1000, description="inner raceway (eccentric) diameter [mm]; default crank_stage.bearing_bore_mm")

    crank_bearing_roller_profile: Literal["logarithmic", "crowned", "straight"] = Field(
        "logarithmic", description="generatrix of the needle rollers (docs/rigidity-elements.md): logarithmic (ISO/TS "
                                   "16281's profile for an unknown one; scale crank_bearing_roller_log_scale_um), "
                                   "crowned (a circular crown, crank_bearing_roller_crown_drop_um at the ends), "
                                   "straight (no profile: the law per roller as before)")
    crank_bearing_roller_crown_drop_um: float | None = Field(
        None, gt=0, le=100, description="crowned needle rollers: drop of the circular crown at the ends of the "
                                        "effective length (radius) [um]; required with roller_profile = crowned")
    crank_bearing_roller_log_scale_um: float | None = Field(
        None, gt=0, le=100, description="logarithmic needle rollers: K in P(x) = K ln(1 / (1 - (2x/L)^2)) [um]; "
                                        "default ISO/TS 16281: 0.35 D_we (D_we in mm; 0.5 D_we over the ends when "
                                        "L > 2.5 D_we)")

    mesh_stiffness_n_per_mm_um: float = Field(
        20.0, gt=0, le=1000, description="involute mesh stiffness c_gamma per face width [N/(mm um)] "
                                         "(ISO 6336-1 / DIN 3990: about 20 for solid steel spur gears)")
    main_bearing_stiffness_nm_per_arcmin: float | None = Field(
        None, gt=0, le=1e9, description="torsional stiffness of the main bearings at the output [N m/arcmin]; "
                                        "default: none (a pure-torque test does not load them; docs/elastic.md)")
    structure_stiffness_nm_per_arcmin: float | None = Field(
        None, gt=0, le=1e9, description="torsional stiffness of everything else in series (crankshafts, support "
                                        "bearings, carrier, housing) [N m/arcmin]; replaces what [structure] derives; "
                                        "default: derived from [structure], rigid without it")

    friction_torque_nm: float | None = Field(
        None, ge=0, le=1e6, description="Coulomb friction torque at the output, constant part T_f0 [N m]; not "
                                        "stated: 0, or the contacts' (friction_model)")
    friction_load_fraction: float | None = Field(
        None, ge=0, lt=0.5, description="Coulomb friction torque proportional to the transmitted torque, "
                                        "T_f = T_f0 + mu |T| [-]; not stated: 0, or the contacts' (friction_model)")
    friction_model: Literal["stated", "contacts"] | None = Field(
        None, description="where the loop's Coulomb friction comes from: contacts (T_f0 and mu from the contacts' "
                          "friction under the twist: the pins, bearings, mesh and seal with [lubrication]'s "
                          "coefficients; a friction_torque_nm or friction_load_fraction stated with it wins) or "
                          "stated (friction_torque_nm and friction_load_fraction as given, 0 when not). Not stated: "
                          "stated when friction_torque_nm or friction_load_fraction is given (a file that states "
                          "its friction keeps its meaning), else contacts (docs/efficiency.md)")

    @model_validator(mode="after")
    def _consistent(self) -> "ElasticInputs":
        check_profile("crank_bearing_roller", self.crank_bearing_roller_profile,
                      self.crank_bearing_roller_crown_drop_um, self.crank_bearing_roller_log_scale_um)
        low, high = self.rigidity_interval_fraction
        if not 0.0 <= low < high <= 1.0:
            raise ValueError(f"rigidity_interval_fraction = [{low}, {high}]: allowed 0 <= low < high <= 1 "
                             f"(fractions of rated_torque_nm)")
        limit = self.rated_torque_nm * (1.0 - self.stated_friction_fraction)
        if not self.stated_friction_nm < limit:
            raise ValueError(f"friction_torque_nm = {self.friction_torque_nm}: friction this large never lets the "
                             f"output move; allowed friction_torque_nm < rated_torque_nm (1 - friction_load_fraction)"
                             f" = {limit:g}")
        return self

    @property
    def loop_friction_model(self) -> str:
        """The friction model the loop uses: ``friction_model`` as stated; not stated, "stated" when the
        design gives friction_torque_nm or friction_load_fraction (the typed-in constant as an override:
        such a file means what it meant before the contacts' friction became the default), else
        "contacts" (issue 40 item 3)."""
        if self.friction_model is not None:
            return self.friction_model
        if self.friction_torque_nm is not None or self.friction_load_fraction is not None:
            return "stated"
        return "contacts"

    @property
    def stated_friction_nm(self) -> float:
        """friction_torque_nm as stated (0 when not)."""
        return self.friction_torque_nm or 0.0

    @property
    def stated_friction_fraction(self) -> float:
        """friction_load_fraction as stated (0 when not)."""
        return self.friction_load_fraction or 0.0


def check_profile(prefix: str, profile: str, crown_drop_um: float | None, log_scale_um: float | None) -> None:
    """A roller profile's parameter belongs to its profile: ``{prefix}_crown_drop_um`` is required by
    and only read with "crowned", ``{prefix}_log_scale_um`` only read with "logarithmic" (a value
    given for another profile would be silently ignored: refused, naming the field)."""
    if profile == "crowned" and crown_drop_um is None:
        raise InputError(f"{prefix}_crown_drop_um", None,
                         "required with roller_profile = \"crowned\": the crown's drop at the roller's ends [um], > 0")
    if profile != "crowned" and crown_drop_um is not None:
        raise InputError(f"{prefix}_crown_drop_um", crown_drop_um,
                         f"only with roller_profile = \"crowned\" (this roller is {profile}); allowed: remove it")
    if profile != "logarithmic" and log_scale_um is not None:
        raise InputError(f"{prefix}_log_scale_um", log_scale_um,
                         f"only with roller_profile = \"logarithmic\" (this roller is {profile}); allowed: remove it")
