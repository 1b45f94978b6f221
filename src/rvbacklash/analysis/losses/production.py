"""The efficiency of every unit of a production run (docs/efficiency.md, "Per unit"): units drawn as
the elastic model's production run draws them (``simulate(..., model="elastic", save_units=N)``: the same
seed, the same units), each followed through K crank angles of its output revolution
(``LossModel`` with the unit's errors: its pins' forces, so its flanks' and bearings' loads), its
efficiency and input torque at the rated point; their distribution and the yield against a spec
(the efficiency's lower limit).
"""

from __future__ import annotations

import math

import numpy as np

from rvbacklash.analysis.losses.efficiency import DEFAULT_ANGLES, LossModel
from rvbacklash.analysis.losses.run_results import EfficiencyRun, RunAtTorque, UnitAtTorque, UnitEfficiency
from rvbacklash.errors import InputError
from rvbacklash.problem import Problem

MAX_UNITS = 10_000


def check_run(units: int, spec_min_efficiency: float | None) -> None:
    """A production run's parameters (0 units: no run), before any work."""
    if isinstance(units, bool) or not isinstance(units, int) or not 0 <= units <= MAX_UNITS:
        raise InputError("samples", units, f"allowed: a whole number of units from 1 to {MAX_UNITS} (0: none)")
    if spec_min_efficiency is not None and not (0.0 < spec_min_efficiency < 1.0):
        raise InputError("spec_min_efficiency", spec_min_efficiency, "allowed: a number between 0 and 1")


def _distribution(torque_nm: float, eff: np.ndarray, spec: float | None) -> RunAtTorque:
    return RunAtTorque(float(torque_nm), float(eff.mean()), float(eff.std(ddof=1)) if eff.size > 1 else 0.0,
                       float(eff.min()), float(np.median(eff)), float(eff.max()),
                       None if spec is None else float(np.mean(eff >= spec)))


def efficiency_run(problem: Problem, *, units: int, seed: int = 0, angles: int = DEFAULT_ANGLES,
                   temperature_c: float | None = None, output_speed_rpm: float | None = None,
                   spec_min_efficiency: float | None = None, torque_fractions=(), progress=None) -> EfficiencyRun:
    """The EfficiencyRun of ``units`` units of the elastic model's production run with ``seed``;
    ``torque_fractions`` (of the rated torque, each in (0, 1]): also every unit's efficiency at those output
    torques (the rated speed and temperature; each a further pass of its K crank angles) and their
    distribution per torque (the yield against ``spec_min_efficiency`` at each)."""
    from rvbacklash.analysis.simulation import simulate

    check_run(units, spec_min_efficiency)
    fractions = tuple(float(f) for f in torque_fractions)
    if any(not (math.isfinite(f) and 0.0 < f <= 1.0) for f in fractions):
        raise InputError("torque_fractions", list(torque_fractions), "allowed: fractions of the rated torque in (0, 1]")
    if units < 1:
        raise InputError("samples", units, f"allowed: a whole number of units from 1 to {MAX_UNITS}")
    lube = problem.design.lubrication
    temp = lube.temperature_c if temperature_c is None else float(temperature_c)
    n0 = problem.design.capacity.rated_output_speed_rpm if output_speed_rpm is None else float(output_speed_rpm)
    nominal = LossModel(problem, angles)
    t_r = nominal.rated_torque_nm
    nominal_eff = nominal.point(t_r, n0, temp).efficiency
    sim = simulate(problem, model="elastic", samples=units, seed=seed, save_units=units, workers=1)
    rows, cells = [], []
    for i, (r, _, stage) in enumerate(sim.units):
        lm = LossModel(problem, angles, realization=r, crank_clearance_um=r.crank_clearance_um, model=nominal.model)
        b = lm.point(t_r, n0, temp)
        play, preload = (math.nan, -stage) if stage < 0.0 else (stage, 0.0)  # models.contact.recorded_stage
        rows.append(UnitEfficiency(i, float(b.efficiency), float(b.input_torque_nm), b.total_loss_w,
                                   b.loss_w[0] + b.loss_w[1], float(play), float(preload)))
        for f in fractions:
            e = b.efficiency if f == 1.0 else lm.point(f * t_r, n0, temp).efficiency
            cells.append(UnitAtTorque(i, f * t_r, float(e)))
        if progress is not None:
            progress(i + 1)
    eff = np.array([u.efficiency for u in rows])
    y = None if spec_min_efficiency is None else float(np.mean(eff >= spec_min_efficiency))
    return EfficiencyRun(len(rows), seed, angles, t_r, n0, temp, float(eff.mean()),
                         float(eff.std(ddof=1)) if eff.size > 1 else 0.0, float(eff.min()), float(np.median(eff)),
                         float(eff.max()), spec_min_efficiency, y, float(nominal_eff), tuple(rows),
                         tuple(_distribution(f * t_r, np.array([c.efficiency for c in cells[k::len(fractions)]]),
                                             spec_min_efficiency) for k, f in enumerate(fractions)),
                         tuple(cells))
