"""Angular transmission error and lost motion of one unit over a full output revolution
(``rvbacklash transmission-error``; docs/transmission-error.md).

A unit (the error-free design, a measured unit, or a unit a run drew) goes through
``models.kinematics``: at every output position the output's position with each flank in
contact. The figures: TE(theta) of each load direction [arcsec] (the position minus the
error-free unit's at the same theta), its peak-to-peak (the catalogue figure, Yang et al. 2021
Eq. (38)) and amplitude spectrum by order of the output revolution, the rigid lost motion at
every position [arcmin] (max, min, at the bench's reference position theta = 0), and the share
of each error group (by switching the group off).

Lost motion has one meaning across the project (``contact``, ``simulate --model transmission``):
the output's, i.e. the cycloid stage's play at that position plus the involute and crank stages'
linear part (``other_stages_arcmin``: the measured unit's when its file gives it, as a run's saved
units do, else their linear means). The cycloid stage alone is ``cycloid_stage_*_arcmin``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rvbacklash.analysis.contact import linear_stage_means
from rvbacklash.errors import InputError
from rvbacklash.models.unit_errors import Realization
from rvbacklash.models.kinematics import (ARCSEC_PER_RAD, DEFAULT_POSITIONS, Kinematics, Revolution, kinematics,  # noqa: F401
                                          cached_table, curve_extremes, lost_motion_arcmin, perfect_unit,
                                          reference_revolution, revolution)
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result

MAX_POSITIONS = 1 << 16
LEADING_ORDERS = 8  # at most this many lines listed in the summary and the JSON
# A spectral line below this is no line: 0.001 arcsec is ~0.4 nm at the rv80e pin circle, far below
# what a bench resolves and far above the solver's tolerances (~1e-7 arcsec); the error-free unit's
# spectrum is exactly 0 (TE is measured from it), and its sorted zeros once made a table of orders
# 512, 511, ... at 0.000.
SPECTRUM_FLOOR_ARCSEC = 1e-3
LOAD_DIRECTIONS = ("ccw", "cw")
ASSUMPTIONS = ("rigid bodies, no load; exact cycloid-pin geometry with every tooth and pin indexed as they meet; "
               "the discs placed on the cranks by a least-squares fit (needle-bearing clearances absorb the "
               "residual, not checked); involute stage through the crank angles it gives; output angles in Eq. (1)'s "
               "convention (Yang's kinematic factor 1/(1 + (z1 + z2)/(z2 z_c)) not applied); TE is the position "
               "minus the error-free unit's at the same output angle")


def min_positions(problem: Problem) -> int:
    """Fewest positions per revolution: 8 z_p, the production run's (sampling.te_source), so that a
    saved unit can be re-run on the run's own grid; orders below 4 z_p resolved."""
    from rvbacklash.sampling.te_source import POSITIONS_PER_PIN

    return POSITIONS_PER_PIN * problem.cycloid.zp


def check_positions(problem: Problem, positions) -> int:
    lo = min_positions(problem)
    if isinstance(positions, bool) or not isinstance(positions, (int, np.integer)) or not lo <= positions <= MAX_POSITIONS:
        raise InputError("positions", positions, f"allowed: a whole number {lo} <= positions <= {MAX_POSITIONS} "
                                                 f"(8 z_p, the production run's grid, and up; z_p = {problem.cycloid.zp})")
    return int(positions)


def amplitude_spectrum(curve: np.ndarray) -> np.ndarray:
    """One-sided amplitude of each order 0..N/2 of a curve sampled at N equal steps of a revolution
    (order 0: the mean; order m: the amplitude of its cos/sin line)."""
    n = curve.size
    amp = np.abs(np.fft.rfft(curve)) / n
    amp[1:] *= 2.0
    if n % 2 == 0:
        amp[-1] /= 2.0
    return amp


@dataclass(frozen=True, repr=False)
class SpectralLine(Result):
    order: int
    amplitude_arcsec: float


@dataclass(frozen=True, repr=False)
class GroupShare(Result):
    """TE peak-to-peak with one error group switched off, and the group's share of the TE variance
    (1 - var(without) / var(all); shares need not add up: the first contact is not linear)."""

    group: str
    te_peak_to_peak_without_arcsec: float
    variance_share: float


@dataclass(frozen=True, repr=False)
class TransmissionErrorResult(Result):
    """Transmission error and rigid lost motion of one unit over a full output revolution."""

    design_name: str
    unit: str  # "nominal", or which measured / sampled unit
    positions: int
    load_direction: str  # the flank of the headline TE figures: ccw (output driven counter-clockwise) or cw
    te_peak_to_peak_arcsec: float  # the catalogue figure, load_direction's flank: the curve's, refined between positions
    te_min_arcsec: float  # (the sampled curve te_*_arcsec may stay inside these: kinematics.curve_extremes)
    te_max_arcsec: float
    te_peak_to_peak_other_flank_arcsec: float
    # the output's rigid lost motion = cycloid stage + other_stages_arcmin (module docstring)
    lost_motion_max_arcmin: float
    lost_motion_min_arcmin: float
    lost_motion_reference_arcmin: float  # at the bench's reference position (theta = 0: the unit's crank angle)
    cycloid_stage_max_arcmin: float  # the cycloid stage alone (its play; 0 where preloaded)
    cycloid_stage_min_arcmin: float
    cycloid_stage_reference_arcmin: float
    other_stages_arcmin: float  # the involute and crank stages' linear part, the same at every position
    other_stages_from: str  # "given" (the measured unit's other_stages_arcmin) | "linear means"
    preloaded_positions: int  # positions where no rotation frees every pin (the cycloid stage's play 0 there)
    nominal_ripple_arcsec: float  # peak-to-peak of the error-free unit's own flank curve (the modifications')
    leading_orders: tuple[SpectralLine, ...]  # the largest lines above SPECTRUM_FLOOR_ARCSEC (none: no spectrum)
    group_shares: tuple[GroupShare, ...]
    crank_angle_deg: float
    assumptions: str
    output_angle_deg: np.ndarray = field(metadata={EXPORT: True})
    te_ccw_arcsec: np.ndarray = field(metadata={EXPORT: True})
    te_cw_arcsec: np.ndarray = field(metadata={EXPORT: True})
    lost_motion_arcmin: np.ndarray = field(metadata={EXPORT: True})  # cycloid_stage_arcmin + other_stages_arcmin
    spectrum_amplitude_arcsec: np.ndarray = field(metadata={EXPORT: True})  # by order 0..N/2, load_direction
    temperature_c: float | None = None  # the parts' temperature (their expansion; None: the reference, none)

    @property
    def te_arcsec(self) -> np.ndarray:
        return self.te_ccw_arcsec if self.load_direction == "ccw" else self.te_cw_arcsec

    def rows(self) -> list[dict]:
        """One row per output position (CSV, DataFrame)."""
        return [{"output_angle_deg": float(a), "te_ccw_arcsec": float(p), "te_cw_arcsec": float(m),
                 "lost_motion_arcmin": float(lm), "cycloid_stage_arcmin": float(lm - self.other_stages_arcmin)}
                for a, p, m, lm in zip(self.output_angle_deg, self.te_ccw_arcsec, self.te_cw_arcsec,
                                       self.lost_motion_arcmin)]

    def no_spectrum(self) -> str | None:
        """Why there is no line to list (None when there are lines)."""
        if self.leading_orders:
            return None
        if self.te_peak_to_peak_arcsec == 0.0:
            return (f"no spectrum: TE is measured from the error-free unit, so a unit without errors has TE 0 at every "
                    f"position (the modifications' own ripple, {self.nominal_ripple_arcsec:.3f} arcsec peak-to-peak at "
                    f"the mesh order z_c z_p, is not TE)")
        return f"no spectral line above {SPECTRUM_FLOOR_ARCSEC:g} arcsec"

    def summary(self) -> list[str]:
        lines = ", ".join(f"{s.order}: {s.amplitude_arcsec:.2f}" for s in self.leading_orders[:5])
        out = [f"{self.design_name}, {self.unit}: TE ({self.load_direction}) peak-to-peak "
               f"{self.te_peak_to_peak_arcsec:.2f} arcsec over {self.positions} positions",
               f"lost motion {self.lost_motion_min_arcmin:.4f} .. {self.lost_motion_max_arcmin:.4f} arcmin "
               f"({self.lost_motion_reference_arcmin:.4f} at the reference position; cycloid stage "
               f"{self.cycloid_stage_reference_arcmin:.4f} + other stages {self.other_stages_arcmin:.4f})",
               f"leading orders [arcsec]: {lines}" if lines else self.no_spectrum()]
        if self.group_shares:
            out.append("variance share by group: " + ", ".join(f"{s.group} {s.variance_share:.0%}"
                                                                for s in self.group_shares))
        return out


# error groups: what switching a group off resets in a Realization (to the error-free unit's values)
GROUPS: dict[str, tuple[str, ...]] = {
    "disc teeth (cumulative pitch)": ("tooth_pitch_um",),
    "pins (position, radius, hole clearance)": ("pin_radial_um", "pin_tangential_um", "pin_radius_um",
                                                "pin_clearance_um"),
    "disc run-out and crank eccentricity": ("runout_um", "eccentricity_error_um"),
    "modification errors": ("equidistance_um", "moving_distance_um"),
    "crank holes (disc, carrier)": ("disc_crank_hole_um", "carrier_crank_hole_um"),
    "involute stage (gear eccentricities)": ("centre_gear_eccentricity_um", "planet_eccentricity_um"),
}


def _without(r: Realization, perfect: Realization, group: str) -> Realization:
    return r.with_(**{name: getattr(perfect, name) for name in GROUPS[group]})


def _has(r: Realization, perfect: Realization, group: str) -> bool:
    """Does unit r carry errors of ``group`` (any field differing from the error-free unit's; None = 0)?"""
    for name in GROUPS[group]:
        v, p = getattr(r, name), getattr(perfect, name)
        if v is not None and np.any(np.asarray(v, float) != np.asarray(0.0 if p is None else p, float)):
            return True
    return False


def transmission_error(problem: Problem, r: Realization, label: str, positions: int = DEFAULT_POSITIONS,
                       load_direction: str = "ccw", shares: bool = True,
                       other_stages_arcmin: float | None = None) -> TransmissionErrorResult:
    """The figures of one unit (module docstring). ``shares``: also the TE with each error group
    the unit has switched off (one more revolution per group). ``other_stages_arcmin``: the
    unit's involute and crank stages [arcmin] (a measured or drawn unit's); None: their linear
    means."""
    positions = check_positions(problem, positions)
    if load_direction not in LOAD_DIRECTIONS:
        raise InputError("load_direction", load_direction, f"allowed: {', '.join(LOAD_DIRECTIONS)}")
    g = problem.cycloid
    table = cached_table(g, positions, float(r.chi_rad))  # None beyond TABLE_POSITIONS: solved a part at a time
    perfect = perfect_unit(problem, r.chi_rad)
    ref = reference_revolution(problem, positions, float(r.chi_rad), record=True)
    run = revolution(problem, r, positions, table=table, record=True)
    theta = ref.theta_rad

    def te(rev: Revolution) -> tuple[np.ndarray, np.ndarray]:
        return (rev.ccw_rad - ref.ccw_rad) * ARCSEC_PER_RAD, (rev.cw_rad - ref.cw_rad) * ARCSEC_PER_RAD

    ccw, cw = te(run)
    main = ccw if load_direction == "ccw" else cw
    loaded = load_direction == "ccw"
    kin = kinematics(problem)

    def extremes(unit: Realization, rev: Revolution) -> tuple[tuple[float, float], tuple[float, float]]:
        """(min, max) [arcsec] of the load direction's flank and of the other, refined between the
        positions (models.kinematics.curve_extremes)."""
        ccw_x, cw_x = curve_extremes(g, unit, perfect, kin, rev.curve, ref.between)
        main_x, other_x = (ccw_x, cw_x) if loaded else (cw_x, ccw_x)
        return (main_x[0] * ARCSEC_PER_RAD, main_x[1] * ARCSEC_PER_RAD), \
            (other_x[0] * ARCSEC_PER_RAD, other_x[1] * ARCSEC_PER_RAD)

    (te_min, te_max), (other_min, other_max) = extremes(r, run)
    stage = lost_motion_arcmin(run.ccw_rad, run.cw_rad)  # the cycloid stage's gap
    other_from = "given" if other_stages_arcmin is not None else "linear means"
    other = float(other_stages_arcmin) if other_stages_arcmin is not None else \
        float(sum(linear_stage_means(problem)[0].values()))
    lm = stage + other
    spec = amplitude_spectrum(main)
    lead = [k for k in np.argsort(spec[1:])[::-1][:LEADING_ORDERS] + 1
            if spec[k] > SPECTRUM_FLOOR_ARCSEC]
    out_shares = []
    if shares:
        var = float(np.var(main))
        for group in GROUPS:
            if not _has(r, perfect, group):
                continue
            without = _without(r, perfect, group)
            rev = revolution(problem, without, positions, table=table, record=True)
            c, w = te(rev)
            m = c if loaded else w
            (m_lo, m_hi), _ = extremes(without, rev)
            out_shares.append(GroupShare(group, m_hi - m_lo, 1.0 - float(np.var(m)) / var if var > 0 else 0.0))
    ripple = (ref.ccw_rad if load_direction == "ccw" else ref.cw_rad) * ARCSEC_PER_RAD
    return TransmissionErrorResult(
        problem.name, label, positions, load_direction, te_max - te_min, te_min, te_max,
        other_max - other_min, float(lm.max()), float(lm.min()), float(lm[0]), float(stage.max()),
        float(stage.min()), float(stage[0]), other, other_from, int(np.count_nonzero(run.preload_um > 0)),
        float(np.ptp(ripple)), tuple(SpectralLine(int(k), float(spec[k])) for k in lead), tuple(out_shares),
        math.degrees(r.chi_rad), ASSUMPTIONS, np.degrees(theta), ccw, cw, lm, spec)


REPORT_UNITS = 64  # units drawn for the report's 5 % / 95 % curves (exact curve each, ~20 ms)


@dataclass(frozen=True, repr=False)
class TransmissionSection(Result):
    """What the report's transmission-error section shows: the nominal unit's curve and spectrum,
    the curves of the drawn units at given quantiles of TE peak-to-peak (among ``samples`` units of
    the production run's first block, exact geometry), and the production run (its TE histogram)."""

    nominal: TransmissionErrorResult
    quantile_units: dict[str, TransmissionErrorResult]  # "5 %" -> the unit at that quantile of TE p-p
    samples: int
    seed: int
    spec_te_arcsec: float | None
    simulation: object | None = field(default=None, metadata={EXPORT: False})  # SimulationResult, transmission

    def to_dict(self) -> dict:
        return {"nominal": self.nominal.to_dict(),
                "quantile_units": {k: v.to_dict() for k, v in self.quantile_units.items()},
                "samples": self.samples, "seed": self.seed, "spec_te_arcsec": self.spec_te_arcsec}

    def summary(self) -> list[str]:
        return self.nominal.summary()[:1] + [f"{k} unit: TE p-p {v.te_peak_to_peak_arcsec:.2f} arcsec"
                                             for k, v in self.quantile_units.items()]


def transmission_section(problem: Problem, simulation=None, spec_te_arcsec: float | None = None, seed: int = 0,
                         samples: int = REPORT_UNITS, probabilities: tuple[float, ...] = (0.05, 0.95),
                         positions: int = DEFAULT_POSITIONS) -> TransmissionSection:
    """The report's section (TransmissionSection): the nominal unit, and among the first ``samples``
    units the run draws with ``seed`` those at ``probabilities`` of TE peak-to-peak (lower order
    statistic of the exact curves' peak-to-peak)."""
    from rvbacklash.sampling.te_source import sample_units_with_stages

    nominal = transmission_error(problem, perfect_unit(problem), "nominal", positions, shares=False)
    units, other_stages = sample_units_with_stages(problem, seed, samples)
    curves = [transmission_error(problem, u, f"unit {k} of seed {seed}", positions, shares=False,
                                 other_stages_arcmin=float(other_stages[k]))
              for k, u in enumerate(units)]
    order = np.argsort([c.te_peak_to_peak_arcsec for c in curves], kind="stable")
    chosen = {f"{p * 100:g} %": curves[int(order[min(samples - 1, int(p * (samples - 1)))])] for p in probabilities}
    return TransmissionSection(nominal, chosen, samples, seed, spec_te_arcsec, simulation)
