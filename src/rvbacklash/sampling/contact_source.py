"""Monte-Carlo of the contact model through the engine: a block source whose outputs are the
backlash of every unit [arcmin], the backlash of the units whose cycloid stage is free, and the
preload of the others [um].

Every catalog factor draws from a random stream of its own, and the crank angle of the
measurement from one more (``SeedSequence(seed, spawn_key=(*stream, block, factor))``): a
factor's values do not depend on the others' draws, so that a factor can be redrawn alone
(global sensitivity: a factor with per-pin or per-tooth draws is one group). What a unit draws
and how: ``sampling.unit_draw`` (docs/contact.md, "Part errors"). The crank angle is uniform over
one pin pitch in CRANK_STEPS steps (the geometry repeats every pin pitch).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.random import SeedSequence

from rvbacklash._numba import njit
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models.contact import (crank_step_angle_rad, mesh_table, pin_gaps, recorded_stage, stage_play,
                                      stage_work)
from rvbacklash.models.unit_errors import (Realization, UnitErrors, empty_unit, empty_units, realization_at,
                                           store_unit)
from rvbacklash.problem import Problem
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import states_from_generators, stream_states
from rvbacklash.sampling.unit_draw import (ERROR_MODELS, N_STREAMS, FactorLaws, draw_scratch, draw_unit,
                                           factor_laws)

CRANK_STEPS = 256  # crank-angle steps per pin pitch
# units per engine block (the engine's default is 65 536): ~40 ms of contact work per block (0.25 s
# of elastic work), so that both cores share even a short run and the pilot block is not a run of
# its own. Part of the numbers' contract (block b draws from spawn key (*stream, b)); the elastic
# and transmission-error sources cut the same blocks, so that they draw the same units.
BLOCK_UNITS = 4096


def block_streams(seed: int, block: int, stream: tuple[int, ...] = (), swap: tuple[int, ...] = (),
                  swap_stream: tuple[int, ...] = ()) -> np.ndarray:
    """The streams of block ``block`` (N_STREAMS, 4): one xoshiro256++ state per catalog factor and
    one for the crank angle (``fast_normals.stream_states``), each from
    ``SeedSequence(seed, spawn_key=(*stream, block, f))``. Factors listed in ``swap`` draw from
    ``swap_stream`` instead (a Sobol-type redraw)."""
    return stream_states([SeedSequence(seed, spawn_key=(*(swap_stream if f in swap else stream), block, f))
                          for f in range(N_STREAMS)])


class SavedUnits(NamedTuple):
    """The first units of a run, recorded as they were drawn (``--save-units``)."""

    errors: UnitErrors  # a batch: one unit per row
    crank_step: np.ndarray  # (k,) int64: the crank angle of the measurement, in CRANK_STEPS steps per pin pitch
    linear_arcmin: np.ndarray  # (k,) the involute and crank stages' lost motion (the linear model's sum)
    crank_clearance_um: np.ndarray  # (k,) the crank bearings' radial clearance drawn
    cycloid_stage: np.ndarray  # (k,) the cycloid stage as the kernel found it: its play [arcmin], or -preload [um]


def saved_units(k: int, g: ContactGeometry, planets: int = 0) -> SavedUnits:
    """Room for k saved units (``planets``: the kinematic errors' cranks, 0 when not drawn)."""
    return SavedUnits(empty_units(k, g.zp, g.zc, g.discs, planets), np.zeros(k, dtype=np.int64), np.empty(k),
                      np.empty(k), np.empty(k))


def saved_slice(saved: SavedUnits, start: int, stop: int) -> SavedUnits:
    """Units start to stop of a SavedUnits (views)."""
    return SavedUnits(UnitErrors(*(a[start:stop] for a in saved.errors)), *(a[start:stop] for a in saved[1:]))


def recorded_units(saved: dict[int, SavedUnits], crank_angle_rad) -> list[tuple[Realization, float, float]]:
    """The units of a run's SavedUnits (block -> its record), in run order: (errors at the crank angle
    ``crank_angle_rad(step)`` of their step, linear stages [arcmin], cycloid stage as recorded)."""
    return [(realization_at(rec.errors, s, crank_angle_rad(int(rec.crank_step[s])),
                            crank_clearance_um=float(rec.crank_clearance_um[s])),
             float(rec.linear_arcmin[s]), float(rec.cycloid_stage[s]))
            for b in sorted(saved) for rec in (saved[b],) for s in range(rec.crank_step.size)]


@njit(nogil=True, cache=True)
def save_unit(saved, s, unit, drawn, stage):
    """Record unit s of a run's first units: its errors, its UnitDraw and its cycloid stage."""
    store_unit(saved.errors, s, unit)
    saved.crank_step[s] = drawn.crank_step
    saved.linear_arcmin[s] = drawn.linear_arcmin
    saved.crank_clearance_um[s] = drawn.crank_clearance_um
    saved.cycloid_stage[s] = stage


@njit(nogil=True, cache=True)
def contact_block(streams, laws, stage, coef, out, saved):
    """Units drawn from ``streams`` with FactorLaws ``laws`` (StageGeometry ``stage``, ``coef``: the
    mesh_table at the crank-angle steps): out[0] backlash of every unit [arcmin], out[1] the same of
    the units whose cycloid stage is free (NaN if preloaded), out[2] preload [um] (NaN if free),
    one column per unit. The first units are recorded in ``saved`` (as many as it holds)."""
    unit = empty_unit(stage.zp, stage.zc, stage.discs, np.int64(0))  # no kinematic errors (not a literal 0: one
    #                                                                 compiled empty_unit for every kernel)
    scratch = draw_scratch(stage.zp, stage.zc)
    gaps, work = pin_gaps(stage.discs, stage.zp), stage_work(stage.discs, stage.zp)
    steps = coef.shape[0]
    play_too = steps > 0  # True, not as a literal: the elastic model's compiled stage_play serves (a literal
    #                       True, or the default, compiles a copy of that large function of its own)
    for s in range(out.shape[1]):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        play = stage_play(coef[drawn.crank_step], stage, unit, gaps, work, play_too)
        lin, cycloid = drawn.linear_arcmin, recorded_stage(play)
        if math.isnan(play.play_ccw_rad):  # preloaded: the stage adds no play
            out[0, s] = lin
            out[1, s] = np.nan
            out[2, s] = play.preload_um
        else:
            out[0, s] = lin + cycloid
            out[1, s] = out[0, s]
            out[2, s] = np.nan
        if s < saved.crank_step.size:
            save_unit(saved, s, unit, drawn, cycloid)


PRELOAD_OUTPUT = Output("preload", "um", "preload of the units whose cycloid stage is preloaded (deepest "
                        "interference)", conditional=True, hint_range=(0.0, 50.0))
CONTACT_OUTPUTS = (
    Output("backlash", "arcmin", "output backlash (rigid lost motion), every unit; a preloaded cycloid stage adds 0"),
    Output("backlash_free", "arcmin", "output backlash of the units whose cycloid stage is free", conditional=True),
    PRELOAD_OUTPUT,
)


def units_to_save(save_units: int, block_size: int, b: int, n: int) -> int:
    """How many of block b's n units are recorded: those among the run's first ``save_units``."""
    return min(max(save_units - b * block_size, 0), n)


@dataclass(frozen=True, eq=False)
class ContactBlockSource:
    """Block source of the engine for the contact model (methods: default, box-muller)."""

    seed: int
    stream: tuple[int, ...]
    geometry: ContactGeometry
    error_model: str
    laws: FactorLaws
    coef: np.ndarray  # mesh_table at the crank-angle steps
    save_units: int = 0  # record the errors of the first units of the run
    saved: dict = field(default_factory=dict)  # block -> its recorded SavedUnits (the first blocks)
    swap: tuple[int, ...] = ()  # factors drawn from ``swap_stream`` (Sobol redraws)
    swap_stream: tuple[int, ...] = ()
    outputs: tuple[Output, ...] = CONTACT_OUTPUTS
    block_size: int = BLOCK_UNITS

    def block(self, b: int, n: int) -> np.ndarray:
        """(3, n) outputs of block b (CONTACT_OUTPUTS)."""
        out = np.empty((len(self.outputs), n))
        saved = saved_units(units_to_save(self.save_units, self.block_size, b, n), self.geometry)
        contact_block(block_streams(self.seed, b, self.stream, self.swap, self.swap_stream), self.laws,
                      self.geometry.stage_geometry, self.coef, out, saved)
        if saved.crank_step.size:
            self.saved[b] = saved
        return out

    def crank_angle_rad(self, step: int) -> float:
        return crank_step_angle_rad(step, self.geometry.zp, self.coef.shape[0])

    def saved_units(self) -> list[tuple[Realization, float, float]]:
        """The recorded units, in run order: (errors, linear stages [arcmin], cycloid stage [arcmin]
        as the kernel found it, or -preload [um] when preloaded)."""
        return recorded_units(self.saved, self.crank_angle_rad)


def contact_source(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                   error_model: str | None = None, save_units: int = 0, swap: tuple[int, ...] = (),
                   swap_stream: tuple[int, ...] = ()) -> ContactBlockSource:
    """The contact model's block source. ``error_model`` overrides the design's ``[contact]``."""
    if method not in ("default", "box-muller"):
        raise InputError("method", method, "allowed with model 'contact': default, box-muller")
    if problem.correlated:
        raise InputError("correlation", "given", "the contact model draws independent per-pin errors; "
                                                 "remove [correlation] or use the linear model")
    model = error_model or problem.contact_errors.error_model
    if model not in ERROR_MODELS:
        raise InputError("error_model", model, f"allowed: {', '.join(ERROR_MODELS)}")
    g = problem.cycloid
    return ContactBlockSource(seed, tuple(stream), g, model, factor_laws(problem, model, method == "box-muller"),
                              crank_mesh_table(g), int(save_units), {}, tuple(swap), tuple(swap_stream))


@lru_cache(maxsize=8)
def crank_mesh_table(g: ContactGeometry) -> np.ndarray:
    """``models.contact.mesh_table`` at the CRANK_STEPS crank angles the units are drawn at,
    chi_s = 2 pi / z_p (s + 1/2) / CRANK_STEPS: the same for every run of a geometry, so built once
    per process (~10 ms, as long as 2000 contact units take on two threads: an allocation's
    candidates share it). Shared between runs: the kernels only read it."""
    return mesh_table(g, np.array([crank_step_angle_rad(s, g.zp, CRANK_STEPS) for s in range(CRANK_STEPS)]))


@dataclass(frozen=True, eq=False)
class ContactStreams:
    """The contact model as global sensitivity needs it (analysis.sensitivity_global.StreamModel):
    every catalog factor, and the crank angle, draws from a stream seeded by the generator it is
    given (``fast_normals.states_from_generators``)."""

    source: ContactBlockSource
    random: tuple[bool, ...]
    inputs: tuple[str, ...] = tuple(f.key for f in CATALOG) + ("crank_angle",)
    outputs: tuple[Output, ...] = CONTACT_OUTPUTS

    def block(self, generators, n: int) -> np.ndarray:
        s, g = self.source, self.source.geometry
        out = np.empty((len(self.outputs), n))
        contact_block(states_from_generators(generators), s.laws, g.stage_geometry, s.coef, out, saved_units(0, g))
        return out


def contact_streams(problem: Problem, error_model: str | None = None) -> ContactStreams:
    source = contact_source(problem, "default", 0, error_model=error_model)
    random = tuple(bool(x) for x in problem.random_mask) + (True,)
    return ContactStreams(source, random)
