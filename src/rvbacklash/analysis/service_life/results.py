"""Typed results of the service-life analysis (docs/service-life.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rvbacklash.analysis.sensitivity_global import SensitivityResult
from rvbacklash.analysis.statistics import Proportion
from rvbacklash.results import EXPORT, Result


@dataclass(frozen=True, repr=False)
class LifePoint(Result):
    """The nominal unit after some hours of the duty cycle: its bench figures (read at its crank
    angle) and its wear."""

    hours: float
    lost_motion_arcmin: float
    backlash_arcmin: float
    rigidity_nm_per_arcmin: float
    max_flank_wear_um: float  # the deepest place of any disc's flank
    max_pin_and_seat_wear_um: float  # a pin's surface and its seat, at the deepest direction
    crank_clearance_growth_um: float  # the needle bearings' radial clearance growth (mean over the bearings)
    max_pin_stress_mpa: float  # the largest pin-flank Hertz pressure over the cycle's steps and the revolution


@dataclass(frozen=True, repr=False)
class LifeRipple(Result):
    """The nominal unit's transmission error after some hours: its rigid, unloaded flank curve's
    peak-to-peak over the output revolution on each flank (analysis/service_life/ripple.py)."""

    hours: float
    te_peak_to_peak_ccw_arcsec: float
    te_peak_to_peak_cw_arcsec: float
    rigid_play_mean_arcmin: float  # the cycloid stage's rigid play (both flanks' edges apart), mean over the curve


@dataclass(frozen=True, repr=False)
class ContactWearRate(Result):
    """One contact's wear at the start of the service (steady coefficient; running-in multiplies it)."""

    contact: str
    max_depth_rate_um_per_kh: float  # the deepest place's wear depth per 1000 h of the duty cycle
    mean_depth_rate_um_per_kh: float  # over the places where it wears at all
    wear_coefficient_mm3_per_nm: float
    sliding: str  # how the sliding speed is obtained


@dataclass(frozen=True, repr=False)
class FlankProfile(Result):
    """A disc's flank wear along its tooth at the last hour (phase of the meeting pin; 0 at the
    root line through the eccentric, pi at the tip)."""

    hours: float
    phase_deg: tuple[float, ...]
    wear_um: tuple[tuple[float, ...], ...]  # per disc


@dataclass(frozen=True, repr=False)
class ProductionLife(Result):
    """A production run's precision over the service life: each unit read at every step of the nominal
    unit's trajectory with its own wear (its discs' load shares scale the nominal unit's wear) or the
    nominal unit's (docs/service-life.md)."""

    units: int
    seed: int
    unit_wear: str  # "own": each unit's wear from its own discs' load shares; "nominal": the nominal unit's wear
    spec_lost_motion_arcmin: float
    hours: tuple[float, ...]  # the requested hours
    yield_at_hours: tuple[Proportion, ...]  # lost motion <= spec, 95 % Wilson intervals
    lost_motion_quantiles_arcmin: tuple[tuple[float, float, float], ...]  # (5 %, 50 %, 95 %) at each requested hour
    accuracy_life_quantiles_h: dict[str, float]  # "5%", "50%", "95%" ; inf: beyond the last hour
    out_at_start: int  # units out of spec at 0 h
    still_in_spec: int  # units in spec at the last hour (their accuracy life is beyond it)
    grid_hours: tuple[float, ...] = field(default=(), metadata={EXPORT: False})  # the trajectory's times
    grid_yield: tuple[float, ...] = field(default=(), metadata={EXPORT: False})
    grid_lost_motion_arcmin: tuple[tuple[float, float, float], ...] = field(default=(), metadata={EXPORT: False})
    partial: bool = False
    # the units whose lost motion stays within the spec at every time of the trajectory to the last hour
    # (their accuracy life reaches it), 95 % Wilson interval: what `allocate --spec-accuracy-life-h` asks for
    accuracy_life_yield: Proportion | None = None

    def rows(self) -> list[dict]:
        return [{"hours": h, "yield": p.fraction, "yield_ci95_low": p.ci95_low, "yield_ci95_high": p.ci95_high,
                 "lost_motion_p05_arcmin": q[0], "lost_motion_p50_arcmin": q[1], "lost_motion_p95_arcmin": q[2]}
                for h, p, q in zip(self.hours, self.yield_at_hours, self.lost_motion_quantiles_arcmin)]

    def summary(self) -> list[str]:
        life = ", ".join(f"{k} {_h(v)}" for k, v in self.accuracy_life_quantiles_h.items())
        return [f"{self.units} units, lost motion <= {self.spec_lost_motion_arcmin:g} arcmin",
                f"accuracy life quantiles [h]: {life}"]


def _h(v: float) -> str:
    return "beyond" if not math.isfinite(v) else f"{v:,.0f}"


@dataclass(frozen=True, repr=False)
class ServiceLifeResult(Result):
    """The precision datasheet over time (docs/service-life.md): the nominal unit's figures at the
    requested hours of a duty cycle, its contacts' wear rates, its worn flank, the production run's
    yield and accuracy life."""

    design_name: str
    duty_cycle: str
    mean_output_speed_rpm: float
    crank_angles: int
    step_fraction: float
    steps: int
    wear_inputs: dict[str, float]
    points: tuple[LifePoint, ...]  # at the requested hours
    trajectory: tuple[LifePoint, ...]  # at every step
    wear_rates: tuple[ContactWearRate, ...]
    flank_profile: FlankProfile
    production: ProductionLife | None
    partial: bool = False
    transmission_error: tuple[LifeRipple, ...] = ()  # the nominal unit's at the requested hours
    # first-order and total Sobol indices of the units' accuracy life (censored at the last hour), asked with
    # sensitivity_samples (`service-life --sensitivity`); None: not asked
    accuracy_life_sensitivity: SensitivityResult | None = None

    def rows(self) -> list[dict]:
        return [p.to_dict() for p in self.points]

    def summary(self) -> list[str]:
        out = [f"{self.design_name}, duty cycle {self.duty_cycle}: {self.steps} steps"
               + ("  [PARTIAL]" if self.partial else "")]
        for p in self.points:
            out.append(f"{p.hours:g} h: lost motion {p.lost_motion_arcmin:.3f} arcmin, backlash "
                       f"{p.backlash_arcmin:.3f}, rigidity {p.rigidity_nm_per_arcmin:.0f} N m/arcmin")
        for t in self.transmission_error:
            out.append(f"{t.hours:g} h: TE {t.te_peak_to_peak_ccw_arcsec:.3f} / {t.te_peak_to_peak_cw_arcsec:.3f} "
                       f"arcsec peak-to-peak (ccw / cw flank)")
        return out
