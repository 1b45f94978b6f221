"""The default method's own generator (xoshiro256++ bits, ziggurat normals): the compiled
kernels against a plain-Python oracle, the statistical quality of the normals, and the same
numbers whatever the threads or the block order."""

import math

import numpy as np
import pytest
from scipy import stats

from rvbacklash.analysis.exact import exact_distribution
from rvbacklash.analysis.simulation import _linear, simulate
from rvbacklash.sampling import fast_normals as fn
from rvbacklash.sampling.engine import BLOCK_SIZE, run_blocks

MASK = (1 << 64) - 1


def _rotl(x, k):
    return ((x << k) | (x >> (64 - k))) & MASK


def _oracle(state, count):
    """``count`` normals by a line-by-line reading of Blackman & Vigna's xoshiro256++ and
    Marsaglia & Tsang's ziggurat (52-bit form), in plain Python integers."""
    s = [int(v) for v in state]

    def bits():
        out = (_rotl((s[0] + s[3]) & MASK, 23) + s[0]) & MASK
        t = (s[1] << 17) & MASK
        s[2] ^= s[0]
        s[3] ^= s[1]
        s[1] ^= s[2]
        s[0] ^= s[3]
        s[2] ^= t
        s[3] = _rotl(s[3], 45)
        return out

    def unit():
        return (bits() >> 11) * 2.0**-53

    k, w, f = fn.ZIG_K, fn.ZIG_W, fn.ZIG_F
    zs = []
    while len(zs) < count:
        r = bits()
        i, sign, j = r & 0xFF, (r >> 8) & 1, (r >> 9) & ((1 << 52) - 1)
        x = j * float(w[i])
        if j < int(k[i]):
            pass
        elif i == 0:
            while True:
                xt = -math.log(1.0 - unit()) / fn.ZIGGURAT_R
                yt = -math.log(1.0 - unit())
                if yt + yt > xt * xt:
                    break
            x = fn.ZIGGURAT_R + xt
        elif not float(f[i]) + unit() * (float(f[i + 1]) - float(f[i])) < math.exp(-0.5 * x * x):
            continue
        zs.append(-x if sign else x)
    return np.array(zs)


def test_xoshiro_first_word_is_the_reference_one():
    """From state (1, 2, 3, 4) the first output is rotl(1 + 4, 23) + 1 = 41943041 (the
    reference implementation's well-known first value)."""
    out, *_ = fn._next(np.uint64(1), np.uint64(2), np.uint64(3), np.uint64(4))
    assert int(out) == 41943041


def test_kernels_equal_the_plain_python_oracle():
    state = fn.block_state(3, 1, (2,))
    out = np.empty((1000, 21))
    fn.standard_normals(state.copy(), out)
    np.testing.assert_array_equal(out.ravel(), _oracle(state, 21000))  # ~250 tail and wedge draws among them


def test_stored_layer_edges_are_the_recurrence_and_every_layer_has_area_v():
    x = np.array(fn.LAYER_EDGES)
    assert fn.layer_edges() == fn.LAYER_EDGES and x.size == 257 and x[1] == fn.ZIGGURAT_R and x[-1] == 0.0
    f = np.exp(-0.5 * x * x)
    np.testing.assert_allclose(x[1:-1] * (f[2:] - f[1:-1]), fn.ZIGGURAT_V, rtol=1e-8)  # layers 1..255
    tail = math.sqrt(math.pi / 2) * math.erfc(fn.ZIGGURAT_R / math.sqrt(2))
    assert fn.ZIGGURAT_R * f[1] + tail == pytest.approx(fn.ZIGGURAT_V, rel=1e-9)  # the base layer


def test_the_normals_are_standard_normal():
    """2^22 normals from 4 blocks: moments within 5 standard errors, KS and a 1000-bin
    chi-square test at 1e-4, the tail algorithm's share beyond r and beyond 4.5 within 5
    binomial standard errors, no lag-1 or cross-block correlation."""
    blocks = []
    for b in range(4):
        out = np.empty((BLOCK_SIZE, 16))
        fn.standard_normals(fn.block_state(2024, b), out)
        blocks.append(out.ravel())
    z = np.concatenate(blocks)
    n = z.size
    assert abs(z.mean()) < 5 / math.sqrt(n)
    assert abs(z.var() - 1) < 5 * math.sqrt(2 / n)
    assert abs(stats.skew(z)) < 5 * math.sqrt(6 / n)
    assert abs(stats.kurtosis(z)) < 5 * math.sqrt(24 / n)
    assert stats.kstest(z[: 1 << 20], "norm").pvalue > 1e-4
    counts = np.bincount(np.minimum((stats.norm.cdf(z) * 1000).astype(int), 999), minlength=1000)
    assert stats.chisquare(counts).pvalue > 1e-4
    for t in (fn.ZIGGURAT_R, 4.5):
        p = 2 * stats.norm.sf(t)
        assert abs(np.mean(np.abs(z) > t) - p) < 5 * math.sqrt(p * (1 - p) / n)
    assert abs(np.corrcoef(z[:-1], z[1:])[0, 1]) < 5 / math.sqrt(n)
    assert abs(np.corrcoef(blocks[0], blocks[1])[0, 1]) < 5 / math.sqrt(blocks[0].size)


def test_the_linear_kernel_is_the_normals_weighted_in_order(sun2014_problem):
    src = _linear(sun2014_problem, "default", 5, (1,))
    weights, offset = src.fast
    n = 1000 + 17  # not a multiple of the kernel's chunk
    z = src.normals(2, n)
    expected = np.full(n, offset)
    for j in range(weights.size):
        expected += z[:, j] * weights[j]
    np.testing.assert_array_equal(src.values(2, n), expected)
    np.testing.assert_allclose(src.model(src.transform(z)), expected, rtol=1e-12, atol=1e-12)  # the generic path


def test_same_numbers_on_one_or_two_threads_and_any_block_order(sun2014_problem):
    src = _linear(sun2014_problem, "default", 9)
    runs = [run_blocks(src, 5 * BLOCK_SIZE + 7, (3.0,), workers=w, chunk_blocks=c) for w, c in ((1, 1), (2, 1), (2, 3))]
    for r in runs[1:]:
        assert r.outputs[0].moments == runs[0].outputs[0].moments
        np.testing.assert_array_equal(r.outputs[0].histogram.counts, runs[0].outputs[0].histogram.counts)
    late_first = src.values(3, 100)
    src.values(0, 100)
    np.testing.assert_array_equal(src.values(3, 100), late_first)


def test_known_values_pin_the_stream():
    """Regression guard of the seed contract (any machine): block 0 of seed 1."""
    out = np.empty((1, 4))
    fn.standard_normals(fn.block_state(1, 0), out)
    np.testing.assert_array_equal(out[0], KNOWN)


KNOWN = np.array([-0.9711146997490543, -0.9308578372499602, -0.337904722089569, -1.2033228304286974])


@pytest.mark.parametrize("design", ["sun2014_problem", "rv80e_problem"])
def test_yield_of_the_linear_model_matches_its_exact_distribution(design, request):
    """Monte-Carlo yield at the exact 10, 50, 90 and 99 % points within 5 binomial standard
    errors, and the reported 95 % interval covers at least 3 of the 4."""
    problem = request.getfixturevalue(design)
    exact = exact_distribution(problem)
    n = 1 << 19
    covered = 0
    for p in (0.1, 0.5, 0.9, 0.99):
        spec = float(exact.ppf(p))
        y = simulate(problem, samples=n, seed=17, spec_arcmin=spec).output.yield_
        assert abs(y.fraction - p) < 5 * math.sqrt(p * (1 - p) / n)
        covered += y.ci95_low <= p <= y.ci95_high
    assert covered >= 3
