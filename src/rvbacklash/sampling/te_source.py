"""Monte-Carlo of the transmission error through the engine (``--model transmission``, or
``--model contact`` with ``--spec-te-arcsec``; docs/transmission-error.md).

A unit draws exactly what the contact model draws (same streams, same numbers: ``draw_unit``),
plus the kinematic factors (factors.catalog.KINEMATIC_FACTORS), each from a stream of its own
after the contact model's (``SeedSequence(seed, spawn_key=(*stream, block, N_STREAMS + m))``).
Every unit then turns through one output revolution from the reference position (crank angle
0) at POSITIONS_PER_PIN x z_p positions, each flank's first contact linearised at its position
(``models.kinematics.te_curve`` with exact=False; the tests bound the difference to the exact
solve), and its TE peak-to-peak is refined between the positions (``models.te_refine``: the
extremes narrower than a step that the positions straddle). Outputs per unit: the rigid backlash at the reference position (as the contact model's
``backlash``: the cycloid stage plus the involute and crank stages' linear part), the TE
peak-to-peak of the ccw flank [arcsec], the largest lost motion over the revolution.

Units are drawn serially (one stream per factor) in chunks and evaluated by a small thread pool
(the kernel is nogil): the numbers do not depend on the number of threads.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from numpy.random import SeedSequence

from rvbacklash._numba import njit
from rvbacklash.factors.catalog import KINEMATIC_FACTORS
from rvbacklash.errors import InputError
from rvbacklash.interrupt import check_abandoned
from rvbacklash.models.kinematics import (ARCSEC_PER_RAD, FlankCurve, Kinematics, PositionTable, curve_scratch,
                                          kinematics, perfect_unit, position_table, reference_revolution, te_curve)
from rvbacklash.models.te_refine import REFERENCE_POINTS, TEReference, point_work, reference_between, refined_peak_to_peak
from rvbacklash.models.unit_errors import (Realization, UnitErrors, empty_unit, empty_units, realization_at, store_unit,
                                           unit_at, unit_errors)
from rvbacklash.problem import Problem
from rvbacklash.problem.kinematic_errors import kinematic_zones
from rvbacklash.sampling.chunked import draw_then_evaluate
from rvbacklash.sampling.contact_source import (BLOCK_UNITS, ContactBlockSource, SavedUnits, block_streams,
                                                contact_source, recorded_units, save_unit, saved_slice, saved_units,
                                                units_to_save)
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import states_from_generators, stream_states
from rvbacklash.sampling.unit_draw import N_STREAMS, _normal, draw_scratch, draw_unit
from rvbacklash.units import ARCMIN_PER_RAD

POSITIONS_PER_PIN = 8  # output positions per revolution = 8 z_p (320 for rv80e): orders below 4 z_p resolved
# The TE peak-to-peak is refined between the positions (models.te_refine; schema 9.0): on the first 40 units of
# seed 3 it reads -0.3 % below the converged figure on average, where the figure sampled at the positions read -8.0 %
# (worst -2.7 against -30.8 %), at ~6 times the sampled evaluation's CPU (bench/bench_te_refine.py,
# docs/transmission-error.md, "The production run"). False: the sampled figure (a lower bound of the refined one).
REFINE = True
CHUNK = 256  # units drawn, then evaluated, at a time
EVAL_THREADS = 2

TE_OUTPUTS = (
    Output("backlash", "arcmin", "output backlash (rigid lost motion) at the reference position, every unit: the "
                                 "cycloid stage (0 when preloaded) plus the involute and crank stages"),
    Output("transmission_error", "arcsec", "transmission error peak-to-peak over one output revolution (ccw flank), "
                                       "refined between the run's 8 z_p positions"),
    Output("lost_motion_max", "arcmin", "largest rigid lost motion over the output revolution: the cycloid stage's "
                                        "largest plus the involute and crank stages"),
)


def te_streams(seed: int, block: int, stream: tuple[int, ...] = ()) -> np.ndarray:
    """The contact model's streams of block ``block`` and one per kinematic factor after them
    (N_STREAMS + len(KINEMATIC_FACTORS), 4)."""
    return np.concatenate([block_streams(seed, block, stream), stream_states(
        [SeedSequence(seed, spawn_key=(*stream, block, N_STREAMS + m)) for m in range(len(KINEMATIC_FACTORS))])])


class KinematicLaws(NamedTuple):
    """The kinematic factors' sigma per component [um] and the stream each draws from (its index among
    the kinematic streams: KINEMATIC_FACTORS order). The streams are run-time numbers in the record,
    not constants in the code: a compiled call with a constant argument is compiled again for each
    value (here the ziggurat, four times)."""

    centre_gear_um: float
    planet_um: float
    disc_hole_um: float
    carrier_hole_um: float
    centre_gear_stream: int = 0
    planet_stream: int = 1
    disc_hole_stream: int = 2
    carrier_hole_stream: int = 3


class TEBatch(NamedTuple):
    """m drawn units as the transmission-error evaluation takes them: their errors (a UnitErrors
    batch) and their involute and crank stages' lost motion [arcmin]."""

    units: UnitErrors
    linear_arcmin: np.ndarray


@njit(nogil=True, cache=True)
def draw_chunk(streams, kin_streams, laws, kin_laws, batch, saved):
    """The units of ``batch`` (TEBatch), one row each: the contact model's draws (unit_draw.draw_unit
    with FactorLaws ``laws``; crank angle ignored: every unit starts at the reference position)
    and the kinematic factors' (``kin_streams``: one xoshiro stream state each, KINEMATIC_FACTORS
    order; ``kin_laws``: KinematicLaws): the gears' eccentricities and the crank holes of the discs
    and of the carrier. The first units are recorded in ``saved`` (SavedUnits, as many as it holds;
    their cycloid stage: ``evaluate_chunk``)."""
    units = batch.units
    zp, discs, zc = units.pin_radial_um.shape[1], units.tooth_pitch_um.shape[1], units.tooth_pitch_um.shape[2]
    unit = empty_unit(zp, zc, discs, units.planet_eccentricity_um.shape[1])
    scratch = draw_scratch(zp, zc)
    steps = np.int64(1)  # one crank-angle step, but not a literal: draw_unit then compiles once for all the kernels
    for s in range(batch.linear_arcmin.size):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        batch.linear_arcmin[s] = drawn.linear_arcmin
        draw_kinematic(kin_streams, kin_laws, unit)
        store_unit(units, s, unit)
        if s < saved.crank_step.size:
            save_unit(saved, s, unit, drawn, np.nan)


@njit(nogil=True, cache=True)
def draw_kinematic(kin_streams, kin_laws, unit):
    """The kinematic factors of one unit (draw_chunk; ``kin_laws``: KinematicLaws) into ``unit``:
    the gears' eccentricities and the crank holes of the discs and of the carrier."""
    centre, planet, hd, hc = unit.centre_gear_eccentricity_um, unit.planet_eccentricity_um, unit.disc_crank_hole_um, \
        unit.carrier_crank_hole_um
    planets, discs = planet.shape[0], hd.shape[0]
    for c in range(2):
        centre[c] = kin_laws.centre_gear_um * _normal(kin_streams, kin_laws.centre_gear_stream, False)
    for k in range(planets):
        for c in range(2):
            planet[k, c] = kin_laws.planet_um * _normal(kin_streams, kin_laws.planet_stream, False)
    for d in range(discs):
        for k in range(planets):
            for c in range(2):
                hd[d, k, c] = kin_laws.disc_hole_um * _normal(kin_streams, kin_laws.disc_hole_stream, False)
    for k in range(planets):
        for c in range(2):
            hc[k, c] = kin_laws.carrier_hole_um * _normal(kin_streams, kin_laws.carrier_hole_stream, False)


@njit(nogil=True, cache=True)
def evaluate_chunk(stage, kin, table, batch, ref, out, saved):
    """TE_OUTPUTS of the units of ``batch`` (TEBatch) into out (3, m): StageGeometry ``stage``, the
    design's Kinematics ``kin``, the PositionTable of the positions, the error-free unit
    (``ref``: TEReference, its ccw flank there); the cycloid stage of the first units into ``saved``
    (SavedUnits: its rigid lost motion at the reference position [arcmin], 0 where preloaded). The TE
    peak-to-peak: refined between the positions when ref.refine (te_refine.refined_peak_to_peak, the
    default: docs/transmission-error.md, "The production run"), else the curve's at the positions."""
    n = table.chi_rad.size
    scratch = curve_scratch(stage.zp, stage.zc, stage.discs, kin.planets)
    rows = n if ref.refine else 0  # the pins' gaps and levers recorded: where to refine
    curve = FlankCurve(np.empty(n), np.empty(n), np.empty(n), np.empty((rows, stage.discs, stage.zp), np.float32),
                       np.empty((rows, stage.discs, stage.zp), np.float32))
    work = point_work(stage, kin.planets, n)
    ccw, cw = curve.ccw_rad, curve.cw_rad
    lin = batch.linear_arcmin
    linearised = n < 0  # False, not as a literal: te_curve (and stage_play) compiled once for every caller
    for s in range(lin.size):
        unit = unit_at(batch.units, s)
        te_curve(stage, kin, table, unit, 0.0, scratch, curve, linearised)
        lm_max = 0.0
        for k in range(n):
            lm_max = max(lm_max, ccw[k] - cw[k])
        cycloid = (ccw[0] - cw[0]) * ARCMIN_PER_RAD
        out[0, s] = lin[s] + cycloid
        if s < saved.cycloid_stage.size:
            saved.cycloid_stage[s] = cycloid
        if ref.refine:
            pp = refined_peak_to_peak(stage, kin, unit, ref, scratch, work, curve)
        else:
            lo, hi = np.inf, -np.inf
            for k in range(n):
                v = ccw[k] - ref.ccw_rad[k]
                lo = min(lo, v)
                hi = max(hi, v)
            pp = hi - lo
        out[1, s] = pp * ARCSEC_PER_RAD
        out[2, s] = lin[s] + lm_max * ARCMIN_PER_RAD


@dataclass(frozen=True, eq=False)
class TransmissionBlockSource:
    """Block source of the engine for the transmission error (method: default)."""

    contact: ContactBlockSource  # laws, error model, harmonics of the contact model
    kin_laws: KinematicLaws
    kinematics: Kinematics
    table: PositionTable  # the output positions
    reference: TEReference  # the error-free unit: its ccw flank at the positions, its errors
    outputs: tuple[Output, ...] = TE_OUTPUTS
    block_size: int = BLOCK_UNITS  # the contact model's blocks: the same units
    save_units: int = 0  # record the errors of the first units of the run (kinematic errors included)
    saved: dict = field(default_factory=dict)  # block -> its recorded SavedUnits (the first blocks)

    def _draw(self, streams: np.ndarray, m: int, saved: SavedUnits | None = None) -> TEBatch:
        c, g = self.contact, self.contact.geometry
        batch = TEBatch(empty_units(m, g.zp, g.zc, g.discs, self.kinematics.planets), np.empty(m))
        draw_chunk(streams[:N_STREAMS], streams[N_STREAMS:], c.laws, self.kin_laws, batch,
                   saved if saved is not None else self._no_saving)
        return batch

    def _evaluate(self, batch: TEBatch, out: np.ndarray, saved: SavedUnits | None = None) -> None:
        # the kernel writes a C-contiguous array (a block's chunk is columns of its outputs: copied back), so
        # that it is compiled for one set of argument types (tests/sampling/test_te_kernel_types.py)
        dense = out if out.flags.c_contiguous else np.empty(out.shape)
        evaluate_chunk(self.contact.geometry.stage_geometry, self.kinematics, self.table, batch, self.reference,
                       dense, saved if saved is not None else self._no_saving)
        if dense is not out:
            out[...] = dense

    @property
    def _no_saving(self) -> SavedUnits:
        return saved_units(0, self.contact.geometry, self.kinematics.planets)

    def block(self, b: int, n: int) -> np.ndarray:
        """(3, n) outputs of block b (TE_OUTPUTS)."""
        c = self.contact
        streams = te_streams(c.seed, b, c.stream)
        out = np.empty((len(self.outputs), n))
        keep = units_to_save(self.save_units, self.block_size, b, n)
        saved = saved_units(keep, c.geometry, self.kinematics.planets)

        def part(start: int, m: int) -> SavedUnits | None:
            return saved_slice(saved, start, start + m) if start < keep else None

        draw_then_evaluate(n, CHUNK, EVAL_THREADS, lambda start, m: self._draw(streams, m, part(start, m)),
                           lambda start, batch: self._evaluate(batch, out[:, start:start + batch.linear_arcmin.size],
                                                               part(start, batch.linear_arcmin.size)))
        if keep:
            self.saved[b] = saved
        return out

    def saved_units(self) -> list[tuple[Realization, float, float]]:
        """The recorded units, in run order, as the contact model records them: (errors with the
        kinematic ones, at the reference position (crank angle 0); linear stages [arcmin]; the
        cycloid stage's lost motion at the reference position [arcmin], 0 where preloaded)."""
        return recorded_units(self.saved, lambda step: 0.0)


def transmission_source(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                        save_units: int = 0, refine: bool | None = None) -> TransmissionBlockSource:
    """The transmission-error model's block source (positions per revolution: POSITIONS_PER_PIN z_p;
    ``refine``: each unit's TE peak-to-peak refined between them, models.te_refine; None: REFINE)."""

    if method != "default":
        raise InputError("method", method, "allowed with the transmission-error model: default")
    c = contact_source(problem, "default", seed, stream)
    g = problem.cycloid
    n = POSITIONS_PER_PIN * g.zp
    ref = reference_revolution(problem, n, 0.0, exact=False)
    kin_laws = KinematicLaws(*(float(z.sigma_um) for z in kinematic_zones(problem.design, problem.zones)))
    kin = kinematics(problem)
    refine = REFINE if refine is None else bool(refine)
    reference = TEReference(ref.ccw_rad, unit_errors(perfect_unit(problem, 0.0), kin.planets), refine, _NO_POINTS)
    if refine:
        reference = reference._replace(between_rad=_reference_between(g, kin, reference))
    return TransmissionBlockSource(c, kin_laws, kin, position_table(g, n, 0.0), reference, TE_OUTPUTS,
                                   save_units=int(save_units))


# the sampled run's placeholder of TEReference.between_rad: read-only like the refined run's points, so that
# evaluate_chunk sees one set of argument types and is compiled once (tests/sampling/test_te_kernel_types.py)
_NO_POINTS = np.empty((0, 0))
_NO_POINTS.flags.writeable = False
_BETWEEN: dict = {}  # (geometry, Kinematics, the error-free unit's flank at the positions) -> its points between


def _reference_between(g, kin: Kinematics, reference: TEReference) -> np.ndarray:
    """The error-free unit's flank at REFERENCE_POINTS points a step (te_refine.reference_between), computed
    once per design and grid (~50 ms for rv80e; read-only)."""
    key = (g, kin, reference.ccw_rad.tobytes())
    if key not in _BETWEEN:
        out = np.empty((reference.ccw_rad.size, REFERENCE_POINTS))
        reference_between(g.stage_geometry, kin, reference, out)
        out.flags.writeable = False
        if len(_BETWEEN) >= 8:
            _BETWEEN.pop(next(iter(_BETWEEN)))
        _BETWEEN[key] = out
    return _BETWEEN[key]


def sample_units(problem: Problem, seed: int, n: int, stream: tuple[int, ...] = ()) -> list[Realization]:
    """The first n units of block 0 of a production run (the same numbers ``simulate`` draws) as
    Realizations at the reference position (crank angle 0), for one-unit curves."""
    return sample_units_with_stages(problem, seed, n, stream)[0]


def sample_units_with_stages(problem: Problem, seed: int, n: int,
                             stream: tuple[int, ...] = ()) -> tuple[list[Realization], np.ndarray]:
    """``sample_units`` and each unit's involute and crank stages [arcmin] (what the run adds to
    the cycloid stage's lost motion: ``other_stages_arcmin``)."""
    src = transmission_source(problem, "default", seed, stream)
    batch = src._draw(te_streams(seed, 0, tuple(stream)), n)
    return [realization_at(batch.units, s, 0.0) for s in range(n)], batch.linear_arcmin.copy()


@dataclass(frozen=True, eq=False)
class TransmissionStreams:
    """The transmission-error model as global sensitivity needs it (analysis.sensitivity_global.
    StreamModel): every catalog factor, the crank angle and every kinematic factor draws from the
    stream seeded by the generator it is given (Sobol indices of TE by part group)."""

    source: TransmissionBlockSource
    random: tuple[bool, ...]
    inputs: tuple[str, ...]
    outputs: tuple[Output, ...] = TE_OUTPUTS

    def block(self, generators, n: int) -> np.ndarray:
        streams = states_from_generators(generators)
        out = np.empty((len(self.outputs), n))
        for start in range(0, n, CHUNK):
            check_abandoned()  # a workbench job's stop drops the block between two chunks
            m = min(CHUNK, n - start)
            self.source._evaluate(self.source._draw(streams, m), out[:, start:start + m])
        return out


def transmission_streams(problem: Problem) -> TransmissionStreams:
    from rvbacklash.factors.catalog import FACTOR_KEYS, KINEMATIC_KEYS

    source = transmission_source(problem, "default", 0)
    k = source.kin_laws
    sigmas = (k.centre_gear_um, k.planet_um, k.disc_hole_um, k.carrier_hole_um)  # KINEMATIC_FACTORS order
    random = tuple(bool(x) for x in problem.random_mask) + (True,) + tuple(bool(s > 0) for s in sigmas)
    return TransmissionStreams(source, random, tuple(FACTOR_KEYS) + ("crank_angle",) + KINEMATIC_KEYS)
