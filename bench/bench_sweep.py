"""A 64-point contact-model sweep (rv80e, 8 x 8 modifications) inline and on a local Dask
cluster of 2 worker processes: times and speed-up (issue 13: target >= 1.7x on 2 cores).

Fair comparison: inline runs one point after the other with one thread per point (``workers=1``;
by default each point would use every core through threads); the cluster has 2 processes of one
thread each. Kernels are compiled (cached) and the cluster's workers warmed up before timing;
the cluster's start-up is timed apart and included in a second speed-up. The rows of both runs
must be identical (same seed, stream (point,) per point).

    .venv/bin/python bench/bench_sweep.py [--samples N] [--workers 2]
"""

from __future__ import annotations

import argparse
import os
import time

from rvbacklash.analysis.executor import executor
from rvbacklash.analysis.sweep import evaluate_point, plan_sweep, point_tasks, run_sweep
from rvbacklash.design.sweep_spec import Parameter, SweepSpec


def warm(task) -> float:
    """One point on a worker: imports, compiled kernels loaded (what its first point pays once)."""
    t = time.perf_counter()
    evaluate_point(task)
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=2**16, help="samples per point (default 2^16: one block)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    args = ap.parse_args()
    count = 8
    if args.tiny:
        args.samples, args.workers, count = 256, 1, 2
    spec = SweepSpec(design="rv80e", model="contact", samples=args.samples, seed=1, name="bench",
                     specs={"backlash": 1.0, "preload": 5.0},
                     parameters=[Parameter(path="second_stage.equidistance_modification_um", start=0.0, stop=17.5,
                                           count=count),
                                 Parameter(path="second_stage.moving_distance_modification_um", start=-10.0,
                                           stop=7.5, count=count)])
    t = time.perf_counter()
    plan = plan_sweep(spec)
    print(f"plan: {len(plan)} points x {args.samples:,} samples, contact model, validated in "
          f"{time.perf_counter() - t:.2f} s")
    evaluate_point(point_tasks(plan, [0], 1)[0])  # compile / load the kernels in this process

    t = time.perf_counter()
    inline = run_sweep(plan, scheduler="inline", workers=1)
    t_inline = time.perf_counter() - t

    t = time.perf_counter()
    with executor("local", workers=args.workers) as ex:
        t_start = time.perf_counter() - t
        t = time.perf_counter()
        ex.client.run(warm, point_tasks(plan, [0], 1)[0])  # on every worker
        t_warm = time.perf_counter() - t
        t = time.perf_counter()
        cluster = run_sweep(plan, scheduler=ex)
        t_cluster = time.perf_counter() - t

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"inline (1 thread):          {t_inline:7.2f} s  ({t_inline / len(plan):.3f} s/point)")
    print(f"local cluster, {args.workers} workers:  {t_cluster:7.2f} s  (+ start-up {t_start:.2f} s, warm-up "
          f"{t_warm:.2f} s)")
    print(f"speed-up: {t_inline / t_cluster:.2f}x on a started cluster, "
          f"{t_inline / (t_cluster + t_start + t_warm):.2f}x including its start-up")
    print(f"rows identical: {inline.rows() == cluster.rows()}; cores: {os.cpu_count()}, load average at the end: "
          f"{load:.2f}")
    best = inline.best()
    print(f"best joint yield {best['joint_yield']:.4f} at equidistance {best[plan.parameters[0]]} um, moving distance "
          f"{best[plan.parameters[1]]} um")


if __name__ == "__main__":
    main()
