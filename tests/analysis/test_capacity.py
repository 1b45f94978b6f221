"""Capacity and life (analysis/capacity): the loads over a revolution against statics, the lives'
convergence in the crank angles, the derived ratings' consistency, duty cycles, the main bearings."""

import math

import numpy as np
import pytest

import rvbacklash.api as api
from rvbacklash.analysis.capacity import UnitCapacity, capacity_rating
from rvbacklash.analysis.capacity.duty import duty_cycle_life
from rvbacklash.analysis.capacity.main_bearings import ball_pair, main_bearing_rating, solve_ball_pair
from rvbacklash.design.duty_cycle import DutyCycle, DutyStep, read_duty_cycle
from rvbacklash.errors import InputError
from rvbacklash.models.elastic import elastic_model, nominal_realization, other_stages_nominal
from rvbacklash.units import ARCMIN_PER_RAD


@pytest.fixture(scope="module")
def rv80e():
    problem = api.prepare("rv80e")
    model = elastic_model(problem)
    inv, clr = other_stages_nominal(problem)
    return problem, model, inv, clr


@pytest.fixture(scope="module")
def unit(rv80e):
    problem, model, inv, clr = rv80e
    return UnitCapacity(problem, model, nominal_realization(problem), inv, clr, 24)


def test_loads_balance_the_torque_and_each_other(unit, rv80e):
    problem, model, _, _ = rv80e
    loads = unit.loads(784.0)
    k = model.chain.lever_factor
    # the pins' moments on the discs carry the chain's torque (their lines through the pitch point)
    assert np.allclose(-loads.disc_moment_nm.sum(axis=1), k * 784.0, rtol=1e-3)
    # each disc's bearings carry its pins' resultant
    assert np.allclose(loads.crank_bearing_load_n.sum(axis=2), loads.disc_force_n, rtol=1e-12, atol=1e-9)
    # each crank's torque is the planet gear's: T / i through the first stage's tooth force on each planet
    geo = problem.geometry
    tooth = 784.0 / geo.ratio / (geo.centre_gear_pitch_radius_mm * 1e-3) / problem.design.first_stage.planets
    assert np.allclose(np.abs(loads.crank_torque_nm), tooth * geo.planet_pitch_radius_mm * 1e-3, rtol=5e-3)
    # the support bearings carry the eccentrics' loads and the gear force (the sum of the two supports)
    supports = loads.support_bearing_load_n.sum(axis=2)
    eccentrics = loads.crank_bearing_load_n.sum(axis=1)
    gear = np.linalg.norm(supports - eccentrics, axis=-1)
    tan_a = math.tan(math.radians(geo.pressure_angle_deg))
    assert np.allclose(gear, tooth * math.hypot(1.0, tan_a), rtol=5e-3)


def test_pin_moments_match_the_chains_levers(rv80e):
    # the moment of each pin's line of action (through the pitch point) is the contact model's lever: the
    # same torque as 1e-6 sum F L of the chain
    problem, model, inv, clr = rv80e
    from rvbacklash.analysis.capacity.revolution import CrankAngles, load_geometry
    from rvbacklash.models.elastic.loads import disc_resultants

    angles = CrankAngles(problem, model, nominal_realization(problem), inv, clr, 3)
    forces = angles.pin_forces_n(500.0)
    g = load_geometry(problem, model)
    for k, pu in enumerate(angles.units):
        out = np.empty((2, 3))
        disc_resultants(forces[k], float(angles.chi_rad[k]), g, out)
        chain_moment = 1e-3 * np.sum(forces[k] * pu.unit.lever_um_per_rad, axis=1)
        assert np.allclose(-out[:, 2], chain_moment, rtol=2e-3)


def test_life_converges_in_the_crank_angles(rv80e, unit):
    problem, model, inv, clr = rv80e
    fine = UnitCapacity(problem, model, nominal_realization(problem), inv, clr, 64)
    for method in ("iso16281", "iso281"):
        assert unit.life_h(784.0, 15.0, method) == pytest.approx(fine.life_h(784.0, 15.0, method), rel=2e-3)
    coarse = UnitCapacity(problem, model, nominal_realization(problem), inv, clr, 8)
    assert coarse.life_h(784.0, 15.0) == pytest.approx(fine.life_h(784.0, 15.0), rel=1e-2)


def test_life_scales_as_the_formulas_say(unit):
    # hours at twice the speed: half; the ISO 281 life at twice the torque: the equivalent loads double only
    # if the load sharing were linear; the lives must fall
    assert unit.life_h(784.0, 30.0) == pytest.approx(unit.life_h(784.0, 15.0) / 2, rel=1e-12)
    assert unit.life_h(1568.0, 15.0) < unit.life_h(784.0, 15.0) / 2 ** 3


def test_clearance_shortens_the_needles_iso_16281_life_only(rv80e):
    problem, model, inv, clr = rv80e
    tight = UnitCapacity(problem, model, nominal_realization(problem), inv, 0.0, 12)
    loose = UnitCapacity(problem, model, nominal_realization(problem), inv, 20.0, 12)
    lt = {b.name: b for b in tight.lives(784.0, 15.0)}
    ll = {b.name: b for b in loose.lives(784.0, 15.0)}
    assert ll["needle d0 c0"].l10_iso16281_mrev < 0.9 * lt["needle d0 c0"].l10_iso16281_mrev
    assert ll["needle d0 c0"].l10_iso281_mrev == pytest.approx(lt["needle d0 c0"].l10_iso281_mrev, rel=1e-3)


def test_capacity_rating_is_consistent(rv80e):
    problem = rv80e[0]
    r = capacity_rating(problem)
    # the rated-torque computation: the life at the derived rated torque is the rated life (0.1 %, issue 37)
    assert r.life_at_derived_rated_torque_h == pytest.approx(r.rated_life_h, rel=1e-3)
    assert r.derived_rated_torque_by_method_nm[r.life_method] == r.derived_rated_torque_nm
    # the momentary maximum: the limiting element sits on its limit, the others below
    ratios = {s.element: s.ratio for s in r.static_limits_at_momentary}
    assert ratios[r.limiting_element] == pytest.approx(1.0, rel=1e-6)
    assert all(v <= 1.0 + 1e-9 for v in ratios.values())
    assert r.allowable_acceleration_torque_nm == pytest.approx(0.5 * r.momentary_maximum_torque_nm)
    assert r.reducer_life_h < r.weakest_bearing_life_h
    assert r.bearing_speed_rpm == pytest.approx(40 * 15.0)
    assert r.main_bearings is not None and r.main_bearings.moment_rigidity_nm_per_arcmin > 0
    d = r.to_dict()
    assert d["loads"]["pin_force_n"] and len(d["bearings"]) == 12


def test_duty_cycle_of_one_step_is_the_rated_point(unit):
    cycle = DutyCycle("one step", (DutyStep(1.0, 15.0, 784.0),))
    life = duty_cycle_life(unit, cycle, 784.0, 2000.0, 4000.0, None)
    assert life.life_h == pytest.approx(unit.life_h(784.0, 15.0), rel=1e-9)
    assert life.makers_life_h == pytest.approx(6000.0)
    assert life.mean_output_torque_nm == pytest.approx(784.0) and life.mean_output_speed_rpm == pytest.approx(15.0)
    hold = DutyCycle("with a hold", (DutyStep(0.5, 15.0, 784.0), DutyStep(0.5, 0.0, 300.0)))
    assert duty_cycle_life(unit, hold, 784.0, 2000.0, 4000.0, None).life_h == pytest.approx(2 * life.life_h, rel=1e-9)


def test_duty_cycle_reader(tmp_path):
    p = tmp_path / "cycle.csv"
    p.write_text("time_s,output_speed_rpm,output_torque_nm,moment_nm\n2,10,500,100\n6,15,-300,\n")
    c = read_duty_cycle(p)
    assert [s.time_share for s in c.steps] == [0.25, 0.75]
    assert c.steps[1].output_torque_nm == -300.0 and c.steps[1].moment_nm == 0.0
    assert c.mean_speed_rpm == pytest.approx(0.25 * 10 + 0.75 * 15)
    t = tmp_path / "cycle.toml"
    t.write_text("[[step]]\ntime_share = 1\noutput_speed_rpm = 15\noutput_torque_nm = 784\n")
    assert read_duty_cycle(t).steps[0].output_torque_nm == 784.0
    for text, match in (("time_s,output_speed_rpm\n1,2\n", "output_torque_nm"),
                        ("time_s,time_share,output_speed_rpm,output_torque_nm\n1,1,2,3\n", "exactly one"),
                        ("time_s,output_speed_rpm,output_torque_nm\n1,-2,3\n", "step 1: output_speed_rpm"),
                        ("time_s,output_speed_rpm,output_torque_nm,speed\n1,2,3,4\n", "step 1: speed"),
                        ("time_s,output_speed_rpm,output_torque_nm\n1,2,abc\n", "step 1: output_torque_nm"),
                        ("time_s,output_speed_rpm,output_torque_nm\n0,2,3\n", "summing")):
        p.write_text(text)
        with pytest.raises(InputError, match=match):
            read_duty_cycle(p)
    with pytest.raises(InputError, match="duty_cycle"):
        read_duty_cycle(tmp_path / "missing.csv")


def test_main_bearings_moment_rigidity_closed_form(rv80e):
    # preloaded and unloaded, every ball carries the preload Q0 with the tangent k = 1.5 Q0^(1/3) / K (delta = K Q^(2/3)):
    # dM/dtheta = sum k l^2 cos^2(psi) = Z k l^2 (two rows) = one row's radial stiffness (Z/2 k cos^2 a) L_e^2 / 2
    # with the pressure centres' span L_e = s + D_pw tan(a) (../shared/reference/anchors.md)
    st = rv80e[0].design.structure
    pair = ball_pair(st)
    sol = solve_ball_pair(pair, 0.0)
    z, a = st.main_bearing_balls, math.radians(st.main_bearing_contact_angle_deg)
    q0 = st.main_bearing_preload_n / (z * math.sin(a))
    assert np.allclose(sol.loads_n, q0, rtol=1e-9)
    k = 1.5 * q0 ** (1 / 3) / pair.hertz_mm_per_n23
    span = st.main_bearing_row_spread_mm + st.main_bearing_pitch_diameter_mm * math.tan(a)
    assert sol.moment_rigidity_nmm_per_rad == pytest.approx(z / 2 * k * math.cos(a) ** 2 * span ** 2 / 2, rel=1e-9)
    r = main_bearing_rating(st, 6000.0, 15.0, 1.0)
    assert r.moment_rigidity_nm_per_arcmin == pytest.approx(sol.moment_rigidity_nmm_per_rad * 1e-3 / ARCMIN_PER_RAD)
    # a moment loads one side of each row, the pair's equilibrium holds
    loaded = solve_ball_pair(pair, r.allowable_moment_nm)
    psi = 2 * math.pi * np.arange(z) / z
    moment = np.sum(np.array([-1.0, 1.0])[:, None] * loaded.loads_n * pair.lever_mm * np.cos(psi)) * 1e-3
    assert moment == pytest.approx(r.allowable_moment_nm, rel=1e-8)
    assert r.allowable_moment_nm == min(r.allowable_moment_static_nm, r.allowable_moment_life_nm)


def test_capacity_needs_structure():
    design = api.prepare("rv80e").design
    problem = api.prepare(design.model_copy(update={"structure": None}))
    with pytest.raises(InputError, match="structure"):
        capacity_rating(problem)
