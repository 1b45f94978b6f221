"""The share of a production run that keeps its precision for some hours of a duty cycle: the yield
function of an allocation on the accuracy life (``allocate --spec-accuracy-life-h``; docs/service-life.md,
"Allocating on the accuracy life").

A candidate design is read as ``service-life`` reads it: its nominal unit stepped through the hours
(``stepping.nominal_trajectory``, to [0, hours]), its production run's units along that trajectory, each
with its own wear (``production.units_lost_motion``); a unit counts when its lost motion is within the
spec at every time of the trajectory up to ``hours`` (its accuracy life reaches them: ``ProductionLife.
accuracy_life_yield`` of ``service-life --hours 0,H`` with the same seed, units and stream, bit for bit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rvbacklash.analysis.service_life.datasheet import UNIT_WEAR
from rvbacklash.analysis.service_life.production import accuracy_life_h, units_lost_motion
from rvbacklash.analysis.service_life.stepping import DEFAULT_ANGLES, DEFAULT_STEP_FRACTION, MAX_HOURS, \
    nominal_trajectory
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import elastic_model
from rvbacklash.problem import Problem

SERVICE_LIFE_STREAM = (1,)  # the spawn key `service-life` draws its units from (production.units_lost_motion)


@dataclass(frozen=True)
class AccuracyLifeTarget:
    """What a unit must keep: lost motion <= ``spec_lost_motion_arcmin`` for ``hours`` of ``cycle``, read
    with the service life's ``angles``, ``step_fraction`` and ``unit_wear`` (picklable: a task of the
    allocation's executor)."""

    cycle: DutyCycle
    hours: float
    spec_lost_motion_arcmin: float
    angles: int = DEFAULT_ANGLES
    step_fraction: float = DEFAULT_STEP_FRACTION
    unit_wear: str = "own"

    def check(self) -> "AccuracyLifeTarget":
        """Itself, or the one-line InputError of its first bad field (the API's parameter names)."""
        h = self.hours
        if isinstance(h, bool) or not isinstance(h, (int, float)) or not (math.isfinite(h) and 0.0 < h <= MAX_HOURS):
            raise InputError("spec_accuracy_life_h", h, f"allowed: a number of hours > 0 and <= {MAX_HOURS:g}")
        s = self.spec_lost_motion_arcmin
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not (math.isfinite(s) and s > 0.0):
            raise InputError("spec_lost_motion_arcmin", s, "allowed: a number > 0 [arcmin]")
        if isinstance(self.angles, bool) or not isinstance(self.angles, int) or not 1 <= self.angles <= 4096:
            raise InputError("angles", self.angles, "allowed: a whole number of crank angles from 1 to 4096")
        f = self.step_fraction
        if isinstance(f, bool) or not isinstance(f, (int, float)) or not 0.0 < f <= 1.0:
            raise InputError("step_fraction", f, "allowed: a number in (0, 1]")
        if self.unit_wear not in UNIT_WEAR:
            raise InputError("unit_wear", self.unit_wear, f"allowed: {', '.join(UNIT_WEAR)}")
        return self

    def text(self) -> str:
        return f"accuracy life >= {self.hours:g} h of {Path(self.cycle.source).name} at lost motion <= " \
               f"{self.spec_lost_motion_arcmin:g} arcmin"


def accuracy_life_yield(problem: Problem, target: AccuracyLifeTarget, *, samples: int, seed: int,
                        stream: tuple[int, ...] = SERVICE_LIFE_STREAM) -> tuple[Proportion | None, bool]:
    """(the share of ``samples`` units (seed ``seed``, ``stream``) whose accuracy life reaches
    ``target.hours``, with its 95 % Wilson interval; partial): module docstring. None when stopped
    before any unit was read."""
    if problem.design.elastic is None:
        raise InputError("elastic", None, "the accuracy life needs the design's [elastic] table (docs/elastic.md)")
    model = elastic_model(problem)
    tr = nominal_trajectory(problem, target.cycle, [0.0, float(target.hours)], angles=target.angles,
                            step_fraction=target.step_fraction, model=model)
    if tr.partial:
        return None, True
    lm, done, partial = units_lost_motion(problem, tr, samples=samples, seed=seed, model=model,
                                          own_wear=target.unit_wear == "own", stream=stream)
    if not done:
        return None, True
    life = accuracy_life_h(np.array(tr.hours), lm, float(target.spec_lost_motion_arcmin))
    return Proportion.sampled(int(np.isinf(life).sum()), done), partial
