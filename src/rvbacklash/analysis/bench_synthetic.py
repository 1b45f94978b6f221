"""Synthetic bench files from the model (docs/bench-data.md, the tests of ``bench`` and
``calibrate``): a unit's loop as a bench would record it, with the cycles, noise, offsets, drift,
uneven sampling and start away from zero that real files have, and a TE curve built from known
orders. Every number the bench reads back is then known."""

from __future__ import annotations

from pathlib import Path
from typing import Mapping

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.models.elastic import FALL, RISE, PreparedUnit, elastic_model, nominal_unit
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD

ANGLE_PER_ARCMIN = {"arcmin": 1.0, "arcsec": 60.0, "deg": 1.0 / 60.0, "rad": 1.0 / ARCMIN_PER_RAD}


def model_loop_samples(problem: Problem, *, cycles: int = 2, samples_per_branch: int = 150, noise_arcmin: float = 0.0,
                       offset_arcmin: float = 0.0, drift_arcmin_per_s: float = 0.0, start_fraction: float = 0.0,
                       uneven: bool = False, seed: int = 0, crank_clearance_um: float | None = None,
                       torque_noise_nm: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time [s], torque [N m], angle [arcmin]) of the nominal unit's loop run ``cycles`` times
    (0 -> +T_R -> 0 -> -T_R -> 0, one second per branch), with Gaussian angle noise, an angle offset,
    a linear drift in time, a start ``start_fraction`` of a cycle late, uneven sampling (random
    time steps) and a crank-bearing clearance other than the nominal one. The angle is the model's
    own (analysis.hysteresis centring), so the figures read back are the model's."""
    if problem.design.elastic is None:
        raise InputError("elastic", allowed="the design has no [elastic] table")
    rng = np.random.default_rng(seed)
    unit = nominal_unit(problem)
    if crank_clearance_um is not None:
        unit = unit._replace(crank_clearance_um=float(crank_clearance_um))
    pu = PreparedUnit(elastic_model(problem), unit)
    tr = problem.design.elastic.rated_torque_nm
    centre = 0.5 * (pu.branch(0.0, FALL).sum() + pu.branch(0.0, RISE).sum())
    n = 4 * cycles * samples_per_branch
    ends = np.arange(4 * cycles + 1) / (4 * cycles)  # the turning points and zero crossings: a bench records them
    phase = np.unique(np.concatenate([rng.uniform(0, 1, n - ends.size), ends])) if uneven else np.linspace(0, 1, n + 1)
    n = phase.size
    phase = start_fraction / cycles + phase * (1.0 - start_fraction / cycles)  # one cycle = 1 / cycles of phase
    time = phase * 4.0 * cycles  # [s]
    u = np.mod(time, 4.0)  # 0-1 load+, 1-2 unload+, 2-3 load-, 3-4 unload-
    torque = tr * np.where(u < 1, u, np.where(u < 2, 2 - u, np.where(u < 3, -(u - 2), u - 4)))
    kind = np.where((u < 1) | (u >= 3), RISE, FALL)
    angle = np.array([(pu.branch(float(t), int(k)).sum() - centre) * ARCMIN_PER_RAD for t, k in zip(torque, kind)])
    angle = angle + offset_arcmin + drift_arcmin_per_s * time + rng.normal(0.0, noise_arcmin, n) * (noise_arcmin > 0)
    torque = torque + rng.normal(0.0, torque_noise_nm, n) * (torque_noise_nm > 0)
    return time, torque, angle


def write_loop_csv(path: str | Path, time: np.ndarray, torque: np.ndarray, angle_arcmin: np.ndarray,
                   angle_unit: str = "arcmin", header: str = "") -> Path:
    """A bench file: ``time [s], torque [N·m], angle [<angle_unit>]``."""
    k = ANGLE_PER_ARCMIN[angle_unit]
    rows = [f"# {line}" for line in header.splitlines()] + [f"time [s],torque [N·m],angle [{angle_unit}]"]
    rows += [f"{t:.6f},{q:.6f},{a * k:.10g}" for t, q, a in zip(time, torque, angle_arcmin)]
    path = Path(path)
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def te_curve(orders: Mapping[int, float], *, samples: int = 2000, revolutions: float = 1.0, noise_arcsec: float = 0.0,
             seed: int = 0, start_deg: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(output angle [deg], TE [arcsec]) of sum_m A_m cos(m theta + phase_m) with random phases."""
    rng = np.random.default_rng(seed)
    theta = start_deg + np.linspace(0.0, 360.0 * revolutions, samples, endpoint=False)
    te = np.zeros(samples)
    for m, amp in orders.items():
        te += amp * np.cos(m * np.radians(theta) + rng.uniform(0, 2 * np.pi))
    return theta, te + (rng.normal(0.0, noise_arcsec, samples) if noise_arcsec > 0 else 0.0)


def write_te_csv(path: str | Path, angle_deg: np.ndarray, te_arcsec: np.ndarray) -> Path:
    path = Path(path)
    path.write_text("output angle [deg]\tte [arcsec]\n" + "".join(f"{a:.6f}\t{t:.6f}\n"
                                                                  for a, t in zip(angle_deg, te_arcsec)))
    return path


# the public RV test rig's header of a TE file of two runs, as that rig writes it (its typo kept);
# positions and TE in degrees
RIG_TWO_RUN_HEADER = ("Poisition_Output_Reducer_Fw", "Transmission_Error_Fw", "Position_Output_Reducer_Bw",
                      "Transmission_Error_Bw")


def two_run_te(orders: Mapping[int, float], lost_motion_arcmin: float, *,
               lost_motion_orders: Mapping[int, float] | None = None, samples: int = 2000, revolutions: float = 1.0,
               noise_arcsec: float = 0.0, seed: int = 0, start_deg: float = 0.0
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(forward angle [deg], forward TE [arcsec], backward angle [deg], backward TE [arcsec]) of a
    unit whose flanks' common curve is sum_m A_m cos(m theta + phase_m) and whose lost motion at
    theta is ``lost_motion_arcmin`` + sum_k B_k cos(k theta) [arcmin] (``lost_motion_orders``): the
    forward run half of it below the common curve, the backward run half above (TE = output -
    input / ratio, the output lagging in each run). The backward run turns back from where the
    forward run ended (its angles fall)."""
    rng = np.random.default_rng(seed)
    fwd = start_deg + np.linspace(0.0, 360.0 * revolutions, samples, endpoint=False)
    bwd = fwd[-1] - (fwd - fwd[0])
    phases = {m: rng.uniform(0, 2 * np.pi) for m in orders}

    def common(theta):
        return sum((a * np.cos(m * np.radians(theta) + phases[m]) for m, a in orders.items()), np.zeros_like(theta))

    def gap_arcsec(theta):
        ripple = (b * np.cos(k * np.radians(theta)) for k, b in (lost_motion_orders or {}).items())
        lm = lost_motion_arcmin + sum(ripple, np.zeros_like(theta))
        return 60.0 * lm

    def noise():
        return rng.normal(0.0, noise_arcsec, samples) if noise_arcsec > 0 else 0.0

    return fwd, common(fwd) - 0.5 * gap_arcsec(fwd) + noise(), bwd, common(bwd) + 0.5 * gap_arcsec(bwd) + noise()


def write_rig_te_csv(path: str | Path, fwd_deg: np.ndarray, fwd_te_arcsec: np.ndarray, bwd_deg: np.ndarray,
                     bwd_te_arcsec: np.ndarray, *, header: tuple[str, ...] = RIG_TWO_RUN_HEADER, delimiter: str = ",",
                     decimal: str = ".", metadata: tuple[str, ...] = ()) -> Path:
    """A TE file of two runs as the public RV rig writes it: forward angle, forward TE, backward
    angle, backward TE, all in degrees, no units in the header; ``metadata`` lines above it; runs
    of different lengths leave the shorter's cells blank."""
    n = max(fwd_deg.size, bwd_deg.size)

    def cell(x: np.ndarray, i: int) -> str:
        return "" if i >= x.size else f"{x[i]:.10g}".replace(".", decimal)

    cols = (fwd_deg, fwd_te_arcsec / 3600.0, bwd_deg, bwd_te_arcsec / 3600.0)
    lines = [*metadata, delimiter.join(header)]
    lines += [delimiter.join(cell(c, i) for c in cols) for i in range(n)]
    path = Path(path)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
