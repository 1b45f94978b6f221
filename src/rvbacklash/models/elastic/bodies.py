"""The elements of the chain that beam formulas do not describe: the cycloid discs' bodies and the
carrier, by finite elements (``rvbacklash.mechanics``: computed once per design and cached),
added to the closed-form chain (docs/elastic.md, "The discs' bodies and the carrier by FE").

The disc's FE is loaded by the **nominal unit** — the unit ``hysteresis`` solves
(``unit.nominal_unit``: the designed modifications, the pin/hole clearance at its zone mean,
crank angle 0) — with the load state the rigidity reads: the change of its pins' forces from the
bottom to the top of the rigidity interval on the loading branch (``disc_load_n``). So the disc
bodies see the same gaps as the loop (the same gaps written as a modification or as a hole
clearance give the same element, issue 36), and a preload's self-balanced pin forces, which carry
no torque and do not change the secant, do not read as compliance. The bores are held by the
needle bearings as springs (their secant stiffness at the top of the interval, zero clearance): a
linear model, so its compliance is one number per design, referred to the output as the chain's
``disc_bodies`` element, and a production run's units all use it (their own gaps move their pins,
not this element); the cranks' load shares it finds are reported. The carrier's FE replaces the
clamped-pillar beam when ``[structure]`` gives the plates (``design.structure.has_carrier_fe``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from rvbacklash.design.structure import has_carrier_fe, has_disc_fe
from rvbacklash.models import compliance as cm
from rvbacklash.models.elastic.chain import ElasticModel, RISE, closed_form_model, needle_secant_stiffness_n_per_um
from rvbacklash.models.elastic.unit import ElasticUnit, PreparedUnit, nominal_unit
from rvbacklash.problem import Problem


def disc_load_n(model: ElasticModel, unit: ElasticUnit) -> np.ndarray:
    """The pin forces [N] (discs, z_p) the disc bodies' FE is loaded with: ``unit``'s (the nominal
    unit, ``nominal_unit``: the unit the ``hysteresis`` loop solves) change of every pin's normal force
    from l T_R to h T_R on the loading branch (the rigidity interval [l, h]; friction as the loop
    has it). A free unit's pins only close as the torque rises (every entry >= 0); a preloaded
    unit's opposite pins unload (entries < 0), and the preload they shared at l T_R, self-balanced,
    drops out: the FE reads the increment the rigidity secant reads."""
    c = model.chain
    pu = PreparedUnit(model, unit)

    def forces(fraction: float) -> np.ndarray:
        return pu.pin_forces_n(pu.pins_angle_rad(fraction * c.rated_torque_nm, RISE))  # the angle, then its forces

    return forces(c.rigidity_high) - forces(c.rigidity_low)


def elastic_model(problem: Problem) -> ElasticModel:
    """The design's elastic model: the closed-form chain (``chain.closed_form_model``) with the
    discs' bodies and the carrier by FE where ``[structure]`` gives their dimensions, and with
    ``friction_model = "contacts"`` the loop's friction from the contacts (``twist_friction``)."""
    model = _with_bodies(problem, closed_form_model(problem))
    if model.inputs.loop_friction_model == "contacts":
        from rvbacklash.models.elastic.twist_friction import with_twist_friction
        model = with_twist_friction(problem, model)
    return model


def _with_bodies(problem: Problem, model: ElasticModel) -> ElasticModel:
    """The closed-form model with the discs' bodies and the carrier by FE where [structure] gives them."""
    st = model.structure
    if st is None:
        return model
    c = model.chain
    changes: dict[str, float] = {}
    disc = carrier = None
    if has_disc_fe(st):
        from rvbacklash.mechanics.disc_body import disc_body_compliance  # scikit-fem and gmsh: only when used
        torque = c.rigidity_high * c.rated_torque_nm
        stiffness = needle_secant_stiffness_n_per_um(model, torque * c.bearing_force_n_per_nm)
        unit = nominal_unit(problem)
        disc = disc_body_compliance(problem, float(unit.chi_rad), disc_load_n(model, unit), stiffness)
        changes["disc_body_compliance_rad_per_nm"] = cm.disc_body_output_compliance_rad_per_nm(
            disc.compliance_rad_per_nm, c.lever_factor, problem.cycloid.discs)
    if model.derived and has_carrier_fe(st):  # a stated structure stiffness wins over the derivation
        from rvbacklash.mechanics.carrier_body import carrier_body_compliance
        carrier = carrier_body_compliance(problem, c.lever_factor)
        changes["carrier_compliance_rad_per_nm"] = carrier.output_compliance_rad_per_nm
    if not changes:
        return model
    return replace(model, chain=c._replace(**changes), disc_body=disc, carrier_body=carrier)
