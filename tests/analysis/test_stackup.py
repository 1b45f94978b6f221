"""Invariants of the linear stack-up over random valid designs (hypothesis)."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rvbacklash.analysis.sensitivity import (
    finite_difference_sensitivities,
    normalised_weights,
    rank_descending,
    variance_shares,
)
from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.loading import design_from_dict
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.models.linear import linear_model
from rvbacklash.problem import prepare

finite = dict(allow_nan=False, allow_infinity=False)


@st.composite
def designs(draw):
    zc = draw(st.integers(10, 80))
    a = draw(st.floats(0.5, 5.0, **finite))
    k1 = draw(st.floats(0.3, 0.95, **finite))
    rp = a * (zc + 1) / k1
    rrp = draw(st.floats(0.1, 0.9)) * rp * np.sin(np.pi / (zc + 1))
    factors = {}
    for f in CATALOG:
        lo = draw(st.floats(-50, 50, **finite))
        width = draw(st.floats(0, 60, **finite))
        factors[f.key] = {"lower_um": lo, "upper_um": lo + width}
    data = {
        "name": "random",
        "first_stage": {"centre_gear_teeth": draw(st.integers(5, 40)), "planet_teeth": draw(st.integers(5, 120)),
                        "module_mm": draw(st.floats(0.5, 5, **finite)),
                        "pressure_angle_deg": draw(st.floats(14.5, 30, **finite))},
        "second_stage": {"cycloid_teeth": zc, "pins": zc + 1, "eccentricity_mm": a,
                         "pin_circle_radius_mm": rp, "pin_radius_mm": rrp,
                         "equidistance_modification_um": draw(st.floats(-20, 20, **finite))},
        "crank_stage": {"eccentricity_transfer_coefficient": draw(st.floats(0, 1, **finite))},
        "factors": factors,
    }
    try:
        return design_from_dict(data)
    except InputError:  # e.g. an undercut profile: not a valid design, draw another
        assume(False)


@settings(max_examples=60, deadline=None)
@given(designs())
def test_stackup_invariants(design):
    problem = prepare(design)
    r = analyze(problem)
    model = linear_model(problem)
    mu, sd = problem.means_um, problem.sigmas_um
    S = model.sensitivities_arcmin_per_um
    t = r.total

    # variance of a linear model of independent inputs is the sum of squares
    assert t.sigma_arcmin ** 2 == pytest.approx(float(np.sum((S * sd) ** 2)), rel=1e-9, abs=1e-15)
    assert t.sigma_arcmin ** 2 == pytest.approx(sum(f.sigma_arcmin ** 2 for f in r.factors), rel=1e-9, abs=1e-15)
    # each stage is its own factors' sum (computed from the stage's own sensitivities), and the
    # stages add up to the total
    for stage in r.stages.values():
        fs = [f for f in r.factors if f.stage == stage.stage]
        assert stage.mean_arcmin == pytest.approx(sum(f.mean_arcmin for f in fs), rel=1e-9, abs=1e-12)
        assert stage.sigma_arcmin ** 2 == pytest.approx(sum(f.sigma_arcmin ** 2 for f in fs), rel=1e-9, abs=1e-15)
    assert sum(s.sigma_arcmin ** 2 for s in r.stages.values()) == pytest.approx(t.sigma_arcmin ** 2, rel=1e-9, abs=1e-15)
    # the model evaluated at the means is the mean
    assert float(model(mu)) == pytest.approx(t.mean_arcmin, rel=1e-9, abs=1e-12)

    shares = np.array([f.variance_share for f in r.factors])
    weights = np.array([f.weight for f in r.factors])
    if t.sigma_arcmin > 0:
        assert shares.sum() == pytest.approx(1.0, abs=1e-12)
    assert weights.sum() == pytest.approx(1.0, abs=1e-12)
    assert sorted(f.rank for f in r.factors) == list(range(1, 22))

    # Eq. (6): each sensitivity equals a finite difference of the vectorised model
    fd = finite_difference_sensitivities(model, mu, step_um=0.5)
    np.testing.assert_allclose(fd, S, rtol=1e-7, atol=1e-12)

    # ordering of the stack-ups: worst case encloses RSS encloses the statistical range
    eps = 1e-9 * (1 + abs(t.worst_case_arcmin))
    assert t.worst_case_min_arcmin - eps <= t.minus3sigma_arcmin <= t.mean_arcmin
    assert t.mean_arcmin <= t.plus3sigma_arcmin <= t.worst_case_arcmin + eps
    assert t.rss_arcmin == pytest.approx(t.plus3sigma_arcmin, rel=1e-9, abs=1e-12)  # sigma = half-zone / 3


def test_model_is_vectorised(sun2014_problem):
    model = linear_model(sun2014_problem)
    x = np.random.default_rng(0).normal(size=(1000, 21))
    y = model(x)
    assert y.shape == (1000,)
    np.testing.assert_allclose(y, [model(row) for row in x], rtol=1e-12)
    np.testing.assert_allclose(model.stage_backlash_um(x).sum(axis=1), model.backlash_um(x).sum(axis=1))
    with pytest.raises(ValueError, match="shape"):
        model(np.zeros((3, 20)))


def test_sensitivity_helpers():
    assert normalised_weights(np.array([1.0, -3.0])).tolist() == [0.25, 0.75]
    assert normalised_weights(np.zeros(3)).tolist() == [0, 0, 0]
    assert variance_shares(np.array([1.0, 2.0]), np.array([2.0, 0.0])).tolist() == [1.0, 0.0]
    assert rank_descending(np.array([0.1, 0.5, 0.1]), np.array([1.0, 0.0, 2.0])).tolist() == [3, 1, 2]


def test_result_types(sun2014_result):
    """Typed result: short repr, to_dict / rows / to_frame of the factor table, Jupyter HTML."""
    r = sun2014_result
    assert len(repr(r).splitlines()) <= 5 and "sun2014" in repr(r)
    d = r.to_dict()
    assert [f["id"] for f in d["factors"]] == list(range(1, 22)) and set(d["stages"]) == {"involute", "cycloid", "crank"}
    frame = r.to_frame()
    assert list(frame.index) == list(range(1, 22)) and frame.loc[17, "mean_um"] == pytest.approx(18.0)
    assert "<table>" in r._repr_html_() and "disc_cumulative_pitch" in r._repr_html_()
