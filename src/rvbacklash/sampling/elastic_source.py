"""Monte-Carlo of the elastic hysteresis model through the engine (``simulate --model elastic``).

A block is two steps, kept apart on purpose:

1. **drawing** the units as the contact model draws them (``unit_draw.draw_unit``: the same
   per-factor streams, the same error model, the same numbers), each turned into its pin gaps and
   lever arms (discs x pins, ``models.contact.unit_gaps``), its crank angle, its involute-stage
   backlash and its crank-bearing clearance (``draw_units`` -> ``UnitBatch``), CHUNK units at a
   time;
2. **evaluating** them: ``models.elastic.evaluate_units`` (numba, nogil) turns each unit into its
   lost motion, backlash and torsional rigidity with the design's ``LoopDesign``.

Outputs: lost_motion [arcmin], backlash [arcmin], rigidity [nm_per_arcmin] (a spec on it is a
lower limit), and the contact model's preload [um] (NaN for a unit whose cycloid stage is free):
a spec on the lost motion alone would reward interference, which closes the play.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.interrupt import check_abandoned
from rvbacklash.models.contact import PinGaps, crank_step_angle_rad, recorded_stage, stage_play, stage_work
from rvbacklash.models.elastic import ElasticModel, LoopDesign, elastic_model, evaluate_units, loop_design, pin_law_table
from rvbacklash.models.elastic.unit_life import LIFE_OUTPUTS, LifeTables, evaluate_units_life
from rvbacklash.models.unit_errors import empty_unit
from rvbacklash.problem import Problem
from rvbacklash.sampling.contact_source import (BLOCK_UNITS, CRANK_STEPS, PRELOAD_OUTPUT, ContactBlockSource,
                                                SavedUnits, block_streams, contact_source, save_unit, saved_slice,
                                                saved_units, units_to_save)
from rvbacklash.sampling.chunked import draw_then_evaluate
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import states_from_generators
from rvbacklash.sampling.unit_draw import CRANK_CLEARANCE, draw_scratch, draw_unit
from rvbacklash.units import ARCMIN_PER_RAD


# the life outputs (issue 37; models/elastic/unit_life.py, docs/capacity.md), after the four above, when asked for
LIFE_OUTPUT_DEFS = (
    Output("life", "h", "reducer L10 at the rated torque and output speed (its bearings as a system; each unit read at "
                        "its crank angle against the nominal unit's revolution)", upper_limit=False,
           hint_range=(0.0, 2e4)),
    Output("weakest_bearing_life", "h", "L10 of the unit's weakest bearing at the rated torque and speed",
           upper_limit=False, hint_range=(0.0, 1e5)),
    Output("rated_torque", "nm", "derived rated torque: the reducer's L10 = the rated life at the rated output speed",
           upper_limit=False, hint_range=(0.0, 2000.0)),
    Output("max_pin_stress", "mpa", "largest pin-flank Hertz pressure at the rated torque (the unit's crank angle)",
           hint_range=(0.0, 3000.0)),
)


def elastic_outputs(model: ElasticModel, life: bool = False) -> tuple[Output, ...]:
    """The elastic model's outputs; with ``life``, the life outputs after them (LIFE_OUTPUT_DEFS)."""
    return _precision_outputs(model) + (LIFE_OUTPUT_DEFS if life else ())


def _precision_outputs(model: ElasticModel) -> tuple[Output, ...]:
    x = model.chain.measuring_fraction
    lo, hi = model.chain.rigidity_low, model.chain.rigidity_high
    return (
        Output("lost_motion", "arcmin", f"lost motion at ±{x * 100:g} % rated torque (test-bench definition)",
               hint_range=(0.0, 5.0)),
        Output("backlash", "arcmin", "backlash: width of the hysteresis loop at zero torque", hint_range=(0.0, 5.0)),
        Output("rigidity", "nm_per_arcmin", f"torsional rigidity, secant over {lo * 100:g}–{hi * 100:g} % rated torque",
               upper_limit=False, hint_range=(0.0, 1e4)),
        PRELOAD_OUTPUT,
    )


N_OUTPUTS = 4  # lost motion, backlash, rigidity, preload


class UnitBatch(NamedTuple):
    """n units as the evaluation takes them (C-contiguous float arrays): an ``ElasticUnit`` batch
    (models.elastic.evaluate_units reads these fields) and each unit's preload."""

    gap_um: np.ndarray  # (n, discs, z_p) free gap of each pin at zero rotation [um]
    lever_um_per_rad: np.ndarray  # (n, discs, z_p) signed lever about the disc centre [um/rad]
    chi_rad: np.ndarray  # (n,) crank angle of the measurement
    involute_backlash_rad: np.ndarray  # (n,) involute stage at the output [rad], >= 0
    crank_clearance_um: np.ndarray  # (n,) radial clearance of the crank needle bearings [um]
    preload_um: np.ndarray  # (n,) the cycloid stage's preload (contact model), NaN when it is free [um]

    def take(self, index) -> "UnitBatch":
        """The units at ``index`` (an index array or a slice), as a batch of their own."""
        return UnitBatch(*(np.ascontiguousarray(a[index]) for a in self))


def empty_batch(n: int, discs: int, zp: int) -> UnitBatch:
    return UnitBatch(np.empty((n, discs, zp)), np.empty((n, discs, zp)), np.empty(n), np.empty(n), np.empty(n),
                     np.empty(n))


@njit(nogil=True, cache=True)
def draw_units_kernel(streams, laws, stage, coef, batch, saved):
    """Units drawn as the contact model draws them (unit_draw.draw_unit with FactorLaws ``laws``,
    same streams, same numbers) into ``batch`` (UnitBatch, one row per unit), each turned into the
    elastic model's arrays: every pin's gap and lever (models.contact.unit_gaps), the crank angle,
    the involute stage's backlash at the output [rad] (the stage-1 factors' linear sum, >= 0), the
    crank-bearing clearance [um] and the cycloid stage's preload (models.contact.stage_play; NaN
    when free) [um]. The first units are recorded in ``saved`` (SavedUnits) as the contact model
    records them (cycloid stage: its rigid play [arcmin], or -preload [um])."""
    unit = empty_unit(stage.zp, stage.zc, stage.discs, np.int64(0))  # no kinematic errors (not a literal 0: one
    #                                                                 compiled empty_unit for every kernel)
    scratch = draw_scratch(stage.zp, stage.zc)
    work = stage_work(stage.discs, stage.zp)
    steps = coef.shape[0]
    sens_crank = 0.0  # the crank bearings' clearance's share of the linear stages [arcmin/um]
    for m in range(laws.linear_factors.size):
        if laws.linear_factors[m] == CRANK_CLEARANCE:
            sens_crank = laws.linear_sens_arcmin_per_um[m]
    for s in range(batch.chi_rad.size):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        batch.chi_rad[s] = crank_step_angle_rad(drawn.crank_step, stage.zp, steps)
        batch.involute_backlash_rad[s] = max(drawn.linear_arcmin - sens_crank * drawn.crank_clearance_um,
                                             0.0) / ARCMIN_PER_RAD
        batch.crank_clearance_um[s] = drawn.crank_clearance_um
        # the gaps and levers (unit_gaps) land in the unit's rows; the rigid play of a free unit is
        # not needed (only by a recorded unit)
        save = s < saved.crank_step.size
        play = stage_play(coef[drawn.crank_step], stage, unit, PinGaps(batch.gap_um[s], batch.lever_um_per_rad[s]),
                          work, save)
        batch.preload_um[s] = play.preload_um if math.isnan(play.play_ccw_rad) else np.nan
        if save:
            save_unit(saved, s, unit, drawn, recorded_stage(play))


CHUNK = 4096  # units drawn and evaluated at a time within a block (bounded memory)
EVAL_THREADS = 2  # evaluation threads per block (the kernel is nogil)


def draw_units(source: ContactBlockSource, streams: np.ndarray, n: int, saved: SavedUnits | None = None) -> UnitBatch:
    """n units from ``streams`` (contact_source.block_streams) with the contact source's laws."""
    g = source.geometry
    batch = empty_batch(n, g.discs, g.zp)
    draw_units_kernel(streams, source.laws, g.stage_geometry, source.coef, batch,
                      saved if saved is not None else saved_units(0, g))
    return batch


def evaluate_batch(design: LoopDesign, units: UnitBatch, life: LifeTables | None = None) -> np.ndarray:
    """(4, n): lost motion [arcmin], backlash [arcmin], rigidity [N m/arcmin], preload [um] (NaN
    when free) of every unit, with the design's LoopDesign (``loop_design``); with ``life``
    (LifeTables), (4 + LIFE_OUTPUTS, n): the life outputs after them (``unit_life.evaluate_units_life``)."""
    n = units.chi_rad.size
    if life is None:
        out = np.empty((N_OUTPUTS, n))
        evaluate_units(units, design, out[:3])
        out[3] = units.preload_um
        return out
    out = np.empty((N_OUTPUTS + LIFE_OUTPUTS, n))
    figures = np.empty((3 + LIFE_OUTPUTS, n))
    evaluate_units_life(units, design, life, figures)
    out[:3] = figures[:3]
    out[3] = units.preload_um
    out[N_OUTPUTS:] = figures[3:]
    return out


@dataclass(frozen=True, eq=False)
class ElasticBlockSource:
    """Block source of the engine for the elastic model (method: default): the contact model's
    units (same streams, same numbers), each evaluated on its loop."""

    contact: ContactBlockSource  # draws the units: laws, error model, crank-angle table
    model: ElasticModel
    design: LoopDesign  # what every unit's loop reads (with every pin's contact law at every crank step)
    outputs: tuple[Output, ...]
    save_units: int = 0
    block_size: int = BLOCK_UNITS
    life: LifeTables | None = None  # the life outputs' tables (None: none asked for)

    @property
    def output_warnings(self) -> dict[str, str]:
        """What an output's figures need said beside them, by output (simulation.simulate reads it):
        the lost motion read in the stick band when friction reaches x T_R (docs/elastic.md)."""
        from rvbacklash.models.elastic.chain import stick_band_warning

        w = stick_band_warning(self.model.chain)
        return {"lost_motion": w} if w else {}

    def block(self, b: int, n: int) -> np.ndarray:
        """(4, n) outputs of block b (``elastic_outputs``; with life, 4 + LIFE_OUTPUTS)."""
        c = self.contact
        streams = block_streams(c.seed, b, c.stream, c.swap, c.swap_stream)
        out = np.empty((len(self.outputs), n))
        keep = units_to_save(self.save_units, self.block_size, b, n)
        saved = saved_units(keep, c.geometry)

        def evaluate(start: int, units: UnitBatch) -> None:
            out[:, start:start + units.chi_rad.size] = evaluate_batch(self.design, units, self.life)

        def draw(start: int, m: int) -> UnitBatch:
            return draw_units(c, streams, m, saved_slice(saved, start, start + m) if start < keep else None)

        # Drawing is serial (one stream per factor) and ~5x faster than evaluating: a block larger
        # than a chunk (a direct call) is evaluated by a small pool while the next chunk is drawn.
        # Every chunk fills its own slice: the numbers do not depend on the pool.
        draw_then_evaluate(n, CHUNK, EVAL_THREADS, draw, evaluate)
        if keep:
            c.saved[b] = saved
        return out

    def saved_units(self) -> list:
        """The first ``save_units`` units of the run, as the contact model saves them."""
        return self.contact.saved_units()


def elastic_source(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                   save_units: int = 0, life: LifeTables | None = None) -> ElasticBlockSource:
    if method != "default":
        raise InputError("method", method, "allowed with model 'elastic': default")
    if problem.correlated:
        raise InputError("correlation", "given", "the elastic model draws independent per-pin errors; "
                                                 "remove [correlation] or use the linear model")
    model = elastic_model(problem)
    contact = contact_source(problem, "default", seed, stream)
    return ElasticBlockSource(contact, model, loop_design(model, design_pin_laws(model)),
                              elastic_outputs(model, life is not None), int(save_units), life=life)


def design_pin_laws(model: ElasticModel) -> np.ndarray:
    """Every pin's contact law at each crank-angle step the contact model draws (pin_law_table:
    CRANK_STEPS x pins, ~20 000 laws computed once instead of ~60 per unit)."""
    return pin_law_table(model.chain, model.geometry.zp, model.geometry.discs, CRANK_STEPS)


def sample_units(problem: Problem, seed: int, n: int, stream: tuple[int, ...] = (1,)) -> UnitBatch:
    """n units of block 0 of ``stream`` of ``seed``, drawn as the Monte-Carlo draws them."""
    c = contact_source(problem, "default", seed, stream)
    return draw_units(c, block_streams(c.seed, 0, c.stream), n)


@dataclass(frozen=True, eq=False)
class ElasticStreams:
    """The elastic model as global sensitivity needs it (analysis.sensitivity_global.StreamModel):
    every catalog factor, and the crank angle, draws from the generator it is given."""

    source: ElasticBlockSource
    random: tuple[bool, ...]
    inputs: tuple[str, ...] = tuple(FACTOR_KEYS) + ("crank_angle",)

    @property
    def outputs(self) -> tuple[Output, ...]:
        return self.source.outputs

    def block(self, generators, n: int) -> np.ndarray:
        streams = states_from_generators(generators)
        out = np.empty((len(self.source.outputs), n))
        for start in range(0, n, CHUNK):
            check_abandoned()  # a workbench job's stop drops the block between two chunks
            m = min(CHUNK, n - start)
            out[:, start:start + m] = evaluate_batch(self.source.design, draw_units(self.source.contact, streams, m),
                                                     self.source.life)
        return out


def elastic_streams(problem: Problem, life: LifeTables | None = None) -> ElasticStreams:
    """The elastic model for global sensitivity; with ``life`` (LifeTables) its life outputs too."""
    return ElasticStreams(elastic_source(problem, "default", 0, life=life),
                          tuple(bool(x) for x in problem.random_mask) + (True,))
