"""Life in the production run (docs/capacity.md, "Production run"): each unit's bearing lives, the
reducer's life, its derived rated torque and its largest pin stress, beside its loop's figures, at a
small cost per unit (``evaluate_units_life``; a production run asks for it with a life spec).

The full computation (``analysis.capacity``) follows a unit through K crank angles per revolution;
a production run cannot (each angle is another contact problem). Here a unit is read at its own crank
angle only, against the nominal unit's full computation, made once per design (``LifeTables``,
built by ``analysis.capacity.production``):

- the pins are solved at the rated torque T_R (one more solve of the unit's loop's pins, started
  from its loop's last solution); each disc's resultant and moment load its P needle bearings (the
  rigid-disc statics of ``loads``), which at this instant sit at P bore angles of the load's cycle:
  their p-power mean (p = 10/3) P_d over the P bearings, against the nominal unit's at the same crank
  angle (``nominal_needle_peq``), scales the nominal bearing's load cycle by s_d = P_d / P_d,nominal;
- one needle bearing's ISO/TS 16281 life over that scaled cycle at the unit's crank-bearing clearance
  is read from a table of the nominal cycle's life over (clearance, ln s) (``log_needle_life``,
  bilinear in ln L); every needle bearing of disc d has that life;
- the support bearings likewise: each end's p-mean over the cranks against the nominal's at the same
  angle scales its ISO 281 life by the ratio to the power -10/3;
- the reducer's life is the system of the 2P needle and 2P support bearings (e = 9/8); its derived
  rated torque T0 = T0,nominal (L / L_nominal)^(1/beta) with beta the nominal life's exponent
  -d ln L / d ln T at T0,nominal; the largest pin stress is at the unit's crank angle at T_R.

The error of this reading against the full K-angle computation of the same units is measured
(tests/analysis/test_capacity_production.py; docs/capacity.md).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.models.elastic.chain import (N_ELEMENTS, LoopUnit, loop_figures, paired_rollers,
                                             prepare_pins_indexed)
from rvbacklash.models.elastic.loads import (LoadGeometry, crank_bearing_loads, crank_torques_nmm, disc_resultants,
                                             pin_stresses_mpa, support_bearing_loads)
from rvbacklash.models.elastic.unit import ElasticUnit
from rvbacklash.models.elastic.solver import POSITIVE, law_force, new_state, solve_pins

LIFE_OUTPUTS = 4  # life [h], weakest bearing's life [h], derived rated torque [N m], largest pin stress [MPa]
LIFE, WEAKEST, RATED_TORQUE, PIN_STRESS = range(LIFE_OUTPUTS)
WEIBULL_SLOPE = 9.0 / 8.0  # rollers (ratings.ROLLER_WEIBULL_SLOPE)
LIFE_EXPONENT = 10.0 / 3.0  # ISO 281, rollers


class LifeTables(NamedTuple):
    """What a production run's life reads of its design (module docstring; built by
    ``analysis.capacity.production.life_tables``)."""

    torque_nm: float  # T_R: the chain torque at which each unit's pins are solved
    geometry: LoadGeometry
    chi_grid_rad: np.ndarray  # (n_chi,) crank angles (within one pin pitch) of the nominal references
    nominal_needle_peq: np.ndarray  # (discs, n_chi) the nominal unit's per-disc p-mean needle load there [N]
    nominal_support_peq: np.ndarray  # (2, n_chi) per support end: the p-mean over the cranks [N]
    clearance_um: np.ndarray  # (n_g,) the needle clearance grid [um]
    log_scale: np.ndarray  # (n_s,) the load-scale grid, ln s
    log_needle_life: np.ndarray  # (n_g, n_s) ln of one needle bearing's life [h] over the nominal cycle x s
    log_support_life: np.ndarray  # (2,) ln of the nominal support A and B lives [h]
    nominal_life_h: float  # the nominal unit's reducer life at T_R (K angles)
    nominal_rated_torque_nm: float
    life_exponent: float  # beta = -d ln L / d ln T at the nominal's derived rated torque


class LifeScratch(NamedTuple):
    """Per-thread scratch of ``unit_life``."""

    forces: np.ndarray  # (discs, z_p)
    stress: np.ndarray  # (discs, z_p)
    resultants: np.ndarray  # (discs, 3)
    bearing: np.ndarray  # (discs, cranks, 2)
    torques: np.ndarray  # (cranks,)
    support: np.ndarray  # (cranks, 2, 2)
    order: np.ndarray  # (discs z_p,) int64: each contact's pin (flat index)
    angles: np.ndarray  # (N_ELEMENTS,)


@njit(cache=True)
def life_scratch(discs, zp, cranks):
    return LifeScratch(np.zeros((discs, zp)), np.zeros((discs, zp)), np.empty((discs, 3)), np.empty((discs, cranks, 2)),
                       np.empty(cranks), np.zeros((cranks, 2, 2)), np.empty(discs * zp, dtype=np.int64),
                       np.empty(N_ELEMENTS))


@njit(cache=True)
def _interp_periodic(grid, values, x, period):
    """Linear interpolation of values on an increasing grid within [0, period), periodic."""
    n = grid.size
    if n == 1:
        return values[0]
    x = x - period * math.floor(x / period)
    i = 0
    while i < n - 1 and grid[i + 1] <= x:
        i += 1
    if x < grid[0]:
        lo, hi, x0, x1 = n - 1, 0, grid[n - 1] - period, grid[0]
    elif i == n - 1:
        lo, hi, x0, x1 = n - 1, 0, grid[n - 1], grid[0] + period
    else:
        lo, hi, x0, x1 = i, i + 1, grid[i], grid[i + 1]
    t = (x - x0) / (x1 - x0)
    return values[lo] + t * (values[hi] - values[lo])


@njit(cache=True)
def _bracket(grid, x):
    """(i, t): x between grid[i] and grid[i + 1] at fraction t, clamped to the grid's ends."""
    n = grid.size
    if x <= grid[0]:
        return 0, 0.0
    if x >= grid[n - 1]:
        return n - 2, 1.0
    i = 0
    while grid[i + 1] < x:
        i += 1
    return i, (x - grid[i]) / (grid[i + 1] - grid[i])


@njit(cache=True)
def needle_log_life(tables, clearance_um, log_scale):
    """ln of one needle bearing's life [h] (bilinear in the table; beyond the scale grid, the edge's
    slope extrapolates ln L linearly in ln s)."""
    i, t = _bracket(tables.clearance_um, clearance_um)
    ns = tables.log_scale.size
    j, u = _bracket(tables.log_scale, log_scale)
    if log_scale > tables.log_scale[ns - 1] or log_scale < tables.log_scale[0]:
        u = (log_scale - tables.log_scale[j]) / (tables.log_scale[j + 1] - tables.log_scale[j])
    a = tables.log_needle_life
    lo = a[i, j] + u * (a[i, j + 1] - a[i, j])
    hi = a[i + 1, j] + u * (a[i + 1, j + 1] - a[i + 1, j])
    return lo + t * (hi - lo)


@njit(nogil=True, cache=True)
def unit_life(unit, design, tables, scratch, figures, out):
    """The loop's figures (``chain.loop_figures`` into ``figures``, as ``unit.unit_hysteresis``) and
    the life outputs (module docstring) into out[0:LIFE_OUTPUTS] of one ElasticUnit."""
    c = design.chain
    g = tables.geometry
    translating = c.radial_stiffness_n_per_um < np.inf
    pins = prepare_pins_indexed(unit, c, translating, design.pin_laws, scratch.order)
    rollers = paired_rollers(unit.crank_clearance_um, design.roller_cos, c)
    state = new_state()
    loop_figures(LoopUnit(pins, rollers, max(unit.involute_backlash_rad, 0.0)), design.points, c, state, figures,
                 scratch.angles)
    st = state[0]
    start = (st.pins_start[POSITIVE], (st.pins_tangent_load_nm[POSITIVE], st.pins_tangent_stiffness[POSITIVE]))
    life, weakest, stress = _life_at(pins, unit, tables.torque_nm, start, c, tables, scratch)
    out[LIFE] = life
    out[WEAKEST] = weakest
    out[PIN_STRESS] = stress
    # the rated torque: life ~ (p0 + (1 - p0) T / T_R)^-beta through the life at T_R and at no torque (a preloaded
    # unit's pins load its bearings unloaded: p0 = (L_0 / L_R)^(-1/beta); a free unit's p0 = 0, a power law)
    beta = tables.life_exponent
    p0 = 0.0
    bounds = pins.contacts.bounds
    if bounds.hi < bounds.lo:  # preloaded: no rotation frees every pin
        life0 = _life_at(pins, unit, 0.0, (st.pins_start[POSITIVE], (np.nan, np.nan)), c, tables, scratch)[0]
        p0 = min((life0 / life) ** (-1.0 / beta), 1.0) if life0 < np.inf else 0.0
    target = (life / tables.nominal_life_h) ** (1.0 / beta) * tables.nominal_rated_torque_nm / tables.torque_nm
    if p0 >= 1.0 or target <= p0:
        out[RATED_TORQUE] = 0.0  # the preload alone takes the life below the rated life
    else:
        out[RATED_TORQUE] = tables.torque_nm * (target - p0) / (1.0 - p0)


@njit(nogil=True, cache=True)
def _life_at(pins, unit, torque_nm, start, c, tables, scratch):
    """(reducer life [h], weakest bearing's life [h], largest pin stress [MPa]) of a unit whose pins
    (``pins``, in closure order with scratch.order) are solved at the chain torque ``torque_nm``
    (module docstring), ``start``: (guess, (tangent load, tangent stiffness)) of ``solver.solve_pins``."""
    g = tables.geometry
    translating = c.radial_stiffness_n_per_um < np.inf
    x = solve_pins(pins, torque_nm, 1.0, start[0], c, start[1]).x
    cs = pins.contacts
    gaps = pins.translation.shifted_gaps_um if translating else cs.gaps
    discs, zp = scratch.forces.shape
    for d in range(discs):
        for j in range(zp):
            scratch.forces[d, j] = 0.0
    for i in range(gaps.size):
        delta = cs.levers[i] * x - gaps[i]
        if delta > 0.0:
            j = scratch.order[i]
            scratch.forces[j // zp, j - (j // zp) * zp] = law_force(delta, cs.law_a[i], c.law_b, c.law_n,
                                                                    cs.forces[i])[0]
    chi = unit.chi_rad
    disc_resultants(scratch.forces, chi, g, scratch.resultants)
    crank_bearing_loads(scratch.resultants, chi, g, scratch.bearing)
    pin_stresses_mpa(scratch.forces, chi, g, scratch.stress)
    stress = 0.0
    for d in range(discs):
        for j in range(zp):
            stress = max(stress, scratch.stress[d, j])
    cranks = g.cranks
    pitch = 2.0 * math.pi / g.pins
    total = 0.0
    weakest = np.inf
    for d in range(discs):
        s = 0.0
        for k in range(cranks):
            s += math.hypot(scratch.bearing[d, k, 0], scratch.bearing[d, k, 1]) ** LIFE_EXPONENT
        peq = (s / cranks) ** (1.0 / LIFE_EXPONENT)
        if peq <= 0.0:  # a disc that carries nothing (the other takes it all): its bearings never fail
            continue
        ref = _interp_periodic(tables.chi_grid_rad, tables.nominal_needle_peq[d], chi, pitch)
        life = math.exp(needle_log_life(tables, unit.crank_clearance_um, math.log(peq / ref)))
        total += cranks * life ** -WEIBULL_SLOPE
        weakest = min(weakest, life)
    if g.support_span_mm > 0.0:
        crank_torques_nmm(scratch.bearing, chi, g, scratch.torques)
        support_bearing_loads(scratch.bearing, scratch.torques, chi, g, scratch.support)
        for end in range(2):
            s = 0.0
            for k in range(cranks):
                s += math.hypot(scratch.support[k, end, 0], scratch.support[k, end, 1]) ** LIFE_EXPONENT
            peq = (s / cranks) ** (1.0 / LIFE_EXPONENT)
            if peq <= 0.0:
                continue
            ref = _interp_periodic(tables.chi_grid_rad, tables.nominal_support_peq[end], chi, pitch)
            life = math.exp(tables.log_support_life[end]) * (peq / ref) ** -LIFE_EXPONENT
            total += cranks * life ** -WEIBULL_SLOPE
            weakest = min(weakest, life)
    return (total ** (-1.0 / WEIBULL_SLOPE) if total > 0.0 else np.inf), weakest, stress


@njit(nogil=True, cache=True)
def evaluate_units_life(units, design, tables, out):
    """``unit_life`` of a batch of n units (an ElasticUnit batch) into out (3 + LIFE_OUTPUTS, n): lost
    motion, backlash, rigidity (as ``unit.evaluate_units``), then the life outputs."""
    discs, zp = units.gap_um.shape[1], units.gap_um.shape[2]
    scratch = life_scratch(discs, zp, tables.geometry.cranks)
    fig = np.empty(3 + 2 * N_ELEMENTS)
    life = np.empty(LIFE_OUTPUTS)
    for i in range(units.chi_rad.size):
        unit_life(ElasticUnit(units.gap_um[i], units.lever_um_per_rad[i], units.chi_rad[i],
                              units.involute_backlash_rad[i], units.crank_clearance_um[i]), design, tables, scratch,
                  fig, life)
        out[0, i] = fig[0]
        out[1, i] = fig[1]
        out[2, i] = fig[2]
        for q in range(LIFE_OUTPUTS):
            out[3 + q, i] = life[q]

