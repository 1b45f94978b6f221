"""The service life's cost (issue 38): prints figures, asserts nothing.

    .venv/bin/python bench/bench_service_life.py [--units 10000] [--hours 6000]

1. the nominal unit's time stepping to ``--hours`` of the robot-joint cycle (each step: the worn unit
   prepared at 12 crank angles, its loads solved at each of the cycle's torques): wall and CPU time,
   steps;
2. the production run: ``--units`` units read along that trajectory (each unit at every step's
   time), wall and CPU time, units per second;
3. end to end, ``api.service_life`` (both, plus the result): wall and CPU time.
The issue's target: 10 000 units to 6000 h in at most 2 minutes on this machine. The kernels are
compiled (or loaded from numba's cache) before any timing. CPU time (user + sys of this process)
is printed beside the wall time: the machine is shared and its wall times drift.
"""

from __future__ import annotations

import argparse
import time


def _timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--units", type=int, default=10_000, help="units of the production run")
    ap.add_argument("--hours", type=float, default=6000.0, help="hours of the duty cycle")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.units, a.hours = 64, 200.0
    import rvbacklash.api as api
    from rvbacklash.analysis.service_life import nominal_trajectory
    from rvbacklash.analysis.service_life.production import production_life
    from rvbacklash.design.duty_cycle import read_duty_cycle
    from rvbacklash.models.elastic import elastic_model

    problem = api.prepare("rv80e")
    model = elastic_model(problem)
    cycle = read_duty_cycle(api.example_duty_cycle("robot-joint"))
    warm = nominal_trajectory(problem, cycle, [0, 10], model=model)  # compile / load the kernels
    production_life(problem, warm, [0, 10], samples=16, seed=0, spec_lost_motion_arcmin=1.5, model=model)
    hours = [0.0, a.hours / 6, a.hours]
    tr, w1, c1 = _timed(lambda: nominal_trajectory(problem, cycle, hours, model=model))
    print(f"nominal stepping to {a.hours:g} h: {len(tr.hours) - 1} steps, wall {w1:.2f} s, cpu {c1:.2f} s "
          f"({w1 / max(len(tr.hours), 1):.3f} s per step)")
    prod, w2, c2 = _timed(lambda: production_life(problem, tr, hours, samples=a.units, seed=1,
                                                  spec_lost_motion_arcmin=1.5, model=model))
    print(f"production run: {a.units} units x {len(tr.hours)} times, wall {w2:.2f} s, cpu {c2:.2f} s "
          f"({a.units / w2:,.0f} units/s)")
    y = ", ".join(f"{h:g} h {p.fraction:.1%}" for h, p in zip(prod.hours, prod.yield_at_hours))
    print(f"yield (lost motion <= 1.5 arcmin): {y}")
    r, w3, c3 = _timed(lambda: api.service_life(problem, duty_cycle="robot-joint", hours=hours, samples=a.units,
                                                seed=1))
    print(f"end to end api.service_life, {a.units} units to {a.hours:g} h: wall {w3:.2f} s, cpu {c3:.2f} s "
          f"(target: at most 120 s wall at 10 000 units and 6000 h)")
    print(f"nominal lost motion {r.points[0].lost_motion_arcmin:.3f} -> {r.points[-1].lost_motion_arcmin:.3f} arcmin")


if __name__ == "__main__":
    main()
