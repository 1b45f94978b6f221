"""The efficiency datasheet of a design's nominal unit (``rvbacklash efficiency``; docs/efficiency.md):
the efficiency at the rated point and each element's loss there, the efficiency map against output
torque and speed (and against temperature), the no-load running torque against input speed and
temperature, the starting (breakaway) torque and starting efficiency, and the back-driving torque.

All from ``elements.element_losses`` on the loads of the elastic solution over a revolution
(``analysis/capacity``'s ``UnitCapacity.loads``, cached per torque: the map costs one set of K chain
solves per torque, every speed and temperature reuses them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rvbacklash.analysis.capacity import UnitCapacity
from rvbacklash.analysis.losses.elements import ELEMENTS, LossBreakdown, element_losses, loss_context
from rvbacklash.analysis.losses.run_results import EfficiencyRun
from rvbacklash.analysis.losses.thermal import (TE_POSITIONS_PER_PIN, PrecisionAtTemperature, ThermalResult,
                                                precision_at_temperature, thermal_balance)
from rvbacklash.design.lubrication import LubricationInputs
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import elastic_model, nominal_realization, other_stages_nominal
from rvbacklash.models.elastic.twist_friction import twist_friction
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result

DEFAULT_ANGLES = 12  # crank angles per revolution: the rated point's loss is within 0.1 % of 48 angles (test)
DEFAULT_TORQUE_FRACTIONS = (0.1, 0.25, 0.5, 0.75, 1.0)
DEFAULT_OUTPUT_SPEEDS_RPM = (5.0, 10.0, 15.0, 30.0, 50.0)
DEFAULT_TEMPERATURES_C = (20.0, 40.0, 60.0, 80.0)
DEFAULT_INPUT_SPEEDS_RPM = (500.0, 1000.0, 2000.0, 3000.0, 4000.0)


class LossModel:
    """A design's unit ready for its losses at any torque, speed and temperature (its loads per torque
    cached): the nominal unit, or a unit of a production run (``realization`` with its crank bearings'
    clearance ``crank_clearance_um``; its crank angle is the first of the K). ``lubrication`` overrides
    the design's [lubrication] (e.g. zero friction)."""

    def __init__(self, problem: Problem, angles: int = DEFAULT_ANGLES, lubrication: LubricationInputs | None = None,
                 realization=None, crank_clearance_um: float | None = None, model=None):
        self.problem = problem
        self.model = model or elastic_model(problem)
        inv, clr = other_stages_nominal(problem)
        if realization is None:
            realization = nominal_realization(problem)
        else:
            inv, clr = 0.0, float(crank_clearance_um if crank_clearance_um is not None else clr)
        self.unit = UnitCapacity(problem, self.model, realization, inv, clr, angles)
        self.angles = angles
        self.lubrication = lubrication or problem.design.lubrication
        self._ctx = None

    @property
    def rated_torque_nm(self) -> float:
        return self.unit.rated_torque_nm

    def point(self, output_torque_nm: float, output_speed_rpm: float, temperature_c: float,
              mode: str = "running") -> LossBreakdown:
        """The LossBreakdown at an operating point."""
        loads = self.unit.loads(abs(float(output_torque_nm)))
        if self._ctx is None:
            self._ctx = loss_context(self.problem, self.model, loads, self.lubrication)
        return element_losses(self._ctx, loads, output_speed_rpm, temperature_c, mode)


@dataclass(frozen=True, repr=False)
class ElementLoss(Result):
    """One element's loss at an operating point."""

    element: str
    loss_w: float
    share_of_losses: float
    input_torque_nm: float  # the loss as a torque at the input
    load_dependent_w: float


@dataclass(frozen=True, repr=False)
class EfficiencyPoint(Result):
    """The efficiency and input torque at one operating point."""

    output_torque_nm: float
    output_speed_rpm: float
    temperature_c: float
    efficiency: float
    input_torque_nm: float
    total_loss_w: float


@dataclass(frozen=True, repr=False)
class NoLoadPoint(Result):
    """The no-load running torque at the input at one input speed and temperature."""

    input_speed_rpm: float
    temperature_c: float
    no_load_torque_nm: float


@dataclass(frozen=True, repr=False)
class EfficiencyResult(Result):
    """The efficiency datasheet of a design's nominal unit (module docstring)."""

    design_name: str
    unit: str
    crank_angles: int
    ratio: float
    rated_torque_nm: float
    rated_output_speed_rpm: float
    temperature_c: float
    viscosity_mm2_s: float  # the oil's at temperature_c
    efficiency_at_rated: float
    input_torque_at_rated_nm: float
    total_loss_at_rated_w: float
    output_power_at_rated_w: float
    pin_film_parameter: float
    pin_friction_coefficient: float
    mesh_friction_coefficient: float
    elements: tuple[ElementLoss, ...]
    efficiency_map: tuple[EfficiencyPoint, ...]  # output torque x output speed at temperature_c
    efficiency_by_temperature: tuple[EfficiencyPoint, ...]  # the rated point at each temperature
    no_load_running_torque: tuple[NoLoadPoint, ...]  # input speed x temperature
    starting_torque_nm: float  # breakaway at the input, no load
    starting_efficiency: float  # at the rated torque, breakaway (static friction, no viscous terms)
    back_driving_torque_nm: float  # at the output, input free; inf: self-locking
    breakaway_torque_at_output_nm: float  # T_0 of the Coulomb friction T_0 + lambda |T| at the output (not fed in)
    breakaway_load_fraction: float  # lambda
    stated_friction_torque_nm: float  # T_f0 the hysteresis loop uses ([elastic] friction_torque_nm, or the contacts')
    precision_by_temperature: tuple[PrecisionAtTemperature, ...]  # lost motion and backlash at each temperature
    assumptions: tuple[str, ...]
    thermal: ThermalResult | None = None  # with a duty cycle: its heat balance (analysis/losses/thermal.py)
    production: EfficiencyRun | None = None  # with units: their efficiencies (analysis/losses/production.py)
    _breakdown: LossBreakdown | None = field(default=None, metadata={EXPORT: False})
    # the loop's friction from the contacts under the twist (input locked, quasi-static;
    # models/elastic/twist_friction.py): T_0 + lambda |T|, whether or not the loop uses it
    loop_friction_model: str = "stated"  # [elastic] friction_model: what the hysteresis loop uses
    loop_friction_load_fraction: float = 0.0  # the lambda the hysteresis loop uses
    contacts_loop_friction_nm: float = math.nan  # T_0
    contacts_loop_friction_load_fraction: float = math.nan  # lambda
    contacts_loop_friction_at_rated_nm: float = math.nan  # T_0 + lambda T_R

    def summary(self) -> list[str]:
        return [f"{self.design_name}: efficiency {self.efficiency_at_rated:.1%} at {self.rated_torque_nm:g} N m, "
                f"{self.rated_output_speed_rpm:g} r/min, {self.temperature_c:g} degC",
                f"no-load running torque {self.no_load_running_torque[0].no_load_torque_nm:.3g} N m at "
                f"{self.no_load_running_torque[0].input_speed_rpm:g} r/min input",
                f"starting torque {self.starting_torque_nm:.3g} N m, "
                f"back-driving {self.back_driving_torque_nm:.3g} N m"]

    def rows(self) -> list[dict]:
        """One row per element at the rated point."""
        return [e.to_dict() for e in self.elements]


def _elements(b: LossBreakdown) -> tuple[ElementLoss, ...]:
    total = b.total_loss_w
    torques = b.element_input_torque_nm()
    return tuple(ElementLoss(name, float(w), float(w / total) if total > 0 else 0.0, float(t), float(ld))
                 for name, w, t, ld in zip(ELEMENTS, b.loss_w, torques, b.load_dependent_w))


def _point(b: LossBreakdown) -> EfficiencyPoint:
    return EfficiencyPoint(b.output_torque_nm, b.output_speed_rpm, b.temperature_c, float(b.efficiency),
                           float(b.input_torque_nm), b.total_loss_w)


def no_load_torque_nm(lm: LossModel, input_speed_rpm: float, temperature_c: float) -> float:
    """The input torque that turns the unloaded reducer at an input speed [N m] (the losses at zero output
    torque over the input speed)."""
    b = lm.point(0.0, input_speed_rpm / lm.problem.geometry.ratio, temperature_c)
    return b.input_torque_nm


def starting_torque_nm(lm: LossModel, output_torque_nm: float = 0.0) -> float:
    """The breakaway input torque at an output torque [N m]: static friction, no viscous terms; the
    output torque's share T / R added."""
    b = lm.point(output_torque_nm, 1.0, lm.lubrication.temperature_c, mode="static")
    return b.input_torque_nm


def breakaway_at_output(lm: LossModel) -> tuple[float, float]:
    """(T_0 [N m], lambda [-]): the load-independent breakaway moments referred to the output (seals, the
    main bearings' preload), and the load-dependent breakaway losses' share of the transmitted power at the
    rated torque (static coefficient on the pins and the mesh, the bearings' load terms). The friction of a
    Coulomb model T_f = T_0 + lambda |T| at the output: the form the elastic chain's loop reads
    ([elastic] friction_torque_nm, friction_load_fraction), reported beside the stated constant, not fed in."""
    t_r = lm.rated_torque_nm
    loaded = lm.point(t_r, 1.0, lm.lubrication.temperature_c, mode="static")
    lam = sum(loaded.load_dependent_w) / loaded.output_power_w
    idle = lm.point(0.0, 1.0, lm.lubrication.temperature_c, mode="static")
    w_out = 2.0 * math.pi / 60.0
    t0 = sum(w - ld for w, ld in zip(idle.loss_w, idle.load_dependent_w)) / w_out
    return t0, lam


def back_driving_torque_nm(lm: LossModel) -> float:
    """The output torque that turns the reducer from its output with the input free [N m]: the
    load-independent breakaway moments referred to the output, T_0, over 1 - lambda, lambda the
    load-dependent breakaway losses' share of the transmitted power at the rated torque (linear in the
    torque; ``breakaway_at_output``): T_b = T_0 / (1 - lambda); inf when lambda >= 1 (self-locking). The
    chain's loads driven from the output are taken as those driven from the input (the same contacts carry
    the torque)."""
    t0, lam = breakaway_at_output(lm)
    return t0 / (1.0 - lam) if lam < 1.0 else math.inf


def _check(name: str, values, lo: float, hi: float) -> tuple[float, ...]:
    out = tuple(float(v) for v in values)
    if not out or any(not (math.isfinite(v) and lo <= v <= hi) for v in out):
        raise InputError(name, list(values), f"allowed: one or more numbers from {lo:g} to {hi:g}")
    return out


def progress_steps(torque_fractions=DEFAULT_TORQUE_FRACTIONS, duty_cycle=None, units: int = 0) -> int:
    """How many steps ``efficiency_rating`` reports to its progress callback."""
    return 3 + len(tuple(torque_fractions)) + (duty_cycle is not None) + units


def efficiency_rating(problem: Problem, *, angles: int = DEFAULT_ANGLES, temperature_c: float | None = None,
                      output_speed_rpm: float | None = None, torque_fractions=DEFAULT_TORQUE_FRACTIONS,
                      output_speeds_rpm=DEFAULT_OUTPUT_SPEEDS_RPM, temperatures_c=DEFAULT_TEMPERATURES_C,
                      input_speeds_rpm=DEFAULT_INPUT_SPEEDS_RPM, lubrication: LubricationInputs | None = None,
                      duty_cycle=None, progress=None) -> EfficiencyResult:
    """The EfficiencyResult of a prepared design's nominal unit (module docstring). ``temperature_c``:
    the oil's temperature of the figures (default [lubrication] temperature_c); ``output_speed_rpm``: the
    rated point's speed (default [capacity] rated_output_speed_rpm); the grids of the map; ``duty_cycle``:
    adds the thermal balance (``thermal.thermal_balance``). A production run's units: ``production``
    (the API adds it)."""
    from rvbacklash.models import friction as fr

    fractions = _check("torque_fractions", torque_fractions, 0.0, 10.0)
    speeds_ = _check("output_speeds_rpm", output_speeds_rpm, 1e-6, 1e5)
    temps = _check("temperatures_c", temperatures_c, -40.0, 150.0)
    inputs = _check("input_speeds_rpm", input_speeds_rpm, 1e-6, 1e6)
    lm = LossModel(problem, angles, lubrication)
    lube = lm.lubrication
    temp = lube.temperature_c if temperature_c is None else _check("temperature_c", [temperature_c], -40.0, 150.0)[0]
    n0 = problem.design.capacity.rated_output_speed_rpm if output_speed_rpm is None else \
        _check("output_speed_rpm", [output_speed_rpm], 1e-6, 1e5)[0]
    t_r = lm.rated_torque_nm
    done = [0]

    def tick() -> None:  # the progress callback gets the steps done (``progress_steps``)
        done[0] += 1
        if progress is not None:
            progress(done[0])

    rated = lm.point(t_r, n0, temp)
    tick()
    grid = []
    for f in fractions:
        for n in speeds_:
            grid.append(_point(lm.point(f * t_r, n, temp)))
        tick()
    by_temp = tuple(_point(lm.point(t_r, n0, t)) for t in temps)
    no_load = tuple(NoLoadPoint(n, t, no_load_torque_nm(lm, n, t)) for t in temps for n in inputs)
    tick()
    start = starting_torque_nm(lm)
    start_loaded = lm.point(t_r, 1.0, temp, mode="static")
    back = back_driving_torque_nm(lm)
    t0, lam = breakaway_at_output(lm)
    th = problem.design.thermal
    te_positions = TE_POSITIONS_PER_PIN * problem.cycloid.zp
    precision = tuple(precision_at_temperature(problem, lm.model, th, t, te_positions=te_positions)
                      for t in sorted({th.reference_temperature_c, temp, *temps}))
    tick()
    thermal = None
    if duty_cycle is not None:
        thermal = thermal_balance(lm, duty_cycle)
        tick()
    nu = fr.kinematic_viscosity_mm2_s(temp, lube.viscosity_40c_mm2_s, lube.viscosity_100c_mm2_s)
    twist = lm.model.twist_friction or twist_friction(problem, lm.model)
    assumptions = (
        "nominal unit; loads from the elastic chain at the output torque over one crank revolution (friction does not "
        "feed back into the loads)",
        "pins: sliding at min(mu_flank, mu_seat) F v (the pin rolls on the flank when its seat slips easier); "
        "mu_flank from the film parameter (Dowson-Higginson film, the disc alone entraining) by a linear share "
        "across Tallian's mixed regime (1 < Lambda < 3); rolling resistance left out",
        "bearings: Palmgren M = M0 + M1 (f0, f1 from [lubrication]); tapered support pairs F_beta = F_r; main "
        "bearings carry their preload only (pure torque)",
        "mesh: ISO/TR 14179-2 mu_mZ and H_V (no profile shift, spur); no churning or windage of the gears",
        "seals and churning: stated torques ([lubrication]); the oil at one temperature throughout",
        "starting and back-driving: static coefficient on the pins and the mesh, the bearings' load terms as breakaway "
        "moments, no viscous terms; back-driving loads taken as forward loads",
    )
    return EfficiencyResult(problem.design.name, "nominal", angles, problem.geometry.ratio, t_r, n0, temp, nu,
                            float(rated.efficiency), float(rated.input_torque_nm), rated.total_loss_w,
                            rated.output_power_w, rated.pin_film_parameter, rated.pin_friction_coefficient,
                            rated.mesh_friction_coefficient, _elements(rated), tuple(grid), by_temp, no_load, start,
                            float(start_loaded.efficiency), back, t0, lam,
                            lm.model.chain.friction_nm, precision, assumptions, thermal, None, rated,
                            problem.design.elastic.loop_friction_model, lm.model.chain.friction_fraction,
                            twist.constant_nm, twist.load_fraction, twist.torque_at_nm(t_r))
