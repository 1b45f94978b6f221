"""Monte-Carlo of the transmission error through the engine (``--model transmission``, or
``--model contact`` with ``--spec-te-arcsec``; docs/transmission-error.md).

A unit draws exactly what the contact model draws (same streams, same numbers: ``draw_unit``),
plus the kinematic factors (factors.catalog.KINEMATIC_FACTORS), each from a stream of its own
after the contact model's (``SeedSequence(seed, spawn_key=(*stream, block, N_STREAMS + m))``).
Every unit then turns through one output revolution from the reference position (crank angle
0) at POSITIONS_PER_PIN x z_p positions, each flank's first contact linearised at its position
(``models.kinematics.te_curve`` with exact=False; the tests bound the difference to the exact
solve). Outputs per unit: the rigid backlash at the reference position (as the contact model's
``backlash``: the cycloid stage plus the involute and crank stages' linear part), the TE
peak-to-peak of the ccw flank [arcsec], the largest lost motion over the revolution.

Units are drawn serially (one stream per factor) in chunks and evaluated by a small thread pool
(the kernel is nogil): the numbers do not depend on the number of threads.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.random import SeedSequence

from rvbacklash._numba import njit
from rvbacklash.factors.catalog import KINEMATIC_FACTORS
from rvbacklash.errors import InputError
from rvbacklash.models.kinematics import (ARCSEC_PER_RAD, crank_fit, curve_scratch, kinematics, position_table,
                                          reference_revolution, te_curve)
from rvbacklash.problem import Problem
from rvbacklash.problem.kinematic_errors import kinematic_zones
from rvbacklash.sampling.chunked import draw_then_evaluate
from rvbacklash.sampling.contact_source import (BLOCK_UNITS, IDX, N_STREAMS, STAGE2_ORDER, ContactBlockSource, _normal,
                                                block_streams, contact_source, draw_unit, unit_scratch)
from rvbacklash.sampling.engine import Output
from rvbacklash.sampling.fast_normals import states_from_generators, stream_states
from rvbacklash.units import ARCMIN_PER_RAD

POSITIONS_PER_PIN = 8  # output positions per revolution = 8 z_p (320 for rv80e): orders below 4 z_p resolved
CHUNK = 256  # units drawn, then evaluated, at a time
EVAL_THREADS = 2

TE_OUTPUTS = (
    Output("backlash", "arcmin", "output backlash (rigid lost motion) at the reference position, every unit; a "
                                 "preloaded cycloid stage adds 0"),
    Output("transmission_error", "arcsec", "transmission error peak-to-peak over one output revolution (ccw flank)"),
    Output("lost_motion_max", "arcmin", "largest rigid lost motion over the output revolution"),
)


def te_streams(seed: int, block: int, stream: tuple[int, ...] = ()) -> np.ndarray:
    """The contact model's streams of block ``block`` and one per kinematic factor after them
    (N_STREAMS + len(KINEMATIC_FACTORS), 4)."""
    return np.concatenate([block_streams(seed, block, stream), stream_states(
        [SeedSequence(seed, spawn_key=(*stream, block, N_STREAMS + m)) for m in range(len(KINEMATIC_FACTORS))])])


@njit(nogil=True, cache=True)
def draw_chunk(streams, kin, m, long_wave, codes, params, tables, harmonics, linear_idx, linear_sens, idx, zp, zc,
               discs, planets, crank_radius_mm, sigmas, dr, dt, rho, cl, teeth, eq, md, ux, uy, da, lin, centre,
               planet, shift, turn):
    """m units into the arrays (first axis: unit): the contact model's draws (draw_unit, crank angle
    ignored: every unit starts at the reference position) and the kinematic factors' (``kin``: one
    xoshiro stream state each, KINEMATIC_FACTORS order; ``sigmas`` per component [um]), the holes reduced by
    crank_fit to each disc's shift and turn."""
    sc = unit_scratch(zp, zc, discs)
    hd = np.empty((discs, planets, 2))
    hc = np.empty((planets, 2))
    # False and one crank-angle step, but not literals: draw_unit then compiles once for all the kernels
    bm, steps = m < 0, np.int64(1)
    for s in range(m):
        _, lin[s], _, _, _ = draw_unit(streams, bm, long_wave, codes, params, tables, harmonics, linear_idx,
                                       linear_sens, idx, zp, zc, discs, steps, sc)
        dr[s, :] = sc[0]
        dt[s, :] = sc[1]
        rho[s, :] = sc[2]
        cl[s, :] = sc[3]
        teeth[s, :, :] = sc[4]
        eq[s, :] = sc[5]
        md[s, :] = sc[6]
        ux[s, :] = sc[7]
        uy[s, :] = sc[8]
        da[s, :] = sc[9]
        for c in range(2):
            centre[s, c] = sigmas[0] * _normal(kin, 0, False)
        for k in range(planets):
            for c in range(2):
                planet[s, k, c] = sigmas[1] * _normal(kin, 1, False)
        for d in range(discs):
            for k in range(planets):
                for c in range(2):
                    hd[d, k, c] = sigmas[2] * _normal(kin, 2, False)
        for k in range(planets):
            for c in range(2):
                hc[k, c] = sigmas[3] * _normal(kin, 3, False)
        crank_fit(hd, hc, crank_radius_mm, planets, discs, shift[s], turn[s])


@njit(nogil=True, cache=True)
def evaluate_chunk(m, coef, chis, thetas, a, rp, zc, zp, discs, azc_um, ratio, base_radius_mm, crank_radius_mm,
                   planets, dr, dt, rho, cl, teeth, eq, md, ux, uy, da, lin, centre, planet, shift, turn, ref_ccw, out):
    """TE_OUTPUTS of m drawn units into out (3, m)."""
    teeth_s, ux_s, uy_s, dchi, gap, lever, work, res = curve_scratch(zp, zc, discs, planets)
    n = chis.size
    ccw, cw, pre = np.empty(n), np.empty(n), np.empty(n)
    for s in range(m):
        te_curve(coef, chis, thetas, 0.0, a, rp, zc, zp, discs, azc_um, ratio, base_radius_mm, crank_radius_mm,
                 dr[s], dt[s], rho[s], cl[s], teeth[s], eq[s], md[s], ux[s], uy[s], da[s], centre[s], planet[s],
                 shift[s], turn[s], teeth_s, ux_s, uy_s, dchi, gap, lever, work, res, ccw, cw, pre, False)
        lo, hi, lm_max = np.inf, -np.inf, 0.0
        for k in range(n):
            v = ccw[k] - ref_ccw[k]
            lo = min(lo, v)
            hi = max(hi, v)
            lm_max = max(lm_max, ccw[k] - cw[k])
        out[0, s] = lin[s] + (ccw[0] - cw[0]) * ARCMIN_PER_RAD
        out[1, s] = (hi - lo) * ARCSEC_PER_RAD
        out[2, s] = lin[s] + lm_max * ARCMIN_PER_RAD


@dataclass(frozen=True, eq=False)
class TransmissionBlockSource:
    """Block source of the engine for the transmission error (method: default)."""

    contact: ContactBlockSource  # laws, error model, harmonics of the contact model
    sigmas_um: np.ndarray  # per component, KINEMATIC_FACTORS order
    ratio: float
    base_radius_mm: float
    crank_radius_mm: float
    planets: int
    table: tuple  # (theta, chi, mesh_table) of the positions
    ref_ccw_rad: np.ndarray  # the error-free unit's ccw flank at the positions
    outputs: tuple[Output, ...] = TE_OUTPUTS
    block_size: int = BLOCK_UNITS  # the contact model's blocks: the same units

    def _draw(self, streams: np.ndarray, m: int) -> tuple:
        c, g = self.contact, self.contact.geometry
        p = self.planets
        arrays = (np.empty((m, g.zp)), np.empty((m, g.zp)), np.empty((m, g.zp)), np.empty((m, g.zp)),
                  np.empty((m, g.discs, g.zc)), *(np.empty((m, g.discs)) for _ in range(5)), np.empty(m),
                  np.empty((m, 2)), np.empty((m, p, 2)), np.empty((m, g.discs, 2)), np.empty((m, g.discs)))
        draw_chunk(streams[:N_STREAMS], streams[N_STREAMS:], m, c.error_model == "long_wave", c.codes, c.params,
                   c.ppf_tables, c.harmonics, c.linear_idx, c.linear_sens, np.array([IDX[k] for k in STAGE2_ORDER]),
                   g.zp, g.zc, g.discs, p, self.crank_radius_mm, self.sigmas_um, *arrays)
        return arrays

    def _evaluate(self, arrays: tuple, out: np.ndarray) -> None:
        g = self.contact.geometry
        theta, chis, coef = self.table
        evaluate_chunk(out.shape[1], coef, chis, theta, g.a_mm, g.rp_mm, g.zc, g.zp, g.discs, g.pitch_radius_um,
                       self.ratio, self.base_radius_mm, self.crank_radius_mm, self.planets, *arrays, self.ref_ccw_rad,
                       out)

    def block(self, b: int, n: int) -> np.ndarray:
        """(3, n) outputs of block b (TE_OUTPUTS)."""
        c = self.contact
        streams = te_streams(c.seed, b, c.stream)
        out = np.empty((len(self.outputs), n))
        draw_then_evaluate(n, CHUNK, EVAL_THREADS, lambda start, m: self._draw(streams, m),
                           lambda start, units: self._evaluate(units, out[:, start:start + units[0].shape[0]]))
        return out

    def saved_units(self) -> list:
        return []


def transmission_source(problem: Problem, method: str, seed: int, stream: tuple[int, ...] = (),
                        save_units: int = 0, positions: int | None = None) -> TransmissionBlockSource:
    """The transmission-error model's block source (positions per revolution: POSITIONS_PER_PIN z_p)."""

    if method != "default":
        raise InputError("method", method, "allowed with the transmission-error model: default")
    if save_units:
        raise InputError("save_units", save_units, "allowed with the contact and elastic models")
    c = contact_source(problem, "default", seed, stream)
    g = problem.cycloid
    n = positions or POSITIONS_PER_PIN * g.zp
    table = position_table(g, n, 0.0)
    ref = reference_revolution(problem, n, 0.0, exact=False)
    k = kinematics(problem)
    sigmas = np.array([z.sigma_um for z in kinematic_zones(problem.design, problem.zones)])
    return TransmissionBlockSource(c, sigmas, k.ratio, k.base_radius_mm, k.crank_radius_mm, k.planets, table,
                                   ref.ccw_rad, TE_OUTPUTS)


def sample_units(problem: Problem, seed: int, n: int, stream: tuple[int, ...] = ()) -> list:
    """The first n units of block 0 of a production run (the same numbers ``simulate`` draws) as
    Realizations at the reference position (crank angle 0), for one-unit curves. The crank holes
    are given as the disc holes that the least-squares fit maps to the same placement (carrier holes
    zero): -(shift + turn R_c t_k), t_k the tangent at crank k."""
    from rvbacklash.models.contact import Realization

    src = transmission_source(problem, "default", seed, stream)
    dr, dt, rho, cl, teeth, eq, md, ux, uy, da, lin, centre, planet, shift, turn = src._draw(
        te_streams(seed, 0, tuple(stream)), n)
    gam = 2 * np.pi * np.arange(src.planets) / src.planets
    tangent = np.stack([-np.sin(gam), np.cos(gam)], axis=1)  # (P, 2)
    out = []
    for s in range(n):
        holes = -(shift[s][:, None, :] + turn[s][:, None, None] * src.crank_radius_mm * 1e3 * tangent[None, :, :])
        out.append(Realization(0.0, dr[s].copy(), dt[s].copy(), rho[s].copy(), cl[s].copy(), teeth[s].copy(),
                               np.stack([ux[s], uy[s]], axis=1), da[s].copy(), eq[s].copy(), md[s].copy(),
                               centre_gear_eccentricity_um=centre[s].copy(), planet_eccentricity_um=planet[s].copy(),
                               disc_crank_hole_um=holes, carrier_crank_hole_um=np.zeros((src.planets, 2))))
    return out


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
            m = min(CHUNK, n - start)
            self.source._evaluate(self.source._draw(streams, m), out[:, start:start + m])
        return out


def transmission_streams(problem: Problem) -> TransmissionStreams:
    from rvbacklash.factors.catalog import FACTOR_KEYS, KINEMATIC_KEYS

    source = transmission_source(problem, "default", 0)
    random = tuple(bool(x) for x in problem.random_mask) + (True,) + tuple(bool(s > 0) for s in source.sigmas_um)
    return TransmissionStreams(source, random, tuple(FACTOR_KEYS) + ("crank_angle",) + KINEMATIC_KEYS)
