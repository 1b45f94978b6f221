"""Monte-Carlo simulation and the exact distribution: reproducibility, statistics against the
exact distribution and closed forms, input distributions through the sampler, typed results."""

import math

import numpy as np
import pytest
from scipy import stats

from helpers import with_factor
from rvbacklash.analysis.exact import exact_distribution
from rvbacklash.analysis.simulation import exact_result, simulate
from rvbacklash.design.loading import design_from_toml, example_text
from rvbacklash.errors import InputError
from rvbacklash.factors.distributions import ResolvedZone
from rvbacklash.problem import prepare
from rvbacklash.sampling.engine import BLOCK_SIZE


@pytest.fixture(scope="module")
def mixed():
    """sun2014 with one factor of every reading, including the biggest contributors."""
    t = example_text("sun2014")
    t = with_factor(t, "disc_cumulative_pitch", "plus_minus_um = 29.76\ndistribution = \"uniform\"")
    t = with_factor(t, "pin_cumulative_pitch", "lower_um = 0.0\nupper_um = 46.5\ndistribution = \"rayleigh\"")
    t = with_factor(t, "moving_distance_modification_error",
                    "plus_minus_um = 11.762\ndistribution = \"truncated_normal\"\nsigma_um = 8.0")
    t = with_factor(t, "disc_runout", "plus_minus_um = 23.0\ndistribution = \"rayleigh\"")
    t = with_factor(t, "pin_hole_clearance", "lower_um = 0.0\nupper_um = 17.5\ndistribution = \"fixed\"")
    return prepare(design_from_toml(t))


def test_same_seed_same_numbers_any_chunking_or_threads(sun2014_problem):
    n = 3 * BLOCK_SIZE + 12345  # a partial last block too
    ref = simulate(sun2014_problem, samples=n, seed=7, spec_arcmin=3.0, workers=1, chunk_blocks=1).to_dict()
    for workers, chunk in [(2, 1), (2, 3), (1, 8)]:
        other = simulate(sun2014_problem, samples=n, seed=7, spec_arcmin=3.0, workers=workers,
                         chunk_blocks=chunk).to_dict()
        assert other["outputs"] == ref["outputs"] and other["convergence"] == ref["convergence"]


def test_published_seed_figures_are_kept(sun2014_problem):
    """`simulate sun2014 --seed 1` at 2^20 samples: mean 1.84980, sigma 0.77840 (the default
    method's stream after 0.1.0, CHANGELOG.md; exact: 1.85091, 0.77842); a
    regression guard on the seed contract."""
    r = simulate(sun2014_problem, samples=1 << 20, seed=1)
    assert r.mean_arcmin == pytest.approx(1.84980, abs=1e-5) and r.sigma_arcmin == pytest.approx(0.77840, abs=1e-5)


def test_seed_zero_is_valid_and_seeds_differ(sun2014_problem):
    a = simulate(sun2014_problem, samples=20000, seed=0)
    b = simulate(sun2014_problem, samples=20000, seed=0)
    c = simulate(sun2014_problem, samples=20000, seed=1)
    assert a.to_dict()["outputs"] == b.to_dict()["outputs"] and a.mean_arcmin != c.mean_arcmin


def test_generic_path_is_seeded_and_chunk_invariant(mixed):
    n = 2 * BLOCK_SIZE + 99
    a = simulate(mixed, samples=n, seed=3, workers=1, chunk_blocks=1)
    b = simulate(mixed, samples=n, seed=3, workers=2, chunk_blocks=2)
    assert a.to_dict()["outputs"] == b.to_dict()["outputs"]


def _misses(result, exact, spec):
    """How many reported 95 % intervals miss the exact value."""
    o = result.output
    misses = sum(not (q.ci95_low <= float(exact.ppf(q.probability)) <= q.ci95_high) for q in o.quantiles)
    misses += not (o.yield_.ci95_low <= float(exact.cdf(spec)) <= o.yield_.ci95_high)
    misses += not (o.mean_ci95_low <= exact.mean <= o.mean_ci95_high)
    return misses


def test_sampled_statistics_cover_the_exact_values(sun2014_problem, mixed):
    """5 intervals x 3 methods x 2 designs = 30 checks at 95 %: expect 1.5 misses; more than
    5 has probability < 0.5 % if the intervals are right (binomial), so that fails."""
    misses, checks = 0, 0
    for problem, spec in [(sun2014_problem, 3.0), (mixed, 3.5)]:
        exact = exact_distribution(problem)
        for method in ("default", "box-muller", "sobol"):
            r = simulate(problem, samples=1 << 19, seed=11, method=method, spec_arcmin=spec)
            misses += _misses(r, exact, spec)
            checks += 5
            assert r.sigma_arcmin == pytest.approx(exact.std, rel=0.01)
    assert checks == 30 and misses <= 5, misses


def test_mc_mean_and_sigma_agree_with_the_stackup(sun2014_problem, sun2014_result):
    r = simulate(sun2014_problem, samples=1_000_000, seed=1)
    assert r.output.mean_ci95_low <= sun2014_result.total.mean_arcmin <= r.output.mean_ci95_high
    # sample sigma of 1e6 normals: relative standard error 1/sqrt(2 n) = 7e-4
    assert r.sigma_arcmin == pytest.approx(sun2014_result.total.sigma_arcmin, rel=4 * 7.1e-4)
    assert r.linear_reference.sigma_arcmin == sun2014_result.total.sigma_arcmin


def _problem_of(zones, sens):
    """A Problem-like stand-in for the exact distribution of given zones and sensitivities."""
    from types import SimpleNamespace

    from rvbacklash.factors.distributions import marginal, moments_um
    m = np.array([moments_um(z) for z in zones])
    return SimpleNamespace(sensitivities_arcmin_per_um=np.asarray(sens, float), means_um=m[:, 0], sigmas_um=m[:, 1],
                           zones=tuple(zones), correlated=False, correlation=np.eye(len(zones)),
                           marginals=tuple(marginal(z) for z in zones))


def test_exact_against_closed_forms():
    """Two uniforms give a triangle; a normal plus a uniform has a closed-form cdf."""
    fixed = ResolvedZone(0.0, 0.0, "fixed", "t", value_um=0.0)
    zones = [ResolvedZone(-1.0, 1.0, "uniform", "t"), ResolvedZone(-1.0, 1.0, "uniform", "t")] + [fixed] * 19
    s = np.zeros(21)
    s[0] = s[1] = 1.0
    ex = exact_distribution(_problem_of(zones, s))
    tri = stats.triang(c=0.5, loc=-2, scale=4)
    for p in (0.001, 0.1, 0.5, 0.9, 0.99865):
        assert float(ex.ppf(p)) == pytest.approx(tri.ppf(p), abs=2e-5)
    assert ex.std == pytest.approx(tri.std())

    zones[1] = ResolvedZone(-3.0, 3.0, "normal", "t")  # sigma 1
    ex = exact_distribution(_problem_of(zones, s))
    # P(U + Z <= x) = (1/2) int_{-1}^{1} Phi(x - u) du
    for x in (-2.5, 0.3, 1.7):
        ref = 0.5 * (_int_phi(x + 1) - _int_phi(x - 1))
        assert float(ex.cdf(x)) == pytest.approx(ref, abs=1e-6)


def _int_phi(t):  # antiderivative of Phi: t Phi(t) + phi(t)
    return t * stats.norm.cdf(t) + stats.norm.pdf(t)


def test_exact_all_normal_is_the_closed_form(sun2014_problem):
    ex = exact_distribution(sun2014_problem)
    assert ex.is_closed_form
    ref = stats.norm(ex.mean, ex.std)
    for p in (1e-6, 0.00135, 0.5, 0.99865):
        assert float(ex.ppf(p)) == pytest.approx(ref.ppf(p), rel=1e-12)
    for x in (-1.0, 1.85, 4.0):
        assert float(ex.cdf(x)) == pytest.approx(ref.cdf(x), rel=1e-12, abs=1e-15)
        assert float(ex.pdf(x)) == pytest.approx(ref.pdf(x), rel=1e-12)


def test_exact_result_is_a_simulation_result(rv80e_problem):
    r = exact_result(rv80e_problem, spec_arcmin=1.5)
    assert r.method == "exact" and r.samples is None and r.samples_done is None and not r.partial
    assert 0 < r.yield_.fraction < 1 and r.yield_.ci95_low == r.yield_.fraction
    assert r.quantiles.at(0.5).value == pytest.approx(r.mean_arcmin, rel=1e-12)  # normal: median = mean
    assert r.output.histogram.counts is None and len(r.output.histogram.density) == 200


@pytest.mark.parametrize("reading", ["normal", "uniform", "truncated_normal", "rayleigh_mag", "rayleigh_phase"])
def test_the_sampler_draws_each_reading(reading):
    """The copula transform of normals reproduces every reading's moments and support."""
    from rvbacklash.sampling.inputs import InputTransform

    kind = {"rayleigh_phase": "phase", "rayleigh_mag": "magnitude"}.get(reading, "signed")
    dist = reading.split("_")[0] if reading.startswith("rayleigh") else reading
    lo, hi = (0.0, 12.0) if kind == "magnitude" else (-6.0, 6.0)
    z = ResolvedZone(lo, hi, dist, "t", kind=kind)
    p = _problem_of([z] + [ResolvedZone(0.0, 0.0, "fixed", "t", value_um=0.0)] * 20, np.zeros(21))
    law = p.marginals[0]
    normal = law.dist.name == "norm"
    tr = InputTransform(np.array([0]), np.zeros(21), (law,), np.array([normal]),
                        np.array([p.means_um[0] if normal else 0.0]), np.array([p.sigmas_um[0] if normal else 0.0]),
                        None)
    x = tr(np.random.default_rng(3).standard_normal((400_000, 1)))[:, 0]
    assert x.mean() == pytest.approx(p.means_um[0], abs=4 * p.sigmas_um[0] / math.sqrt(x.size))
    assert x.std() == pytest.approx(p.sigmas_um[0], rel=0.01)
    if kind == "magnitude":
        assert (x >= lo).all() and np.mean(x <= hi) == pytest.approx(0.9973, abs=1e-3)
    if dist in ("uniform", "truncated_normal"):
        assert (x >= lo).all() and (x <= hi).all()


def test_correlated_normals_follow_the_covariance(sun2014_problem):
    t = example_text("sun2014") + (
        "\n[correlation]\nfactors = [\"disc_cumulative_pitch\", \"pin_cumulative_pitch\"]\n"
        "matrix = [[1.0, 0.8], [0.8, 1.0]]\n")
    p = prepare(design_from_toml(t))
    r = simulate(p, samples=1 << 20, seed=2)
    assert r.linear_reference.sigma_arcmin > simulate(sun2014_problem, samples=1 << 12, seed=2).linear_reference.sigma_arcmin
    assert r.sigma_arcmin == pytest.approx(r.linear_reference.sigma_arcmin, rel=4 / math.sqrt(2 * (1 << 20)))
    ex = exact_result(p, spec_arcmin=3.0)
    assert ex.sigma_arcmin == pytest.approx(r.linear_reference.sigma_arcmin, rel=1e-12)


@pytest.mark.parametrize("kwargs,field", [
    ({"samples": 0}, "samples"), ({"samples": 1.5}, "samples"), ({"samples": True}, "samples"),
    ({"samples": 10 ** 13}, "samples"), ({"samples": 2 * 10 ** 9, "method": "sobol"}, "samples"),
    ({"seed": -1}, "seed"), ({"seed": "1"}, "seed"), ({"spec_arcmin": -1.0}, "spec_arcmin"),
    ({"spec_arcmin": math.nan}, "spec_arcmin"), ({"method": "latin"}, "method"), ({"quantiles": (1.5,)}, "quantiles"),
    ({"model": "gears"}, "model"), ({"workers": 0}, "workers"), ({"specs": {"rigidity": 3.0}}, "specs"),
    ({"model": "contact", "method": "sobol"}, "method"), ({"model": "contact", "method": "exact"}, "method"),
])
def test_bad_parameters_name_the_python_parameter(rv80e_problem, kwargs, field):
    """Regression (issue 9): library errors quoted CLI flags ('--samples = None')."""
    with pytest.raises(InputError) as e:
        simulate(rv80e_problem, **{"samples": 1000, **kwargs})
    assert e.value.field == field and "allowed" in str(e.value) and "--" not in str(e.value)


def test_one_sample_is_a_valid_run_without_warnings(rv80e_problem, recwarn):
    """Regression (issue 9): -n 1 printed RuntimeWarnings."""
    r = simulate(rv80e_problem, samples=1, seed=0, spec_arcmin=3.0)
    assert r.samples_done == 1 and r.sigma_arcmin == 0.0
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]


def test_simulation_result_is_typed_and_short(rv80e_problem):
    r = simulate(rv80e_problem, samples=50_000, seed=1, spec_arcmin=3.0, quantiles=(0.9,))
    assert 2 <= len(repr(r).splitlines()) <= 6 and len(repr(r)) < 600
    q = r.quantiles.at(0.9)
    assert q.ci95_low <= q.value <= q.ci95_high
    with pytest.raises(KeyError, match="computed: 0.00135, 0.5, 0.9, 0.99865"):
        r.quantiles.at(0.95)
    d = r.to_dict()
    assert set(d["outputs"]) == {"backlash"} and "sigma" in d["outputs"]["backlash"]
    assert {"probability", "value", "ci95_low", "ci95_high", "bounded", "needs_samples"} == \
        set(d["outputs"]["backlash"]["quantiles"]["table"][0])
    assert "yield" in d["outputs"]["backlash"] and "std_arcmin" not in str(d)
    frame = r.to_frame()
    assert frame.loc[frame["statistic"] == "mean", "value"].item() == pytest.approx(r.mean_arcmin)
    assert "<table>" in r._repr_html_()


def test_streams_of_one_seed_are_independent_and_reproducible(sun2014_problem):
    """A sweep point runs on SeedSequence(seed, spawn_key=(point, block)): same stream, same
    numbers; other stream, other numbers; the empty stream is the plain seed."""
    from rvbacklash.sampling.engine import block_generator

    a = simulate(sun2014_problem, samples=5000, seed=3, stream=(7,))
    b = simulate(sun2014_problem, samples=5000, seed=3, stream=(7,))
    c = simulate(sun2014_problem, samples=5000, seed=3, stream=(8,))
    assert a.to_dict()["outputs"] == b.to_dict()["outputs"] and a.mean_arcmin != c.mean_arcmin
    assert a.stream == (7,)
    assert block_generator(3, 0, ()).random() == block_generator(3, 0).random()
    assert block_generator(3, 0, (7,)).random() != block_generator(3, 0).random()
    with pytest.raises(InputError, match="stream"):
        simulate(sun2014_problem, samples=10, stream=(-1,))


def test_every_csv_row_says_whether_the_run_was_interrupted():
    """Regression: an interrupted `simulate --csv` (transmission, elastic models) wrote a CSV with
    no partial mark though the JSON and the table said PARTIAL. Every row has a `partial` column,
    as compare's CSV does (a column: pandas and spreadsheets read it as data; a comment line
    would be a data row to Excel and an error to pandas.read_csv)."""
    import dataclasses

    from rvbacklash.report.files import render_csv

    sim = simulate(prepare(design_from_toml(example_text("rv80e"))), samples=2000, seed=1, spec_arcmin=3.0)
    assert [r["partial"] for r in sim.rows()] == [False] * len(sim.rows())
    stopped = dataclasses.replace(sim, partial=True)
    lines = render_csv(stopped.rows()).splitlines()
    assert lines[0].split(",")[-1] == "partial" and all(line.endswith(",True") for line in lines[1:])
