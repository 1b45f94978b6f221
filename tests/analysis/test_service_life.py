"""Service life (analysis/service_life): zero load or sliding wears nothing, the wear is linear in k
and in time, the worn profile read back by the contact and elastic models (a uniform flank wear w is
an equidistance modification of w, to the bit), the time step's convergence, the production run."""

import dataclasses
import math

import numpy as np
import pytest

import rvbacklash.api as api
from rvbacklash.analysis.capacity.revolution import load_geometry, needle_rollers, revolution_loads
from rvbacklash.analysis.service_life import (WearIncrement, WornAngles, nominal_trajectory, wear_geometry,
                                              wear_per_revolution, worn_unit)
from rvbacklash.analysis.service_life.production import accuracy_life_h, production_life
from rvbacklash.analysis.service_life.rates import PHASE_BINS
from rvbacklash.analysis.service_life.worn import worn_model
from rvbacklash.design.duty_cycle import DutyCycle, DutyStep
from rvbacklash.design.wear import WearInputs
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import (LOST_MOTION, PreparedUnit, elastic_model, nominal_realization, nominal_unit,
                                       other_stages_nominal)

CYCLE = DutyCycle("test", (DutyStep(0.5, 15.0, 784.0), DutyStep(0.3, 15.0, -500.0), DutyStep(0.2, 0.0, 300.0)))


@pytest.fixture(scope="module")
def rv80e(rv80e_elastic):  # the shared (problem, model, inv, clr): tests/conftest.py
    return rv80e_elastic


@pytest.fixture(scope="module")
def nominal_angles(rv80e):
    problem, model, inv, clr = rv80e
    geo = wear_geometry(problem, model)
    return WornAngles(problem, model, nominal_realization(problem), inv, clr, WearIncrement.zero(2), geo, 12), geo


def test_zero_load_and_zero_sliding_wear_nothing(rv80e, nominal_angles):
    problem, model, _, _ = rv80e
    angles, geo = nominal_angles
    lg, needles = load_geometry(problem, model), needle_rollers(model)
    # no torque: no pin force, no needle load (rv80e's nominal unit has no interference)
    idle = wear_per_revolution(revolution_loads(angles, 0.0, lg, needles), geo)
    assert idle.largest_depth_um() == 0.0 and idle.clearance_um == 0.0
    # a torque without sliding (every coefficient of sliding 0): nothing either
    still = wear_geometry(problem, model, WearInputs(pin_rolling_fraction=1.0, seat_wear_coefficient=0.0,
                                                     needle_slip_fraction=0.0))
    loaded = wear_per_revolution(revolution_loads(angles, 784.0, lg, needles), still)
    assert loaded.largest_depth_um() == 0.0 and loaded.clearance_um == 0.0
    # ... and with sliding, it wears
    assert wear_per_revolution(revolution_loads(angles, 784.0, lg, needles), geo).largest_depth_um() > 0.0
    # a cycle of holds (no revolutions) leaves the unit as it was
    holds = DutyCycle("holds", (DutyStep(1.0, 0.0, 784.0),))
    tr = nominal_trajectory(problem, holds, [0, 1000], model=model)
    assert tr.points[-1].lost_motion_arcmin == tr.points[0].lost_motion_arcmin
    assert tr.wear[-1].largest_depth_um() == 0.0


def test_wear_is_proportional_to_k(rv80e, nominal_angles):
    problem, model, _, _ = rv80e
    angles, geo = nominal_angles
    loads = revolution_loads(angles, 784.0, load_geometry(problem, model), needle_rollers(model))
    one = wear_per_revolution(loads, geo)
    w = geo.inputs
    doubled = WearInputs(flank_wear_coefficient=2 * w.flank_wear_coefficient,
                         seat_wear_coefficient=2 * w.seat_wear_coefficient,
                         needle_wear_coefficient=2 * w.needle_wear_coefficient)
    two = wear_per_revolution(loads, wear_geometry(problem, model, doubled))
    for a, b in ((one.flank_um, two.flank_um), (one.pin_um, two.pin_um), (one.seat_um, two.seat_um)):
        assert np.allclose(b, 2 * a, rtol=1e-13, atol=0)
    assert two.clearance_um == pytest.approx(2 * one.clearance_um, rel=1e-13)


def test_wear_is_proportional_to_time_in_the_linear_regime(rv80e):
    # one step from 0 h (the loads of the start), no running-in: twice the hours, twice the wear
    problem, model, _, _ = rv80e
    steady = WearInputs(running_in_factor=1.0)
    a = nominal_trajectory(problem, CYCLE, [0, 50], model=model, wear=steady, step_fraction=1.0)
    b = nominal_trajectory(problem, CYCLE, [0, 100], model=model, wear=steady, step_fraction=1.0)
    assert len(a.hours) == len(b.hours) == 2
    assert np.allclose(b.wear[-1].flank_um, 2 * a.wear[-1].flank_um, rtol=1e-12, atol=0)
    assert np.allclose(b.wear[-1].seat_um, 2 * a.wear[-1].seat_um, rtol=1e-12, atol=0)
    assert b.wear[-1].clearance_um == pytest.approx(2 * a.wear[-1].clearance_um, rel=1e-12)
    # running-in: the first hours wear faster than the steady rate (m = 5 at t = 0)
    run_in = nominal_trajectory(problem, CYCLE, [0, 50], model=model, step_fraction=1.0)
    ratio = run_in.wear[-1].flank_um.max() / a.wear[-1].flank_um.max()
    assert ratio == pytest.approx(1 + 4 * 100 / 50 * (1 - math.exp(-0.5)), rel=1e-12)


def test_uniform_flank_wear_is_an_equidistance_modification_to_the_bit(rv80e):
    problem, model, inv, clr = rv80e
    geo = wear_geometry(problem, model)
    w = 2.0
    wear = dataclasses.replace(WearIncrement.zero(2), flank_um=np.full((2, PHASE_BINS), w))
    worn = PreparedUnit(worn_model(problem, model, wear),
                        worn_unit(problem, nominal_realization(problem), inv, clr, wear, geo)).figures()
    d = problem.design
    s2 = d.second_stage
    modified = d.model_copy(update={"second_stage": s2.model_copy(
        update={"equidistance_modification_um": s2.equidistance_modification_um + w})})
    p2 = api.prepare(modified)
    m2 = elastic_model(p2)
    # the disc's body (finite elements of the unworn disc: docs/service-life.md) is not re-meshed for
    # the wear, nor the loop's friction law re-derived (the contacts' friction, the default since heat40,
    # is derived once per design on its nominal unit): with the same body and friction the worn unit IS
    # the modified design, to the bit
    same_body = dataclasses.replace(m2, chain=m2.chain._replace(
        disc_body_compliance_rad_per_nm=model.chain.disc_body_compliance_rad_per_nm,
        friction_nm=model.chain.friction_nm, friction_fraction=model.chain.friction_fraction))
    other = PreparedUnit(same_body, nominal_unit(p2)).figures()
    assert worn[LOST_MOTION] == other[LOST_MOTION]  # bit for bit
    assert np.array_equal(worn, other)
    # with the modified disc's own body (its teeth 2 um thinner): within 0.1 %
    own = PreparedUnit(m2, nominal_unit(p2)).figures()
    assert worn[LOST_MOTION] == pytest.approx(own[LOST_MOTION], rel=1e-3)
    fresh = PreparedUnit(model, nominal_unit(problem)).figures()
    assert worn[LOST_MOTION] > fresh[LOST_MOTION] + 0.1  # and it is a real change (~0.2 arcmin for 2 um)


def test_halving_the_steps_moves_the_6000_h_lost_motion_by_less_than_one_percent(rv80e):
    problem, model, _, _ = rv80e
    from rvbacklash.design.duty_cycle import read_duty_cycle

    cycle = read_duty_cycle(api.example_duty_cycle("robot-joint"))
    coarse = nominal_trajectory(problem, cycle, [0, 6000], model=model, step_fraction=0.1)
    fine = nominal_trajectory(problem, cycle, [0, 6000], model=model, step_fraction=0.05)
    assert len(fine.hours) > 1.6 * len(coarse.hours)
    lm_c, lm_f = coarse.points[-1].lost_motion_arcmin, fine.points[-1].lost_motion_arcmin
    lm_0 = coarse.points[0].lost_motion_arcmin
    assert lm_c > lm_0 + 0.2  # the lost motion grows
    assert abs(lm_c - lm_f) / lm_f < 0.01


def test_accuracy_life_reads_the_crossing():
    hours = np.array([0.0, 100.0, 300.0])
    lm = np.array([[1.0, 2.0, 1.0, 1.0], [1.2, 2.1, 1.0, 1.6], [1.6, 2.2, 1.1, 1.8]])
    life = accuracy_life_h(hours, lm, 1.5)
    assert life[0] == pytest.approx(100 + 200 * 0.3 / 0.4)
    assert life[1] == 0.0 and math.isinf(life[2])
    assert life[3] == pytest.approx(100 * 0.5 / 0.6)


def test_production_run_yield_falls_with_the_hours_and_is_seeded(rv80e):
    problem, model, _, _ = rv80e
    tr = nominal_trajectory(problem, CYCLE, [0, 2000], model=model, step_fraction=0.5)
    a = production_life(problem, tr, [0, 2000], samples=300, seed=3, spec_lost_motion_arcmin=1.5, model=model)
    b = production_life(problem, tr, [0, 2000], samples=300, seed=3, spec_lost_motion_arcmin=1.5, model=model)
    assert a.to_dict() == b.to_dict()
    assert a.yield_at_hours[1].fraction < a.yield_at_hours[0].fraction
    assert a.lost_motion_quantiles_arcmin[1][1] > a.lost_motion_quantiles_arcmin[0][1]
    with pytest.raises(InputError, match="samples"):
        production_life(problem, tr, [0], samples=0, seed=0, spec_lost_motion_arcmin=1.5)


def test_bad_wear_inputs_are_refused_in_one_line(rv80e_toml, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(rv80e_toml + "\n[wear]\nflank_wear_coefficient = -1e-8\n")
    with pytest.raises(InputError) as e:
        api.prepare(str(path))
    text = str(e.value)
    assert "wear.flank_wear_coefficient" in text and "\n" not in text
    with pytest.raises(InputError, match="hours"):
        nominal_trajectory(api.prepare("rv80e"), CYCLE, [-5])


def test_calibration_recovers_k_from_two_synthetic_measurements(rv80e):
    """A unit 'measured' at 0 h and 1000 h of the robot-joint cycle: the model's own lost motion with
    the coefficients 1.7 times the design's, plus reading noise (sigma 0.01 arcmin, seeded): the fitted
    scale's 95 % interval holds 1.7."""
    from rvbacklash.analysis.service_life.calibration import calibrate_wear, scaled_inputs
    from rvbacklash.design.duty_cycle import read_duty_cycle

    problem, model, _, _ = rv80e
    cycle = read_duty_cycle(api.example_duty_cycle("robot-joint"))
    true = 1.7
    tr = nominal_trajectory(problem, cycle, [0, 1000], wear=scaled_inputs(problem.design.wear, true), model=model)
    rng = np.random.default_rng(7)
    lm0, lm1 = (p.lost_motion_arcmin + rng.normal(0.0, 0.01) for p in (tr.points[0], tr.points[-1]))
    r = calibrate_wear(problem, cycle, [(0, lm0), (1000, lm1)], sigma_arcmin=0.01)
    assert r.scale_ci95_low < true < r.scale_ci95_high
    assert r.scale == pytest.approx(true, rel=0.1)
    assert r.scale_ci95_high / r.scale_ci95_low < 1.5  # 1000 h of wear bound it
    assert r.k_flank_mm3_per_nm == pytest.approx(r.scale * 1.4567e-9, rel=1e-3)
    with pytest.raises(InputError, match="measurements"):
        calibrate_wear(problem, cycle, [(1000, 2.0)])


def test_the_production_run_gaps_are_the_worn_unit_gaps(rv80e):
    """The production run's wear on a unit's gaps (vectorised over units) is the worn unit's, pin by pin."""
    from rvbacklash.analysis.service_life.rates import flank_wear_at, pin_wear_at
    from rvbacklash.analysis.service_life.worn import pin_phases_rad, worn_gaps_um

    problem, model, _, _ = rv80e
    tr = nominal_trajectory(problem, CYCLE, [0, 300], model=model, step_fraction=0.5)
    geo, wear = tr.geometry, tr.wear[-1]
    chi = np.array([0.01, 0.05, 0.13])
    grown = worn_gaps_um(wear, geo, chi)
    for i, c in enumerate(chi):
        ph = pin_phases_rad(float(c), geo.discs, geo.zp)
        assert np.allclose(grown[i], flank_wear_at(wear.flank_um, geo, ph) + pin_wear_at(wear, geo, ph),
                           rtol=1e-14, atol=1e-15)
    assert grown.max() > 0.1
