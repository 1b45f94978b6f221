"""Monte-Carlo of the elastic hysteresis model through the engine (``simulate --model elastic``).

A block is two steps, kept apart on purpose:

1. **drawing** the units as the contact model draws them (``contact_source.draw_unit``: the same
   per-factor streams, the same error model, the same numbers), each turned into its pin gaps and
   lever arms (discs x pins, ``models.contact.unit_gaps``), its crank angle, its involute-stage
   backlash and its crank-bearing clearance (``draw_units`` -> ``UnitBatch``), CHUNK units at a
   time;
2. **evaluating** them: ``models.elastic.evaluate_units`` (numba, nogil) turns each unit into its
   lost motion, backlash and torsional rigidity.

Outputs: lost_motion [arcmin], backlash [arcmin], rigidity [nm_per_arcmin] (a spec on it is a
lower limit), and the contact model's preload [um] (NaN for a unit whose cycloid stage is free):
a spec on the lost motion alone would reward interference, which closes the play.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import FACTOR_KEYS
from rvbacklash.models.contact import stage_play
from rvbacklash.models.elastic import ElasticModel, elastic_model, evaluate_units, pin_law_table
from rvbacklash.problem import Problem
from rvbacklash.sampling.contact_source import (BLOCK_UNITS, CRANK_STEPS, PRELOAD_OUTPUT, STAGE2_ORDER,
                                                ContactBlockSource, block_streams, contact_source, draw_unit,
                                                save_unit, save_width, unit_scratch, units_to_save)
from rvbacklash.sampling.chunked import draw_then_evaluate
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import states_from_generators
from rvbacklash.units import ARCMIN_PER_RAD

IDX = {k: i for i, k in enumerate(FACTOR_KEYS)}


def elastic_outputs(model: ElasticModel) -> tuple[Output, ...]:
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


@dataclass(frozen=True)
class UnitBatch:
    """n units as the evaluation takes them (C-contiguous float arrays)."""

    gap_um: np.ndarray  # (n, discs, z_p) free gap of each pin at zero rotation [um]
    lever_um_per_rad: np.ndarray  # (n, discs, z_p) signed lever about the disc centre [um/rad]
    chi_rad: np.ndarray  # (n,) crank angle of the measurement
    involute_backlash_rad: np.ndarray  # (n,) involute stage at the output [rad], >= 0
    crank_clearance_um: np.ndarray  # (n,) radial clearance of the crank needle bearings [um]
    preload_um: np.ndarray  # (n,) the cycloid stage's preload (contact model), NaN when it is free [um]

    def take(self, index) -> "UnitBatch":
        """The units at ``index`` (an index array or a slice), as a batch of their own."""
        return UnitBatch(*(np.ascontiguousarray(getattr(self, f.name)[index]) for f in fields(self)))


@njit(nogil=True, cache=True)
def draw_units_kernel(streams, n, long_wave, codes, params, tables, harmonics, linear_idx, linear_sens, idx,
                      a, rp, zc, zp, discs, azc_um, coef, gap_out, lever_out, chi_out, inv_out, crank_out, preload_out,
                      save):
    """n units drawn as the contact model draws them (contact_source.draw_unit, same streams, same
    numbers), each turned into the elastic model's arrays: every pin's gap and lever
    (models.contact.unit_gaps), the crank angle, the involute stage's backlash at the output [rad]
    (the stage-1 factors' linear sum, >= 0), the crank-bearing clearance [um] and the cycloid
    stage's preload (models.contact.stage_play; NaN when free) [um]. The first save.shape[0] units
    are recorded as the contact model records them (cycloid stage: its rigid play [arcmin], or
    -preload [um])."""
    sc = unit_scratch(zp, zc, discs)
    dr, dt, rho, cl, teeth, eq, md, ux, uy, da = sc[:10]
    work, res = sc[19], sc[20]
    steps = coef.shape[0]
    sens_crank = linear_sens[linear_sens.size - 1]
    bm = n < 0  # False, but not a literal: draw_unit then compiles once for all the kernels
    for s in range(n):
        step, lin, crank, eq0, md0 = draw_unit(streams, bm, long_wave, codes, params, tables, harmonics, linear_idx,
                                               linear_sens, idx, zp, zc, discs, steps, sc)
        chi = 2.0 * math.pi / zp * (step + 0.5) / steps
        chi_out[s] = chi
        inv_out[s] = max(lin - sens_crank * crank, 0.0) / ARCMIN_PER_RAD
        crank_out[s] = crank
        # the gaps and levers (unit_gaps) land in the unit's rows; the rigid play of a free unit is
        # not needed (only by a recorded unit)
        stage_play(coef[step], a, rp, zc, zp, discs, azc_um, dr, dt, rho, cl, teeth, eq, md, ux, uy, da,
                   gap_out[s], lever_out[s], work, res, s < save.shape[0])
        preload_out[s] = res[2] if math.isnan(res[0]) else np.nan
        if s < save.shape[0]:
            stage = -res[2] if math.isnan(res[0]) else (res[0] + res[1]) * ARCMIN_PER_RAD
            save_unit(save[s], step, lin, eq0, md0, sc, zp, zc, discs, stage, crank)


CHUNK = 4096  # units drawn and evaluated at a time within a block (bounded memory)
EVAL_THREADS = 2  # evaluation threads per block (the kernel is nogil)


def draw_units(source: ContactBlockSource, streams: tuple, n: int, save: np.ndarray | None = None) -> UnitBatch:
    """n units from ``streams`` (contact_source.block_streams) with the contact source's laws."""
    g = source.geometry
    gap = np.empty((n, g.discs, g.zp))
    lever = np.empty((n, g.discs, g.zp))
    chi, inv, crank, preload = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    draw_units_kernel(streams, n, source.error_model == "long_wave", source.codes, source.params, source.ppf_tables,
                      source.harmonics, source.linear_idx, source.linear_sens, np.array([IDX[k] for k in STAGE2_ORDER]),
                      g.a_mm, g.rp_mm, g.zc, g.zp, g.discs, g.pitch_radius_um, source.coef, gap, lever, chi, inv, crank,
                      preload, save if save is not None else np.empty((0, save_width(g))))
    return UnitBatch(gap, lever, chi, inv, crank, preload)


def evaluate_batch(model: ElasticModel, units: UnitBatch, pin_laws: np.ndarray | None = None) -> np.ndarray:
    """(4, n): lost motion [arcmin], backlash [arcmin], rigidity [N m/arcmin], preload [um] (NaN
    when free) of every unit. ``pin_laws``: the design's ``pin_law_table`` at the contact model's
    crank angles (``design_pin_laws``; None: each unit's contact laws computed, the same numbers)."""
    out = np.empty((N_OUTPUTS, units.chi_rad.size))
    evaluate_units(units.gap_um, units.lever_um_per_rad, units.chi_rad, units.involute_backlash_rad,
                   units.crank_clearance_um, model.chain, model.roller_cos, out[:3], pin_laws)
    out[3] = units.preload_um
    return out


@dataclass(frozen=True, eq=False)
class ElasticBlockSource:
    """Block source of the engine for the elastic model (method: default): the contact model's
    units (same streams, same numbers), each evaluated on its loop."""

    contact: ContactBlockSource  # draws the units: laws, error model, crank-angle table
    model: ElasticModel
    outputs: tuple[Output, ...]
    save_units: int = 0
    block_size: int = BLOCK_UNITS
    pin_laws: np.ndarray | None = None  # design_pin_laws: every pin's contact law at every crank step

    def block(self, b: int, n: int) -> np.ndarray:
        """(4, n) outputs of block b (``elastic_outputs``)."""
        c = self.contact
        streams = block_streams(c.seed, b, c.stream, c.swap, c.swap_stream)
        out = np.empty((N_OUTPUTS, n))
        keep = units_to_save(self.save_units, self.block_size, b, n)
        save = np.empty((keep, save_width(c.geometry)))

        def evaluate(start: int, units: UnitBatch) -> None:
            out[:, start:start + units.chi_rad.size] = evaluate_batch(self.model, units, self.pin_laws)

        def draw(start: int, m: int) -> UnitBatch:
            return draw_units(c, streams, m, save[start:start + m] if start < keep else None)

        # Drawing is serial (one stream per factor) and ~5x faster than evaluating: a block larger
        # than a chunk (a direct call) is evaluated by a small pool while the next chunk is drawn.
        # Every chunk fills its own slice: the numbers do not depend on the pool.
        draw_then_evaluate(n, CHUNK, EVAL_THREADS, draw, evaluate)
        if keep:
            c.saved[b] = save
        return out

    def saved_units(self) -> list:
        """The first ``save_units`` units of the run, as the contact model saves them."""
        return self.contact.saved_units()


def elastic_source(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                   save_units: int = 0) -> ElasticBlockSource:
    if method != "default":
        raise InputError("method", method, "allowed with model 'elastic': default")
    if problem.correlated:
        raise InputError("correlation", "given", "the elastic model draws independent per-pin errors; "
                                                 "remove [correlation] or use the linear model")
    model = elastic_model(problem)
    contact = contact_source(problem, "default", seed, stream)
    return ElasticBlockSource(contact, model, elastic_outputs(model), int(save_units),
                              pin_laws=design_pin_laws(model))


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
        out = np.empty((N_OUTPUTS, n))
        for start in range(0, n, CHUNK):
            m = min(CHUNK, n - start)
            out[:, start:start + m] = evaluate_batch(self.source.model, draw_units(self.source.contact, streams, m),
                                                     self.source.pin_laws)
        return out


def elastic_streams(problem: Problem) -> ElasticStreams:
    return ElasticStreams(elastic_source(problem, "default", 0), tuple(bool(x) for x in problem.random_mask) + (True,))
