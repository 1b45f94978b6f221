"""The Monte-Carlo kernel of the contact model against the exact geometry, over units drawn by
the sampler itself (tolerance-sized realisations of the rv80e zones)."""

import numpy as np
import pytest

from helpers import example_with
from rvbacklash.analysis.simulation import simulate
from rvbacklash.models.contact import exact_play
from rvbacklash.problem import prepare

BOUND = 0.005  # per-realisation relative error of the kernel's play against the exact play


@pytest.fixture(scope="module")
def wide():
    """rv80e with a 20 um equidistance modification, so that most units are free (issue 10)."""
    return prepare(example_with("rv80e", ("equidistance_modification_um = 5.0", "equidistance_modification_um = 20.0")))


@pytest.mark.parametrize("error_model", ["independent", "long_wave"])
def test_kernel_play_within_half_a_percent_of_exact(wide, error_model):
    """Issue 10: 'linearisation <= 2 %' was false (5 of 150 realisations above 2 %, worst 6.5 %);
    required now: <= 0.5 % over >= 1000 realisations. The kernel's osculating circles plus its exact
    refinement of the first-contact candidates measured a worst relative error of 2e-10."""
    r = simulate(wide, samples=1200, seed=17, model="contact", error_model=error_model, save_units=1200, workers=1)
    worst, free = 0.0, 0
    for unit, _, stage_arcmin in r.units:
        e = exact_play(wide.cycloid, unit)
        if e.preloaded or stage_arcmin <= 0:
            assert e.preloaded == (stage_arcmin <= 0)  # the two agree on which units are preloaded
            continue
        free += 1
        worst = max(worst, abs(stage_arcmin - e.lost_motion_arcmin) / e.lost_motion_arcmin)
    assert free >= 1000 and worst < BOUND, (free, worst)


def test_preload_depth_of_the_kernel_is_the_exact_one(rv80e_problem):
    """The kernel's preload (linear max-min over the pins) against the exact one, rv80e units."""
    r = simulate(rv80e_problem, samples=300, seed=4, model="contact", save_units=300, workers=1)
    depths = [(-stage, exact_play(rv80e_problem.cycloid, unit).preload_um) for unit, _, stage in r.units if stage < 0]
    assert len(depths) > 100
    k, e = np.array(depths).T
    assert np.max(np.abs(k - e)) < 0.02 * max(1.0, e.max())



# Issue 36 item 7: unit 9 of `simulate rv80e --model transmission -n 256 --seed 3 --save-units 12` (the
# same numbers as te_source.sample_units(problem, 3, 10)[9]) at these crank angles read, in the kernel,
# 1.1043 / 1.3445 / 1.0030 arcmin of play where the exact play is 7.96e-5 / 2.7e-5 / 1.99e-3.
ISSUE_ANGLES_DEG = (94.06, 166.34, 166.36)


def _exact_arcmin(m):
    """A MeshPlay as one number: its lost motion [arcmin], minus its preload [um] when preloaded."""
    return -m.preload_um if m.preloaded else m.lost_motion_arcmin


@pytest.mark.parametrize("degrees", ISSUE_ANGLES_DEG)
def test_a_unit_only_just_free_of_preload_reads_its_exact_play(rv80e_problem, degrees):
    """Issue 36 item 7 (the issue's reproducer): where the linear screen calls the stage preloaded but
    the max-min of the osculating gaps frees it after all, the first contacts were searched with the
    gaps linearised at beta = 0, some negative at the recentred rotation; a negative first estimate
    turned the '3 x the first estimate' screen inside out and the pin that stops the disc went unseen."""
    from rvbacklash.models.contact import kernel_play
    from rvbacklash.sampling.te_source import sample_units

    unit = sample_units(rv80e_problem, 3, 10)[9].with_(chi_rad=np.radians(degrees))
    kernel, exact = kernel_play(rv80e_problem.cycloid, unit), exact_play(rv80e_problem.cycloid, unit)
    assert not exact.preloaded and exact.lost_motion_arcmin < 2.5e-3
    assert kernel.lost_motion_arcmin == pytest.approx(exact.lost_motion_arcmin, abs=1e-6)


def test_the_transmission_models_lost_motion_is_the_exact_play_for_the_issues_unit(rv80e_problem):
    """The same unit through the transmission model (`transmission-error --measured`, crank angle
    94.06 deg): its cycloid stage at the reference position read 1.1043 arcmin, `contact --measured`
    7.96e-5 (exact)."""
    from rvbacklash.analysis.transmission import min_positions, transmission_error
    from rvbacklash.sampling.te_source import sample_units

    unit = sample_units(rv80e_problem, 3, 10)[9].with_(  # as the issue ran it: its [kinematics] dropped
        chi_rad=np.radians(94.06), centre_gear_eccentricity_um=None, planet_eccentricity_um=None,
        disc_crank_hole_um=None, carrier_crank_hole_um=None)
    r = transmission_error(rv80e_problem, unit, "unit 9", min_positions(rv80e_problem), shares=False)
    exact = exact_play(rv80e_problem.cycloid, unit)
    assert r.cycloid_stage_reference_arcmin == pytest.approx(exact.lost_motion_arcmin, abs=1e-6)


def test_kernel_play_is_the_exact_play_on_dense_crank_angle_scans(rv80e_problem):
    """Issue 36 item 7, property: over dense crank-angle scans of many units (20 units of the
    transmission model's seed 3, 2000 crank angles each, 0.18 deg apart) the kernel's play is the
    exact play wherever the stage is only just free of preload, the case the kernel got wrong:
    every position the linear screen (unit_gaps' free interval) calls preloaded that the kernel
    finds free or preloaded by less than 0.02 um, and, as a control, 60 positions drawn at random
    (free and preloaded alike). Exact solves are ~10 ms each, so only those are solved exactly;
    the scan of 20 units x 18 000 angles in the issue's closing note found none differing either."""
    from rvbacklash.models.contact import mesh_table, pin_gaps, stage_play, stage_work, unit_gaps
    from rvbacklash.models.unit_errors import unit_errors
    from rvbacklash.sampling.te_source import sample_units

    g = rv80e_problem.cycloid
    stage, gaps, work = g.stage_geometry, pin_gaps(g.discs, g.zp), stage_work(g.discs, g.zp)
    degrees = 0.0123 + 0.18 * np.arange(2000)
    coef = mesh_table(g, np.radians(degrees))  # one table, every unit
    units = sample_units(rv80e_problem, 3, 20)
    just_free, others = [], []
    for k, unit in enumerate(units):
        errors = unit_errors(unit)
        for i in range(degrees.size):
            lo, hi, flat = unit_gaps(coef[i], stage, errors, gaps, work)
            p = stage_play(coef[i], stage, errors, gaps, work, True)
            kernel = -p.preload_um if p.preload_um > 0 else (p.play_ccw_rad + p.play_cw_rad) * 60 * 180 / np.pi
            row = (k, degrees[i], kernel)
            (just_free if (hi < lo or flat < 0.0) and kernel > -0.02 else others).append(row)
    rng = np.random.default_rng(36)
    picked = [others[i] for i in rng.choice(len(others), 60, replace=False)]
    assert len(just_free) >= 40  # the scan reached the case (rv80e's units sit near preload)
    worst = (0.0, None)
    for k, deg, kernel in just_free + picked:
        exact = _exact_arcmin(exact_play(g, units[k].with_(chi_rad=np.radians(deg))))
        assert (kernel > 0) == (exact > 0) or max(abs(kernel), abs(exact)) < 1e-3, (k, deg, kernel, exact)
        # plays agree to 1e-6 arcmin; preloads (negative) to the existing kernel's 2 %
        tol = 1e-6 if exact > 0 else 0.02 * max(1.0, -exact)
        worst = max(worst, (abs(kernel - exact) / tol, (k, deg, kernel, exact)))
    assert worst[0] <= 1.0, worst
