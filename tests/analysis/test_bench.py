"""Measured loops and TE curves read by the model's definitions (analysis/bench.py, issue 29):
a loop the model generates, with noise, an offset, drift, two cycles, uneven sampling and degrees,
is read back within the reported uncertainty; a TE curve of known orders gives those orders."""

from __future__ import annotations


import numpy as np
import pytest

import rvbacklash as rb
from rvbacklash.analysis.bench import read_bench, turning_points
from rvbacklash.analysis.bench_synthetic import model_loop_samples, te_curve, write_loop_csv, write_te_csv
from rvbacklash.analysis.hysteresis import hysteresis
from rvbacklash.analysis.loop_reading import angle_at, as_branches, hysteresis_loss_j, loop_figures
from rvbacklash.units import ARCMIN_PER_RAD

FIGS = ("lost_motion_arcmin", "backlash_arcmin", "torsional_rigidity_nm_per_arcmin")


@pytest.fixture(scope="module")
def stated(rv80e):
    """rv80e with a known structure stiffness (a bench would measure one) and 3 N m of friction."""
    e = rv80e.elastic.model_copy(update={"structure_stiffness_nm_per_arcmin": 400.0, "friction_torque_nm": 3.0})
    return rb.prepare(rv80e.model_copy(update={"elastic": e}))


def test_the_reader_reproduces_the_models_figures_exactly(rv80e_problem):
    h = hysteresis(rv80e_problem, points=9)
    f = loop_figures(h.loop, h.rated_torque_nm, h.measuring_torque_fraction, h.rigidity_interval_fraction)
    for k in FIGS:
        assert f[k] == pytest.approx(getattr(h, k), rel=1e-12)
    for s in h.rigidity_secants:
        assert f[f"rigidity_{s.from_fraction * 100:g}_{s.to_fraction * 100:g}"] == s.rigidity_nm_per_arcmin
    # the first node at a torque wins (the end a branch arrives from); between nodes, interpolation
    assert angle_at([0.0, 1.0, 1.0, 2.0], [0.0, 1.0, 5.0, 6.0], 1.0) == 1.0
    assert angle_at([2.0, 0.0], [4.0, 0.0], 0.5) == pytest.approx(1.0)


def test_hysteresis_loss_is_the_friction_parallelogram(stated, rv80e):
    """Constant Coulomb friction T_f shifts the loading and unloading branches by +-T_f in torque:
    the loop's area is 2 T_f (theta(+T_R) - theta(-T_R)) [J]; no friction, no area."""
    h = hysteresis(stated, points=161)
    b = as_branches(h.loop)
    travel = (b["load+"][1][-1] - b["load-"][1][-1]) / ARCMIN_PER_RAD
    assert hysteresis_loss_j(b) == pytest.approx(2 * 3.0 * travel, rel=0.01)
    e = rv80e.elastic.model_copy(update={"friction_torque_nm": 0.0})
    free = hysteresis(rb.prepare(rv80e.model_copy(update={"elastic": e})), points=41)
    assert hysteresis_loss_j(as_branches(free.loop)) < 1e-3 * hysteresis_loss_j(b)


def test_a_model_loop_with_noise_offset_drift_two_cycles_in_degrees_reads_back(stated, tmp_path):
    """Done-when check: the model's own loop, as a bench records it, gives the model's figures
    within the reported (k = 2) uncertainty; the reader says what it found."""
    h = hysteresis(stated)
    t, q, a = model_loop_samples(stated, cycles=2, samples_per_branch=400, noise_arcmin=0.01, offset_arcmin=3.0,
                                 drift_arcmin_per_s=0.01, uneven=True, seed=1)
    f = write_loop_csv(tmp_path / "unit.csv", t, q, a, angle_unit="deg")
    u = read_bench([f], rated_torque_nm=784.0).units[0]
    for k in FIGS:
        assert abs(getattr(u, k) - getattr(h, k)) <= u.uncertainty_k2[k], (k, getattr(u, k), getattr(h, k))
        assert 0 < u.uncertainty_k2[k] < 0.05 * abs(getattr(h, k))
    assert u.cycles == 2 and all(n >= 2 for n in u.branch_stretches.values())
    assert u.noise_arcmin == pytest.approx(0.01, rel=0.2)
    assert u.drift_arcmin_per_s == pytest.approx(0.01, rel=0.1) and u.drift_per == "s"
    assert u.rated_torque_from == "given"
    # no noise: the reading is the model's to the reader's own resolution
    t, q, a = model_loop_samples(stated, cycles=1, samples_per_branch=400, offset_arcmin=-2.0, seed=2)
    exact = read_bench([write_loop_csv(tmp_path / "exact.csv", t, q, a)], rated_torque_nm=784.0).units[0]
    assert exact.lost_motion_arcmin == pytest.approx(h.lost_motion_arcmin, abs=2e-3)
    assert exact.torsional_rigidity_nm_per_arcmin == pytest.approx(h.torsional_rigidity_nm_per_arcmin, rel=5e-3)


def test_the_turning_points_ignore_noise_below_the_threshold():
    t = np.concatenate([np.linspace(0, 10, 50), np.linspace(10, -10, 100), np.linspace(-10, 3, 60)])
    noisy = t + np.random.default_rng(0).normal(0, 0.5, t.size)
    assert turning_points(noisy, 4.0) == [int(np.argmax(noisy[:100])), int(np.argmin(noisy))]


def test_a_te_curve_of_known_orders_reads_back(tmp_path):
    """Done-when check: TE = sum A_m cos(m theta + phi_m) + noise, 1.2 revolutions from 37 deg."""
    orders = {1: 10.0, 2: 4.0, 40: 1.5, 78: 0.8}
    th, te = te_curve(orders, samples=3000, noise_arcsec=0.3, start_deg=37.0, revolutions=1.2, seed=4)
    u = read_bench([write_te_csv(tmp_path / "te.tsv", th, te)]).units[0]
    found = {s.order: s.amplitude_arcsec for s in u.leading_orders}
    assert list(found)[:4] == [1, 2, 40, 78]
    for m, amp in orders.items():
        assert found[m] == pytest.approx(amp, rel=0.05)
    assert u.noise_arcsec == pytest.approx(0.3, rel=0.2) and u.revolutions == pytest.approx(1.2, rel=1e-3)
    clean = te_curve(orders, samples=4096, seed=4)[1]
    assert u.te_peak_to_peak_arcsec == pytest.approx(np.ptp(clean), rel=0.05)


def test_te_from_input_and_output_angles_with_the_ratio(tmp_path):
    th, te = te_curve({3: 6.0}, samples=2000, seed=1)
    ratio = 81.0
    inp = ratio * (th - te / 3600.0)  # TE = output - input / ratio
    f = tmp_path / "io.csv"
    f.write_text("output angle [deg],input angle [deg]\n" + "".join(f"{o:.9f},{i:.9f}\n" for o, i in zip(th, inp)))
    u = read_bench([f], ratio=ratio).units[0]
    assert u.leading_orders[0].order == 3 and u.leading_orders[0].amplitude_arcsec == pytest.approx(6.0, rel=0.01)
