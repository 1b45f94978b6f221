"""The one registry of input distributions: every entry's moments, scipy law and compiled
sampler agree; the schema and the documentation follow the registry."""

import math
from pathlib import Path
from typing import get_args

import numpy as np
import pytest
from scipy import stats

from rvbacklash.design.schema import ToleranceZone
from rvbacklash.factors import distributions as dist
from rvbacklash.factors.distributions import REGISTRY, ResolvedZone, rayleigh_scale_um

ROOT = Path(__file__).resolve().parents[2]

# (reading, kind, zone) -> (mean, sigma) worked out by hand
CASES = {
    "normal": ("signed", (-6.0, 6.0), (0.0, 2.0)),
    "uniform": ("signed", (-6.0, 6.0), (0.0, 12 / math.sqrt(12))),
    "truncated_normal": ("signed", (-6.0, 6.0), (0.0, stats.truncnorm(-3, 3, scale=2.0).std())),
    "rayleigh": ("magnitude", (0.0, 12.0), (rayleigh_scale_um(12.0) * math.sqrt(math.pi / 2),
                                             rayleigh_scale_um(12.0) * math.sqrt((4 - math.pi) / 2))),
    "rayleigh-phase": ("phase", (-6.0, 6.0), (0.0, rayleigh_scale_um(6.0))),
    "fixed": ("signed", (2.5, 2.5), (2.5, 0.0)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_moments_scipy_and_closed_form_agree(case):
    kind, (lo, hi), expected = CASES[case]
    z = ResolvedZone(lo, hi, case.split("-")[0], "test", kind=kind)
    assert dist.moments_um(z) == pytest.approx(expected, rel=1e-12, abs=1e-12)
    law = dist.marginal(z)
    if expected[1] == 0:
        assert law is None
    else:
        assert (float(law.mean()), float(law.std())) == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_every_registry_entry_is_in_the_schema_and_the_docs():
    assert set(get_args(ToleranceZone.model_fields["distribution"].annotation)) == set(REGISTRY)
    page = (ROOT / "docs" / "distributions.md").read_text(encoding="utf-8")
    assert dist.markdown_table() in page, "docs/distributions.md: paste factors.distributions.markdown_table()"


def test_truncated_normal_moments_formula():
    """Johnson, Kotz & Balakrishnan 13.10.1 against scipy's numerical truncnorm, asymmetric case."""
    m, s = dist.truncated_normal_moments(1.0, 2.0, -1.0, 6.0)
    ref = stats.truncnorm(-1.0, 2.5, loc=1.0, scale=2.0)
    assert (m, s) == pytest.approx((ref.mean(), ref.std()), rel=1e-12)


def test_rayleigh_scale_covers_9973_percent():
    assert stats.rayleigh(scale=rayleigh_scale_um(10.0)).cdf(10.0) == pytest.approx(0.9973002, abs=1e-7)
    assert rayleigh_scale_um(1.0) == pytest.approx(1 / 3.4393, rel=1e-4)


def test_a_law_without_a_compiled_branch_is_drawn_from_its_table():
    """The generic branch of the compiled sampler: a tabulated inverse cdf reproduces the law."""
    from rvbacklash.sampling.fast_normals import stream_states
    from rvbacklash.sampling.unit_draw import CYCLOID_FACTORS, FactorLaws, WaveSigmas, draw

    z = ResolvedZone(-6.0, 6.0, "uniform", "test")
    zero, w = np.zeros(1), WaveSigmas(0.0, 0.0, 0.0, 0.0)
    laws = FactorLaws(code=np.array([dist.KERNEL_TABLE]), loc=zero, scale=zero, lower=zero, upper=zero,
                      ppf_table=dist.ppf_table(z)[None, :], disc_wave=w, pin_hole_wave=w, cycloid=CYCLOID_FACTORS,
                      linear_factors=np.zeros(0, dtype=np.int64), linear_sens_arcmin_per_um=np.zeros(0),
                      long_wave=False, box_muller=False)
    streams = stream_states([np.random.SeedSequence(4)])
    x = np.array([draw(streams, laws, 0) for _ in range(40000)])
    assert stats.kstest(x, dist.marginal(z).cdf).pvalue > 0.01
    assert x.min() >= -6.0 and x.max() <= 6.0
