"""Which tolerance buys hours: Sobol indices of the accuracy life (docs/service-life.md, "Which
tolerance buys hours"), by the project's global sensitivity (``analysis.sensitivity_global``: every
factor group draws from its own stream, Saltelli/Jansen estimators, bootstrap intervals).

The model: each unit of the elastic model's production run (the same draws as ``sensitivity --model
elastic``), worn along the nominal unit's trajectory with its own wear (``units.worn_units``), read at
every step; its accuracy life (``production.accuracy_life_h``) CENSORED at the last hour (a unit still
in spec counts as lasting the last hour: Sobol indices need a finite output of every unit); a unit out
of spec at 0 h has life 0. The indices then say which groups' variance moves the (censored) life.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from rvbacklash.analysis.service_life.production import accuracy_life_h, step_designs
from rvbacklash.analysis.service_life.stepping import Trajectory
from rvbacklash.analysis.service_life.units import NominalAtAngles, worn_units
from rvbacklash.models.elastic import evaluate_units
from rvbacklash.problem import Problem
from rvbacklash.sampling.elastic_source import ElasticStreams, draw_units, elastic_streams
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import states_from_generators

ACCURACY_LIFE = Output("accuracy_life", "h", "hours of the duty cycle until the lost motion exceeds the spec, "
                                             "censored at the last hour", upper_limit=False)
CHUNK = 2048


@dataclass(frozen=True, eq=False)
class AccuracyLifeStreams:
    """The accuracy life as a StreamModel (analysis.sensitivity_global): the elastic model's inputs."""

    problem: Problem
    streams: ElasticStreams
    trajectory: Trajectory
    designs: tuple
    spec_lost_motion_arcmin: float
    nominal: NominalAtAngles  # the nominal unit at the units' crank angles, shared by the blocks
    name: str = "elastic accuracy life"

    @property
    def inputs(self) -> tuple[str, ...]:
        return self.streams.inputs

    @property
    def random(self) -> tuple[bool, ...]:
        return self.streams.random

    @property
    def outputs(self) -> tuple[Output, ...]:
        return (ACCURACY_LIFE,)

    def block(self, generators: Sequence, n: int) -> np.ndarray:
        states = states_from_generators(generators)
        times = np.array(self.trajectory.hours)
        out = np.empty((1, n))
        nominal = self.nominal
        for start in range(0, n, CHUNK):
            m = min(CHUNK, n - start)
            chunk = draw_units(self.streams.source.contact, states, m)
            lm = np.empty((times.size, m))
            fig = np.empty((3, m))
            for k, worn in worn_units(chunk, self.trajectory, self.designs, nominal):
                evaluate_units(worn, self.designs[k], fig)
                lm[k] = fig[0]
            out[0, start:start + m] = np.minimum(accuracy_life_h(times, lm, self.spec_lost_motion_arcmin), times[-1])
        return out


def accuracy_life_streams(problem: Problem, trajectory: Trajectory, spec_lost_motion_arcmin: float,
                          model) -> AccuracyLifeStreams:
    """The AccuracyLifeStreams of a design along the nominal ``trajectory`` (its elastic ``model``)."""
    return AccuracyLifeStreams(problem, elastic_streams(problem), trajectory,
                               tuple(step_designs(problem, trajectory, model)), float(spec_lost_motion_arcmin),
                               NominalAtAngles(problem))
