"""The output's main bearings (docs/capacity.md, "Main bearings"): an angular-contact ball pair,
back to back (O), between the carrier and the housing: the balls' loads under an external moment,
thrust and radial load with the pair's preload, the moment rigidity, the allowable moment (static
and for life) and their life.

Model (Harris & Kotzalas, Rolling Bearing Analysis 5th ed. (2007), vol. 2, ch. 1: the loads of a
ball bearing under combined loads, here with each ball's contact angle held at its nominal value
(small displacements), which is the linearised form): the inner ring (the carrier) moves by an
axial delta_a, a radial delta_r and a tilt theta against the outer ring; ball i of row r (r = +1
at z = +s/2, -1 at -s/2; the O arrangement's contact lines point outwards) closes by

    delta_ri = delta_0 + delta_r cos(alpha) cos(psi_i) - r delta_a sin(alpha) + r theta l cos(psi_i),
    l = (s/2) cos(alpha) + (D_pw/2) sin(alpha)       (the pressure centre's lever)

and pushes back with Hertz's Q = (delta / K_b)^(3/2) (both raceway contacts in series,
``ratings.hertz_point_contact``; delta_0 sets the preload). Equilibrium: F_r = sum Q cos(alpha)
cos(psi), F_a = -sum r Q sin(alpha), M = sum r Q l cos(psi). The moment rigidity is dM/dtheta
(tangent at the operating point; the secant to the allowable moment is reported too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rvbacklash.design.structure import StructureInputs
from rvbacklash.models import compliance as cm
from rvbacklash.models import ratings as rt
from rvbacklash.results import Result
from rvbacklash.units import ARCMIN_PER_RAD

MAIN_BEARING_E_GPA = 206.0  # bearing steel (the elastic model's default steel)
MAIN_BEARING_NU = 0.3


class BallPair(NamedTuple):
    """An angular-contact ball pair, back to back (``ball_pair``): per row Z balls of D_w on D_pw at
    alpha; rows s apart; the ball's Hertz constant K_b (delta = K_b Q^(2/3), both contacts) [mm/N^(2/3)];
    the inner and outer contacts' curvatures; the preload's approach delta_0 [mm]; one row's C_r [N]."""

    balls: int
    ball_diameter_mm: float
    pitch_diameter_mm: float
    contact_angle_rad: float
    row_spread_mm: float
    hertz_mm_per_n23: float
    inner_curvature: tuple[float, float]
    outer_curvature: tuple[float, float]
    preload_approach_mm: float
    row_rating_n: float
    e_star_n_per_mm2: float

    @property
    def lever_mm(self) -> float:
        return 0.5 * self.row_spread_mm * math.cos(self.contact_angle_rad) + \
            0.5 * self.pitch_diameter_mm * math.sin(self.contact_angle_rad)


def ball_pair(st: StructureInputs) -> BallPair:
    """The BallPair of a design's [structure] main-bearing fields (``design.structure.has_main_bearings``)."""
    z, dw, dpw = st.main_bearing_balls, st.main_bearing_ball_diameter_mm, st.main_bearing_pitch_diameter_mm
    alpha = math.radians(st.main_bearing_contact_angle_deg)
    gamma = dw * math.cos(alpha) / dpw
    e_star = cm.contact_modulus_n_per_mm2(MAIN_BEARING_E_GPA, MAIN_BEARING_NU, MAIN_BEARING_E_GPA, MAIN_BEARING_NU)
    inner = rt.ball_raceway_curvatures(dw, st.main_bearing_groove_ratio_inner, gamma, True)
    outer = rt.ball_raceway_curvatures(dw, st.main_bearing_groove_ratio_outer, gamma, False)
    q = 1000.0
    k = (rt.hertz_point_contact(q, *inner, e_star)[3] + rt.hertz_point_contact(q, *outer, e_star)[3]) / q ** (2 / 3)
    preload_ball = st.main_bearing_preload_n / (z * math.sin(alpha))
    c_row = rt.dynamic_load_rating_radial_ball_n(1, st.main_bearing_contact_angle_deg, z, dw, dpw)
    return BallPair(z, dw, dpw, alpha, st.main_bearing_row_spread_mm, k, inner, outer,
                    k * preload_ball ** (2 / 3) if preload_ball > 0 else 0.0, c_row, e_star)


class BallLoads(NamedTuple):
    """The solved pair: (delta_a, delta_r [mm], theta [rad]), each ball's load (2, Z) [N] (row -1,
    row +1), the tangent moment rigidity dM/dtheta [N mm/rad]."""

    displacement: tuple[float, float, float]
    loads_n: np.ndarray
    moment_rigidity_nmm_per_rad: float


def _ball_loads(pair: BallPair, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Q (2, Z), dQ/ddelta (2, Z)) at the ring displacement x = (delta_a, delta_r, theta)."""
    psi = 2.0 * math.pi * np.arange(pair.balls) / pair.balls
    rows = np.array([-1.0, 1.0])[:, None]
    ca, sa = math.cos(pair.contact_angle_rad), math.sin(pair.contact_angle_rad)
    d = (pair.preload_approach_mm + x[1] * ca * np.cos(psi)[None, :] - rows * x[0] * sa
         + rows * x[2] * pair.lever_mm * np.cos(psi)[None, :])
    d = np.maximum(d, 0.0)
    q = (d / pair.hertz_mm_per_n23) ** 1.5
    dq = 1.5 * np.sqrt(d) / pair.hertz_mm_per_n23 ** 1.5
    return q, dq


def solve_ball_pair(pair: BallPair, moment_nm: float, axial_n: float = 0.0, radial_n: float = 0.0) -> BallLoads:
    """The pair's balls under an external moment M [N m] (about the axis perpendicular to the radial
    load's plane), thrust F_a and radial load F_r [N] (Newton on the three equilibria, from the
    preloaded state)."""
    from scipy.optimize import root

    psi = 2.0 * math.pi * np.arange(pair.balls) / pair.balls
    rows = np.array([-1.0, 1.0])[:, None]
    ca, sa, lev = math.cos(pair.contact_angle_rad), math.sin(pair.contact_angle_rad), pair.lever_mm
    target = np.array([axial_n, radial_n, moment_nm * 1e3])
    scale = np.maximum(np.abs(target), pair.row_rating_n * np.array([0.01, 0.01, 0.01 * lev]))

    def residual(x):
        q, _ = _ball_loads(pair, x)
        fa = -np.sum(rows * q * sa)
        fr = np.sum(q * ca * np.cos(psi)[None, :])
        m = np.sum(rows * q * lev * np.cos(psi)[None, :])
        return (np.array([fa, fr, m]) - target) / scale

    x0 = np.zeros(3)
    if pair.preload_approach_mm == 0.0:  # no preload: start loaded, so that some balls touch
        x0 = np.array([-1e-3 * np.sign(axial_n or 1.0), 1e-3 * np.sign(radial_n) if radial_n else 0.0,
                       1e-5 * np.sign(moment_nm or 1.0)])
    sol = root(residual, x0, method="hybr", options={"xtol": 1e-13})
    q, dq = _ball_loads(pair, sol.x)
    k_theta = float(np.sum(dq * (lev * np.cos(psi)[None, :]) ** 2))
    return BallLoads((float(sol.x[0]), float(sol.x[1]), float(sol.x[2])), q, k_theta)


def max_ball_stress_mpa(pair: BallPair, loads: BallLoads) -> float:
    """The largest Hertz pressure of any ball on either raceway [MPa] (the inner's, more curved)."""
    qmax = float(loads.loads_n.max())
    if qmax <= 0.0:
        return 0.0
    return max(rt.hertz_point_contact(qmax, *pair.inner_curvature, pair.e_star_n_per_mm2)[2],
               rt.hertz_point_contact(qmax, *pair.outer_curvature, pair.e_star_n_per_mm2)[2])


def row_life_mrev(pair: BallPair, loads_n: np.ndarray) -> float:
    """One row's L10 from its balls' loads by ISO/TS 16281 (inner ring rotating against the load):

        Q_ei = (sum Q^3 / Z)^(1/3),  Q_ee = (sum Q^(10/3) / Z)^(3/10)
        L_10r = ((Q_ci / Q_ei)^(-10/3) + (Q_ce / Q_ee)^(-10/3))^(-9/10)

    with Q_ci, Q_ce from the row's C_r (ISO/TS 16281:2008, Eqs. (19)-(29) as numbered in a public
    implementation: Q_c = C / (0.407 or 0.389 Z cos(alpha)^0.7) [1 + (1.044 ((1-g)/(1+g))^1.72
    (f_i (2 f_e - 1) / (f_e (2 f_i - 1)))^0.41)^(+-10/3)]^0.3). [Mrev]"""
    g = pair.ball_diameter_mm * math.cos(pair.contact_angle_rad) / pair.pitch_diameter_mm
    fi = _groove_ratio(pair.ball_diameter_mm, pair.inner_curvature[0], g, True)
    fe = _groove_ratio(pair.ball_diameter_mm, pair.outer_curvature[0], g, False)
    t = 1.044 * ((1 - g) / (1 + g)) ** 1.72 * (fi * (2 * fe - 1) / (fe * (2 * fi - 1))) ** 0.41
    base = pair.row_rating_n / (pair.balls * math.cos(pair.contact_angle_rad) ** 0.7)
    qci = base / 0.407 * (1 + t ** (10 / 3)) ** 0.3
    qce = base / 0.389 * (1 + t ** (-10 / 3)) ** 0.3
    z = loads_n.size
    qei = (np.sum(loads_n ** 3) / z) ** (1 / 3)
    qee = (np.sum(loads_n ** (10 / 3)) / z) ** 0.3
    if qei <= 0.0:
        return math.inf
    return float(((qci / qei) ** (-10 / 3) + (qce / qee) ** (-10 / 3)) ** (-0.9))


def _groove_ratio(d: float, curvature_sum: float, gamma: float, inner: bool) -> float:
    """The groove ratio f back from the curvature sum (``ratings.ball_raceway_curvatures``)."""
    s = curvature_sum * d
    return 1.0 / (4.0 + (2.0 * gamma / (1.0 - gamma) if inner else -2.0 * gamma / (1.0 + gamma)) - s)


def pair_life_mrev(pair: BallPair, loads: BallLoads) -> float:
    """The pair's L10: its two rows as a system (e = 10/9, ``ratings.system_life``) [Mrev]."""
    return rt.system_life([row_life_mrev(pair, loads.loads_n[0]), row_life_mrev(pair, loads.loads_n[1])],
                          rt.BALL_WEIBULL_SLOPE)


@dataclass(frozen=True, repr=False)
class MainBearingRating(Result):
    """The main bearings' figures (docs/capacity.md)."""

    balls_per_row: int
    ball_diameter_mm: float
    pitch_diameter_mm: float
    contact_angle_deg: float
    row_spread_mm: float
    preload_n: float
    row_dynamic_load_rating_n: float
    moment_rigidity_nm_per_arcmin: float  # tangent at zero external load (preloaded)
    moment_rigidity_secant_nm_per_arcmin: float  # secant from 0 to the allowable moment
    allowable_moment_static_nm: float  # the largest ball stress reaches 4200 MPa / s0
    allowable_moment_life_nm: float  # the pair's L10 reaches the rated life at the rated output speed
    allowable_moment_nm: float  # the smaller of the two
    static_safety: float
    thrust_n: float  # the thrust and radial load the allowable moments were computed with
    radial_n: float


def main_bearing_rating(st: StructureInputs, rated_life_h: float, output_speed_rpm: float, static_safety: float,
                        thrust_n: float = 0.0, radial_n: float = 0.0) -> MainBearingRating:
    """Moment rigidity and allowable moments of the design's main bearings (module docstring);
    ``thrust_n``/``radial_n``: the external loads acting with the moment (a duty cycle's)."""
    from scipy.optimize import brentq

    pair = ball_pair(st)
    k0 = solve_ball_pair(pair, 0.0, thrust_n, radial_n).moment_rigidity_nmm_per_rad * 1e-3 / ARCMIN_PER_RAD
    limit = rt.ISO76_BALL_STRESS_MPA / static_safety
    scale = pair.row_rating_n * pair.lever_mm * 1e-3  # ~ C l [N m]: the moment's scale

    def stress_gap(m: float) -> float:
        return max_ball_stress_mpa(pair, solve_ball_pair(pair, m, thrust_n, radial_n)) - limit

    def life_gap(m: float) -> float:
        life = pair_life_mrev(pair, solve_ball_pair(pair, m, thrust_n, radial_n))
        return math.log(rt.life_hours(life, output_speed_rpm)) - math.log(rated_life_h)

    m_static = _first_root(stress_gap, scale, brentq, increasing=True)
    m_life = _first_root(life_gap, scale, brentq, increasing=False)
    m_allow = min(m_static, m_life)
    sol = solve_ball_pair(pair, m_allow, thrust_n, radial_n)
    secant = m_allow / sol.displacement[2] / ARCMIN_PER_RAD if sol.displacement[2] != 0 else math.nan
    return MainBearingRating(st.main_bearing_balls, st.main_bearing_ball_diameter_mm, st.main_bearing_pitch_diameter_mm,
                             st.main_bearing_contact_angle_deg, st.main_bearing_row_spread_mm,
                             st.main_bearing_preload_n, pair.row_rating_n, k0, secant, m_static, m_life, m_allow,
                             static_safety, thrust_n, radial_n)


def _first_root(f, scale: float, brentq, increasing: bool) -> float:
    """The moment M > 0 [N m] at which f crosses 0 (f rises with M when ``increasing``, else falls)."""
    lo, hi = 0.0, 0.05 * scale
    f_lo = f(1e-6 * scale)
    if (f_lo >= 0.0) == increasing:  # already beyond at no moment (e.g. a thrust alone)
        return 0.0
    for _ in range(80):
        if (f(hi) >= 0.0) == increasing:
            break
        lo, hi = hi, hi * 1.6
    return float(brentq(f, max(lo, 1e-6 * scale), hi, xtol=1e-10 * scale, rtol=1e-12))
