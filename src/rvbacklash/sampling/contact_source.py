"""Monte-Carlo of the contact model through the same engine: a block source whose values are
the output backlash [arcmin] of independent realisations of every per-pin and per-tooth error.

Each pin draws its own radial position (factor 14's zone), tangential position (17), radius
(15) and hole clearance (16); each disc its own cumulative pitch error per tooth space (10),
run-out vector (13: two components, each half a draw of the phase-weighted reading, i.e. a
Rayleigh magnitude with a uniform direction for normal readings), crank eccentricity error (21)
and modification errors (18, 19); the modifications themselves (11, 12) are drawn once per
reducer (one grinding set-up). The crank angle of the measurement is uniform. Stage 1 and the
crank bearing clearance (20) enter linearly, as in the linear model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.factors.distributions import KERNEL_TABLE, TABLE_POINTS, kernel_draw, ppf_table
from rvbacklash.geometry.cycloid import ContactGeometry
from rvbacklash.models.contact import MIN_LEVER, N_COEF, disc_play, mesh_coefficients
from rvbacklash.problem import Problem
from rvbacklash.sampling.engine import Output, block_generator
from rvbacklash.sampling.kernels import box_muller_normal
from rvbacklash.units import ARCMIN_PER_RAD

IDX = {f.key: f.id - 1 for f in CATALOG}


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


@nb.njit(nogil=True, cache=True, inline="always")
def _normal(rng, bm):
    if bm:
        return box_muller_normal(rng.random(), rng.random())
    return rng.standard_normal()


@nb.njit(nogil=True, cache=True, inline="always")
def draw(rng, code, p0, p1, p2, p3, bm, table):
    """One draw of a factor's marginal (branches: factors.distributions.KERNEL_*); truncated
    normal by rejection; any other law from its inverse cdf tabulated in ``table``."""
    if code == 0:
        return p0
    if code == 1:
        return p0 + p1 * _normal(rng, bm)
    if code == 2:
        return p0 + (p1 - p0) * rng.random()
    if code == 3:
        while True:
            x = p0 + p1 * _normal(rng, bm)
            if p2 <= x <= p3:
                return x
    if code == 4:
        return p0 + p1 * math.sqrt(-2.0 * math.log(1.0 - rng.random()))
    t = rng.random() * table.size - 0.5  # KERNEL_TABLE: linear interpolation between the tabulated points
    i = min(max(int(math.floor(t)), 0), table.size - 2)
    f = min(max(t - i, 0.0), 1.0)
    return table[i] + f * (table[i + 1] - table[i])


CRANK_STEPS = 256  # crank-angle steps per pin pitch (the mesh geometry repeats every pin pitch)


@nb.njit(nogil=True, cache=True)
def mesh_tables(k1, azc_um, zc, discs, cos_psi, sin_psi, min_lever, steps):
    """Coefficients of every disc at ``steps`` crank angles spread over one pin pitch."""
    zp = cos_psi.size
    coef = np.empty((steps, discs, zp, N_COEF))
    pins = np.empty((steps, discs, zp), dtype=np.int64)
    count = np.empty((steps, discs), dtype=np.int64)
    for s in range(steps):
        chi = 2.0 * math.pi / zp * (s + 0.5) / steps
        for d in range(discs):
            count[s, d] = mesh_coefficients(chi + 2.0 * math.pi * d / discs, k1, azc_um, zc, cos_psi, sin_psi,
                                            min_lever, coef[s, d], pins[s, d])
    return coef, pins, count


@nb.njit(nogil=True, cache=True)
def contact_block(rng, n, bm, codes, params, tables, linear_idx, linear_sens, azc_over_rp, azc_um, zp, zc, discs,
                  coef, pins, count, idx, out):
    """Outputs of n independent realisations: out[0] output backlash [arcmin] of every unit,
    out[1] the same for units whose cycloid stage is free (NaN if preloaded), out[2] preload
    [um] (NaN if free). The catalog indices in idx are idx holds the catalog indices of
    of [pitch_disc, eq, md, runout, pin_r, pin_rad, clear, pin_t, eq_err, md_err, ecc] (STAGE2_ORDER).
    The crank angle is uniform over one pin pitch in coef.shape[0] steps: the geometry repeats
    every pin pitch and the pins' errors are exchangeable, so that covers every position.
    A negative play of the cycloid stage means interference: that stage is preloaded and adds no
    lost motion (0); its preload is the interference at the disc pitch circle, -play a z_c."""
    dr = np.empty(zp)
    dt = np.empty(zp)
    rho = np.empty(zp)
    cl = np.empty(zp)
    teeth = np.empty(zc)
    res = np.empty(4)
    steps = coef.shape[0]
    nl = linear_idx.size
    lc = np.empty(nl, dtype=np.int64)
    lp = np.empty((nl, 4))
    lt = np.empty((nl, tables.shape[1]))
    for m in range(nl):
        lc[m] = codes[linear_idx[m]]
        lp[m] = params[linear_idx[m]]
        lt[m] = tables[linear_idx[m]]
    c = np.empty(11, dtype=np.int64)
    q = np.empty((11, 4))
    tb = np.empty((11, tables.shape[1]))
    for m in range(11):
        c[m] = codes[idx[m]]
        q[m] = params[idx[m]]
        tb[m] = tables[idx[m]]
    for s in range(n):
        step = int(steps * rng.random())
        lin = 0.0
        for m in range(nl):
            lin += linear_sens[m] * draw(rng, lc[m], lp[m, 0], lp[m, 1], lp[m, 2], lp[m, 3], bm, lt[m])
        eq = draw(rng, c[1], q[1, 0], q[1, 1], q[1, 2], q[1, 3], bm, tb[1])
        md = draw(rng, c[2], q[2, 0], q[2, 1], q[2, 2], q[2, 3], bm, tb[2])
        for j in range(zp):
            dr[j] = draw(rng, c[4], q[4, 0], q[4, 1], q[4, 2], q[4, 3], bm, tb[4])
            dt[j] = draw(rng, c[7], q[7, 0], q[7, 1], q[7, 2], q[7, 3], bm, tb[7])
            rho[j] = draw(rng, c[5], q[5, 0], q[5, 1], q[5, 2], q[5, 3], bm, tb[5])
            cl[j] = draw(rng, c[6], q[6, 0], q[6, 1], q[6, 2], q[6, 3], bm, tb[6])
        best_p = np.inf
        best_m = np.inf
        for d in range(discs):
            eqd = eq + draw(rng, c[8], q[8, 0], q[8, 1], q[8, 2], q[8, 3], bm, tb[8])
            mdd = md + draw(rng, c[9], q[9, 0], q[9, 1], q[9, 2], q[9, 3], bm, tb[9])
            ux = 0.5 * draw(rng, c[3], q[3, 0], q[3, 1], q[3, 2], q[3, 3], bm, tb[3])
            uy = 0.5 * draw(rng, c[3], q[3, 0], q[3, 1], q[3, 2], q[3, 3], bm, tb[3])
            da = draw(rng, c[10], q[10, 0], q[10, 1], q[10, 2], q[10, 3], bm, tb[10])
            for k in range(zc):
                teeth[k] = draw(rng, c[0], q[0, 0], q[0, 1], q[0, 2], q[0, 3], bm, tb[0])
            disc_play(coef[step, d], pins[step, d], count[step, d], azc_over_rp, eqd, mdd, dr, dt, rho, cl,
                      ux, uy, da, teeth, res)
            if res[0] < best_p:
                best_p = res[0]
            if res[1] < best_m:
                best_m = res[1]
        play = best_p + best_m
        if play < 0.0:
            out[0, s] = lin
            out[1, s] = np.nan
            out[2, s] = -play * azc_um
        else:
            out[0, s] = lin + play * ARCMIN_PER_RAD
            out[1, s] = out[0, s]
            out[2, s] = np.nan


STAGE2_ORDER = ("disc_cumulative_pitch", "equidistance_modification", "moving_distance_modification", "disc_runout",
                "pin_circle_radius", "pin_radius", "pin_hole_clearance", "pin_cumulative_pitch",
                "equidistance_modification_error", "moving_distance_modification_error", "crank_eccentricity")


CONTACT_OUTPUTS = (
    Output("backlash", "arcmin", "output backlash (rigid lost motion); a preloaded cycloid stage adds 0"),
    Output("backlash_free", "arcmin", "output backlash of the units whose cycloid stage is free", conditional=True),
    Output("preload", "um", "interference of a preloaded cycloid stage at the disc pitch circle", conditional=True,
           hint_range=(0.0, 50.0)),
)


@dataclass(frozen=True, eq=False)
class ContactBlockSource:
    """Block source of the engine for the contact model (methods: default, box-muller)."""

    method: str
    seed: int
    stream: tuple[int, ...]
    geometry: ContactGeometry
    codes: np.ndarray
    params: np.ndarray
    ppf_tables: np.ndarray
    linear_idx: np.ndarray
    linear_sens: np.ndarray
    tables: tuple  # (coef, pins, count) from mesh_tables
    outputs: tuple[Output, ...] = CONTACT_OUTPUTS

    def block(self, b: int, n: int) -> np.ndarray:
        """(3, n) outputs of block b (CONTACT_OUTPUTS)."""
        g = self.geometry
        out = np.empty((len(self.outputs), n))
        coef, pins, count = self.tables
        contact_block(block_generator(self.seed, b, self.stream), n, self.method == "box-muller", self.codes, self.params,
                      self.ppf_tables, self.linear_idx, self.linear_sens, g.a_mm * g.zc / g.rp_mm, g.pitch_radius_um,
                      g.zp, g.zc, g.discs, coef, pins, count, np.array([IDX[k] for k in STAGE2_ORDER]), out)
        return out


def contact_source(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = ()) -> ContactBlockSource:
    if method not in ("default", "box-muller"):
        raise InputError("method", method, "allowed with model 'contact': default, box-muller")
    if problem.correlated:
        raise InputError("correlation", "given", "the contact model draws independent per-pin errors; "
                                                 "remove [correlation] or use the linear model")
    geometry = problem.cycloid
    codes, params, ppf = marginal_table(problem)
    linear_keys = [f.key for f in CATALOG if f.stage.label in ("involute", "crank") and f.key != "crank_eccentricity"]
    linear_idx = np.array([IDX[k] for k in linear_keys])
    psi = geometry.pin_angles
    tables = mesh_tables(geometry.K1, geometry.pitch_radius_um, geometry.zc, geometry.discs,
                         np.cos(psi), np.sin(psi), MIN_LEVER, CRANK_STEPS)
    return ContactBlockSource(method, seed, tuple(stream), geometry, codes, params, ppf, linear_idx,
                              np.ascontiguousarray(problem.sensitivities_arcmin_per_um[linear_idx]), tables)
