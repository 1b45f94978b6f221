"""The typed results of a production run's efficiency (``production.efficiency_run``)."""

from __future__ import annotations

from dataclasses import dataclass, field

from rvbacklash.results import KEY, Result


@dataclass(frozen=True, repr=False)
class UnitEfficiency(Result):
    """One unit's efficiency at the rated point."""

    unit: int
    efficiency: float
    input_torque_nm: float
    total_loss_w: float
    pins_loss_w: float
    cycloid_play_arcmin: float  # the unit's cycloid-stage play as its run recorded it (NaN: preloaded)
    cycloid_preload_um: float  # its preload (0: free); a preloaded unit's pins bear on both flanks


@dataclass(frozen=True, repr=False)
class UnitAtTorque(Result):
    """One unit's efficiency at one output torque of the run's map (the rated speed and temperature)."""

    unit: int
    output_torque_nm: float
    efficiency: float


@dataclass(frozen=True, repr=False)
class RunAtTorque(Result):
    """The run's efficiency at one output torque: its distribution over the units."""

    output_torque_nm: float
    mean: float
    sigma: float
    min: float
    median: float
    max: float
    yield_: float | None = field(metadata={KEY: "yield"})  # against spec_min_efficiency at this torque


@dataclass(frozen=True, repr=False)
class EfficiencyRun(Result):
    """The efficiency of the units of a production run at the rated point (module docstring)."""

    units: int
    seed: int
    crank_angles: int
    output_torque_nm: float
    output_speed_rpm: float
    temperature_c: float
    mean: float
    sigma: float
    min: float
    median: float
    max: float
    spec_min_efficiency: float | None
    yield_: float | None = field(metadata={KEY: "yield"})
    nominal_efficiency: float
    per_unit: tuple[UnitEfficiency, ...]
    by_torque: tuple[RunAtTorque, ...] = ()  # with a map over torque (``torque_fractions``): per torque
    unit_map: tuple[UnitAtTorque, ...] = ()  # every unit at every torque of the map

    def summary(self) -> list[str]:
        s = [f"{self.units} units: efficiency mean {self.mean:.2%}, sigma {self.sigma:.2%}, "
             f"range {self.min:.2%} to {self.max:.2%} (nominal {self.nominal_efficiency:.2%})"]
        if self.yield_ is not None:
            s.append(f"yield at efficiency >= {self.spec_min_efficiency:.1%}: {self.yield_:.1%}")
        s += [f"at {b.output_torque_nm:g} N m: mean {b.mean:.2%}, min {b.min:.2%}" for b in self.by_torque]
        return s

    def rows(self) -> list[dict]:
        return [u.to_dict() for u in self.per_unit]
