"""Ratings and rating lives of the reducer's bearings from their loads over a revolution
(docs/capacity.md, "Life"): every crank needle bearing and crank support bearing, the reducer as
their system.

- **crank needle bearings** (the needles run on the eccentric and in the disc's bore): C_r and C_0r
  from their geometry (ISO 281 / ISO 76, i = 1, alpha = 0, D_pw = eccentric + D_w); life by ISO 281
  (the load's p-power mean over the revolution, p = 10/3) and by ISO/TS 16281 (the rollers' slices
  at every state of the revolution, each raceway's laminae's equivalent loads over the cycle:
  ``models.elastic.loads.cycle_equivalent_lamina_loads``);
- **crank support bearings** (tapered rollers, two per crank, face to face): C_r from the stated
  catalogue value or ISO 281 from the rollers, C_0r likewise (ISO 76); the pair's axial loads by the
  makers' rule, P = X F_r + Y F_a (ISO 281 Table 8) at every state, its p-power mean: ISO 281;
- **the reducer**: the L10 of the system of all these bearings (Lundberg-Palmgren, e = 9/8 for
  roller bearings: ``ratings.system_life``), in hours at the output speed (the bearings turn at
  z_p times the output speed against the carrier).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rvbacklash.analysis.capacity.revolution import RevolutionLoads
from rvbacklash.errors import InputError
from rvbacklash.models import ratings as rt
from rvbacklash.models.elastic import ElasticModel
from rvbacklash.models.elastic.loads import RollerSet, cycle_equivalent_lamina_loads
from rvbacklash.results import Result

RACEWAY_POINTS = 72  # points round a raceway at which the cycle's lamina loads are followed (5 degrees)
ISO76_TAPERED_Y0 = 0.22  # ISO 76:2006 Table 4: single-row tapered roller bearings, Y_0 = 0.22 cot(alpha)


class NeedleRatings(NamedTuple):
    """A crank needle bearing's ratings (``needle_ratings``): C_r, C_0r [N] (ISO 281 / ISO 76 from
    its geometry), its raceways' lamina ratings q_ci, q_ce [N] (ISO/TS 16281), its pitch diameter."""

    dynamic_n: float
    static_n: float
    inner_lamina_n: float
    outer_lamina_n: float
    pitch_diameter_mm: float


class SupportRatings(NamedTuple):
    """A crank support bearing's ratings (``support_ratings``): C_r, C_0r [N], contact angle [deg],
    whether each rating is the catalogue's (stated) or ISO's (geometry)."""

    dynamic_n: float
    static_n: float
    contact_angle_deg: float
    pitch_diameter_mm: float
    dynamic_stated: bool
    static_stated: bool


def needle_ratings(model: ElasticModel, slices: int) -> NeedleRatings:
    """The crank needle bearing's ratings from the design's [elastic] rollers: Z, D_w, L_we, the
    eccentric's raceway diameter D_e (D_pw = D_e + D_w)."""
    e = model.inputs
    z, dw, lw = e.crank_bearing_rollers, e.crank_bearing_roller_diameter_mm, e.crank_bearing_roller_length_mm
    dpw = model.raceway_diameter_mm + dw
    try:
        c = rt.dynamic_load_rating_radial_roller_n(1, lw, 0.0, z, dw, dpw)
    except InputError as err:
        raise InputError("elastic.crank_bearing_roller_diameter_mm", dw, err.allowed) from None
    c0 = rt.static_load_rating_radial_roller_n(1, lw, 0.0, z, dw, dpw)
    qci, qce = rt.iso16281_raceway_ratings_n(c, z, dw / dpw)
    return NeedleRatings(c, c0, rt.iso16281_lamina_rating_n(qci, slices), rt.iso16281_lamina_rating_n(qce, slices),
                         dpw)


def support_ratings(model: ElasticModel) -> SupportRatings | None:
    """The crank support bearings' ratings from [structure] (None: no [structure]): the catalogue's
    C_r, C_0r where stated, else ISO 281 / ISO 76 from the rollers (Z, D_w, L_we, alpha) on the
    pitch diameter (stated, or the mean of the journal and the seat)."""
    st = model.structure
    if st is None:
        return None
    dpw = st.support_bearing_pitch_diameter_mm
    if dpw is None:
        if st.support_bearing_seat_diameter_mm is None:
            raise InputError("structure.support_bearing_pitch_diameter_mm", None,
                             "required for the support bearings' ratings without support_bearing_seat_diameter_mm; "
                             "allowed: the rollers' pitch diameter [mm]")
        dpw = 0.5 * (st.crankshaft_diameter_mm + st.support_bearing_seat_diameter_mm)
    args = (1, st.support_bearing_roller_length_mm, st.support_bearing_contact_angle_deg, st.support_bearing_rollers,
            st.support_bearing_roller_diameter_mm, dpw)
    c = st.support_bearing_dynamic_load_rating_n
    if c is None:
        try:
            c = rt.dynamic_load_rating_radial_roller_n(*args)
        except InputError as err:
            raise InputError("structure.support_bearing_roller_diameter_mm", st.support_bearing_roller_diameter_mm,
                             err.allowed) from None
    c0 = st.support_bearing_static_load_rating_n or rt.static_load_rating_radial_roller_n(*args)
    return SupportRatings(float(c), float(c0), st.support_bearing_contact_angle_deg, float(dpw),
                          st.support_bearing_dynamic_load_rating_n is not None,
                          st.support_bearing_static_load_rating_n is not None)


@dataclass(frozen=True, repr=False)
class BearingLife(Result):
    """One bearing's ratings, loads over the revolution and rating life (docs/capacity.md)."""

    name: str  # "needle d0 c1" (disc 0, crank 1), "support c0 A" (crank 0, support A: disc 0's side)
    kind: str  # crank_needle | crank_support
    dynamic_load_rating_n: float
    static_load_rating_n: float
    equivalent_load_n: float  # ISO 281: the p-power mean of P over the revolution
    max_load_n: float  # the largest radial load over the revolution
    static_equivalent_load_n: float  # ISO 76 P_0 at the largest load
    static_safety: float  # C_0 / P_0
    l10_iso281_mrev: float  # (C / P)^(10/3)
    l10_iso16281_mrev: float  # from the internal load distribution (NaN: not computed for this kind)
    l10_mrev: float  # the design's life method's
    l10_h: float  # at the rated output speed


def needle_bearing_lives(loads: RevolutionLoads, needles: RollerSet, ratings: NeedleRatings, method: str,
                         speed_rpm: float) -> list[BearingLife]:
    """Every crank needle bearing's life over the revolution ``loads`` (``method`` "iso16281" or
    "iso281"; ``speed_rpm``: the bearing's speed, z_p times the output's)."""
    out = []
    mag = loads.crank_bearing_load_magnitude_n
    _, discs, cranks = mag.shape
    n_s = needles.drop_um.size
    qi, qe = np.empty(n_s), np.empty(n_s)
    for d in range(discs):
        for c in range(cranks):
            p = mag[:, d, c]
            p_eq = rt.equivalent_load_variable_n(p, 1.0, rt.ROLLER_LIFE_EXPONENT)
            l281 = rt.basic_rating_life_mrev(ratings.dynamic_n, p_eq, rt.ROLLER_LIFE_EXPONENT)
            approach = np.ascontiguousarray(loads.crank_bearing_approach_um[:, d, c])
            cycle_equivalent_lamina_loads(approach, np.ascontiguousarray(loads.crank_bearing_inner_angle_rad[:, d, c]),
                                          loads.crank_clearance_um, needles, RACEWAY_POINTS, qi)
            cycle_equivalent_lamina_loads(approach, np.ascontiguousarray(loads.crank_bearing_outer_angle_rad[:, d, c]),
                                          loads.crank_clearance_um, needles, RACEWAY_POINTS, qe)
            l16281 = rt.iso16281_reference_life_mrev(qi, qe, ratings.inner_lamina_n, ratings.outer_lamina_n)
            life = l16281 if method == "iso16281" else l281
            pmax = float(p.max())
            out.append(BearingLife(f"needle d{d} c{c}", "crank_needle", ratings.dynamic_n, ratings.static_n, p_eq,
                                   pmax, pmax, ratings.static_n / pmax if pmax > 0 else math.inf, l281, l16281, life,
                                   rt.life_hours(life, speed_rpm)))
    return out


def support_bearing_lives(loads: RevolutionLoads, ratings: SupportRatings, speed_rpm: float) -> list[BearingLife]:
    """Every crank support bearing's life over the revolution (ISO 281: each state's P = X F_r + Y F_a
    with the pair's axial loads by the makers' rule, its p-power mean)."""
    mag = loads.support_bearing_load_magnitude_n  # (K, cranks, 2)
    k_n, cranks, _ = mag.shape
    alpha = ratings.contact_angle_deg
    y0 = ISO76_TAPERED_Y0 / math.tan(math.radians(alpha))
    out = []
    for c in range(cranks):
        p = np.empty((k_n, 2))
        p0 = np.empty((k_n, 2))
        for k in range(k_n):
            fa = rt.tapered_pair_axial_loads_n(mag[k, c, 0], mag[k, c, 1], alpha, 0.0)
            for end in range(2):
                fr = mag[k, c, end]
                p[k, end] = rt.tapered_equivalent_load_n(fr, fa[end], alpha)
                p0[k, end] = max(fr, 0.5 * fr + y0 * fa[end])  # ISO 76, clause 6.2: P_0 >= F_r
        for end, label in enumerate("AB"):
            p_eq = rt.equivalent_load_variable_n(p[:, end], 1.0, rt.ROLLER_LIFE_EXPONENT)
            life = rt.basic_rating_life_mrev(ratings.dynamic_n, p_eq, rt.ROLLER_LIFE_EXPONENT)
            p0max = float(p0[:, end].max())
            out.append(BearingLife(f"support c{c} {label}", "crank_support", ratings.dynamic_n, ratings.static_n, p_eq,
                                   float(mag[:, c, end].max()), p0max,
                                   ratings.static_n / p0max if p0max > 0 else math.inf, life, math.nan, life,
                                   rt.life_hours(life, speed_rpm)))
    return out


def bearing_speed_rpm(model: ElasticModel, output_speed_rpm: float) -> float:
    """The crank bearings' speed against their rings [r/min]: the cranks turn z_p times per output
    revolution against the carrier (the discs do not turn against it: they orbit)."""
    return model.geometry.zp * output_speed_rpm


def reducer_life(lives: list[BearingLife], hours: bool = True) -> float:
    """The reducer's L10 as the system of its bearings (``ratings.system_life``, e = 9/8: rollers)."""
    values = [b.l10_h if hours else b.l10_mrev for b in lives]
    return rt.system_life(values, rt.ROLLER_WEIBULL_SLOPE)
