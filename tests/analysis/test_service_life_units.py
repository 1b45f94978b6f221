"""Each unit's own wear in the service life's production run (analysis/service_life/units.py): the
vectorised profile wear is the nominal unit's formulas, a unit without deviations wears exactly as the
nominal unit, the wear of every unit is linear in k, and the first-order correction follows each
unit's full stepping (its own loads at 12 crank angles) where the nominal shortcut does not."""

import numpy as np
import pytest

import rvbacklash.api as api
from rvbacklash.analysis.capacity.revolution import load_geometry, needle_rollers, revolution_loads
from rvbacklash.analysis.service_life import WearIncrement, WornAngles, nominal_trajectory, wear_geometry, \
    wear_per_revolution
from rvbacklash.analysis.service_life.calibration import scaled_inputs
from rvbacklash.analysis.service_life.production import step_designs
from rvbacklash.analysis.service_life.rates import pin_force_by_phase
from rvbacklash.analysis.service_life.units import NominalAtAngles, profile_wear, samples_to_grid, worn_units
from rvbacklash.design.duty_cycle import read_duty_cycle
from rvbacklash.models.elastic import (elastic_model, evaluate_units, nominal_realization, other_stages_nominal,
                                       unit_from_realization)
from rvbacklash.models.unit_errors import realization_at
from rvbacklash.sampling.contact_source import block_streams, contact_source, saved_units
from rvbacklash.sampling.elastic_source import UnitBatch, draw_units


@pytest.fixture(scope="module")
def rv80e():
    problem = api.prepare("rv80e")
    return problem, elastic_model(problem), read_duty_cycle(api.example_duty_cycle("robot-joint"))


def _drawn(problem, n, seed):
    c = contact_source(problem, "default", seed, (1,))
    saved = saved_units(n, c.geometry)
    return draw_units(c, block_streams(c.seed, 0, c.stream), n, saved), saved


def _lost_motion(problem, tr, designs, batch, own):
    lm = []
    for k, worn in worn_units(batch, tr, designs, NominalAtAngles(problem) if own else None):
        out = np.empty((3, batch.chi_rad.size))
        evaluate_units(worn, designs[k], out)
        lm.append(out[0].copy())
    return np.array(lm)


def test_profile_wear_is_the_nominal_wear_formulas(rv80e):
    problem, model, _ = rv80e
    geo = wear_geometry(problem, model)
    inv, clr = other_stages_nominal(problem)
    angles = WornAngles(problem, model, nominal_realization(problem), inv, clr, WearIncrement.zero(2), geo, 12)
    loads = revolution_loads(angles, 784.0, load_geometry(problem, model), needle_rollers(model))
    ref = wear_per_revolution(loads, geo)
    flank, pin, local, seat = profile_wear(pin_force_by_phase(loads, geo)[None] / geo.contact_length_mm, geo)
    assert np.allclose(flank[0], ref.flank_um, rtol=1e-12, atol=0)
    assert np.allclose(pin[0], ref.pin_um, rtol=1e-12, atol=0)
    assert np.allclose(seat[0], ref.seat_um, rtol=1e-12, atol=1e-18)
    assert np.allclose(local[0], ref.pin_local_um, rtol=1e-12, atol=1e-18)
    assert flank.max() > 0.0 and seat.max() > 0.0


def test_samples_to_grid_passes_through_the_pins_and_is_linear_between(rv80e):
    problem, model, _ = rv80e
    geo = wear_geometry(problem, model)
    chi = np.array([0.0, 0.0123])
    phases = (2 * np.pi * np.arange(geo.zp) / geo.zp)[None, None, :] \
        - (chi[:, None] + np.pi * np.arange(2)[None, :])[:, :, None]
    values = np.cos(np.mod(phases, 2 * np.pi))  # a smooth profile sampled at the pins
    grid = samples_to_grid(values, chi, geo)
    assert np.allclose(grid, np.cos(geo.phase_rad)[None, None, :], atol=(2 * np.pi / geo.zp) ** 2 / 8 + 1e-12)


def test_a_unit_without_deviations_wears_exactly_as_the_nominal_unit(rv80e):
    problem, model, cycle = rv80e
    tr = nominal_trajectory(problem, cycle, [0, 500, 2000], model=model)
    designs = step_designs(problem, tr, model)
    inv, clr = other_stages_nominal(problem)
    chi = np.array([0.0, 0.01, 0.05, 0.11])
    units = [unit_from_realization(problem, nominal_realization(problem, float(c)), inv, clr) for c in chi]
    batch = UnitBatch(np.array([u.gap_um for u in units]), np.array([u.lever_um_per_rad for u in units]), chi,
                      np.full(chi.size, inv), np.full(chi.size, clr), np.full(chi.size, np.nan))
    own = list(worn_units(batch, tr, designs, NominalAtAngles(problem)))
    shortcut = list(worn_units(batch, tr, designs, None))
    for (_, a), (_, b) in zip(own, shortcut):
        assert np.array_equal(a.gap_um, b.gap_um)  # bit for bit: the forces are the nominal's, the correction 0
    assert (own[-1][1].gap_um - batch.gap_um).max() > 1.0


def test_every_units_wear_is_proportional_to_k(rv80e):
    problem, model, cycle = rv80e
    batch, _ = _drawn(problem, 8, 5)
    growth = []
    for scale in (1.0, 2.0):
        w = scaled_inputs(problem.design.wear, scale)
        tr = nominal_trajectory(problem, cycle, [0, 20], model=model, wear=w, step_fraction=1.0)
        assert len(tr.hours) == 2  # one step: the loads of the unworn units
        designs = step_designs(problem, tr, model)
        last = list(worn_units(batch, tr, designs, NominalAtAngles(problem)))[-1][1]
        growth.append(last.gap_um - batch.gap_um)
    assert np.abs(growth[0]).max() > 1e-3
    assert np.allclose(growth[1], 2.0 * growth[0], rtol=1e-9, atol=1e-12)


def test_own_wear_follows_each_units_full_stepping(rv80e):
    """Six drawn units to 2000 h of the robot-joint cycle: the growth of their lost motion by the
    first-order correction against each unit's full stepping (its own loads at 12 crank angles, its own
    flank profile, re-solved every step). Measured (seed 3; the contacts' friction, schema 8.0): full 0.439 /
    0.772 / 0.409 / 0.345 / 0.504 / 0.873 arcmin; own 0.517 / 0.802 / 0.428 / 0.355 / 0.642 / 1.026; the nominal
    shortcut 0.312 / 0.256 / 0.089 / 0.199 / 0.465 / 0.110."""
    problem, model, cycle = rv80e
    n = 6
    batch, saved = _drawn(problem, n, 3)
    hours = [0.0, 2000.0]
    tr = nominal_trajectory(problem, cycle, hours, model=model)
    designs = step_designs(problem, tr, model)
    own = _lost_motion(problem, tr, designs, batch, True)
    shortcut = _lost_motion(problem, tr, designs, batch, False)
    full = np.empty(n)
    for s in range(n):
        r = realization_at(saved.errors, s, float(batch.chi_rad[s]), crank_clearance_um=float(batch.crank_clearance_um[s]),
                           involute_backlash_rad=float(batch.involute_backlash_rad[s]))
        pts = nominal_trajectory(problem, cycle, hours, model=model, realization=r).points
        assert pts[0].lost_motion_arcmin == pytest.approx(own[0, s], rel=1e-6)  # the same unit at 0 h
        full[s] = pts[-1].lost_motion_arcmin - pts[0].lost_motion_arcmin
    e_own = np.abs(own[-1] - own[0] - full)
    e_short = np.abs(shortcut[-1] - shortcut[0] - full)
    assert e_own.sum() < 0.4 * e_short.sum()
    assert np.all(e_own < 0.35 * full)


def test_the_compiled_pin_growth_is_the_profile_wear_read_at_the_pins(rv80e):
    from rvbacklash.analysis.service_life.units import growth_at_pins, profile_tables
    from rvbacklash.models.wear_kernel import pins_growth_um

    problem, model, _ = rv80e
    for inputs in (problem.design.wear, problem.design.wear.model_copy(update={"pin_rolling_fraction": 0.0})):
        geo = wear_geometry(problem, model, inputs)
        rng = np.random.default_rng(2)
        chi = rng.uniform(0.0, 0.2, 5)
        load = rng.normal(10.0, 30.0, (5, geo.discs, geo.zp))  # N/mm, a correction may be negative
        flank, pin, local, seat = profile_wear(samples_to_grid(load, chi, geo), geo)
        ref = growth_at_pins(flank, pin, local + seat, chi, geo)
        out = np.ones_like(load)
        pins_growth_um(load, chi, profile_tables(geo), 3.0, out)
        assert np.allclose(out, 1.0 + 3.0 * ref, rtol=1e-11, atol=1e-12 * np.abs(ref).max())
        assert np.abs(ref).max() > 1e-6


def test_the_te_over_the_life_starts_at_the_te_models_ripple_and_moves_with_the_worn_profile(rv80e):
    """At 0 h the worn-unit flank curve's peak-to-peak is the transmission-error model's own ripple of
    the error-free unit (0.0701 arcsec for rv80e; 0.0707 here: linearised, within 2 %); a uniform wear
    of 2 um gives the ripple the TE model gives the design with 2 um more equidistance modification (the
    modifications make the ripple); the worn profile after 6000 h changes it."""
    from rvbacklash.analysis.service_life.ripple import worn_ripple

    problem, model, cycle = rv80e
    geo = wear_geometry(problem, model)
    te0 = api.transmission_error(problem, shares=False).nominal_ripple_arcsec
    zero = worn_ripple(problem, 0.0, WearIncrement.zero(2), geo)
    assert zero.te_peak_to_peak_ccw_arcsec == pytest.approx(te0, rel=2e-2)  # linearised, 64 angles a pitch
    assert zero.te_peak_to_peak_cw_arcsec == pytest.approx(te0, rel=2e-2)
    uniform = WearIncrement.zero(2).plus(WearIncrement(np.full((2, geo.phase_rad.size), 2.0), np.zeros(2),
                                                       np.zeros((2, 90)), np.zeros((2, 90)), 0.0, 0.0, np.zeros(3)))
    flat = worn_ripple(problem, 0.0, uniform, geo)
    d = problem.design
    s2 = d.second_stage.model_copy(update={"equidistance_modification_um": d.second_stage.equidistance_modification_um
                                           + 2.0})
    te2 = api.transmission_error(d.model_copy(update={"second_stage": s2}), shares=False).nominal_ripple_arcsec
    assert abs(te2 - te0) > 0.01  # the modification moves the ripple ...
    assert flat.te_peak_to_peak_ccw_arcsec == pytest.approx(te2, rel=2e-2)  # ... and the uniform wear as much
    assert flat.rigid_play_mean_arcmin > zero.rigid_play_mean_arcmin + 0.1
    tr = nominal_trajectory(problem, cycle, [0, 6000], model=model)
    worn = worn_ripple(problem, 6000.0, tr.wear[-1], geo)
    assert abs(worn.te_peak_to_peak_ccw_arcsec - zero.te_peak_to_peak_ccw_arcsec) > 0.01


def test_sobol_indices_of_the_accuracy_life(rv80e):
    """Which tolerance buys hours (rv80e, robot-joint, 300 h, lost motion <= 1.2 arcmin, N = 64): the
    censored accuracy life's indices by the project's Sobol machinery, within [0, 300] h; the pin
    circle radius leads (measured here: total 0.47, the equidistance modification error 0.38, the
    discs' run-out 0.38; rv80e at N = 128 and 6000 h, lost motion <= 1.5: 0.46 [0.31, 0.63], the next
    0.28), the involute stage's factors do not move the cycloid stage's wear (< 0.05)."""
    from rvbacklash.analysis.sensitivity_global import InlineExecutor, global_sensitivity
    from rvbacklash.analysis.service_life.sensitivity import accuracy_life_streams

    problem, model, cycle = rv80e
    tr = nominal_trajectory(problem, cycle, [0, 300], model=model)
    sm = accuracy_life_streams(problem, tr, 1.2, model)
    r = global_sensitivity(problem, model=sm, output="accuracy_life", samples=64, seed=2, resamples=100,
                           executor=InlineExecutor())
    assert r.output == "accuracy_life"
    total = {g.input: g.total for g in r.groups}
    assert max(total, key=total.get) == "pin_circle_radius" and total["pin_circle_radius"] > 0.2
    assert max(total[k] for k in ("gear_runout", "tooth_profile", "single_pitch", "centre_distance")) < 0.05
