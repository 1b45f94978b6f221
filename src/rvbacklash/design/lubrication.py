"""Inputs of the losses and the thermal balance (docs/efficiency.md; issue 40): the optional
``[lubrication]`` and ``[thermal]`` tables of a design. Every field has a default, each an
assumption stated here (none chosen to meet a published efficiency):

``[lubrication]``
- the lubricant: RV reducers are delivered grease-filled (the maker's grease; its base oil's grade is
  not public). Default: an ISO VG 100 mineral base oil, nu40 = 100, nu100 = 11.1 mm^2/s (viscosity
  index ~95, the usual paraffinic mineral oil of that grade), density 870 kg/m^3, pressure-viscosity
  coefficient 20 /GPa (mineral oils 10-30 /GPa: Hamrock, Schmid & Jacobson, "Fundamentals of Machine
  Elements" 3rd ed., Ch. 8). The grease's thickener and its churning are
  not modelled beyond the bearings' viscous terms;
- friction coefficients: boundary 0.10 (lubricated hardened steel in boundary lubrication: 0.05-0.15,
  Hutchings & Shipway, "Tribology" 2nd ed., Ch. 4), full film 0.03 (EHL traction of mineral oils at
  moderate slide-roll ratios: 0.02-0.05), static (breakaway) 0.12 (a little above the boundary value),
  pins in their seats 0.10 (a hardened pin sliding in a lubricated ground groove: boundary);
- roughness: pins Rq 0.10 um (ground and polished rollers), discs' flanks Rq 0.25 um (ground), gears
  Ra 0.5 um (ground, ISO 1328 grade 5);
- Palmgren's factors (Harris & Kotzalas 5th ed., vol. 1, tables of f0 and f1; grease lubrication):
  needle roller bearings f0 = 12, f1 = 0.0005; tapered roller bearings f0 = 6, f1 = 0.0004; angular
  contact ball bearings f0 = 2 (f1 from their load: ``models.friction.angular_ball_f1``);
- the mesh's lubricant factor X_L = 1.0 (mineral oil, ISO/TR 14179-2);
- seals: the output's radial lip seal 1.0 N m (the order of a ~170 mm lip seal's friction torque in
  makers' power-loss diagrams at low speed; the design's former ``friction_torque_nm`` note said the
  same), the input's 0 (the motor's own seal), churning 0 (grease-filled: the bearings' viscous terms
  stand for the drag);
- ``temperature_c`` 40: the oil's temperature at which ``efficiency`` reports its figures unless a
  temperature is given (the catalogues print their curves at a stated case temperature).

``[thermal]``
- ambient 20 degC (ISO 1: the reference temperature of dimensional specifications, and so of the
  parts' sizes; ``reference_temperature_c``), case limit 60 degC (an assumption the issue states;
  makers limit the case temperature of RV reducers about there);
- convection 8 W/(m^2 K): natural convection of a ~0.2 m horizontal cylinder in still air at a
  20-40 K rise (Churchill-Chu correlation, Incropera & DeWitt 6th ed., Eq. (9.34): 5-9 W/(m^2 K));
  emissivity 0.5 (between machined steel ~0.3 and a painted case ~0.9); the mounting's conduction
  0 W/K (unknown; 0 is the conservative bound);
- the housing: a cylinder of the stated diameter and length; default diameter 2 (r_p + 2 r_rp) + 24 mm
  (the pin ring with a 12 mm wall) and length 0.45 x that diameter (RV-E proportions, assumption);
  its heat capacity from its mass (default: a steel cylinder of that envelope half filled, 7850 kg/m^3
  x 0.5) x 460 J/(kg K) (steel);
- expansion coefficients [1/K]: housing 11.0e-6 (ductile cast iron EN-GJS, the usual RV housing:
  10.5-12.5e-6), pins, discs, cranks and needles 12.5e-6 (through-hardened bearing steel 100Cr6/GCr15,
  11.5-12.6e-6 between 20 and 100 degC), carrier 11.0e-6 (ductile iron).
"""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field


class _Strict(BaseModel):
    # same rules as every design table (design/schema.py): no coercion, no unknown keys
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class LubricationInputs(_Strict):
    """The lubricant, the contacts' friction and the seals (module docstring)."""

    viscosity_40c_mm2_s: float = Field(100.0, gt=2, le=10000, description="the oil's (a grease's base oil's) "
                                                                          "kinematic viscosity at 40 degC [mm^2/s]")
    viscosity_100c_mm2_s: float = Field(11.1, gt=2, le=2000, description="... at 100 degC [mm^2/s] (ASTM D341 "
                                                                        "Walther line through the two)")
    density_kg_m3: float = Field(870.0, gt=500, le=2000, description="the oil's density [kg/m^3]")
    pressure_viscosity_per_gpa: float = Field(20.0, gt=0, le=60, description="pressure-viscosity coefficient "
                                                                             "alpha [1/GPa] (EHL film)")
    boundary_friction_coefficient: float = Field(0.10, ge=0, le=1, description="boundary friction coefficient of "
                                                                               "the pins on the flanks (Lambda <= 1)")
    full_film_friction_coefficient: float = Field(0.03, ge=0, le=1, description="full-film (EHL) traction "
                                                                                "coefficient (Lambda >= 3)")
    static_friction_coefficient: float = Field(0.12, ge=0, le=1, description="breakaway friction coefficient of "
                                                                             "the pins and the mesh at standstill")
    pin_seat_friction_coefficient: float = Field(0.10, ge=0, le=1, description="a pin turning in its housing seat")
    pin_roughness_rq_um: float = Field(0.10, ge=0, le=10, description="pins' rms roughness Rq [um]")
    disc_roughness_rq_um: float = Field(0.25, ge=0, le=10, description="discs' flanks' rms roughness Rq [um]")
    gear_roughness_ra_um: float = Field(0.5, gt=0, le=10, description="involute flanks' mean roughness Ra [um]")
    mesh_lubricant_factor: float = Field(1.0, ge=0, le=3, description="ISO/TR 14179-2 lubricant factor X_L "
                                                                      "(mineral oil 1.0)")
    needle_bearing_f0: float = Field(12.0, ge=0, le=100, description="Palmgren f0 of the crank needle bearings")
    needle_bearing_f1: float = Field(0.0005, ge=0, le=0.01, description="Palmgren f1 of the crank needle bearings")
    support_bearing_f0: float = Field(6.0, ge=0, le=100, description="Palmgren f0 of the crank support bearings")
    support_bearing_f1: float = Field(0.0004, ge=0, le=0.01, description="Palmgren f1 of the support bearings")
    main_bearing_f0: float = Field(2.0, ge=0, le=100, description="Palmgren f0 of the main bearings")
    main_bearing_f1_scale: float = Field(0.001, ge=0, le=0.01, description="z of f1 = z (P0/C0)^0.33 of the main "
                                                                           "(angular contact ball) bearings")
    output_seal_torque_nm: float = Field(1.0, ge=0, le=1000, description="the output's lip seal's friction torque "
                                                                         "[N m] (stated term)")
    input_seal_torque_nm: float = Field(0.0, ge=0, le=100, description="an input seal's friction torque [N m]")
    churning_torque_nm: float = Field(0.0, ge=0, le=100, description="churning drag at the input [N m] (stated "
                                                                     "term; grease-filled: 0)")
    temperature_c: float = Field(40.0, ge=-40, le=150, description="the oil's temperature of the reported "
                                                                   "efficiency figures [degC]")


class ThermalInputs(_Strict):
    """The housing's heat balance and the parts' thermal expansion (module docstring)."""

    ambient_c: float = Field(20.0, ge=-40, le=80, description="ambient temperature [degC]")
    case_limit_c: float = Field(60.0, gt=-40, le=150, description="the allowable case temperature [degC]")
    reference_temperature_c: float = Field(20.0, ge=-40, le=80, description="the temperature the parts' sizes "
                                                                            "refer to (ISO 1: 20) [degC]")
    convection_w_m2k: float = Field(8.0, ge=0, le=1000, description="convection coefficient [W/(m^2 K)]")
    emissivity: float = Field(0.5, ge=0, le=1, description="the case's emissivity [-]")
    flange_conductance_w_k: float = Field(0.0, ge=0, le=1000, description="conduction into the mounting [W/K]")
    housing_outer_diameter_mm: float | None = Field(None, gt=0, le=5000, description="the case's outer diameter "
                                                    "[mm]; default 2 (r_p + 2 r_rp) + 24")
    housing_length_mm: float | None = Field(None, gt=0, le=5000, description="the case's length [mm]; default "
                                                                             "0.45 x its diameter")
    mass_kg: float | None = Field(None, gt=0, le=10000, description="the reducer's mass [kg]; default: a steel "
                                                                    "cylinder of the case's envelope half filled")
    specific_heat_j_kgk: float = Field(460.0, gt=0, le=5000, description="specific heat [J/(kg K)] (steel 460)")
    housing_expansion_per_k: float = Field(11.0e-6, ge=0, le=1e-4, description="the housing's (pin ring's) "
                                                                                "expansion coefficient [1/K]")
    pin_expansion_per_k: float = Field(12.5e-6, ge=0, le=1e-4, description="the pins' [1/K]")
    disc_expansion_per_k: float = Field(12.5e-6, ge=0, le=1e-4, description="the discs' [1/K]")
    crank_expansion_per_k: float = Field(12.5e-6, ge=0, le=1e-4, description="the crankshafts' (eccentrics') [1/K]")
    needle_expansion_per_k: float = Field(12.5e-6, ge=0, le=1e-4, description="the needle rollers' [1/K]")
    carrier_expansion_per_k: float = Field(11.0e-6, ge=0, le=1e-4, description="the carrier's [1/K]")
    gear_expansion_per_k: float = Field(12.5e-6, ge=0, le=1e-4, description="the involute stage's gears' (centre "
                                                                             "gear and planets) [1/K]")


def housing_envelope(thermal: ThermalInputs, pin_circle_radius_mm: float, pin_radius_mm: float
                     ) -> tuple[float, float, float, float]:
    """(diameter [mm], length [mm], outer surface [m^2], mass [kg]) of the case: stated or the defaults
    (module docstring). The surface is the cylinder's mantle and both ends."""
    d = thermal.housing_outer_diameter_mm or 2.0 * (pin_circle_radius_mm + 2.0 * pin_radius_mm) + 24.0
    length = thermal.housing_length_mm or 0.45 * d
    area = (math.pi * d * length + 2.0 * math.pi * d * d / 4.0) * 1e-6
    mass = thermal.mass_kg or 7850.0 * 0.5 * math.pi * d * d / 4.0 * length * 1e-9
    return d, length, area, mass
