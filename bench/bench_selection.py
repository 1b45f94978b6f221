"""Selective assembly's added time on a production run (issue 39: at most 20 %), side by side in one
run: prints figures, asserts nothing.

    .venv/bin/python bench/bench_selection.py [--samples 20000] [--repeats 3]

The elastic model's run of rv80e at random and with ``pins=5x2um,rollers=3x2um,noise=0.5um`` (the
same units), alternated ``repeats`` times after a warm-up of each (compilation or cache load outside
the timing); CPU time (user + sys of this process: the machine's wall time drifts under other work)
and wall time, the best of the repeats. The drawing alone (where selection's work is) is timed the
same way. Beside the selected run as built, the first selected run's drawing ("selected, first
kernel", kept here as it was: a second ``unit_gaps`` per unit for the gaps the factory reads, one
pass over the pins per pin class, a searched cdf table), so that before and after are one run.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.analysis.selection.rules import predicted_play_arcmin, roller_class_rule, window_distance
from rvbacklash.models.contact import (PinGaps, crank_step_angle_rad, pin_gaps, recorded_stage, stage_play, stage_work,
                                      unit_gaps)
from rvbacklash.models.unit_errors import empty_unit
from rvbacklash.sampling.contact_source import save_unit
from rvbacklash.sampling.unit_draw import UnitDraw, draw_scratch, draw_unit
from rvbacklash.units import ARCMIN_PER_RAD


def cpu() -> float:
    t = os.times()
    return t.user + t.system


# --- the first selected drawing kernel (issue 39, first stop), kept for the side-by-side figures ---

@njit(nogil=True, cache=True)
def in_class_searched(x_um, table, c):
    u = np.interp(x_um, table.x_um, table.cdf)
    k = table.ppf_um.shape[1]
    t = u * k - 0.5
    i = min(max(int(math.floor(t)), 0), k - 2)
    w = min(max(t - i, 0.0), 1.0)
    row = table.ppf_um[c]
    return row[i] + w * (row[i + 1] - row[i])


@njit(nogil=True, cache=True)
def pin_rule_per_class(gap, lever, radius, pins, noise_um, window, tol):
    k = pins.mean_um.size
    best, best_c, best_p = np.inf, -1, 0.0
    for c in range(k):
        if pins.share[c] <= 0.0:
            continue
        p = predicted_play_arcmin(gap, lever, radius, pins.mean_um[c] + noise_um, tol)
        e = window_distance(p, window[0], window[1])
        if best_c < 0 or e < best - 1e-12 or (e <= best + 1e-12 and abs(2 * c - (k - 1)) <
                                              abs(2 * best_c - (k - 1))):
            best, best_c, best_p = e, c, p
    return best_c, best_p


@njit(nogil=True, cache=True)
def first_kernel(streams, laws, stage, coef, batch, saved, tables, record):
    unit = empty_unit(stage.zp, stage.zc, stage.discs, np.int64(0))
    scratch = draw_scratch(stage.zp, stage.zc)
    work = stage_work(stage.discs, stage.zp)
    seen = pin_gaps(stage.discs, stage.zp)
    steps = coef.shape[0]
    sens = tables.crank_sens_arcmin_per_um
    pick_pins, pick_rollers = tables.pins.mean_um.size > 1, tables.rollers.mean_um.size > 1
    for s in range(batch.chi_rad.size):
        drawn = draw_unit(streams, laws, steps, unit, scratch)
        mesh = coef[drawn.crank_step]
        unit_gaps(mesh, stage, unit, seen, work)
        c_p, play = pin_rule_per_class(seen.gap_um, seen.lever_um_per_rad, unit.pin_radius_um, tables.pins,
                                       record.noise_um[s], tables.play_window_arcmin, tables.lever_tol)
        if pick_pins:
            for j in range(stage.zp):
                unit.pin_radius_um[j] = in_class_searched(unit.pin_radius_um[j], tables.pins, c_p)
        c_r = roller_class_rule(play, tables.rollers, sens, tables.target_arcmin)
        crank = drawn.crank_clearance_um
        if pick_rollers:
            crank = in_class_searched(crank, tables.rollers, c_r)
        record.pin_class[s], record.roller_class[s], record.predicted_play_arcmin[s] = c_p, c_r, play
        batch.chi_rad[s] = crank_step_angle_rad(drawn.crank_step, stage.zp, steps)
        batch.involute_backlash_rad[s] = max(drawn.linear_arcmin - sens * drawn.crank_clearance_um,
                                             0.0) / ARCMIN_PER_RAD
        batch.crank_clearance_um[s] = crank
        save = s < saved.crank_step.size
        p = stage_play(mesh, stage, unit, PinGaps(batch.gap_um[s], batch.lever_um_per_rad[s]), work, save)
        batch.preload_um[s] = p.preload_um if math.isnan(p.play_ccw_rad) else np.nan
        if save:
            save_unit(saved, s, unit, UnitDraw(drawn.crank_step, drawn.linear_arcmin + sens * (
                crank - drawn.crank_clearance_um), crank), recorded_stage(p))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=20000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    if a.tiny:
        a.samples, a.repeats = 64, 1

    from rvbacklash import prepare
    from rvbacklash.analysis.selection.classes import parse_selection
    from rvbacklash.analysis.selection.source import (draw_selected_kernel, empty_record, measurement_errors,
                                                      selected_source, selection_tables)
    from rvbacklash.analysis.simulation import simulate
    from rvbacklash.sampling.contact_source import block_streams, saved_units
    from rvbacklash.sampling.elastic_source import draw_units, elastic_source, empty_batch

    import rvbacklash.analysis.selection.source as source_module

    problem = prepare("rv80e")
    n = int(a.samples)
    selection = parse_selection("pins=5x2um,rollers=3x2um,noise=0.5um")
    spec = {"lost_motion": 1.0}
    new_kernel, old_kernel = draw_selected_kernel, first_kernel

    def random_run():
        return simulate(problem, samples=n, seed=1, model="elastic", specs=spec)

    def selected_run():
        return simulate(problem, samples=n, seed=1, model="elastic", specs=spec, wrap=selected_source(selection))

    def first_selected_run():
        source_module.draw_selected_kernel = old_kernel
        try:
            return selected_run()
        finally:
            source_module.draw_selected_kernel = new_kernel

    src = elastic_source(problem, "default", 1)
    c, g = src.contact, src.contact.geometry
    tables = selection_tables(src, selection)

    def draw_random():
        draw_units(c, block_streams(c.seed, 0, c.stream), n)

    def drawing(kernel):
        def draw():
            record = empty_record(measurement_errors(1, (), 0, n, selection.noise_um))
            kernel(block_streams(c.seed, 0, c.stream), c.laws, g.stage_geometry, c.coef,
                   empty_batch(n, g.discs, g.zp), saved_units(0, g), tables, record)
            return record
        return draw

    runs = (("random", random_run), ("selected", selected_run), ("selected, first kernel", first_selected_run),
            ("draw random", draw_random), ("draw selected", drawing(new_kernel)),
            ("draw selected, first kernel", drawing(old_kernel)))
    small = n
    for name, f in runs:  # warm-up: compile or load
        n = min(small, 256)
        f()
        n = small
    same = np.array_equal(drawing(new_kernel)().pin_class, drawing(old_kernel)().pin_class)
    best = {}
    for _ in range(a.repeats):
        for name, f in runs:
            c0, w0 = cpu(), time.perf_counter()
            f()
            c1, w1 = cpu() - c0, time.perf_counter() - w0
            b = best.get(name, (np.inf, np.inf))
            best[name] = (min(b[0], c1), min(b[1], w1))
    print(f"rv80e, elastic model, {n} units, best of {a.repeats} alternated runs; selection {selection}")
    for name, _ in runs:
        print(f"{name:28s} CPU {best[name][0]:8.2f} s   wall {best[name][1]:8.2f} s")
    print(f"the two kernels pick the same pin classes: {same}")
    print("selection adds (CPU, as built | first kernel; wall in brackets):")
    for what, r, s_new, s_old in (("production run", "random", "selected", "selected, first kernel"),
                                  ("drawing", "draw random", "draw selected", "draw selected, first kernel")):
        def added(x, k):
            return (best[x][k] / best[r][k] - 1) * 100 if best[r][k] > 0 else float("nan")
        print(f"  {what:15s} {added(s_new, 0):+6.1f} % | {added(s_old, 0):+6.1f} %   "
              f"(wall {added(s_new, 1):+6.1f} % | {added(s_old, 1):+6.1f} %)")

if __name__ == "__main__":
    main()
