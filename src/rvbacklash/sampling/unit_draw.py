"""The compiled draw of one unit: every catalog factor from its own random stream, into the unit's
``UnitErrors`` record (docs/contact.md, "Part errors"; docs/architecture.md, "One unit's path").

What a unit draws:
- ``long_wave`` (default): each disc's teeth and the housing's pin holes are an indexed part,
  a first and a second harmonic plus a per-element part (``part_errors``), calibrated to
  conform to the part's F_p, f_pt (and F_r) at 97 %; the pin-circle radius deviation (factor
  14) is one value per housing; every pin's radius (15) and hole clearance (16) are drawn per
  pin within their zones (ISO 286 fields: truncated);
- ``independent``: today's pessimistic reading, every element drawn on its own from its zone
  (pins: radial position 14, tangential position 17, radius 15, clearance 16; teeth: 10).
Both: the modifications (11, 12) once per reducer (one grinding set-up), per disc the run-out
vector (13: two components, each half a draw of the phase-weighted reading), the crank
eccentricity error (21) and the modification errors (18, 19); stage 1 and the crank bearing
clearance (20) enter linearly, as in the linear model. The crank angle of the measurement is
uniform over one pin pitch in ``steps`` steps (the geometry repeats every pin pitch).

The draw order within each stream is part of the numbers' contract (same seed, same units).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit, njit_borrowing
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.factors.distributions import (KERNEL_NORMAL, KERNEL_TABLE, KERNEL_TRUNCNORM, TABLE_POINTS,
                                              kernel_draw, ppf_table)
from rvbacklash.problem import Problem
from rvbacklash.sampling.fast_normals import stream_normal, stream_normals, stream_uniform
from rvbacklash.sampling.kernels import box_muller_normal
from rvbacklash.sampling.part_errors import Harmonics, Wave, calibrate, element_harmonics, harmonic_deviations

IDX = {f.key: f.id - 1 for f in CATALOG}
CRANK_STREAM = len(CATALOG)  # the stream after the 21 factors': the crank angle of the measurement
N_STREAMS = len(CATALOG) + 1
# the stages that enter linearly (as in the linear model): the involute stage's factors and the crank bearings'
# clearance (the elastic model also reads the clearance itself: a dead band of the needle bearings)
CRANK_CLEARANCE_KEY = "crank_bearing_clearance"
LINEAR_KEYS = tuple(f.key for f in CATALOG if f.stage.label == "involute") + (CRANK_CLEARANCE_KEY,)
CRANK_CLEARANCE = IDX[CRANK_CLEARANCE_KEY]  # its catalog index (compared, never passed: no specialisation)
ERROR_MODELS = ("long_wave", "independent")


class WaveSigmas(NamedTuple):
    """Standard deviations [um] of an indexed part's long-wave model (part_errors.HarmonicPart)."""

    first_um: float
    second_um: float
    element_um: float
    radial_element_um: float


class CycloidFactors(NamedTuple):
    """The catalog index of each factor of the cycloid stage: the stream it draws from and its law's
    row in FactorLaws. Run-time numbers in the record, not constants in the code: a compiled call
    with a constant argument is compiled again for each value."""

    disc_pitch: int
    equidistance: int
    moving_distance: int
    disc_runout: int
    pin_circle: int
    pin_radius: int
    pin_clearance: int
    pin_pitch: int
    equidistance_error: int
    moving_distance_error: int
    crank_eccentricity: int


CYCLOID_FACTORS = CycloidFactors(*(IDX[k] for k in (
    "disc_cumulative_pitch", "equidistance_modification", "moving_distance_modification", "disc_runout",
    "pin_circle_radius", "pin_radius", "pin_hole_clearance", "pin_cumulative_pitch", "equidistance_modification_error",
    "moving_distance_modification_error", "crank_eccentricity")))


class FactorLaws(NamedTuple):
    """Everything a unit's draw reads: each catalog factor's law (``factors.distributions.KernelLaw``
    as arrays over the catalog, and its tabulated inverse cdf for a law without a branch), the
    long-wave sigmas of the disc teeth and of the pin holes, the cycloid stage's factors, the
    stages that enter linearly (LINEAR_KEYS: the involute stage's factors and the crank bearings'
    clearance, CRANK_CLEARANCE: catalog indices and sensitivities [arcmin/um]), and how it draws (the
    error model, Box-Muller normals). (Two more fields here made a contact unit 8 % slower: keep the
    record lean.)"""

    code: np.ndarray  # (21,) int64
    loc: np.ndarray  # (21,) [um]
    scale: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    ppf_table: np.ndarray  # (21, TABLE_POINTS) [um]
    disc_wave: WaveSigmas
    pin_hole_wave: WaveSigmas
    cycloid: CycloidFactors
    linear_factors: np.ndarray  # (k,) int64
    linear_sens_arcmin_per_um: np.ndarray  # (k,)
    long_wave: bool
    box_muller: bool


class UnitDraw(NamedTuple):
    """What a unit's draw returns besides its errors: its crank-angle step, its involute and crank
    stages' lost motion (the linear model's sum) [arcmin], the crank-bearing clearance drawn [um]."""

    crank_step: int
    linear_arcmin: float
    crank_clearance_um: float


class DrawScratch(NamedTuple):
    """The arrays draw_unit works in (allocated once per kernel call, ``draw_scratch``)."""

    pin_element_um: np.ndarray  # (z_p) the pin holes' per-element tangential parts
    pin_radial_element_um: np.ndarray  # (z_p) and radial parts
    tooth_element_um: np.ndarray  # (z_c) a disc's per-element parts
    tooth_radial_um: np.ndarray  # (z_c) a disc's radial deviations (computed, not used: teeth have none)
    no_radial_um: np.ndarray  # (z_c) zeros
    pin_harmonics: Harmonics
    tooth_harmonics: Harmonics
    normals: np.ndarray  # (4 + 2 max(z_p, z_c)) one stream's standard normals, in draw order


def factor_laws(problem: Problem, error_model: str, box_muller: bool) -> FactorLaws:
    """The FactorLaws of a design: every factor's marginal (the registry's ``kernel_draw``; a
    table only where a law has no branch of its own), the long-wave calibration of its indexed
    parts (``long_wave``: pin radius and clearance then truncated to their zones, a conforming
    part)."""
    zones = problem.zones
    n = len(zones)
    code = np.zeros(n, dtype=np.int64)
    loc, scale, lower, upper = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    tables = np.zeros((n, TABLE_POINTS))
    for i, z in enumerate(zones):
        law = kernel_draw(z)
        code[i], loc[i], scale[i], lower[i], upper[i] = law
        if law.code == KERNEL_TABLE:
            tables[i] = ppf_table(z)
    long_wave = error_model == "long_wave"
    waves = [WaveSigmas(0.0, 0.0, 0.0, 0.0)] * 2
    if long_wave:
        for key in ("pin_radius", "pin_hole_clearance"):  # a normal reading truncated to its zone
            i = IDX[key]
            if code[i] == KERNEL_NORMAL and zones[i].upper_um > zones[i].lower_um:
                code[i], lower[i], upper[i] = KERNEL_TRUNCNORM, zones[i].lower_um, zones[i].upper_um
        for row, part in enumerate((problem.contact_errors.disc, problem.contact_errors.pin_holes)):
            h = calibrate(part)
            waves[row] = WaveSigmas(h.first_um, h.second_um, h.element_um, h.radial_element_um)
    linear = np.array([IDX[k] for k in LINEAR_KEYS], dtype=np.int64)
    sens = problem.sensitivities_arcmin_per_um
    return FactorLaws(code=code, loc=loc, scale=scale, lower=lower, upper=upper, ppf_table=tables, disc_wave=waves[0],
                      pin_hole_wave=waves[1], cycloid=CYCLOID_FACTORS, linear_factors=linear,
                      linear_sens_arcmin_per_um=np.ascontiguousarray(sens[linear]),
                      long_wave=long_wave, box_muller=bool(box_muller))


@njit(nogil=True, cache=True, inline="always")
def _normal(streams, f, bm):
    """A standard normal from stream f: the ziggurat, or Box-Muller (Sun et al. Eq. 8) on two
    uniforms of the stream when ``bm``."""
    if bm:
        return box_muller_normal(stream_uniform(streams, f), stream_uniform(streams, f))
    return stream_normal(streams, f)


@njit(nogil=True, cache=True, inline="always")
def draw(streams, laws, f):
    """One draw of factor f's marginal from stream f of ``streams`` (branches:
    factors.distributions.KERNEL_*); truncated normal by rejection; any other law from its inverse
    cdf tabulated in laws.ppf_table[f]."""
    code, bm = laws.code[f], laws.box_muller
    if code == 0:
        return laws.loc[f]
    if code == 1:
        return laws.loc[f] + laws.scale[f] * _normal(streams, f, bm)
    if code == 2:
        return laws.lower[f] + (laws.upper[f] - laws.lower[f]) * stream_uniform(streams, f)
    if code == 3:
        while True:
            x = laws.loc[f] + laws.scale[f] * _normal(streams, f, bm)
            if laws.lower[f] <= x <= laws.upper[f]:
                return x
    if code == 4:
        return laws.loc[f] + laws.scale[f] * math.sqrt(-2.0 * math.log(1.0 - stream_uniform(streams, f)))
    table = laws.ppf_table[f]
    t = stream_uniform(streams, f) * table.size - 0.5  # KERNEL_TABLE: linear interpolation between the tabulated points
    i = min(max(int(math.floor(t)), 0), table.size - 2)
    w = min(max(t - i, 0.0), 1.0)
    return table[i] + w * (table[i + 1] - table[i])


@njit(nogil=True, cache=True)
def draw_many(streams, laws, f, out, m):
    """out[:m] <- m draws of factor f's marginal from stream f (``draw``, in order): normal and
    truncated-normal laws in one pass with the stream's state in registers (stream_normals)."""
    code = laws.code[f]
    if not laws.box_muller and code == 1:
        stream_normals(streams, f, laws.loc[f], laws.scale[f], -np.inf, np.inf, out, m)
    elif not laws.box_muller and code == 3:
        stream_normals(streams, f, laws.loc[f], laws.scale[f], laws.lower[f], laws.upper[f], out, m)
    else:
        for i in range(m):
            out[i] = draw(streams, laws, f)


@njit(nogil=True, cache=True)
def standard_normals(streams, f, bm, out, m):
    """out[:m] <- m standard normals from stream f (a long-wave part's harmonics and per-element
    parts), as ``draw`` of a N(0, 1) law would draw them."""
    if not bm:
        stream_normals(streams, f, 0.0, 1.0, -np.inf, np.inf, out, m)
    else:
        for i in range(m):
            out[i] = 0.0 + 1.0 * _normal(streams, f, bm)


@njit(nogil=True, cache=True)
def draw_scratch(zp, zc):
    """DrawScratch of a stage of z_p pins and z_c teeth per disc."""
    return DrawScratch(np.empty(zp), np.empty(zp), np.empty(zc), np.empty(zc), np.zeros(zc), element_harmonics(zp),
                       element_harmonics(zc), np.empty(4 + 2 * max(zp, zc)))


@njit_borrowing(nogil=True, cache=True)
def draw_unit(streams, laws, steps, unit, scratch):
    """Draw one unit's errors into ``unit`` (its UnitErrors record; the kinematic errors are left as
    they are) and return its UnitDraw (the crank angle in ``steps`` steps per pin pitch). Each
    factor draws from its own stream."""
    zp, zc, discs = unit.pin_radial_um.size, unit.tooth_pitch_um.shape[1], unit.tooth_pitch_um.shape[0]
    dr, dt, rho, cl, teeth = unit.pin_radial_um, unit.pin_tangential_um, unit.pin_radius_um, unit.pin_clearance_um, \
        unit.tooth_pitch_um
    z = scratch.normals
    hd, hp, fa = laws.disc_wave, laws.pin_hole_wave, laws.cycloid
    step = int(steps * stream_uniform(streams, CRANK_STREAM))
    lin = 0.0  # the stages that enter linearly
    crank = 0.0
    for m in range(laws.linear_factors.size):
        f = laws.linear_factors[m]
        x = draw(streams, laws, f)
        lin += laws.linear_sens_arcmin_per_um[m] * x
        if f == CRANK_CLEARANCE:
            crank = x
    eq0 = draw(streams, laws, fa.equidistance)
    md0 = draw(streams, laws, fa.moving_distance)
    # the pins and their holes
    # each stream's draws in one pass (the factors' streams are independent: their order across
    # streams does not change a number)
    if laws.long_wave:
        common = draw(streams, laws, fa.pin_circle)
        standard_normals(streams, fa.pin_pitch, laws.box_muller, z, 4 + 2 * zp)  # ux, uy, cx, cy, (s_j, q_j)
        s_p, q_p = scratch.pin_element_um, scratch.pin_radial_element_um
        for j in range(zp):
            s_p[j] = hp.element_um * z[4 + 2 * j]
            q_p[j] = hp.radial_element_um * z[5 + 2 * j]
        harmonic_deviations(Wave(hp.first_um * z[0], hp.first_um * z[1], hp.second_um * z[2], hp.second_um * z[3]),
                            s_p, q_p, scratch.pin_harmonics, dt, dr)
        for j in range(zp):
            dr[j] += common
    else:
        draw_many(streams, laws, fa.pin_circle, dr, zp)
        draw_many(streams, laws, fa.pin_pitch, dt, zp)
    draw_many(streams, laws, fa.pin_radius, rho, zp)
    draw_many(streams, laws, fa.pin_clearance, cl, zp)
    # the discs
    for d in range(discs):
        unit.equidistance_um[d] = eq0 + draw(streams, laws, fa.equidistance_error)
        unit.moving_distance_um[d] = md0 + draw(streams, laws, fa.moving_distance_error)
        unit.runout_along_um[d] = 0.5 * draw(streams, laws, fa.disc_runout)
        unit.runout_across_um[d] = 0.5 * draw(streams, laws, fa.disc_runout)
        unit.eccentricity_error_um[d] = draw(streams, laws, fa.crank_eccentricity)
        if laws.long_wave:
            standard_normals(streams, fa.disc_pitch, laws.box_muller, z, 4 + zc)  # ux, uy, cx, cy, s_k
            s_c = scratch.tooth_element_um
            for k in range(zc):
                s_c[k] = hd.element_um * z[4 + k]
            harmonic_deviations(Wave(hd.first_um * z[0], hd.first_um * z[1], hd.second_um * z[2],
                                     hd.second_um * z[3]), s_c, scratch.no_radial_um, scratch.tooth_harmonics,
                                teeth[d], scratch.tooth_radial_um)
        else:
            draw_many(streams, laws, fa.disc_pitch, teeth[d], zc)
    return UnitDraw(step, lin, crank)
