"""The bearings' rollers by slices with their profile (ISO/TS 16281:2008; docs/rigidity-elements.md).

A profiled roller's law (``compliance.sliced_roller_load_n``) is computed once per design:

- **support bearings** (tapered rollers): each roller by slices, with its profile and the tilt
  that the crankshaft's bending slope gives at the bearing (``SlicedRoller``); the bearing's
  rollers are solved as a set (``solver.solve_sliced_set``) at the loop's ten torques, once per
  design (``chain.loop_points``): nothing per unit;
- **crank needle bearings** (per unit, in the compiled kernel): the sliced law over the load range
  the bearing sees, represented in the kernel's law form delta = Q^n (a - b ln Q) as a power law
  (b = 0, its own n: ``fit_roller_law``), so that the kernel is the same code with other
  coefficients (the closed-form inverse of Palmgren's law).

A straight profile is today's model: no slices, no tilt, the straight law itself.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from rvbacklash.mechanics.fe_cache import cached
from rvbacklash.models import compliance as cm

ROLLER_SLICES = 30  # slices per roller: ISO/TS 16281's worked examples; rv80e's laws change < 0.1 % at 60 (tests)
FIT_POINTS = 80  # loads (0, Q_max] at which the needle law's fit is made and its error read
FIT_VERSION = 2  # of fit_roller_law's method: its cached results (mechanics.fe_cache) are keyed by it
# the needle law's fit starts at the roller loads of this fraction of the rated torque (fit_load_range_n): below
# the measuring fractions in use (2-5 %, Nabtesco 3 %), fixed so that the reading does not move the law
FIT_LOW_TORQUE_FRACTION = 0.01
PROFILES = ("straight", "crowned", "logarithmic")


class SlicedRoller(NamedTuple):
    """A roller cut into slices: their centres x_k [mm] from the roller's middle, the profile's drop
    P_k at each [um] (per side), and the raceways' misalignment per N of the bearing's radial load
    [rad/N] (the support bearings: the crank's slope; 0: none). No slices: a straight roller
    without tilt (today's law)."""

    x_mm: np.ndarray
    drop_um: np.ndarray
    tilt_rad_per_n: float


STRAIGHT = SlicedRoller(np.empty(0), np.empty(0), 0.0)


def sliced_roller(profile: str, length_mm: float, diameter_mm: float, tapered: bool, crown_drop_um: float | None,
                  log_scale_um: float | None, tilt_rad_per_n: float = 0.0,
                  slices: int = ROLLER_SLICES) -> SlicedRoller:
    """The SlicedRoller of a profile (PROFILES): "straight" -> STRAIGHT (today's law); "crowned": a
    circular crown with ``crown_drop_um`` at the ends (``compliance.crowned_profile_drop_um``);
    "logarithmic": ISO/TS 16281's profile (``compliance.iso_logarithmic_profile``), its scale K
    replaced by ``log_scale_um`` when given. Lengths [mm], drops [um]."""
    if profile == "straight":
        return STRAIGHT
    x = cm.roller_slice_positions_mm(length_mm, slices)
    if profile == "crowned":
        drop = np.array([cm.crowned_profile_drop_um(v, length_mm, crown_drop_um) for v in x])
    else:
        scale, relief = cm.iso_logarithmic_profile(diameter_mm, length_mm, tapered)
        if log_scale_um is not None:
            scale = log_scale_um
        drop = np.array([cm.logarithmic_profile_drop_um(v, length_mm, scale, relief) for v in x])
    # measured from the slice that touches first: the profile's crown (drop 0 at the middle) lies between slice
    # centres, and a drop left at the innermost slices read as a dead band of a line-to-line bearing
    return SlicedRoller(x, drop - drop.min(), float(tilt_rad_per_n))


class RollerLawFit(NamedTuple):
    """A sliced roller's law represented as delta = a Q^n [um, N] (``fit_roller_law``) over the loads
    [Q_min, Q_max], and how well: the largest relative error in the approach over [Q_min, Q_max]
    [-], the largest error over (0, Q_max] [um]."""

    a: float
    n: float
    load_min_n: float
    load_max_n: float
    max_relative_error: float
    max_error_um: float


def fit_load_range_n(most_loaded_n: Callable[[float], float], rated_load_n: float) -> tuple[float, float]:
    """The roller loads [N] a crank needle bearing's law is fitted over (``fit_roller_law``): from half
    the most loaded roller's at FIT_LOW_TORQUE_FRACTION of the rated bearing load (its neighbours
    carry about half of it) to the most loaded roller's at the rated load, both without clearance.
    ``most_loaded_n(load)``: the most loaded roller [N] of the bearing carrying ``load`` [N] without
    clearance (``chain.most_loaded_roller_n``); ``rated_load_n``: the bearing's load at the rated
    torque [N]. Set by the design's rated torque and bearing alone: not by where the loop is read (the
    measuring fraction) nor by the clearance zone, so that a unit's figures do not move when neither
    does the unit (issue 36; before, the range ran from the lost motion's torque to the rated torque
    with the zone's largest clearance, and rv80e's nominal rigidity moved 0.3 % between measuring
    fractions of 1 and 5 %). Units with a clearance load their top roller beyond the range: the law
    extrapolates there (rv80e: the bearing's deflection within 3 % of the exactly sliced bearing from 1
    to 100 % of T_R with clearances up to 18 um, twice the zone's largest; tests)."""
    return 0.5 * most_loaded_n(FIT_LOW_TORQUE_FRACTION * rated_load_n), most_loaded_n(rated_load_n)


def fit_roller_law(roller: SlicedRoller, a: float, b: float, n: float, load_min_n: float,
                   load_max_n: float, points: int = FIT_POINTS) -> RollerLawFit:
    """The sliced roller's law (no tilt; straight law a, b, n) as a power law delta = a' Q^n' over
    [Q_min, Q_max], minimising the largest relative error in the approach at ``points`` loads
    spaced geometrically (least squares first, scipy.optimize.least_squares, then Nelder-Mead on
    the largest error: minimax). The kernel's law delta = Q^n (a - b ln Q) with b = 0 and its own
    n (its closed-form inverse, no Newton step). Why a power law: a profiled roller stiffens as its
    contact lengthens, delta ~ Q^(0.6-0.7) over the needle bearings' range (a straight roller:
    0.9-1); Johnson's form Q (a - b ln Q) cannot bend that far (fitted to rv80e's needles it
    missed the bearing's deflection at 3 % of the rated torque by 30 %, its F_lim fell inside the
    range), the power law fits within 3 % (tests). Relative errors because both ends matter: the
    lost motion reads the bearing at +-3 % of the rated torque, the rigidity at 50-100 %.
    Once per design: kept in process and on disk (``mechanics.fe_cache.cached``, keyed by the
    profile, the law and the range), so that a sweep or the next command does not fit again."""
    inputs = {"x_mm": roller.x_mm.tolist(), "drop_um": roller.drop_um.tolist(), "law": [a, b, n],
              "loads_n": [load_min_n, load_max_n], "points": points}
    result = cached("roller_law_fit", FIT_VERSION, inputs,
                    lambda: _fit_roller_law(roller, a, b, n, load_min_n, load_max_n, points)._asdict())
    return RollerLawFit(**result)


def _fit_roller_law(roller: SlicedRoller, a: float, b: float, n: float, load_min_n: float, load_max_n: float,
                    points: int) -> RollerLawFit:
    """``fit_roller_law`` computed."""
    from scipy.optimize import least_squares, minimize  # here: a design with straight needles never imports it

    loads = np.geomspace(load_min_n, load_max_n, points)
    target = np.array([cm.sliced_roller_approach_um(q, 0.0, roller.x_mm, roller.drop_um, a, b, n) for q in loads])

    def error(p: np.ndarray) -> np.ndarray:
        return p[0] * loads ** p[1] / target - 1.0

    slope = math.log(target[-1] / target[0]) / math.log(loads[-1] / loads[0])
    p = least_squares(error, np.array([target[-1] / load_max_n ** slope, slope]), x_scale="jac").x
    p = minimize(lambda q: float(np.abs(error(q)).max()), p, method="Nelder-Mead",
                 options={"xatol": 1e-14, "fatol": 1e-14, "maxiter": 4000}).x
    below = load_max_n * np.arange(1, points + 1) / points  # the absolute error over the whole range from 0
    exact = np.array([cm.sliced_roller_approach_um(q, 0.0, roller.x_mm, roller.drop_um, a, b, n) for q in below])
    return RollerLawFit(float(p[0]), float(p[1]), float(load_min_n), float(load_max_n),
                        float(np.abs(error(p)).max()), float(np.abs(p[0] * below ** p[1] - exact).max()))


def fitted_law_valid(fit: RollerLawFit) -> bool:
    """The fitted law is a law: a > 0 and 0 < n (its approach rises with the load)."""
    return fit.a > 0.0 and fit.n > 0.0
