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

from rvbacklash.design.derived import ResolvedZone
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.model.contact import MIN_LEVER, N_COEF, ContactGeometry, disc_play, mesh_coefficients
from rvbacklash.sampling.distributions import fixed_value_um, marginal
from rvbacklash.sampling.engine import block_generator
from rvbacklash.sampling.kernels import box_muller_normal
from rvbacklash.units import ARCMIN_PER_RAD

FIXED, NORMAL, UNIFORM, TRUNCNORM, RAYLEIGH = 0, 1, 2, 3, 4
IDX = {f.key: f.id - 1 for f in CATALOG}


def marginal_table(zones: tuple[ResolvedZone, ...]) -> tuple[np.ndarray, np.ndarray]:
    """(code[21], params[21, 4]) describing every factor's marginal for the compiled sampler."""
    codes = np.zeros(len(zones), dtype=np.int64)
    params = np.zeros((len(zones), 4))
    for i, z in enumerate(zones):
        d = marginal(z)
        if d is None:
            codes[i], params[i, 0] = FIXED, fixed_value_um(z)
            continue
        name = d.dist.name
        if name == "norm":
            codes[i], params[i, :2] = NORMAL, (float(d.mean()), float(d.std()))
        elif name == "uniform":
            codes[i], params[i, :2] = UNIFORM, (z.lower_um, z.upper_um)
        elif name == "truncnorm":
            loc, scale = d.kwds["loc"], d.kwds["scale"]
            codes[i], params[i] = TRUNCNORM, (loc, scale, z.lower_um, z.upper_um)
        elif name == "rayleigh":
            codes[i], params[i, :2] = RAYLEIGH, (d.kwds["loc"], d.kwds["scale"])
        else:  # pragma: no cover - every reading of the schema is handled above
            raise ValueError(name)
    return codes, params


@nb.njit(nogil=True, cache=True, inline="always")
def _normal(rng, bm):
    if bm:
        return box_muller_normal(rng.random(), rng.random())
    return rng.standard_normal()


@nb.njit(nogil=True, cache=True, inline="always")
def draw(rng, code, p0, p1, p2, p3, bm):
    """One draw of a factor's marginal (codes above); truncated normal by rejection."""
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
    return p0 + p1 * math.sqrt(-2.0 * math.log(1.0 - rng.random()))


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
def contact_block(rng, n, bm, codes, params, linear_idx, linear_sens, azc_over_rp, zp, zc, discs,
                  coef, pins, count, idx, out):
    """Output backlash [arcmin] of n independent realisations. idx holds the catalog indices of
    [pitch_disc, eq, md, runout, pin_r, pin_rad, clear, pin_t, eq_err, md_err, ecc] (STAGE2_ORDER).
    The crank angle is uniform over one pin pitch in coef.shape[0] steps: the geometry repeats
    every pin pitch and the pins' errors are exchangeable, so that covers every position.
    A negative play of the cycloid stage means interference: that stage is preloaded and adds no
    lost motion (0), and the realisation is counted; returns that count."""
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
    for m in range(nl):
        lc[m] = codes[linear_idx[m]]
        lp[m] = params[linear_idx[m]]
    c = np.empty(11, dtype=np.int64)
    q = np.empty((11, 4))
    for m in range(11):
        c[m] = codes[idx[m]]
        q[m] = params[idx[m]]
    preloaded = 0
    for s in range(n):
        step = int(steps * rng.random())
        lin = 0.0
        for m in range(nl):
            lin += linear_sens[m] * draw(rng, lc[m], lp[m, 0], lp[m, 1], lp[m, 2], lp[m, 3], bm)
        eq = draw(rng, c[1], q[1, 0], q[1, 1], q[1, 2], q[1, 3], bm)
        md = draw(rng, c[2], q[2, 0], q[2, 1], q[2, 2], q[2, 3], bm)
        for j in range(zp):
            dr[j] = draw(rng, c[4], q[4, 0], q[4, 1], q[4, 2], q[4, 3], bm)
            dt[j] = draw(rng, c[7], q[7, 0], q[7, 1], q[7, 2], q[7, 3], bm)
            rho[j] = draw(rng, c[5], q[5, 0], q[5, 1], q[5, 2], q[5, 3], bm)
            cl[j] = draw(rng, c[6], q[6, 0], q[6, 1], q[6, 2], q[6, 3], bm)
        best_p = np.inf
        best_m = np.inf
        for d in range(discs):
            eqd = eq + draw(rng, c[8], q[8, 0], q[8, 1], q[8, 2], q[8, 3], bm)
            mdd = md + draw(rng, c[9], q[9, 0], q[9, 1], q[9, 2], q[9, 3], bm)
            ux = 0.5 * draw(rng, c[3], q[3, 0], q[3, 1], q[3, 2], q[3, 3], bm)
            uy = 0.5 * draw(rng, c[3], q[3, 0], q[3, 1], q[3, 2], q[3, 3], bm)
            da = draw(rng, c[10], q[10, 0], q[10, 1], q[10, 2], q[10, 3], bm)
            for k in range(zc):
                teeth[k] = draw(rng, c[0], q[0, 0], q[0, 1], q[0, 2], q[0, 3], bm)
            disc_play(coef[step, d], pins[step, d], count[step, d], azc_over_rp, eqd, mdd, dr, dt, rho, cl,
                      ux, uy, da, teeth, res)
            if res[0] < best_p:
                best_p = res[0]
            if res[1] < best_m:
                best_m = res[1]
        play = best_p + best_m
        if play < 0.0:
            preloaded += 1
            play = 0.0
        out[s] = lin + play * ARCMIN_PER_RAD
    return preloaded


STAGE2_ORDER = ("disc_cumulative_pitch", "equidistance_modification", "moving_distance_modification", "disc_runout",
                "pin_circle_radius", "pin_radius", "pin_hole_clearance", "pin_cumulative_pitch",
                "equidistance_modification_error", "moving_distance_modification_error", "crank_eccentricity")


@dataclass(frozen=True, eq=False)
class ContactBlockSource:
    """Block source of the engine for the contact model (methods: default, box-muller)."""

    method: str
    seed: int
    geometry: ContactGeometry
    codes: np.ndarray
    params: np.ndarray
    linear_idx: np.ndarray
    linear_sens: np.ndarray

    tables: tuple  # (coef, pins, count) from mesh_tables

    def block(self, b: int, n: int) -> tuple[np.ndarray, int]:
        """Outputs of block b [arcmin] and how many realisations have a preloaded cycloid stage."""
        g = self.geometry
        out = np.empty(n)
        coef, pins, count = self.tables
        preloaded = contact_block(block_generator(self.seed, b), n, self.method == "box-muller", self.codes,
                                  self.params, self.linear_idx, self.linear_sens, g.a_mm * g.zc / g.rp_mm, g.zp, g.zc,
                                  g.discs, coef, pins, count, np.array([IDX[k] for k in STAGE2_ORDER]), out)
        return out, int(preloaded)

    def values(self, b: int, n: int) -> np.ndarray:
        return self.block(b, n)[0]


def make_contact_source(method: str, seed: int, geometry: ContactGeometry, zones, sensitivities: np.ndarray,
                        correlated: bool) -> ContactBlockSource:
    if method not in ("default", "box-muller"):
        raise InputError("--method", method, "allowed with --model contact: default, box-muller")
    if correlated:
        raise InputError("correlation", "given", "the contact model draws independent per-pin errors; "
                                                 "remove [correlation] or use --model linear")
    codes, params = marginal_table(zones)
    linear_keys = [f.key for f in CATALOG if f.stage.label in ("involute", "crank") and f.key != "crank_eccentricity"]
    linear_idx = np.array([IDX[k] for k in linear_keys])
    psi = geometry.pin_angles
    tables = mesh_tables(geometry.K1, geometry.a_mm * geometry.zc * 1e3, geometry.zc, geometry.discs,
                         np.cos(psi), np.sin(psi), MIN_LEVER, CRANK_STEPS)
    return ContactBlockSource(method, seed, geometry, codes, params, linear_idx,
                              np.ascontiguousarray(sensitivities[linear_idx]), tables)
