"""Monte-Carlo of the contact model through the engine: a block source whose outputs are the
backlash of every unit [arcmin], the backlash of the units whose cycloid stage is free, and the
preload of the others [um].

Every catalog factor draws from a random stream of its own, and the crank angle of the
measurement from one more (``SeedSequence(seed, spawn_key=(*stream, block, factor))``): a
factor's values do not depend on the others' draws, so that a factor can be redrawn alone
(global sensitivity: a factor with per-pin or per-tooth draws is one group).

What a unit draws (docs/contact.md, "Part errors"):
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
clearance (20) enter linearly, as in the linear model. The crank angle is uniform over one
pin pitch in CRANK_STEPS steps (the geometry repeats every pin pitch).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

from rvbacklash._numba import njit, njit_borrowing
import numpy as np
from numpy.random import SeedSequence

from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.factors.distributions import (KERNEL_NORMAL, KERNEL_TABLE, KERNEL_TRUNCNORM, TABLE_POINTS,
                                              kernel_draw, ppf_table)
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models.contact import Realization, mesh_table, stage_play, stage_work
from rvbacklash.problem import Problem
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import (states_from_generators, stream_normal, stream_normals, stream_states,
                                              stream_uniform)
from rvbacklash.sampling.kernels import box_muller_normal
from rvbacklash.sampling.part_errors import calibrate, harmonic_deviations
from rvbacklash.units import ARCMIN_PER_RAD

IDX = {f.key: f.id - 1 for f in CATALOG}
CRANK_STREAM = len(CATALOG)  # the stream after the 21 factors': the crank angle of the measurement
N_STREAMS = len(CATALOG) + 1
CRANK_STEPS = 256  # crank-angle steps per pin pitch
# units per engine block (the engine's default is 65 536): ~40 ms of contact work per block (0.25 s
# of elastic work), so that both cores share even a short run and the pilot block is not a run of
# its own. Part of the numbers' contract (block b draws from spawn key (*stream, b)); the elastic
# and transmission-error sources cut the same blocks, so that they draw the same units.
BLOCK_UNITS = 4096
ERROR_MODELS = ("long_wave", "independent")
STAGE2_ORDER = ("disc_cumulative_pitch", "equidistance_modification", "moving_distance_modification", "disc_runout",
                "pin_circle_radius", "pin_radius", "pin_hole_clearance", "pin_cumulative_pitch",
                "equidistance_modification_error", "moving_distance_modification_error", "crank_eccentricity")
LINEAR_KEYS = tuple(f.key for f in CATALOG if f.stage.label in ("involute", "crank") and f.key != "crank_eccentricity")


def block_streams(seed: int, block: int, stream: tuple[int, ...] = (), swap: tuple[int, ...] = (),
                  swap_stream: tuple[int, ...] = ()) -> np.ndarray:
    """The streams of block ``block`` (N_STREAMS, 4): one xoshiro256++ state per catalog factor and
    one for the crank angle (``fast_normals.stream_states``), each from
    ``SeedSequence(seed, spawn_key=(*stream, block, f))``. Factors listed in ``swap`` draw from
    ``swap_stream`` instead (a Sobol-type redraw)."""
    return stream_states([SeedSequence(seed, spawn_key=(*(swap_stream if f in swap else stream), block, f))
                          for f in range(N_STREAMS)])


def marginal_table(problem: Problem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(code[21], params[21, 4], ppf tables[21, T]) of every factor's marginal for the compiled
    sampler (the registry's ``kernel_draw``); a table only where a law has no branch of its own."""
    zones = problem.zones
    codes = np.zeros(len(zones), dtype=np.int64)
    params = np.zeros((len(zones), 4))
    tables = np.zeros((len(zones), TABLE_POINTS))
    for i, z in enumerate(zones):
        codes[i], params[i] = kernel_draw(z)
        if codes[i] == KERNEL_TABLE:
            tables[i] = ppf_table(z)
    return codes, params, tables


def within_zone(problem: Problem, key: str, codes: np.ndarray, params: np.ndarray) -> None:
    """A normal reading of ``key`` truncated to its zone (a conforming part), in place."""
    i = IDX[key]
    z = problem.zones[i]
    if codes[i] == KERNEL_NORMAL and z.upper_um > z.lower_um:
        codes[i] = KERNEL_TRUNCNORM
        params[i] = (params[i, 0], params[i, 1], z.lower_um, z.upper_um)


@njit(nogil=True, cache=True, inline="always")
def _normal(streams, f, bm):
    """A standard normal from stream f: the ziggurat, or Box-Muller (Sun et al. Eq. 8) on two
    uniforms of the stream when ``bm``."""
    if bm:
        return box_muller_normal(stream_uniform(streams, f), stream_uniform(streams, f))
    return stream_normal(streams, f)


@njit(nogil=True, cache=True, inline="always")
def draw(streams, f, code, p0, p1, p2, p3, bm, table):
    """One draw of a factor's marginal from stream f of ``streams`` (branches:
    factors.distributions.KERNEL_*); truncated normal by rejection; any other law from its inverse
    cdf tabulated in ``table``."""
    if code == 0:
        return p0
    if code == 1:
        return p0 + p1 * _normal(streams, f, bm)
    if code == 2:
        return p0 + (p1 - p0) * stream_uniform(streams, f)
    if code == 3:
        while True:
            x = p0 + p1 * _normal(streams, f, bm)
            if p2 <= x <= p3:
                return x
    if code == 4:
        return p0 + p1 * math.sqrt(-2.0 * math.log(1.0 - stream_uniform(streams, f)))
    t = stream_uniform(streams, f) * table.size - 0.5  # KERNEL_TABLE: linear interpolation between the tabulated points
    i = min(max(int(math.floor(t)), 0), table.size - 2)
    w = min(max(t - i, 0.0), 1.0)
    return table[i] + w * (table[i + 1] - table[i])


@njit(nogil=True, cache=True)
def draw_many(streams, f, code, p0, p1, p2, p3, bm, table, out, m):
    """out[:m] <- m draws of a factor's marginal from stream f (``draw``, in order): normal and
    truncated-normal laws in one pass with the stream's state in registers (stream_normals)."""
    if not bm and code == 1:
        stream_normals(streams, f, p0, p1, -np.inf, np.inf, out, m)
    elif not bm and code == 3:
        stream_normals(streams, f, p0, p1, p2, p3, out, m)
    else:
        for i in range(m):
            out[i] = draw(streams, f, code, p0, p1, p2, p3, bm, table)


@njit(nogil=True, cache=True)
def unit_scratch(zp, zc, discs):
    """The arrays one unit's errors are drawn into: dr, dt, rho, cl (z_p), teeth (discs, z_c), eq,
    md, ux, uy, da (discs), and the scratch of draw_unit and stage_play (the last: a stream's normals)."""
    return (np.empty(zp), np.empty(zp), np.empty(zp), np.empty(zp), np.empty((discs, zc)), np.empty(discs),
            np.empty(discs), np.empty(discs), np.empty(discs), np.empty(discs),
            np.empty(zp), np.empty(zp), np.empty(zc), np.empty(zc), np.zeros(zc), harmonics_trig(zp),
            harmonics_trig(zc), np.empty((discs, zp)), np.empty((discs, zp)), stage_work(discs, zp), np.empty(7),
            np.empty(4 + 2 * max(zp, zc)))


@njit(nogil=True, cache=True)
def harmonics_trig(n):
    """(4, n): cos theta_k, sin theta_k, cos 2 theta_k, sin 2 theta_k (part_errors.harmonics_table)."""
    out = np.empty((4, n))
    for k in range(n):
        th = 2.0 * math.pi * k / n
        out[0, k], out[1, k], out[2, k], out[3, k] = math.cos(th), math.sin(th), math.cos(2 * th), math.sin(2 * th)
    return out


@njit_borrowing(nogil=True, cache=True)
def draw_unit(streams, bm, long_wave, codes, params, tables, harmonics, linear_idx, linear_sens, idx, zp, zc, discs,
              steps, sc):
    """Draw one unit's errors into the arrays of ``sc`` (unit_scratch); returns (crank-angle step,
    linear stages [arcmin], the crank-bearing clearance drawn [um], eq, md). The linear stages are
    the factors of ``linear_idx`` (LINEAR_KEYS: stage 1, then the crank-bearing clearance, the
    last). ``idx`` holds the catalog indices of STAGE2_ORDER,
    ``harmonics`` (2, 4) the sigmas [first, second, element, radial element] of the disc teeth
    and of the pin holes (part_errors). Each factor draws from its own stream."""
    dr, dt, rho, cl, teeth, eq, md, ux, uy, da, s_p, q_p, s_c, tr, zeros_z, trig_p, trig_c = sc[:17]
    z = sc[21]
    # each stage-2 factor's stream, law and table, hoisted out of the loops (STAGE2_ORDER)
    g_pitch, c_pitch, p_pitch, t_pitch = idx[0], codes[idx[0]], params[idx[0]], tables[idx[0]]
    g_eq, c_eq, p_eq, t_eq = idx[1], codes[idx[1]], params[idx[1]], tables[idx[1]]
    g_md, c_md, p_md, t_md = idx[2], codes[idx[2]], params[idx[2]], tables[idx[2]]
    g_ro, c_ro, p_ro, t_ro = idx[3], codes[idx[3]], params[idx[3]], tables[idx[3]]
    g_rad, c_rad, p_rad, t_rad = idx[4], codes[idx[4]], params[idx[4]], tables[idx[4]]
    g_rho, c_rho, p_rho, t_rho = idx[5], codes[idx[5]], params[idx[5]], tables[idx[5]]
    g_cl, c_cl, p_cl, t_cl = idx[6], codes[idx[6]], params[idx[6]], tables[idx[6]]
    g_t, c_t, p_t, t_t = idx[7], codes[idx[7]], params[idx[7]], tables[idx[7]]
    g_eqe, c_eqe, p_eqe, t_eqe = idx[8], codes[idx[8]], params[idx[8]], tables[idx[8]]
    g_mde, c_mde, p_mde, t_mde = idx[9], codes[idx[9]], params[idx[9]], tables[idx[9]]
    g_da, c_da, p_da, t_da = idx[10], codes[idx[10]], params[idx[10]], tables[idx[10]]
    hd, hp = harmonics[0], harmonics[1]
    step = int(steps * stream_uniform(streams, CRANK_STREAM))
    lin = 0.0
    last = 0.0
    for m in range(linear_idx.size):
        f = linear_idx[m]
        last = draw(streams, f, codes[f], params[f, 0], params[f, 1], params[f, 2], params[f, 3], bm, tables[f])
        lin += linear_sens[m] * last
    eq0 = draw(streams, g_eq, c_eq, p_eq[0], p_eq[1], p_eq[2], p_eq[3], bm, t_eq)
    md0 = draw(streams, g_md, c_md, p_md[0], p_md[1], p_md[2], p_md[3], bm, t_md)
    # the pins and their holes
    # each stream's draws in one pass (the factors' streams are independent: their order across
    # streams does not change a number)
    if long_wave:
        common = draw(streams, g_rad, c_rad, p_rad[0], p_rad[1], p_rad[2], p_rad[3], bm, t_rad)
        draw_many(streams, g_t, 1, 0.0, 1.0, 0.0, 0.0, bm, t_t, z, 4 + 2 * zp)  # hx, hy, cx, cy, (s_j, q_j)
        for j in range(zp):
            s_p[j] = hp[2] * z[4 + 2 * j]
            q_p[j] = hp[3] * z[5 + 2 * j]
        harmonic_deviations(hp[0] * z[0], hp[0] * z[1], hp[1] * z[2], hp[1] * z[3], s_p, q_p, trig_p, dt, dr)
        for j in range(zp):
            dr[j] += common
    else:
        draw_many(streams, g_rad, c_rad, p_rad[0], p_rad[1], p_rad[2], p_rad[3], bm, t_rad, dr, zp)
        draw_many(streams, g_t, c_t, p_t[0], p_t[1], p_t[2], p_t[3], bm, t_t, dt, zp)
    draw_many(streams, g_rho, c_rho, p_rho[0], p_rho[1], p_rho[2], p_rho[3], bm, t_rho, rho, zp)
    draw_many(streams, g_cl, c_cl, p_cl[0], p_cl[1], p_cl[2], p_cl[3], bm, t_cl, cl, zp)
    # the discs
    for d in range(discs):
        eq[d] = eq0 + draw(streams, g_eqe, c_eqe, p_eqe[0], p_eqe[1], p_eqe[2], p_eqe[3], bm, t_eqe)
        md[d] = md0 + draw(streams, g_mde, c_mde, p_mde[0], p_mde[1], p_mde[2], p_mde[3], bm, t_mde)
        ux[d] = 0.5 * draw(streams, g_ro, c_ro, p_ro[0], p_ro[1], p_ro[2], p_ro[3], bm, t_ro)
        uy[d] = 0.5 * draw(streams, g_ro, c_ro, p_ro[0], p_ro[1], p_ro[2], p_ro[3], bm, t_ro)
        da[d] = draw(streams, g_da, c_da, p_da[0], p_da[1], p_da[2], p_da[3], bm, t_da)
        if long_wave:
            draw_many(streams, g_pitch, 1, 0.0, 1.0, 0.0, 0.0, bm, t_pitch, z, 4 + zc)  # hx, hy, cx, cy, s_k
            for k in range(zc):
                s_c[k] = hd[2] * z[4 + k]
            harmonic_deviations(hd[0] * z[0], hd[0] * z[1], hd[1] * z[2], hd[1] * z[3], s_c, zeros_z, trig_c, teeth[d],
                                tr)
        else:
            draw_many(streams, g_pitch, c_pitch, p_pitch[0], p_pitch[1], p_pitch[2], p_pitch[3], bm, t_pitch, teeth[d],
                      zc)
    return step, lin, last, eq0, md0


@njit(nogil=True, cache=True)
def save_unit(row, step, lin, eq0, md0, sc, zp, zc, discs, stage, crank):
    """One unit's errors into a row of the --save-units record (ContactBlockSource.saved_units)."""
    dr, dt, rho, cl, teeth, eq, md, ux, uy, da = sc[:10]
    row[0] = step
    row[1] = lin
    row[2] = eq0
    row[3] = md0
    c = 4
    for d in range(discs):
        row[c] = eq[d]
        row[c + 1] = md[d]
        row[c + 2] = ux[d]
        row[c + 3] = uy[d]
        row[c + 4] = da[d]
        c += 5
    for arr in (dr, dt, rho, cl):
        for j in range(zp):
            row[c] = arr[j]
            c += 1
    for d in range(discs):
        for k in range(zc):
            row[c] = teeth[d, k]
            c += 1
    row[c] = stage
    row[c + 1] = crank


@njit(nogil=True, cache=True)
def contact_block(streams, n, bm, long_wave, codes, params, tables, harmonics, linear_idx, linear_sens, idx,
                  a, rp, zc, zp, discs, azc_um, coef, out, save):
    """n units: out[0] backlash of every unit [arcmin], out[1] the same of the units whose cycloid
    stage is free (NaN if preloaded), out[2] preload [um] (NaN if free). The first save.shape[0]
    units are recorded in ``save`` (save_unit)."""
    sc = unit_scratch(zp, zc, discs)
    dr, dt, rho, cl, teeth, eq, md, ux, uy, da = sc[:10]
    gap, lever, work, res = sc[17], sc[18], sc[19], sc[20]
    steps = coef.shape[0]
    for s in range(n):
        step, lin, crank, eq0, md0 = draw_unit(streams, bm, long_wave, codes, params, tables, harmonics, linear_idx,
                                           linear_sens, idx, zp, zc, discs, steps, sc)
        stage_play(coef[step], a, rp, zc, zp, discs, azc_um, dr, dt, rho, cl, teeth, eq, md, ux, uy, da,
                   gap, lever, work, res)
        if math.isnan(res[0]):
            out[0, s] = lin
            out[1, s] = np.nan
            out[2, s] = res[2]
            stage = -res[2]
        else:
            stage = (res[0] + res[1]) * ARCMIN_PER_RAD
            out[0, s] = lin + stage
            out[1, s] = out[0, s]
            out[2, s] = np.nan
        if s < save.shape[0]:
            save_unit(save[s], step, lin, eq0, md0, sc, zp, zc, discs, stage, crank)


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


def save_width(g: ContactGeometry) -> int:
    return 4 + 5 * g.discs + 4 * g.zp + g.discs * g.zc + 2


@dataclass(frozen=True, eq=False)
class ContactBlockSource:
    """Block source of the engine for the contact model (methods: default, box-muller)."""

    method: str
    seed: int
    stream: tuple[int, ...]
    geometry: ContactGeometry
    error_model: str
    codes: np.ndarray
    params: np.ndarray
    ppf_tables: np.ndarray
    harmonics: np.ndarray  # (2, 4): disc teeth, pin holes
    linear_idx: np.ndarray
    linear_sens: np.ndarray
    coef: np.ndarray  # mesh_table at the crank-angle steps
    save_units: int = 0  # record the errors of the first units of the run
    saved: dict = field(default_factory=dict)  # block -> its recorded rows (the first blocks)
    swap: tuple[int, ...] = ()  # factors drawn from ``swap_stream`` (Sobol redraws)
    swap_stream: tuple[int, ...] = ()
    outputs: tuple[Output, ...] = CONTACT_OUTPUTS
    block_size: int = BLOCK_UNITS

    def block(self, b: int, n: int) -> np.ndarray:
        """(3, n) outputs of block b (CONTACT_OUTPUTS)."""
        g = self.geometry
        out = np.empty((len(self.outputs), n))
        nsave = units_to_save(self.save_units, self.block_size, b, n)
        save = np.empty((nsave, save_width(g)))
        contact_block(block_streams(self.seed, b, self.stream, self.swap, self.swap_stream), n,
                      self.method == "box-muller", self.error_model == "long_wave", self.codes, self.params,
                      self.ppf_tables, self.harmonics, self.linear_idx, self.linear_sens,
                      np.array([IDX[k] for k in STAGE2_ORDER]), g.a_mm, g.rp_mm, g.zc, g.zp, g.discs,
                      g.pitch_radius_um, self.coef, out, save)
        if nsave:
            self.saved[b] = save
        return out

    def crank_angle_rad(self, step: int) -> float:
        return 2.0 * math.pi / self.geometry.zp * (step + 0.5) / self.coef.shape[0]

    def saved_units(self) -> list[tuple[Realization, float, float]]:
        """The recorded units, in run order: (errors, linear stages [arcmin], cycloid stage [arcmin]
        as the kernel found it, or -preload [um] when preloaded)."""
        g = self.geometry
        out = []
        for row in (row for b in sorted(self.saved) for row in self.saved[b]):
            c = 4
            per_disc = np.asarray(row[c:c + 5 * g.discs]).reshape(g.discs, 5)
            c += 5 * g.discs
            dr, dt, rho, cl = (np.array(row[c + i * g.zp:c + (i + 1) * g.zp]) for i in range(4))
            c += 4 * g.zp
            teeth = np.array(row[c:c + g.discs * g.zc]).reshape(g.discs, g.zc)
            r = Realization(self.crank_angle_rad(int(row[0])), dr, dt, rho, cl, teeth, per_disc[:, 2:4].copy(),
                            per_disc[:, 4].copy(), per_disc[:, 0].copy(), per_disc[:, 1].copy(),
                            crank_clearance_um=float(row[-1]))
            out.append((r, float(row[1]), float(row[-2])))
        return out


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
    codes, params, ppf = marginal_table(problem)
    harmonics = np.zeros((2, 4))
    if model == "long_wave":
        for key in ("pin_radius", "pin_hole_clearance"):
            within_zone(problem, key, codes, params)
        for row, part in enumerate((problem.contact_errors.disc, problem.contact_errors.pin_holes)):
            h = calibrate(part)
            harmonics[row] = (h.first_um, h.second_um, h.element_um, h.radial_element_um)
    linear_idx = np.array([IDX[k] for k in LINEAR_KEYS])
    return ContactBlockSource(method, seed, tuple(stream), g, model, codes, params, ppf, harmonics, linear_idx,
                              np.ascontiguousarray(problem.sensitivities_arcmin_per_um[linear_idx]),
                              crank_mesh_table(g), int(save_units), {}, tuple(swap), tuple(swap_stream))


@lru_cache(maxsize=8)
def crank_mesh_table(g: ContactGeometry) -> np.ndarray:
    """``models.contact.mesh_table`` at the CRANK_STEPS crank angles the units are drawn at,
    chi_s = 2 pi / z_p (s + 1/2) / CRANK_STEPS: the same for every run of a geometry, so built once
    per process (~10 ms, as long as 2000 contact units take on two threads: an allocation's
    candidates share it). Shared between runs: the kernels only read it."""
    chis = 2.0 * math.pi / g.zp * (np.arange(CRANK_STEPS) + 0.5) / CRANK_STEPS
    return mesh_table(g, chis)


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
        contact_block(states_from_generators(generators), n, False, s.error_model == "long_wave", s.codes, s.params,
                      s.ppf_tables, s.harmonics, s.linear_idx, s.linear_sens, np.array([IDX[k] for k in STAGE2_ORDER]), g.a_mm,
                      g.rp_mm, g.zc, g.zp, g.discs, g.pitch_radius_um, s.coef, out, np.empty((0, save_width(g))))
        return out


def contact_streams(problem: Problem, error_model: str | None = None) -> ContactStreams:
    source = contact_source(problem, "default", 0, error_model=error_model)
    random = tuple(bool(x) for x in problem.random_mask) + (True,)
    return ContactStreams(source, random)
