"""The production run's TE peak-to-peak refined between its positions (models.te_refine, issue 36 item 8)
against the converged per-unit figure, and the mesh placed between a table's positions."""

from __future__ import annotations

import numpy as np
import pytest

from rvbacklash.analysis.transmission import transmission_error
from rvbacklash.design.loading import load_design
from rvbacklash.models.contact import N_COEF, mesh_column, mesh_table
from rvbacklash.problem import prepare
from rvbacklash.sampling.te_source import sample_units, te_streams, transmission_source

UNITS = 12


@pytest.fixture(scope="module")
def problem():
    return prepare(load_design("rv80e"))


def test_mesh_column_is_the_mesh_tables_row(problem):
    """The compiled column (angle addition) equals mesh_table's row at any crank angle, both discs."""
    g = problem.cycloid
    chis = np.array([-3.1, 0.0, 0.4, 7.7, 40.0, -123.45])
    table = mesh_table(g, chis)
    out = np.empty((N_COEF, g.discs, g.zp))
    for k, chi in enumerate(chis):
        mesh_column(g.stage_geometry, float(chi), out)
        np.testing.assert_allclose(out, table[k], rtol=1e-10, atol=1e-9)


def figures(problem, refine):
    src = transmission_source(problem, "default", 3, refine=refine)
    out = np.empty((3, UNITS))
    src._evaluate(src._draw(te_streams(3, 0), UNITS), out)
    return out


def test_the_refined_run_reads_the_converged_figure(problem):
    """Issue 36 item 8: the production run's TE peak-to-peak (the linearised curve sampled at 8 z_p = 320
    positions) reads the first 12 units of seed 3 -9.0 % below the converged figure of
    ``transmission-error`` on average, unit 3 by -22 % (37.93 against 48.68 arcsec): its extremes are
    cusps and swings narrower than a step. Refined between the positions (te_refine.refined_peak_to_peak):
    -1.4 % on average before the screen of every step (unit 8 -4.1 %, unit 2 -3.3 %: a preloaded stage's
    hump and dip inside a step), now within 1 % on average, no unit below -3 %, none above +1 % (every
    figure is a point of the linearised curve), never below the sampled figure; the other outputs are
    unchanged. Re-pinned when the exact curve's preloaded stage came to rest on the exact gaps (issue 36 item
    8: kinematics.exact_rest; the linearised curve this run reads still rests on the linearised ones): the
    linearised curve's own converged figure (curve_extremes(exact=False)) now reads -1.9 % (unit 6) to +2.5 %
    (unit 5) against the exact curve's on these 12 units, before -0.0 to +0.85 %, so the bounds moved from
    -3 / +1 % to -4.5 / +3 % (measured: -3.8 % unit 6, +2.5 % unit 5)."""
    units = sample_units(problem, 3, UNITS)
    converged = np.array([transmission_error(problem, u, f"unit {k}", 1024, shares=False).te_peak_to_peak_arcsec
                          for k, u in enumerate(units)])
    sampled, refined = figures(problem, False), figures(problem, True)
    rel = refined[1] / converged - 1
    assert rel.mean() > -0.01, rel
    assert rel.min() > -0.045, rel
    assert rel.max() < 0.03, rel
    assert np.all(refined[1] >= sampled[1])
    np.testing.assert_array_equal(refined[[0, 2]], sampled[[0, 2]])
    assert (sampled[1] / converged - 1).mean() < -0.05  # what the default run still reads


def test_the_error_free_unit_between_positions_is_its_solved_flank(problem):
    """The refinement reads the error-free unit's flank between the run's positions on its points solved once
    per design (te_refine.reference_at, REFERENCE_POINTS a step, linear between) instead of solving it at
    every point: within 0.025 arcsec of the solved flank (its ripple, order z_c z_p, is 0.07 arcsec, with
    cusps; read between the run's positions alone, 320 a revolution, the line misses it by more)."""
    from rvbacklash.models.kinematics import ARCSEC_PER_RAD, curve_scratch
    from rvbacklash.models.te_refine import point_te, point_work, reference_at

    src = transmission_source(problem, "default", 3, refine=True)
    ref, g, kin = src.reference, problem.cycloid, src.kinematics
    rows = ref.ccw_rad.size
    scratch = curve_scratch(g.zp, g.zc, g.discs, kin.planets)
    work = point_work(g.stage_geometry, kin.planets, rows)
    xs = np.random.default_rng(2).uniform(0.0, rows, 200)
    solved = np.array([point_te(g.stage_geometry, kin, ref.unit, ref, scratch, work, x, False) for x in xs])
    read = np.array([reference_at(ref, x) for x in xs])
    fine = np.abs(read - solved).max() * ARCSEC_PER_RAD
    assert fine < 0.025
    # the line between the run's positions alone misses it by more
    coarse = np.interp(xs, np.arange(rows + 1), np.append(ref.ccw_rad, ref.ccw_rad[0]))
    assert np.abs(coarse - solved).max() * ARCSEC_PER_RAD > 2 * fine


def test_the_refined_run_is_the_same_on_any_thread_count(problem, monkeypatch):
    """The refinement's scratch is each evaluation's own and the error-free unit's points are read-only: the
    refined figures of a block do not depend on the threads or the chunks that evaluate it."""
    from rvbacklash.sampling import te_source

    a = transmission_source(problem, "default", 7, refine=True).block(1, 24)
    monkeypatch.setattr(te_source, "EVAL_THREADS", 1)
    monkeypatch.setattr(te_source, "CHUNK", 5)
    b = transmission_source(problem, "default", 7, refine=True).block(1, 24)
    np.testing.assert_array_equal(a, b)
    assert np.all(a[1] >= transmission_source(problem, "default", 7, refine=False).block(1, 24)[1])
