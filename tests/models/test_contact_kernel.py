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


def _scan(problem, unit, degrees):
    """(crank angle, kernel lost motion, exact lost motion) [deg, arcmin, arcmin] of ``unit`` at each angle."""
    from rvbacklash.models.contact import kernel_play

    out = []
    for deg in degrees:
        r = unit.with_(chi_rad=np.radians(deg))
        out.append((deg, kernel_play(problem.cycloid, r).lost_motion_arcmin, exact_play(problem.cycloid, r).lost_motion_arcmin))
    return out


def test_kernel_play_is_the_exact_play_on_dense_crank_angle_scans(rv80e_problem):
    """Issue 36 item 7: where the linear screen says 'preloaded' but the max-min of the osculating
    gaps frees the unit after all, the first-contact search started from gaps linearised at beta = 0,
    some negative at the centre it had found; a negative first estimate turned the screen inside out
    and the first contact went unseen (unit 9 of seed 3 at 94.06 deg: 1.1043 arcmin against the exact
    7.96e-5). Property: on dense crank-angle scans of sampled units (the transmission model's units of
    seed 3, the contact model's draws), the kernel's lost motion is the exact one, wherever the stage
    is free or only just free. The larger scan (20 units x 18 000 angles) is in the issue's closing note."""
    from rvbacklash.sampling.te_source import sample_units

    units = sample_units(rv80e_problem, 3, 10)
    rows = _scan(rv80e_problem, units[9], np.arange(93.90, 94.20, 0.01))  # the reported spike, densely
    for k in range(0, 10, 2):  # a crank-angle scan of other units, 0.9 deg apart, a different phase each
        rows += _scan(rv80e_problem, units[k], np.arange(400) * 0.9 + 0.17 * k)
    deg, kernel, exact = np.array(rows).T
    free = exact > 0
    assert free.sum() > 200 and (~free).sum() > 200  # both kinds of position were scanned
    worst = np.argmax(np.abs(kernel - exact))
    assert abs(kernel[worst] - exact[worst]) < 1e-6, (deg[worst], kernel[worst], exact[worst])
