"""A unit with its wear (docs/service-life.md): the worn geometry read back by the contact and
elastic models. Wear removes material along each contact's normal, so every pin's gap grows by
the wear depths where it meets its flank (at its phase), on its own surface and in its seat (at the
direction of its normal); the crank needle bearings' clearance grows by their raceways' and
needles' wear.

The part of a disc's flank wear that is the same at every place of the tooth IS an equidistance
modification of that depth (the flank moved inwards along its normal): it is given to the contact
model as one (``Realization.equidistance_um``), so that a uniform wear w and a design with w more
of equidistance modification are the same unit, to the bit (tests); the rest, place by place, is
added to each pin's gap at its phase. The flank's radius of curvature moves with it (an offset
curve's radius, ``compliance.flank_radius_mm``): the worn unit's chain has the generating radius
r_rp + (equidistance modification + the discs' mean uniform wear) (``worn_model``), the design's own
expression, so that the uniform wear w on a design is the design with w more of modification.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from rvbacklash.analysis.capacity.revolution import CrankAngles, crank_angles
from rvbacklash.analysis.service_life.rates import WearGeometry, WearIncrement, flank_wear_at, pin_wear_at
from rvbacklash.models.elastic import ElasticModel, ElasticUnit, PreparedUnit, unit_from_realization
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem


def pin_phases_rad(chi_rad: float, discs: int, zp: int) -> np.ndarray:
    """(discs, z_p): phi = psi_j - chi_d of every pin (models.elastic.chain.pin_phase)."""
    psi = 2.0 * math.pi * np.arange(zp) / zp
    chi_d = chi_rad + 2.0 * math.pi * np.arange(discs) / discs
    return psi[None, :] - chi_d[:, None]


def worn_model(problem: Problem, model: ElasticModel, wear: WearIncrement) -> ElasticModel:
    """The elastic model of the worn flank (module docstring): its chain's generating radius
    r_rp + (dr_rp + mean uniform wear) 1e-3 [mm] (models/elastic/chain.py's expression)."""
    uniform = float(wear.flank_um.min(axis=1).mean())
    if uniform == 0.0:
        return model
    s2 = problem.design.second_stage
    radius = model.geometry.rrp_mm + (s2.equidistance_modification_um + uniform) * 1e-3
    return dataclasses.replace(model, chain=model.chain._replace(generating_radius_mm=radius))


def worn_unit(problem: Problem, realization: Realization, involute_backlash_rad: float, crank_clearance_um: float,
              wear: WearIncrement, geo: WearGeometry) -> ElasticUnit:
    """The ElasticUnit of a realisation after the wear ``wear`` (module docstring)."""
    uniform = wear.flank_um.min(axis=1)  # (discs,) the flank wear common to every place
    r = realization.with_(equidistance_um=np.asarray(realization.equidistance_um, float) + uniform)
    unit = unit_from_realization(problem, r, involute_backlash_rad, crank_clearance_um + wear.clearance_um)
    phases = pin_phases_rad(float(realization.chi_rad), geo.discs, geo.zp)
    extra = flank_wear_at(wear.flank_um - uniform[:, None], geo, phases) + pin_wear_at(wear, geo, phases)
    return unit._replace(gap_um=unit.gap_um + extra)


def worn_gaps_um(wear: WearIncrement, geo: WearGeometry, chi_rad: np.ndarray) -> np.ndarray:
    """(n, discs, z_p): the gap growth of n units at their crank angles from the wear (all of it
    added to the gaps: the production run's units)."""
    n = chi_rad.size
    psi = 2.0 * math.pi * np.arange(geo.zp) / geo.zp
    chi_d = np.asarray(chi_rad, float)[:, None] + 2.0 * math.pi * np.arange(geo.discs)[None, :] / geo.discs
    phases = psi[None, None, :] - chi_d[:, :, None]  # (n, discs, z_p): pin_phases_rad of each unit
    flat = np.ascontiguousarray(phases.transpose(1, 0, 2).reshape(geo.discs, n * geo.zp))
    grown = flank_wear_at(wear.flank_um, geo, flat) + pin_wear_at(wear, geo, flat)
    return np.ascontiguousarray(grown.reshape(geo.discs, n, geo.zp).transpose(1, 0, 2))


class WornAngles(CrankAngles):
    """A worn unit prepared at K crank angles over a crank revolution (``CrankAngles`` with the
    wear's gaps and clearance): its pins' forces at any output torque, for ``revolution_loads``."""

    def __init__(self, problem: Problem, model: ElasticModel, realization: Realization, involute_backlash_rad: float,
                 crank_clearance_um: float, wear: WearIncrement, geo: WearGeometry, angles: int):
        model = worn_model(problem, model, wear)
        self.problem, self.model = problem, model
        self.crank_clearance_um = float(crank_clearance_um + wear.clearance_um)
        g = model.geometry
        self.chi_rad = crank_angles(float(realization.chi_rad), g.zc, g.zp, angles)
        self.units = [PreparedUnit(model, worn_unit(problem, realization.with_(chi_rad=float(chi)),
                                                    involute_backlash_rad, crank_clearance_um, wear, geo))
                      for chi in self.chi_rad]
        self._cache: dict[float, np.ndarray] = {}
