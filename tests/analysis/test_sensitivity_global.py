"""Sobol indices per input group: closed forms (the linear model's variance shares, the Ishigami
function), group swapping of inputs with many draws, seeds and executors, refusals."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from helpers import example_with
from rvbacklash.analysis.sensitivity_global import (BLOCK, STREAM_MODELS, InlineExecutor, LinearStreams,
                                                    ThreadExecutor, _run_task,
                                                    bootstrap_intervals, bootstrap_terms, global_sensitivity,
                                                    indices_from_means, sobol_point)
from rvbacklash.analysis.stackup import analyze
from rvbacklash.errors import InputError
from rvbacklash.problem import prepare
from rvbacklash.sampling.engine import Output


def _check_against(result, truth: dict, inside_share: float, max_half_widths: float) -> None:
    """Every estimate within ``max_half_widths`` of its interval's half-width of the truth, and at
    least ``inside_share`` of the 95 % intervals containing it (a 95 % interval misses 1 in 20)."""
    inside = []
    for g in result.groups:
        first, total = truth[g.input]
        for value, lo, hi, true in ((g.first, g.first_ci95_low, g.first_ci95_high, first),
                                    (g.total, g.total_ci95_low, g.total_ci95_high, total)):
            assert lo <= value <= hi or math.isclose(lo, hi, abs_tol=1e-12), (g.input, lo, value, hi)
            inside.append(lo - 1e-12 <= true <= hi + 1e-12)
            assert abs(value - true) <= max_half_widths * max((hi - lo) / 2, 1e-12), (g.input, value, true, lo, hi)
    assert np.mean(inside) >= inside_share, np.mean(inside)


def test_linear_indices_equal_the_closed_form_variance_shares(rv80e_problem):
    """For the linear model S_i = S_Ti = S_i^2 sigma_i^2 / sigma^2 (StackupResult.variance_share)."""
    r = global_sensitivity(rv80e_problem, samples=1 << 13, seed=1, resamples=500)
    shares = {f.key: f.variance_share for f in analyze(rv80e_problem).factors}
    _check_against(r, {k: (v, v) for k, v in shares.items()}, inside_share=0.85, max_half_widths=2.5)
    assert {g.input for g in r.groups} == {k for k, m in zip(shares, rv80e_problem.random_mask) if m}
    # the factor without effect (k_n = 0): exactly zero, with a zero-width interval
    ecc = next(g for g in r.groups if g.input == "crank_eccentricity")
    assert ecc.first == ecc.total == ecc.first_ci95_low == ecc.total_ci95_high == 0.0
    # the ranking by total index follows the variance shares at the top
    assert [g.input for g in r.groups[:2]] == ["disc_cumulative_pitch", "equidistance_modification_error"]
    assert all(g.linear_variance_share == pytest.approx(shares[g.input]) for g in r.groups)
    assert r.model_runs == r.samples * (len(r.groups) + 2) and r.samples == 1 << 13
    assert r.sum_first == pytest.approx(1.0, abs=0.05)
    assert r.to_frame().loc["disc_cumulative_pitch", "id"] == 10


@dataclass(frozen=True)
class Ishigami:
    """f = sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i ~ U(-pi, pi) (Ishigami & Homma 1990), each
    input from its own stream."""

    a: float = 7.0
    b: float = 0.1
    inputs: tuple = ("x1", "x2", "x3")
    random: tuple = (True, True, True)
    outputs: tuple = (Output("f", "-", "Ishigami function"),)

    def block(self, generators, n):
        x1, x2, x3 = (np.pi * (2 * g.random(n) - 1) for g in generators)
        return (np.sin(x1) + self.a * np.sin(x2) ** 2 + self.b * x3 ** 4 * np.sin(x1))[None, :]

    def truth(self) -> dict:
        a, b, pi = self.a, self.b, math.pi
        v1 = 0.5 * (1 + b * pi ** 4 / 5) ** 2
        v2 = a ** 2 / 8
        v13 = b ** 2 * pi ** 8 * (1 / 18 - 1 / 50)
        var = a ** 2 / 8 + b * pi ** 4 / 5 + b ** 2 * pi ** 8 / 18 + 0.5
        return {"x1": (v1 / var, (v1 + v13) / var), "x2": (v2 / var, v2 / var), "x3": (0.0, v13 / var)}


def test_ishigami_first_and_total_indices(rv80e_problem):
    """Interactions: S_T1 > S_1 and S_3 = 0 < S_T3 (closed form, Sobol' & Levitan 1999 / Saltelli 2010)."""
    m = Ishigami()
    r = global_sensitivity(rv80e_problem, model=m, samples=1 << 14, seed=3, resamples=500)
    _check_against(r, m.truth(), inside_share=4 / 6, max_half_widths=3.0)
    x1 = next(g for g in r.groups if g.input == "x1")
    assert x1.total > x1.first_ci95_high  # the interaction shows
    assert r.model == "Ishigami" and r.output == "f"


@dataclass(frozen=True)
class ManyDraws:
    """Input "a" draws 4 numbers per unit, input "b" one: y = sum of a's four + 2 b, so each
    group carries half the variance; swapping a group must swap all of its draws."""

    inputs: tuple = ("a", "b", "unused")
    random: tuple = (True, True, False)
    outputs: tuple = (Output("y", "-", "sum"),)

    def block(self, generators, n):
        return (generators[0].standard_normal((n, 4)).sum(axis=1) + 2 * generators[1].standard_normal(n))[None, :]


def test_a_group_is_every_draw_of_its_input(rv80e_problem):
    r = global_sensitivity(rv80e_problem, model=ManyDraws(), samples=1 << 13, seed=5, resamples=300)
    assert [g.input for g in r.groups] == ["a", "b"] or [g.input for g in r.groups] == ["b", "a"]
    _check_against(r, {"a": (0.5, 0.5), "b": (0.5, 0.5)}, inside_share=0.5, max_half_widths=3.0)
    assert all(g.id is None and g.linear_variance_share is None for g in r.groups)


class ReversedExecutor:
    """Runs the tasks in reverse order (as a cluster may finish them)."""

    def map_unordered(self, fn, tasks, stop=None):
        for i in reversed(range(len(tasks))):
            yield i, fn(tasks[i])


def test_same_seed_same_numbers_for_any_order_and_block_count(rv80e_problem):
    a = global_sensitivity(rv80e_problem, samples=2 * BLOCK, seed=7, resamples=200)  # one thread per core
    b = global_sensitivity(rv80e_problem, samples=2 * BLOCK, seed=7, resamples=200, executor=ReversedExecutor())
    assert a.rows() == b.rows()
    for ex in (InlineExecutor(), ThreadExecutor(2), ThreadExecutor(3)):
        assert global_sensitivity(rv80e_problem, samples=2 * BLOCK, seed=7, resamples=200, executor=ex).rows() == a.rows()
    c = global_sensitivity(rv80e_problem, samples=2 * BLOCK, seed=8, resamples=200)
    assert c.rows() != a.rows()
    # the first units of a run do not depend on the run's size (a block's numbers are its own)
    m = LinearStreams(rv80e_problem)
    small = _run_task((m, 7, (), 0, 0, 1000, frozenset({9})))
    large = _run_task((m, 7, (), 0, 0, 3000, frozenset({9})))
    np.testing.assert_array_equal(small, large[:1000])


def test_estimates_are_scipys_and_intervals_agree_with_scipys_bca(rv80e_problem):
    """The point estimates are scipy.stats.sobol_indices' (saltelli_2010); our percentile bootstrap
    agrees with scipy's BCa bootstrap to a fraction of the interval width."""
    from scipy.stats import sobol_indices

    m = LinearStreams(rv80e_problem)
    groups = [k for k, r in enumerate(m.random) if r and rv80e_problem.sensitivities_arcmin_per_um[k] != 0]
    cols = [frozenset(), frozenset(groups)] + [frozenset({k}) for k in groups]
    n = 512
    f = np.stack([_run_task((m, 11, (), 0, 0, n, c)) for c in cols])
    f_a, f_b, f_ab = f[0], f[1], f[2:]
    first, total = sobol_point(f_a, f_b, f_ab)
    s, t = indices_from_means(bootstrap_terms(f_a, f_b, f_ab).mean(axis=0), len(groups))
    np.testing.assert_allclose(s[0], first, atol=1e-12)
    np.testing.assert_allclose(t[0], total, atol=1e-12)
    ref = sobol_indices(func={"f_A": f_a[None], "f_B": f_b[None], "f_AB": f_ab[:, None, :]}, n=n).bootstrap(
        n_resamples=999)
    lo1, hi1, lo2, hi2 = bootstrap_intervals(f_a, f_b, f_ab, 999, np.random.default_rng(0))
    for lo, hi, r in ((lo1, hi1, ref.first_order), (lo2, hi2, ref.total_order)):
        width = r.confidence_interval.high - r.confidence_interval.low
        assert np.max(np.abs(lo - r.confidence_interval.low) / width) < 0.25
        assert np.max(np.abs(hi - r.confidence_interval.high) / width) < 0.25


class StopAfter:
    """An executor that requests a stop (as Ctrl-C does) after ``k`` tasks."""

    def __init__(self, k):
        self.k = k

    def map_unordered(self, fn, tasks, stop=None):
        for i, task in enumerate(tasks):
            if i == self.k:
                stop.set()
            if stop.is_set():
                return
            yield i, fn(task)


def test_interrupted_run_keeps_the_finished_blocks(rv80e_problem):
    d = int(rv80e_problem.random_mask.sum())
    r = global_sensitivity(rv80e_problem, samples=2 * BLOCK, seed=2, resamples=200, executor=StopAfter(d + 2 + 3))
    assert r.partial and r.samples == BLOCK and r.notes
    assert [row["partial"] for row in r.rows()] == [True] * len(r.groups)  # the CSV says so on every row
    full = global_sensitivity(rv80e_problem, samples=BLOCK, seed=2, resamples=200)
    assert [g.first for g in r.groups] == [g.first for g in full.groups]  # block 0 is the same numbers


def test_refusals_name_the_parameter(rv80e_problem):
    with pytest.raises(InputError, match="power of two") as e:
        global_sensitivity(rv80e_problem, samples=1000)
    assert e.value.field == "samples"
    with pytest.raises(InputError) as e:
        global_sensitivity(rv80e_problem, output="lost_motion")
    assert e.value.field == "output" and "backlash" in e.value.allowed
    assert set(STREAM_MODELS) == {"linear", "contact", "elastic", "transmission"}  # every model has its streams
    with pytest.raises(InputError) as e:
        global_sensitivity(rv80e_problem, model="nonsense")
    assert e.value.field == "model"
    correlated = prepare(example_with("rv80e", ("[factors.bearing_eccentricity]",
                                                "[correlation]\nfactors = [\"pin_radius\", \"pin_circle_radius\"]\n"
                                                "matrix = [[1.0, 0.5], [0.5, 1.0]]\n\n[factors.bearing_eccentricity]")))
    with pytest.raises(InputError, match="independent inputs"):
        global_sensitivity(correlated, samples=64)


def test_conditional_output_is_refused(rv80e_problem):
    @dataclass(frozen=True)
    class Conditional:
        inputs: tuple = ("x",)
        random: tuple = (True,)
        outputs: tuple = (Output("y", "-", "y"), Output("z", "-", "defined for some units", conditional=True))

        def block(self, generators, n):
            x = generators[0].standard_normal(n)
            return np.stack([x, np.where(x > 0, x, np.nan)])

    with pytest.raises(InputError, match="conditional") as e:
        global_sensitivity(rv80e_problem, model=Conditional(), output="z", samples=64)
    assert e.value.field == "output"
    r = global_sensitivity(rv80e_problem, model=Conditional(), output="y", samples=64, resamples=100)
    assert r.groups[0].first == pytest.approx(1.0, abs=0.3)


def test_contact_model_one_random_group_carries_every_index(sun2014_toml):
    """The contact model through its per-factor streams (issue 10 seam): only the equidistance
    modification error is random (per disc), so its total index is the whole variance and every
    other input's is zero (the crank angle, drawn but without effect on a uniform clearance, too:
    the discrete-pin effect is below 0.5 %)."""
    from rvbacklash.design.loading import design_from_toml
    from rvbacklash.factors.catalog import CATALOG

    head = sun2014_toml.partition("[factors.")[0]
    body = "\n".join(f"[factors.{f.key}]\n" + ("plus_minus_um = 3.0" if f.key == "equidistance_modification_error"
                     else "distribution = \"fixed\"\nvalue_um = 10.0" if f.key == "equidistance_modification"
                     else "distribution = \"fixed\"\nvalue_um = 0.0") for f in CATALOG)
    p = prepare(design_from_toml(head + body))
    r = global_sensitivity(p, model="contact", samples=512, seed=3, resamples=200)
    by = {row["input"]: row for row in r.rows()}
    assert by["equidistance_modification_error"]["total"] == pytest.approx(1.0, abs=0.05)
    assert by["crank_angle"]["total"] < 0.02


def test_threads_give_the_inline_numbers_for_the_elastic_model(rv80e_problem):
    a = global_sensitivity(rv80e_problem, model="elastic", samples=64, seed=3, resamples=100, executor=InlineExecutor())
    b = global_sensitivity(rv80e_problem, model="elastic", samples=64, seed=3, resamples=100, executor=ThreadExecutor(2))
    assert a.rows() == b.rows()
