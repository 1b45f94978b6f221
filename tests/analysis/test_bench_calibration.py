"""Calibration against measured loops (analysis/calibration.py, issue 29): the model's own loop
with a known structure stiffness, friction and clearance gives them back within their 95 %
intervals; the calibrated design's loop is the measured one; a batch of units with different
clearances gives the mean clearance and the spread; what cannot be fitted is said."""

from __future__ import annotations

import numpy as np
import pytest

import rvbacklash as rb
from rvbacklash.analysis.bench import read_bench
from rvbacklash.analysis.bench_synthetic import model_loop_samples, write_loop_csv
from rvbacklash.analysis.calibration import calibrate, calibration_header
from rvbacklash.analysis.hysteresis import hysteresis
from rvbacklash.errors import InputError
from rvbacklash.report.design_toml import design_toml

TRUE_K, TRUE_TF = 400.0, 3.0
NOMINAL_CLEARANCE = 4.5  # rv80e: the zone mean of [0, IT5 of 30 mm] (factor 20)


def with_elastic(design, **fields):
    return rb.prepare(design.model_copy(update={"elastic": design.elastic.model_copy(update=fields)}))


@pytest.fixture(scope="module")
def stated_problem(rv80e):
    """rv80e with the loop's friction the stated constant (friction_model = "stated"): calibrate fits the
    bare torque friction_torque_nm (the default, the contacts' friction, fits its coefficient)."""
    return with_elastic(rv80e, friction_model="stated")


@pytest.fixture(scope="module")
def truth(rv80e):
    return with_elastic(rv80e, structure_stiffness_nm_per_arcmin=TRUE_K, friction_torque_nm=TRUE_TF)


def unit_file(truth, path, clearance, seed, samples=250, noise=0.01):
    t, q, a = model_loop_samples(truth, cycles=2, samples_per_branch=samples, noise_arcmin=noise, offset_arcmin=2.0,
                                 drift_arcmin_per_s=0.005, uneven=True, seed=seed, crank_clearance_um=clearance)
    return write_loop_csv(path, t, q, a, angle_unit="deg")


def test_one_unit_recovers_stiffness_friction_and_clearance(stated_problem, truth, tmp_path):
    """Done-when check: calibrate on the model's loop (noise, offset, drift, two cycles, degrees)
    recovers the structure stiffness and the friction within their 95 % intervals, and the
    calibrated design's loop reproduces the measured one."""
    f = unit_file(truth, tmp_path / "u.csv", 6.0, seed=3)
    r = calibrate(stated_problem, [f], bootstrap=0)
    for name, true in (("structure_stiffness_nm_per_arcmin", TRUE_K), ("friction_torque_nm", TRUE_TF),
                       ("crank_clearance_offset_um", 6.0 - NOMINAL_CLEARANCE)):
        p = r.parameter(name)
        assert p.ci95_low <= true <= p.ci95_high, (name, p)
        assert p.ci_from == "jacobian"
    assert r.parameter("structure_stiffness_nm_per_arcmin").design_value is None  # derived before
    assert r.residual_rms_arcmin == pytest.approx(0.01, rel=0.25)  # the noise: nothing left to explain
    # the calibrated design file: what was fitted, from where, when; it loads and runs
    text = design_toml(r.design, "Calibrated from " + str(f))
    path = tmp_path / "calibrated.toml"
    path.write_text(text)
    again = hysteresis(rb.prepare(str(path)))
    measured = read_bench([f], rated_torque_nm=784.0).units[0]
    for k in ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin"):
        assert abs(getattr(again, k) - getattr(measured, k)) <= measured.uncertainty_k2[k], k
        assert getattr(again, k) == pytest.approx(r.after[k], rel=1e-12)
    assert again.structure_model == "stated"
    assert r.design.factors.crank_bearing_clearance.mean_um == pytest.approx(6.0, abs=0.05)


def test_a_batch_of_five_units_with_different_clearances(stated_problem, truth, tmp_path):
    """Done-when check: five units, clearances 3..7 um: the stiffness and friction come back within
    the bootstrap's intervals, the clearance offset is the batch's mean, the spread is reported."""
    clearances = (3.0, 4.0, 5.0, 6.0, 7.0)
    files = [unit_file(truth, tmp_path / f"u{i}.csv", g, seed=10 + i, samples=60) for i, g in enumerate(clearances)]
    r = calibrate(stated_problem, files, bootstrap=4, seed=1)
    assert r.bootstrap_resamples >= 3
    for name, true in (("structure_stiffness_nm_per_arcmin", TRUE_K), ("friction_torque_nm", TRUE_TF)):
        p = r.parameter(name)
        assert p.ci_from.endswith("bootstrap over units (the wider)") and p.ci95_low <= true <= p.ci95_high, (name, p)
    assert r.parameter("crank_clearance_offset_um").value == pytest.approx(np.mean(clearances) - NOMINAL_CLEARANCE,
                                                                           abs=0.3)
    s = r.spread["backlash_arcmin"]
    assert s["units"] == 5 and s["measured_sigma"] > 0.05  # 1 um of crank clearance ~ 0.08 arcmin of dead band
    assert r.crank_clearance_um_per_unit == pytest.approx(clearances, abs=0.1)
    g = r.spread["crank_clearance_um"]
    assert g["measured_sigma"] == pytest.approx(np.std(clearances, ddof=1), rel=0.1) and g["predicted_sigma"] == 1.5
    assert not r.lack_of_fit and r.flags == ()  # the model's own loops: nothing flagged (issue 36 item 6)


def test_a_rigid_structure_is_not_identifiable(rv80e, rv80e_problem, tmp_path):
    rigid = with_elastic(rv80e, structure_stiffness_nm_per_arcmin=1e8)
    t, q, a = model_loop_samples(rigid, cycles=1, samples_per_branch=80, noise_arcmin=0.005, seed=1)
    f = write_loop_csv(tmp_path / "rigid.csv", t, q, a)
    with pytest.raises(InputError) as e:
        calibrate(rv80e_problem, [f], bootstrap=0)
    assert e.value.value == "structure_stiffness_nm_per_arcmin" and "not identifiable" in str(e.value)
    assert str(f) in e.value.field and "\n" not in str(e.value)


def test_a_calibration_that_does_not_converge_says_so(rv80e_problem, truth, tmp_path):
    f = unit_file(truth, tmp_path / "u.csv", 4.5, seed=5, samples=60)
    with pytest.raises(InputError) as e:
        calibrate(rv80e_problem, [f], bootstrap=0, max_evaluations=2)
    assert "did not converge" in str(e.value) and str(f) in e.value.field


def test_a_te_file_or_another_rated_torque_cannot_be_calibrated(rv80e_problem, truth, tmp_path):
    f = unit_file(truth, tmp_path / "u.csv", 4.5, seed=5, samples=60)
    with pytest.raises(InputError) as e:
        rb.calibrate(rv80e_problem, bench=f, bootstrap=-1)
    assert e.value.field == "bootstrap"
    te = tmp_path / "te.tsv"
    te.write_text("output angle [deg]\tte [arcsec]\n" + "".join(f"{k * 0.5}\t{np.sin(k / 50)}\n" for k in range(720)))
    with pytest.raises(InputError) as e:
        rb.calibrate(rv80e_problem, bench=[f, te])
    assert e.value.field == str(te) and "transmission-error" in str(e.value)


def test_a_loop_the_model_did_not_make_is_flagged(rv80e_problem, truth, tmp_path):
    """Issue 36 item 6: a structure whose stiffness falls with load (500 -> 250 N m/arcmin over
    0..T_R, beside the model's 400) fits to tight intervals and a clearance at its bound (zero);
    both are flagged - lack of fit with where along the loop it sits, the bound - in the result,
    its JSON and the written design's comments. Before: no flag (residual 46x the noise)."""
    t, q, a = model_loop_samples(truth, cycles=2, samples_per_branch=250, noise_arcmin=0.003, offset_arcmin=2.0, seed=3)
    softening = q / (500.0 - 250.0 * np.abs(q) / 784.0) - q / TRUE_K  # [arcmin]
    f = write_loop_csv(tmp_path / "held_out.csv", t, q, a + softening)
    r = calibrate(rv80e_problem, [f], bootstrap=0)
    assert r.lack_of_fit and r.residual_over_expected > 10
    assert r.residual_rms_arcmin > 10 * r.expected_residual_arcmin
    worst = max(r.misfit, key=lambda s: s.over_expected)
    assert worst.over_expected > 10 and worst.samples > 0
    assert {s.branch for s in r.misfit} == {"load+", "unload+", "load-", "unload-"}
    assert r.flags[0].startswith("lack of fit") and f"{worst.branch} " in r.flags[0]
    g = r.parameter("crank_clearance_offset_um")
    assert g.at_bound == "lower" and g.value == pytest.approx(-NOMINAL_CLEARANCE, abs=1e-3)
    assert any(x.startswith("crank_clearance_offset_um at its lower bound") for x in r.flags)
    d = r.to_dict()
    assert d["lack_of_fit"] is True and d["parameters"][2]["at_bound"] == "lower" and len(d["misfit"]) == 16
    header = calibration_header(r)
    assert "WARNING, lack of fit" in header and "WARNING, crank_clearance_offset_um at its lower bound" in header


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_the_models_own_loop_is_not_flagged(stated_problem, truth, tmp_path, noise):
    """The model's own loop (noiseless: the model's resolution is all the residual; with noise, two
    cycles, offset, drift) fits without a flag."""
    f = unit_file(truth, tmp_path / "u.csv", 6.0, seed=3, noise=noise)
    r = calibrate(stated_problem, [f], bootstrap=0)
    assert not r.lack_of_fit and r.flags == () and r.residual_over_expected < 1.1
    assert all(p.at_bound is None for p in r.parameters)
    assert max(s.over_expected for s in r.misfit) < 1.25


def test_the_contacts_friction_model_fits_its_coefficient(rv80e, tmp_path):
    """Issue 40 item 3: with the contacts' friction (the default since heat40: the example states no
    friction) calibrate fits the friction model's uncertain coefficient (the static coefficient on the
    pins and the mesh, [lubrication]) instead of a bare torque: a model-made loop (noise, offset, drift)
    with mu_s = 0.25 gives it back within its 95 % interval, the calibrated design carries it in
    [lubrication] and reproduces the loop's friction."""
    base = rv80e
    assert base.elastic.friction_model is None and base.elastic.loop_friction_model == "contacts"
    truth = with_elastic(base.model_copy(update={"lubrication": base.lubrication.model_copy(
        update={"static_friction_coefficient": 0.25})}), structure_stiffness_nm_per_arcmin=TRUE_K)
    f = unit_file(truth, tmp_path / "u.csv", 6.0, seed=3, samples=150)
    r = calibrate(rb.prepare(base), [f], bootstrap=0)
    p = r.parameter("static_friction_coefficient")
    assert p.design_value == 0.12
    assert p.ci95_low <= 0.25 <= p.ci95_high, p
    assert p.ci95_high - p.ci95_low < 0.05  # the loop resolves it
    k = r.parameter("structure_stiffness_nm_per_arcmin")
    assert k.ci95_low <= TRUE_K <= k.ci95_high
    assert r.design.lubrication.static_friction_coefficient == pytest.approx(p.value, rel=1e-12)
    assert "static_friction_coefficient" in calibration_header(r)
    again = hysteresis(rb.prepare(r.design))
    assert again.friction_model == "contacts"
    assert again.friction_load_fraction == pytest.approx(hysteresis(truth).friction_load_fraction, rel=0.05)
