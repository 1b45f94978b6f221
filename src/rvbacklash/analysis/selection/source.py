"""The production run with selective assembly: the elastic, contact or transmission model's block
source, each unit drawn as the random run draws it (same streams, same numbers), then its pins and
needle rollers taken from the classes the rules pick (``rules``), then evaluated as the model
evaluates it (its loop; its rigid play; its revolution).

Time (issue 39: at most 20 % on a run): the gaps the rules read are the gaps the model reads. A
unit's gaps are found once (unit_gaps) and moved with the pins it is given (a gap is linear in the
pin's radius: contact.shift_pin_radius); the predicted play of every class is one pass over the
pins (rules.class_plays_arcmin).

Common random numbers: a unit of the selected run is the unit of the random run with the same seed,
its selected parts replaced by the parts of their class at the same quantile, so that the two yields
differ by what selection does and not by sampling. The measurement errors draw from a stream of
their own (``SELECTION_STREAM``): the units' streams are untouched, and one class of each part is the
random run bit for bit (no part is replaced).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.random import SeedSequence

from rvbacklash._numba import njit
from rvbacklash.analysis.selection.classes import ClassTable, Selection, class_table, factor_law
from rvbacklash.analysis.selection.rules import in_class_um, pin_class_rule, roller_class_rule
from rvbacklash.errors import InputError
from rvbacklash.models.contact import (FreeInterval, PinGaps, crank_step_angle_rad, free_interval_bounds, mesh_table,
                                      pin_gaps, play_from_gaps, recorded_stage, shift_pin_radius, stage_work,
                                      unit_gaps)
from rvbacklash.models.unit_errors import empty_unit, empty_units, store_unit
from rvbacklash.sampling.chunked import draw_then_evaluate
from rvbacklash.sampling.contact_source import (ContactBlockSource, SavedUnits, block_streams, save_unit, saved_slice,
                                                saved_units, units_to_save)
from rvbacklash.sampling.elastic_source import CHUNK, EVAL_THREADS, ElasticBlockSource, UnitBatch, empty_batch, \
    evaluate_batch
from rvbacklash.sampling.te_source import CHUNK as TE_CHUNK, TEBatch, TransmissionBlockSource, draw_kinematic, te_streams
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


def contact_of(source) -> ContactBlockSource:
    """The contact model's source under a block source (its laws, geometry, streams)."""
    return source if isinstance(source, ContactBlockSource) else source.contact


def selection_tables(source, selection: Selection) -> SelectionTables:
    """The tables of a Selection for a source's laws (pins: factor 15, radius = diameter / 2; rollers:
    factor 20, the crank bearings' radial clearance, a roller diameter class closing it 1:1)."""
    laws = contact_of(source).laws

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
                           1e-9 * contact_of(source).geometry.stage_geometry.pitch_radius_um)


def _reversed(t: ClassTable) -> ClassTable:
    """Roller classes numbered by roller size: class 0 the smallest rollers (the largest clearance)."""
    return ClassTable(t.x_um, t.cdf, np.ascontiguousarray(t.ppf_um[::-1]), t.mean_um[::-1].copy(),
                      t.share[::-1].copy())


@njit(nogil=True, cache=True)
def rule_scratch(tables):
    """Scratch of select_unit: (3, pin classes)."""
    return np.empty((3, tables.pins.mean_um.size))


@njit(nogil=True, cache=True)
def select_unit(mesh, stage, unit, gaps, work, tables, noise_um, scratch):
    """The factory's choice for a drawn unit (``unit``, UnitErrors; ``mesh``: the mesh_table at its
    crank angle): its gaps and levers as drawn (unit_gaps, into ``gaps`` and ``work``), the pin
    class the rule picks from them (read with the measurement error ``noise_um``), every pin then
    replaced by its class's part at the same quantile and the gaps moved with it (a pin's gap is
    linear in its radius: contact.shift_pin_radius; the pins are not placed again), and the roller
    class. Returns (pin class, roller class, predicted play [arcmin], the FreeInterval of the unit as
    selected: stage_play's, for contact.play_from_gaps).
    One class of pins leaves the unit as drawn: the gaps are bit for bit the random run's."""
    lo, hi, flat = unit_gaps(mesh, stage, unit, gaps, work)
    c_p, play = pin_class_rule(gaps.gap_um, gaps.lever_um_per_rad, unit.pin_radius_um, tables.pins, noise_um,
                               tables.play_window_arcmin, tables.lever_tol, scratch)
    if tables.pins.mean_um.size > 1:
        for j in range(stage.zp):
            shift_pin_radius(mesh, unit, gaps, work, j, in_class_um(unit.pin_radius_um[j], tables.pins, c_p))
        lo, hi, flat = free_interval_bounds(gaps, stage.pitch_radius_um)
    c_r = roller_class_rule(play, tables.rollers, tables.crank_sens_arcmin_per_um, tables.target_arcmin)
    return c_p, c_r, play, FreeInterval(lo, hi, flat)


@njit(nogil=True, cache=True, inline="always")
def selected_clearance_um(tables, drawn_um, c_r):
    """The crank bearings' clearance [um] with rollers of class c_r (one class: as drawn)."""
    if tables.rollers.mean_um.size > 1:
        return in_class_um(drawn_um, tables.rollers, c_r)
    return drawn_um


@njit(nogil=True, cache=True)
def draw_selected_kernel(streams, laws, stage, coef, batch, saved, tables, record):
    """``elastic_source.draw_units_kernel`` with selection: each unit drawn (draw_unit, same streams),
    its parts selected (select_unit: the gaps found once, into the unit's rows of ``batch``), then
    its preload found (contact.play_from_gaps); ``record`` receives the classes."""
    unit = empty_unit(stage.zp, stage.zc, stage.discs, np.int64(0))
    scratch = draw_scratch(stage.zp, stage.zc)
    work = stage_work(stage.discs, stage.zp)
    rule = rule_scratch(tables)
    steps = coef.shape[0]
    sens = tables.crank_sens_arcmin_per_um
    for s in range(batch.chi_rad.size):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        mesh = coef[drawn.crank_step]
        gaps = PinGaps(batch.gap_um[s], batch.lever_um_per_rad[s])
        c_p, c_r, play, free = select_unit(mesh, stage, unit, gaps, work, tables, record.noise_um[s], rule)
        crank = selected_clearance_um(tables, drawn.crank_clearance_um, c_r)
        record.pin_class[s], record.roller_class[s], record.predicted_play_arcmin[s] = c_p, c_r, play
        batch.chi_rad[s] = crank_step_angle_rad(drawn.crank_step, stage.zp, steps)
        batch.involute_backlash_rad[s] = max(drawn.linear_arcmin - sens * drawn.crank_clearance_um,
                                             0.0) / ARCMIN_PER_RAD
        batch.crank_clearance_um[s] = crank
        save = s < saved.crank_step.size
        p = play_from_gaps(mesh, stage, unit, gaps, work, free, save)
        batch.preload_um[s] = p.preload_um if math.isnan(p.play_ccw_rad) else np.nan
        if save:
            save_unit(saved, s, unit, UnitDraw(drawn.crank_step, drawn.linear_arcmin + sens * (
                crank - drawn.crank_clearance_um), crank), recorded_stage(p))


@njit(nogil=True, cache=True)
def contact_selected_block(streams, laws, stage, coef, out, saved, tables, record):
    """``contact_source.contact_block`` with selection (select_unit; the involute and crank stages'
    linear sum with the crank bearings' clearance as selected)."""
    unit = empty_unit(stage.zp, stage.zc, stage.discs, np.int64(0))
    scratch = draw_scratch(stage.zp, stage.zc)
    gaps, work = pin_gaps(stage.discs, stage.zp), stage_work(stage.discs, stage.zp)
    rule = rule_scratch(tables)
    steps = coef.shape[0]
    play_too = steps > 0  # True, not as a literal (contact_block)
    sens = tables.crank_sens_arcmin_per_um
    for s in range(out.shape[1]):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        mesh = coef[drawn.crank_step]
        c_p, c_r, pred, free = select_unit(mesh, stage, unit, gaps, work, tables, record.noise_um[s], rule)
        crank = selected_clearance_um(tables, drawn.crank_clearance_um, c_r)
        record.pin_class[s], record.roller_class[s], record.predicted_play_arcmin[s] = c_p, c_r, pred
        play = play_from_gaps(mesh, stage, unit, gaps, work, free, play_too)
        lin = drawn.linear_arcmin + sens * (crank - drawn.crank_clearance_um) if crank != drawn.crank_clearance_um \
            else drawn.linear_arcmin
        cycloid = recorded_stage(play)
        if math.isnan(play.play_ccw_rad):
            out[0, s] = lin
            out[1, s] = np.nan
            out[2, s] = play.preload_um
        else:
            out[0, s] = lin + cycloid
            out[1, s] = out[0, s]
            out[2, s] = np.nan
        if s < saved.crank_step.size:
            save_unit(saved, s, unit, UnitDraw(drawn.crank_step, lin, crank), cycloid)


@njit(nogil=True, cache=True)
def te_selected_chunk(streams, kin_streams, laws, kin_laws, batch, saved, sel):
    """``te_source.draw_chunk`` with selection: each unit drawn as it draws them (the contact
    model's draws, then the kinematic factors'), its parts selected (select_unit on the gaps at the
    reference position, ``sel.mesh``), its errors stored as selected. ``sel``: TESelection."""
    units = batch.units
    stage, tables, record = sel.stage, sel.tables, sel.record
    zp, discs, zc = units.pin_radial_um.shape[1], units.tooth_pitch_um.shape[1], units.tooth_pitch_um.shape[2]
    unit = empty_unit(zp, zc, discs, units.planet_eccentricity_um.shape[1])
    scratch = draw_scratch(zp, zc)
    gaps, work = pin_gaps(discs, zp), stage_work(discs, zp)
    rule = rule_scratch(tables)
    steps = np.int64(1)  # as draw_chunk
    sens = tables.crank_sens_arcmin_per_um
    for s in range(batch.linear_arcmin.size):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        draw_kinematic(kin_streams, kin_laws, unit)
        c_p, c_r, pred, _ = select_unit(sel.mesh, stage, unit, gaps, work, tables, record.noise_um[s], rule)
        crank = selected_clearance_um(tables, drawn.crank_clearance_um, c_r)
        record.pin_class[s], record.roller_class[s], record.predicted_play_arcmin[s] = c_p, c_r, pred
        lin = drawn.linear_arcmin + sens * (crank - drawn.crank_clearance_um) if crank != drawn.crank_clearance_um \
            else drawn.linear_arcmin
        batch.linear_arcmin[s] = lin
        store_unit(units, s, unit)
        if s < saved.crank_step.size:
            save_unit(saved, s, unit, UnitDraw(drawn.crank_step, lin, crank), np.nan)


class TESelection(NamedTuple):
    """What te_selected_chunk reads besides draw_chunk's: the stage, the mesh_table at the reference
    position (crank angle 0: the factory reads the unit where the run turns it from), the tables
    and the block's record."""

    stage: object
    mesh: np.ndarray
    tables: SelectionTables
    record: SelectionRecord


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
class SelectedSource:
    """Block source of the engine: a model's production run with selective assembly (module
    docstring; the elastic, contact and transmission models). ``records``: block -> its
    SelectionRecord (the classes taken, for consumption)."""

    base: object  # ElasticBlockSource | ContactBlockSource | TransmissionBlockSource
    selection: Selection
    tables: SelectionTables
    records: dict = field(default_factory=dict)

    @property
    def outputs(self):
        return self.base.outputs

    @property
    def output_warnings(self) -> dict[str, str]:
        return getattr(self.base, "output_warnings", None) or {}

    @property
    def contact(self) -> ContactBlockSource:
        return contact_of(self.base)

    def block(self, b: int, n: int) -> np.ndarray:
        c = self.contact
        record = empty_record(measurement_errors(c.seed, c.stream, b, n, self.selection.noise_um))
        if isinstance(self.base, ElasticBlockSource):
            out = self._elastic(b, n, record)
        elif isinstance(self.base, ContactBlockSource):
            out = self._contact(b, n, record)
        else:
            out = self._transmission(b, n, record)
        self.records[b] = record
        return out

    def _elastic(self, b: int, n: int, record: SelectionRecord) -> np.ndarray:
        base, c = self.base, self.base.contact
        streams = block_streams(c.seed, b, c.stream, c.swap, c.swap_stream)
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
        return out

    def _contact(self, b: int, n: int, record: SelectionRecord) -> np.ndarray:
        c = self.base
        out = np.empty((len(c.outputs), n))
        saved = saved_units(units_to_save(c.save_units, c.block_size, b, n), c.geometry)
        contact_selected_block(block_streams(c.seed, b, c.stream, c.swap, c.swap_stream), c.laws,
                               c.geometry.stage_geometry, c.coef, out, saved, self.tables, record)
        if saved.crank_step.size:
            c.saved[b] = saved
        return out

    def _transmission(self, b: int, n: int, record: SelectionRecord) -> np.ndarray:
        src = self.base
        c, g = src.contact, src.contact.geometry
        streams = te_streams(c.seed, b, c.stream)
        out = np.empty((len(src.outputs), n))
        keep = units_to_save(src.save_units, src.block_size, b, n)
        saved = saved_units(keep, g, src.kinematics.planets)
        mesh = reference_mesh(g)

        def part(start: int, m: int) -> SavedUnits | None:
            return saved_slice(saved, start, start + m) if start < keep else None

        def draw(start: int, m: int) -> TEBatch:
            batch = TEBatch(empty_units(m, g.zp, g.zc, g.discs, src.kinematics.planets), np.empty(m))
            sel = TESelection(g.stage_geometry, mesh, self.tables, SelectionRecord(*(a[start:start + m]
                                                                                     for a in record)))
            p = part(start, m)
            te_selected_chunk(streams[:N_STREAMS], streams[N_STREAMS:], c.laws, src.kin_laws, batch,
                              p if p is not None else src._no_saving, sel)
            return batch

        draw_then_evaluate(n, TE_CHUNK, EVAL_THREADS, draw,
                           lambda start, batch: src._evaluate(batch, out[:, start:start + batch.linear_arcmin.size],
                                                              part(start, batch.linear_arcmin.size)))
        if keep:
            src.saved[b] = saved
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


SelectedElasticSource = SelectedSource  # the name of the elastic model's first selected run


@lru_cache(maxsize=8)
def reference_mesh(g) -> np.ndarray:
    """The mesh_table at crank angle 0 (the transmission model's reference position), one row."""
    return mesh_table(g, np.array([0.0]))[0]


def selected_source(selection: Selection):
    """The ``wrap`` of analysis.simulation.simulate that turns a model's source (elastic, contact,
    transmission) into the selected run's."""
    def wrap(source):
        if not isinstance(source, (ElasticBlockSource, ContactBlockSource, TransmissionBlockSource)):
            raise InputError("select", str(selection), "allowed with the contact, elastic and transmission models "
                                                       "(the linear model draws no parts)")
        return SelectedSource(source, selection, selection_tables(source, selection))
    return wrap
