"""Every pin's force in a production run's unit at a set of chain torques, at its own crank angle
(docs/service-life.md, "The production run"): the service life reads a unit's own wear from it (a
unit whose part deviations close some pins first loads them, and the flank places they meet, more).

One solve of the unit's pins per torque (``solver.solve_pins``, the bracketed solve the loop's
figures use, from no start), the forces placed on their pins as ``unit_life._life_at`` places them.
"""

from __future__ import annotations

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.models.elastic.chain import prepare_pins_indexed
from rvbacklash.models.elastic.solver import law_force, solve_pins
from rvbacklash.models.elastic.unit import ElasticUnit


@njit(nogil=True, cache=True)
def unit_pin_forces(unit, design, torques_nm, order, out):
    """out (T, discs, z_p): every pin's force [N] of one ElasticUnit with the design's LoopDesign at
    each chain torque torques_nm (T,) [N m] (negative: the other flanks); ``order`` (discs z_p,)
    int64 scratch."""
    c = design.chain
    translating = c.radial_stiffness_n_per_um < np.inf
    pins = prepare_pins_indexed(unit, c, translating, design.pin_laws, order)
    cs = pins.contacts
    zp = unit.gap_um.shape[1]
    for t in range(torques_nm.size):
        load = torques_nm[t]
        side = 1.0 if load >= 0.0 else -1.0
        x = solve_pins(pins, load, side, np.nan, c, (np.nan, np.nan)).x
        gaps = pins.translation.shifted_gaps_um if translating else cs.gaps
        out[t] = 0.0
        for i in range(gaps.size):
            delta = cs.levers[i] * x - gaps[i]
            if delta > 0.0:
                j = order[i]
                out[t, j // zp, j - (j // zp) * zp] = law_force(delta, cs.law_a[i], c.law_b, c.law_n, cs.forces[i])[0]


@njit(nogil=True, cache=True)
def evaluate_pin_forces(units, design, torques_nm, out):
    """``unit_pin_forces`` of a batch of n units (an ElasticUnit batch) into out (n, T, discs, z_p)."""
    order = np.empty(units.gap_um.shape[1] * units.gap_um.shape[2], dtype=np.int64)
    for i in range(units.chi_rad.size):
        unit_pin_forces(ElasticUnit(units.gap_um[i], units.lever_um_per_rad[i], units.chi_rad[i],
                                    units.involute_backlash_rad[i], units.crank_clearance_um[i]), design, torques_nm,
                        order, out[i])


def pin_forces_n(units, design, torques_nm) -> np.ndarray:
    """(n, T, discs, z_p): every pin's force [N] of a batch of units at each chain torque [N m]."""
    n, discs, zp = units.gap_um.shape
    out = np.zeros((n, np.size(torques_nm), discs, zp))
    evaluate_pin_forces(units, design, np.ascontiguousarray(torques_nm, float), out)
    return out
