"""A unit's life under a duty cycle (docs/capacity.md, "Duty cycle"): each bearing's damage per hour
of the cycle by Palmgren-Miner (each step's revolutions over the bearing's L10 at that step's torque),
the reducer as their system; the makers' life-equivalent mean torque and speed and their life
formula beside it; the peak checks against the derived allowables.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rvbacklash.analysis.capacity.life import bearing_speed_rpm
from rvbacklash.analysis.capacity.main_bearings import ball_pair, pair_life_mrev, solve_ball_pair
from rvbacklash.analysis.capacity.unit import UnitCapacity
from rvbacklash.design.duty_cycle import DutyCycle
from rvbacklash.design.structure import has_main_bearings
from rvbacklash.models import ratings as rt
from rvbacklash.results import Result


@dataclass(frozen=True, repr=False)
class PeakCheck(Result):
    """A duty cycle's largest value of a quantity against its allowable."""

    quantity: str
    largest: float
    allowable: float
    ok: bool


@dataclass(frozen=True, repr=False)
class DutyCycleLife(Result):
    """The life of a unit under a duty cycle (module docstring)."""

    source: str
    steps: int
    mean_output_speed_rpm: float  # N_m = sum t_i n_i
    mean_output_torque_nm: float  # T_m = (sum t_i n_i |T_i|^(10/3) / sum t_i n_i)^(3/10)
    life_h: float  # the reducer's L10 [h] for this cycle, bearing by bearing (Miner)
    weakest_bearing: str
    weakest_bearing_life_h: float
    main_bearing_life_h: float  # inf: the cycle puts no external load on them (or none given)
    makers_life_h: float  # K (N0 / N_m) (T0 / T_m)^(10/3) with the derived rated torque T0
    bearing_life_h: dict[str, float]
    peak_checks: tuple[PeakCheck, ...]

    def summary(self) -> list[str]:
        return [f"duty cycle {self.source}: {self.steps} steps, N_m {self.mean_output_speed_rpm:.4g} r/min, "
                f"T_m {self.mean_output_torque_nm:.4g} N m", f"life {self.life_h:.4g} h (makers' formula "
                f"{self.makers_life_h:.4g} h)"]


def duty_cycle_life(unit: UnitCapacity, cycle: DutyCycle, rated_torque_nm: float, acceleration_torque_nm: float,
                    momentary_torque_nm: float, allowable_moment_nm: float | None) -> DutyCycleLife:
    """The DutyCycleLife of a unit (``UnitCapacity``): every bearing's L10 at each step's torque
    (``UnitCapacity.lives``, the same K crank angles), its damage per hour
    D = sum_i t_i 60 n_i / (10^6 L_i) (n_i the bearing's speed: z_p times the output's; the main
    bearings' the output's), its life 1 / D, the reducer's L10 as their system (rollers e = 9/8,
    balls 10/9). ``rated_torque_nm`` T0 for the makers' formula; the allowables for the peaks."""
    cap = unit.inputs
    damage: dict[str, float] = {}
    main_damage = 0.0
    pair = ball_pair(unit.model.structure) if has_main_bearings(unit.model.structure) else None
    for step in cycle.steps:
        if step.output_speed_rpm <= 0.0 or step.time_share <= 0.0:
            continue
        speed = bearing_speed_rpm(unit.model, step.output_speed_rpm)
        for b in unit.lives(step.output_torque_nm, step.output_speed_rpm):
            damage[b.name] = damage.get(b.name, 0.0) + step.time_share * 60.0 * speed / (1e6 * b.l10_mrev)
        if pair is not None and (step.moment_nm or step.thrust_n or step.radial_n):
            life = pair_life_mrev(pair, solve_ball_pair(pair, step.moment_nm, step.thrust_n, step.radial_n))
            main_damage += step.time_share * 60.0 * step.output_speed_rpm / (1e6 * life)
    lives = {name: (1.0 / d if d > 0.0 else math.inf) for name, d in damage.items()}
    main_life = 1.0 / main_damage if main_damage > 0.0 else math.inf
    names = list(lives)
    values = [lives[n] for n in names] + [main_life]
    slopes = [rt.ROLLER_WEIBULL_SLOPE] * len(names) + [rt.BALL_WEIBULL_SLOPE]
    life = rt.system_life(values, slopes)
    weakest = min(names, key=lambda n: lives[n]) if names else ""
    n_m, t_m = cycle.mean_speed_rpm, cycle.mean_torque_nm()
    makers = (rt.makers_reducer_life_h(cap.rated_life_h, cap.rated_output_speed_rpm, n_m, rated_torque_nm, t_m)
              if n_m > 0.0 and t_m > 0.0 else math.inf)
    peak_torque = max(abs(s.output_torque_nm) for s in cycle.steps)
    checks = [PeakCheck("output torque vs allowable acceleration torque [N m]", peak_torque, acceleration_torque_nm,
                        peak_torque <= acceleration_torque_nm),
              PeakCheck("output torque vs momentary maximum torque [N m]", peak_torque, momentary_torque_nm,
                        peak_torque <= momentary_torque_nm)]
    peak_moment = max(s.moment_nm for s in cycle.steps)
    if allowable_moment_nm is not None and peak_moment > 0.0:
        checks.append(PeakCheck("external moment vs allowable moment [N m]", peak_moment, allowable_moment_nm,
                                peak_moment <= allowable_moment_nm))
    return DutyCycleLife(cycle.source, len(cycle.steps), n_m, t_m, life, weakest,
                         lives[weakest] if weakest else math.inf, main_life, makers, lives, tuple(checks))
