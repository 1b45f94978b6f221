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
