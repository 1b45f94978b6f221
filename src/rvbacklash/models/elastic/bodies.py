"""The elements of the chain that beam formulas do not describe: the cycloid discs' bodies and the
carrier, by finite elements (``rvbacklash.mechanics``: computed once per design and cached),
added to the closed-form chain (docs/elastic.md, "The discs' bodies and the carrier by FE").

The disc's FE is loaded by the pins' forces of the designed unit at the top of the rigidity
interval (its load sharing with the profile's modifications; no pin/hole clearance, so that the
result depends on the geometry only and a tolerance change — sensitivity, allocation — reuses it)
and held at its crank bores by the needle bearings as springs (their secant stiffness there, zero
clearance): a linear model, so its compliance is one number per design, referred to the output as
the chain's ``disc_bodies`` element; the cranks' load shares it finds are reported. The carrier's FE replaces the clamped-pillar beam when
``[structure]`` gives the plates (``mechanics.carrier_body.has_carrier_fe``).
"""

from __future__ import annotations

from dataclasses import replace

from rvbacklash.design.structure import has_carrier_fe, has_disc_fe
from rvbacklash.models import compliance as cm
from rvbacklash.models.elastic.chain import ElasticModel, RISE, closed_form_model, needle_secant_stiffness_n_per_um
from rvbacklash.models.elastic.unit import PreparedUnit, unit_from_realization
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem


def elastic_model(problem: Problem) -> ElasticModel:
    """The design's elastic model: the closed-form chain (``chain.closed_form_model``) with the
    discs' bodies and the carrier by FE where ``[structure]`` gives their dimensions."""
    model = closed_form_model(problem)
    st = model.structure
    if st is None:
        return model
    c = model.chain
    changes: dict[str, float] = {}
    disc = carrier = None
    if has_disc_fe(st):
        from rvbacklash.mechanics.disc_body import disc_body_compliance  # scikit-fem and gmsh: only when used
        torque = c.rigidity_high * c.rated_torque_nm
        s2 = problem.design.second_stage
        designed = Realization.nominal(problem.cycloid, s2.equidistance_modification_um,
                                       s2.moving_distance_modification_um)
        unit = unit_from_realization(problem, designed, 0.0, 0.0)
        pu = PreparedUnit(model, unit)
        forces = pu.pin_forces_n(pu.pins_angle_rad(torque, RISE))
        stiffness = needle_secant_stiffness_n_per_um(model, torque * c.bearing_force_n_per_nm)
        disc = disc_body_compliance(problem, float(unit.chi_rad), forces, stiffness)
        changes["disc_body_compliance_rad_per_nm"] = cm.disc_body_output_compliance_rad_per_nm(
            disc.compliance_rad_per_nm, c.lever_factor, problem.cycloid.discs)
    if model.derived and has_carrier_fe(st):  # a stated structure stiffness wins over the derivation
        from rvbacklash.mechanics.carrier_body import carrier_body_compliance
        carrier = carrier_body_compliance(problem, c.lever_factor)
        changes["carrier_compliance_rad_per_nm"] = carrier.output_compliance_rad_per_nm
    if not changes:
        return model
    return replace(model, chain=c._replace(**changes), disc_body=disc, carrier_body=carrier)
