"""The production run's life (docs/capacity.md, "Production run"): the per-design tables that
``models.elastic.unit_life`` reads each unit against (``LifeTables``), from the nominal unit's full
computation. Built once per design and kept in process and on disk (``mechanics.fe_cache``, keyed by
the design), so that a sweep or the next run does not build them again.
"""

from __future__ import annotations

import math

import numpy as np

from rvbacklash.analysis.capacity.life import RACEWAY_POINTS, bearing_speed_rpm
from rvbacklash.analysis.capacity.revolution import CrankAngles, load_geometry, revolution_loads
from rvbacklash.analysis.capacity.unit import UnitCapacity
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.mechanics.fe_cache import cached
from rvbacklash.models import ratings as rt
from rvbacklash.models.elastic import ElasticModel, nominal_realization, other_stages_nominal
from rvbacklash.models.elastic.loads import cycle_equivalent_lamina_loads, roller_set_approach_um
from rvbacklash.models.elastic.unit_life import LifeTables
from rvbacklash.problem import Problem

TABLE_VERSION = 1  # of the tables' method: cached results are keyed by it
TABLE_ANGLES = 12  # crank angles of the nominal unit's revolution (its life within 0.1 % of 64 angles: tests)
CHI_POINTS = 4  # nominal references per pin pitch of the crank angle (the units' angles lie in one pin pitch)
SCALE_GRID = np.log(np.geomspace(0.5, 2.0, 13))  # the needle cycle's load scale s, ln s
CLEARANCE_POINTS = 9


def life_tables(problem: Problem, model: ElasticModel) -> LifeTables:
    """The LifeTables of a design (module docstring): the nominal unit at TABLE_ANGLES crank angles,
    at its own rated torque's computation; the needle bearing's life over its nominal load cycle
    scaled by s at each clearance of the factor's zone; the nominal per-disc and per-end load means at
    CHI_POINTS crank angles of one pin pitch."""
    if model.structure is None:
        raise InputError("structure", None, "the production run's life needs the design's [structure] table (the "
                                            "crankshafts and their support bearings; docs/capacity.md)")
    zone = problem.zones[FACTOR_KEYS.index("crank_bearing_clearance")]
    inputs = {"design": problem.design.model_dump(mode="json"), "angles": TABLE_ANGLES, "chi": CHI_POINTS,
              "scale": SCALE_GRID.tolist(), "clearance_zone": [zone.lower_um, zone.upper_um],
              "points": CLEARANCE_POINTS}
    data = cached("capacity_life_tables", TABLE_VERSION, inputs, lambda: _compute(problem, model))
    return LifeTables(float(data["torque_nm"]), load_geometry(problem, model), np.array(data["chi_grid_rad"]),
                      np.array(data["nominal_needle_peq"]), np.array(data["nominal_support_peq"]),
                      np.array(data["clearance_um"]), np.array(data["log_scale"]), np.array(data["log_needle_life"]),
                      np.array(data["log_support_life"]), float(data["nominal_life_h"]),
                      float(data["nominal_rated_torque_nm"]), float(data["life_exponent"]))


def _peq(values: np.ndarray, axis: int) -> np.ndarray:
    return np.mean(values ** rt.ROLLER_LIFE_EXPONENT, axis=axis) ** (1.0 / rt.ROLLER_LIFE_EXPONENT)


def _compute(problem: Problem, model: ElasticModel) -> dict:
    cap = problem.design.capacity
    inv, clr = other_stages_nominal(problem)
    nominal = nominal_realization(problem)
    unit = UnitCapacity(problem, model, nominal, inv, clr, TABLE_ANGLES)
    t_r, n0 = unit.rated_torque_nm, cap.rated_output_speed_rpm
    life = unit.life_h(t_r, n0)
    t0 = unit.rated_torque()
    step = 0.01
    beta = -(math.log(unit.life_h(t0 * (1 + step), n0)) - math.log(unit.life_h(t0 * (1 - step), n0))) / \
        (math.log(1 + step) - math.log(1 - step))
    lives = {b.name: b for b in unit.lives(t_r, n0)}
    speed = bearing_speed_rpm(model, n0)
    # one needle bearing's cycle (disc 0, crank 0: the nominal's bearings carry the same cycle, shifted)
    loads = unit.loads(t_r)
    mag = loads.crank_bearing_load_magnitude_n[:, 0, 0]
    inner = np.ascontiguousarray(loads.crank_bearing_inner_angle_rad[:, 0, 0])
    outer = np.ascontiguousarray(loads.crank_bearing_outer_angle_rad[:, 0, 0])
    zone = problem.zones[FACTOR_KEYS.index("crank_bearing_clearance")]
    clearances = np.linspace(min(zone.lower_um, 0.0), max(zone.upper_um, 1e-3), CLEARANCE_POINTS)
    n_s = unit.needles.drop_um.size
    qi, qe = np.empty(n_s), np.empty(n_s)
    table = np.empty((clearances.size, SCALE_GRID.size))
    base = lives["needle d0 c0"]
    for i, g in enumerate(clearances):
        for j, ls in enumerate(SCALE_GRID):
            s = math.exp(ls)
            if unit.method == "iso281":
                table[i, j] = math.log(base.l10_h) - rt.ROLLER_LIFE_EXPONENT * ls
                continue
            approach = np.array([roller_set_approach_um(float(p) * s, float(g), unit.needles) for p in mag])
            cycle_equivalent_lamina_loads(approach, inner, float(g), unit.needles, RACEWAY_POINTS, qi)
            cycle_equivalent_lamina_loads(approach, outer, float(g), unit.needles, RACEWAY_POINTS, qe)
            mrev = rt.iso16281_reference_life_mrev(qi, qe, unit.needle_ratings.inner_lamina_n,
                                                   unit.needle_ratings.outer_lamina_n)
            table[i, j] = math.log(rt.life_hours(mrev, speed))
    # the nominal's per-disc and per-end means at the crank angles the units are drawn at (one pin pitch)
    pitch = 2.0 * math.pi / model.geometry.zp
    chis = pitch * (np.arange(CHI_POINTS) + 0.5) / CHI_POINTS
    needle_ref = np.empty((model.geometry.discs, CHI_POINTS))
    support_ref = np.empty((2, CHI_POINTS))
    for k, chi in enumerate(chis):
        at = CrankAngles(problem, model, nominal.with_(chi_rad=float(chi)), inv, clr, 1)
        one = revolution_loads(at, t_r, unit.geometry, unit.needles)
        needle_ref[:, k] = _peq(one.crank_bearing_load_magnitude_n[0], axis=1)
        support_ref[:, k] = _peq(one.support_bearing_load_magnitude_n[0], axis=0)
    return {"torque_nm": t_r, "chi_grid_rad": chis.tolist(), "nominal_needle_peq": needle_ref.tolist(),
            "nominal_support_peq": support_ref.tolist(), "clearance_um": clearances.tolist(),
            "log_scale": SCALE_GRID.tolist(), "log_needle_life": table.tolist(),
            "log_support_life": [math.log(lives["support c0 A"].l10_h), math.log(lives["support c0 B"].l10_h)],
            "nominal_life_h": life, "nominal_rated_torque_nm": t0, "life_exponent": beta}
