"""The production run with selective assembly: the elastic model's block source, each unit drawn as
the random run draws it (same streams, same numbers), then its pins and needle rollers taken from
the classes the rules pick (``rules``), then evaluated on its loop.

Common random numbers: a unit of the selected run is the unit of the random run with the same seed,
its selected parts replaced by the parts of their class at the same quantile, so that the two yields
differ by what selection does and not by sampling. The measurement errors draw from a stream of
their own (``SELECTION_STREAM``): the units' streams are untouched, and one class of each part is the
random run bit for bit (no part is replaced).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.random import SeedSequence

from rvbacklash._numba import njit
from rvbacklash.analysis.selection.classes import ClassTable, Selection, class_table, factor_law
from rvbacklash.analysis.selection.rules import in_class_um, pin_class_rule, roller_class_rule
from rvbacklash.errors import InputError
from rvbacklash.models.contact import PinGaps, crank_step_angle_rad, pin_gaps, recorded_stage, stage_play, \
    stage_work, unit_gaps
from rvbacklash.models.unit_errors import empty_unit
from rvbacklash.sampling.chunked import draw_then_evaluate
from rvbacklash.sampling.contact_source import block_streams, save_unit, saved_slice, saved_units, units_to_save
from rvbacklash.sampling.elastic_source import CHUNK, EVAL_THREADS, ElasticBlockSource, UnitBatch, empty_batch, \
    evaluate_batch
from rvbacklash.sampling.unit_draw import CRANK_CLEARANCE, IDX, N_STREAMS, UnitDraw, draw_scratch, draw_unit
from rvbacklash.units import ARCMIN_PER_RAD

SELECTION_STREAM = N_STREAMS + 1000  # the measurement errors' spawn key (after the units' streams)
PIN_RADIUS = IDX["pin_radius"]


class SelectionTables(NamedTuple):
    """What the selecting kernel reads: each part kind's ClassTable, the targets [arcmin], the
    crank bearings' share [arcmin/um] and the lever below which a pin does not bound the turn."""

    pins: ClassTable
    rollers: ClassTable
    play_window_arcmin: np.ndarray  # (2,) lo, hi
    target_arcmin: float
    crank_sens_arcmin_per_um: float
    lever_tol: float


class SelectionRecord(NamedTuple):
    """Per unit: the measurement error [um] (in), the classes taken and the predicted play of the
    cycloid stage with the pin class taken [arcmin] (out)."""

    noise_um: np.ndarray
    pin_class: np.ndarray  # int64
    roller_class: np.ndarray  # int64
    predicted_play_arcmin: np.ndarray


def selection_tables(source: ElasticBlockSource, selection: Selection) -> SelectionTables:
    """The tables of a Selection for a source's laws (pins: factor 15, radius = diameter / 2; rollers:
    factor 20, the crank bearings' radial clearance, a roller diameter class closing it 1:1)."""
    laws = source.contact.laws

    def law(f: int, name: str):
        return factor_law(int(laws.code[f]), float(laws.loc[f]), float(laws.scale[f]), float(laws.lower[f]),
                          float(laws.upper[f]), name)

    pins = class_table(law(PIN_RADIUS, "select pins"), selection.pins, 0.5)
    rollers = class_table(law(CRANK_CLEARANCE, "select rollers"), selection.rollers, 1.0)
    sens = float(laws.linear_sens_arcmin_per_um[list(laws.linear_factors).index(CRANK_CLEARANCE)])
    target = selection.target_arcmin
    if target is None:  # the crank bearings' share at their mean clearance (the stage just closed)
        target = sens * float(np.sum(rollers.mean_um * rollers.share) / np.sum(rollers.share))
    window = np.array([selection.play_min_arcmin, selection.play_max_arcmin])
    return SelectionTables(pins, _reversed(rollers), window, float(target), sens,
                           1e-9 * source.contact.geometry.stage_geometry.pitch_radius_um)


def _reversed(t: ClassTable) -> ClassTable:
    """Roller classes numbered by roller size: class 0 the smallest rollers (the largest clearance)."""
    return ClassTable(t.x_um, t.cdf, np.ascontiguousarray(t.ppf_um[::-1]), t.mean_um[::-1].copy(),
                      t.share[::-1].copy())


@njit(nogil=True, cache=True)
def draw_selected_kernel(streams, laws, stage, coef, batch, saved, tables, record):
    """``elastic_source.draw_units_kernel`` with selection: each unit drawn (draw_unit, same streams),
    its pin class and roller class picked (rules), its pins and crank clearance replaced by their
    class's parts at the same quantile (a part kind of one class is left as drawn), then its gaps,
    levers and preload found (stage_play) into ``batch``; ``record`` receives the classes."""
    unit = empty_unit(stage.zp, stage.zc, stage.discs, np.int64(0))
    scratch = draw_scratch(stage.zp, stage.zc)
    work = stage_work(stage.discs, stage.zp)
    seen = pin_gaps(stage.discs, stage.zp)  # the gaps as the factory reads them (pins as drawn)
    steps = coef.shape[0]
    sens = tables.crank_sens_arcmin_per_um
    pick_pins, pick_rollers = tables.pins.mean_um.size > 1, tables.rollers.mean_um.size > 1
    for s in range(batch.chi_rad.size):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        mesh = coef[drawn.crank_step]
        unit_gaps(mesh, stage, unit, seen, work)
        c_p, play = pin_class_rule(seen.gap_um, seen.lever_um_per_rad, unit.pin_radius_um, tables.pins,
                                   record.noise_um[s], tables.play_window_arcmin, tables.lever_tol)
        if pick_pins:
            for j in range(stage.zp):
                unit.pin_radius_um[j] = in_class_um(unit.pin_radius_um[j], tables.pins, c_p)
        c_r = roller_class_rule(play, tables.rollers, sens, tables.target_arcmin)
        crank = drawn.crank_clearance_um
        if pick_rollers:
            crank = in_class_um(crank, tables.rollers, c_r)
        record.pin_class[s], record.roller_class[s], record.predicted_play_arcmin[s] = c_p, c_r, play
        batch.chi_rad[s] = crank_step_angle_rad(drawn.crank_step, stage.zp, steps)
        batch.involute_backlash_rad[s] = max(drawn.linear_arcmin - sens * drawn.crank_clearance_um,
                                             0.0) / ARCMIN_PER_RAD
        batch.crank_clearance_um[s] = crank
        save = s < saved.crank_step.size
        p = stage_play(mesh, stage, unit, PinGaps(batch.gap_um[s], batch.lever_um_per_rad[s]), work, save)
        batch.preload_um[s] = p.preload_um if math.isnan(p.play_ccw_rad) else np.nan
        if save:
            save_unit(saved, s, unit, UnitDraw(drawn.crank_step, drawn.linear_arcmin + sens * (
                crank - drawn.crank_clearance_um), crank), recorded_stage(p))


def measurement_errors(seed: int, stream: tuple[int, ...], block: int, n: int, sigma_um: float) -> np.ndarray:
    """Block ``block``'s n measurement errors [um]: N(0, sigma) from SeedSequence(seed, spawn_key=
    (*stream, block, SELECTION_STREAM)); zeros without noise."""
    if sigma_um <= 0:
        return np.zeros(n)
    rng = np.random.Generator(np.random.PCG64(SeedSequence(seed, spawn_key=(*stream, block, SELECTION_STREAM))))
    return sigma_um * rng.standard_normal(n)


def empty_record(noise_um: np.ndarray) -> SelectionRecord:
    n = noise_um.size
    return SelectionRecord(noise_um, np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64), np.empty(n))


@dataclass(frozen=True, eq=False)
class SelectedElasticSource:
    """Block source of the engine: the elastic model's production run with selective assembly (module
    docstring). ``records``: block -> its SelectionRecord (the classes taken, for consumption)."""

    base: ElasticBlockSource
    selection: Selection
    tables: SelectionTables
    records: dict = field(default_factory=dict)

    @property
    def outputs(self):
        return self.base.outputs

    @property
    def output_warnings(self) -> dict[str, str]:
        return self.base.output_warnings

    def block(self, b: int, n: int) -> np.ndarray:
        base, c = self.base, self.base.contact
        streams = block_streams(c.seed, b, c.stream, c.swap, c.swap_stream)
        record = empty_record(measurement_errors(c.seed, c.stream, b, n, self.selection.noise_um))
        out = np.empty((len(base.outputs), n))
        keep = units_to_save(base.save_units, base.block_size, b, n)
        saved = saved_units(keep, c.geometry)
        g = c.geometry

        def evaluate(start: int, units: UnitBatch) -> None:
            out[:, start:start + units.chi_rad.size] = evaluate_batch(base.design, units, base.life)

        def draw(start: int, m: int) -> UnitBatch:
            batch = empty_batch(m, g.discs, g.zp)
            part = SelectionRecord(*(a[start:start + m] for a in record))
            draw_selected_kernel(streams, c.laws, g.stage_geometry, c.coef, batch,
                                 saved_slice(saved, start, start + m) if start < keep else saved_units(0, g),
                                 self.tables, part)
            return batch

        draw_then_evaluate(n, CHUNK, EVAL_THREADS, draw, evaluate)
        if keep:
            c.saved[b] = saved
        self.records[b] = record
        return out

    def saved_units(self) -> list:
        return self.base.saved_units()

    def class_counts(self) -> tuple[np.ndarray, np.ndarray]:
        """Units that took each pin class and each roller class, over the blocks run."""
        kp, kr = self.tables.pins.mean_um.size, self.tables.rollers.mean_um.size
        pins, rollers = np.zeros(kp, dtype=np.int64), np.zeros(kr, dtype=np.int64)
        for r in self.records.values():
            pins += np.bincount(r.pin_class, minlength=kp)
            rollers += np.bincount(r.roller_class, minlength=kr)
        return pins, rollers


def selected_source(selection: Selection):
    """The ``wrap`` of analysis.simulation.simulate that turns the elastic model's source into the
    selected run's."""
    def wrap(source):
        if not isinstance(source, ElasticBlockSource):
            raise InputError("select", str(selection), "allowed with the elastic model only (so far)")
        return SelectedElasticSource(source, selection, selection_tables(source, selection))
    return wrap
