"""Losses, efficiency and heat (analysis/losses; issue 40): the power balance through the gear train's
speed ratios, zero friction, convergence in the crank angles, metamorphic checks of the friction,
the thermal balance's root and duty, and equal expansion coefficients leaving the clearances."""

import math

import pytest

import rvbacklash.api as api
from rvbacklash.analysis.losses import ELEMENTS, LossModel, back_driving_torque_nm, efficiency_rating, speeds
from rvbacklash.analysis.losses.thermal import (clearance_change, cycle_loss_w, precision_at_temperature,
                                                thermal_balance, with_equal_expansion)
from rvbacklash.design.duty_cycle import DutyCycle, DutyStep
from rvbacklash.errors import InputError
from rvbacklash.models import friction as fr

ANGLES = 6


@pytest.fixture(scope="module")
def problem():
    return api.prepare("rv80e")


@pytest.fixture(scope="module")
def lm(problem):
    return LossModel(problem, ANGLES)


def _zero(problem):
    return problem.design.lubrication.model_copy(update=dict(
        boundary_friction_coefficient=0.0, full_film_friction_coefficient=0.0, static_friction_coefficient=0.0,
        pin_seat_friction_coefficient=0.0, mesh_lubricant_factor=0.0, needle_bearing_f0=0.0, needle_bearing_f1=0.0,
        support_bearing_f0=0.0, support_bearing_f1=0.0, main_bearing_f0=0.0, main_bearing_f1_scale=0.0,
        output_seal_torque_nm=0.0, input_seal_torque_nm=0.0, churning_torque_nm=0.0))


def test_speeds_follow_the_gear_train(problem):
    s = speeds(problem, 15.0)
    w = 15.0 * 2 * math.pi / 60
    assert s.input_rad_s == pytest.approx(153.0 * w)  # R = 1 + z_p z2 / z1 = 1 + 40 x 38 / 10
    # the centre gear against the carrier turns at omega_in - omega_out; the planets (cranks) at z_p omega_out,
    # and the mesh's ratio z2 / z1 links the two
    assert s.centre_gear_rad_s == pytest.approx(s.input_rad_s - s.output_rad_s, rel=1e-12)
    assert s.centre_gear_rad_s / s.crank_rad_s == pytest.approx(38 / 10, rel=1e-12)


def test_power_balance_through_each_elements_moment_and_speed_ratio(lm, problem):
    # input torque from the moments: T_in = T_out / R + sum_e M_e omega_e / omega_in, each element's friction
    # moment recomputed here from the formulas and its speed ratio from the tooth counts; against
    # P_in = P_out + sum of the losses the module computes as powers
    b = lm.point(784.0, 15.0, 40.0)
    lube = problem.design.lubrication
    loads = lm.unit.loads(784.0)
    r = problem.geometry.ratio
    zp = problem.design.second_stage.pins
    nu = fr.kinematic_viscosity_mm2_s(40.0, lube.viscosity_40c_mm2_s, lube.viscosity_100c_mm2_s)
    needle_dm = 30.0 + 4.0
    m_needle = sum(fr.palmgren_load_moment_nmm(lube.needle_bearing_f1, float(f), needle_dm)
                   for f in loads.crank_bearing_load_magnitude_n.ravel()) / ANGLES \
        + 6 * fr.palmgren_viscous_moment_nmm(lube.needle_bearing_f0, nu, 15.0 * zp, needle_dm)
    t_in = 784.0 / r + (m_needle * 1e-3) * zp / r + lube.output_seal_torque_nm / r
    others = (b.loss_w[ELEMENTS.index("pins on flanks")] + b.loss_w[ELEMENTS.index("pins in seats")]
              + b.loss_w[ELEMENTS.index("crank support bearings")] + b.loss_w[ELEMENTS.index("main bearings")]
              + b.loss_w[ELEMENTS.index("involute mesh")])
    w_in = r * 15.0 * 2 * math.pi / 60
    assert t_in * w_in + others == pytest.approx(b.input_power_w, rel=1e-12)
    assert b.input_power_w == pytest.approx(b.output_power_w + sum(b.loss_w), rel=1e-12)
    assert b.input_torque_nm * w_in == pytest.approx(b.input_power_w, rel=1e-12)


def test_zero_friction_gives_efficiency_one(problem):
    z = LossModel(problem, ANGLES, lubrication=_zero(problem))
    for mode in ("running", "static"):
        b = z.point(784.0, 15.0, 40.0, mode)
        assert b.total_loss_w == 0.0 and b.efficiency == 1.0
    assert back_driving_torque_nm(z) == 0.0
    assert z.point(0.0, 15.0, 40.0).input_torque_nm == 0.0


def test_losses_converge_in_the_crank_angles(problem, lm):
    # 12 angles (the default) against 48: the rated point's total loss within 0.1 %
    fine = LossModel(problem, 48).point(784.0, 15.0, 40.0).total_loss_w
    assert LossModel(problem, 12).point(784.0, 15.0, 40.0).total_loss_w == pytest.approx(fine, rel=1e-3)


def test_boundary_friction_scales_the_pins_loss(problem, lm):
    # rv80e's pins run at Lambda < 1 at 15 r/min: their loss is the boundary coefficient's, linear in it
    b = lm.point(784.0, 15.0, 40.0)
    assert b.pin_film_parameter < 1.0
    double = LossModel(problem, ANGLES, lubrication=problem.design.lubrication.model_copy(update=dict(
        boundary_friction_coefficient=0.2, pin_seat_friction_coefficient=0.2)))
    d = double.point(784.0, 15.0, 40.0)
    pins = ELEMENTS.index("pins on flanks")
    assert d.loss_w[pins] == pytest.approx(2.0 * b.loss_w[pins], rel=1e-12)
    # a seat that slips easier takes the loss off the flanks, at its own coefficient
    seat = LossModel(problem, ANGLES, lubrication=problem.design.lubrication.model_copy(update=dict(
        pin_seat_friction_coefficient=0.05))).point(784.0, 15.0, 40.0)
    assert seat.loss_w[pins] == 0.0
    assert seat.loss_w[ELEMENTS.index("pins in seats")] == pytest.approx(0.5 * b.loss_w[pins], rel=1e-12)


def test_no_load_has_no_load_dependent_loss_and_efficiency_rises_with_torque(lm):
    idle = lm.point(0.0, 15.0, 40.0)
    assert sum(idle.load_dependent_w) == 0.0 and idle.total_loss_w > 0.0
    effs = [lm.point(t, 15.0, 40.0).efficiency for t in (100.0, 300.0, 784.0)]
    assert effs[0] < effs[1] < effs[2] < 1.0


def test_efficiency_rating_rv80e(problem):
    r = efficiency_rating(problem, angles=ANGLES, torque_fractions=(0.5, 1.0), output_speeds_rpm=(15.0,),
                          temperatures_c=(20.0, 60.0), input_speeds_rpm=(1000.0, 3000.0))
    assert 0.7 < r.efficiency_at_rated < 0.95
    assert sum(e.loss_w for e in r.elements) == pytest.approx(r.total_loss_at_rated_w, rel=1e-12)
    assert sum(e.share_of_losses for e in r.elements) == pytest.approx(1.0)
    # the no-load running torque rises with the input speed and falls with the temperature (viscosity)
    nl = {(p.input_speed_rpm, p.temperature_c): p.no_load_torque_nm for p in r.no_load_running_torque}
    assert nl[(1000.0, 20.0)] < nl[(3000.0, 20.0)] and nl[(3000.0, 60.0)] < nl[(3000.0, 20.0)]
    assert r.starting_torque_nm > 0.0 and 0.0 < r.starting_efficiency < 1.0
    assert 0.0 < r.back_driving_torque_nm < math.inf
    d = r.to_dict()
    assert d["elements"][0]["element"] == "pins on flanks" and "efficiency_map" in d
    with pytest.raises(InputError, match="output_speeds_rpm"):
        efficiency_rating(problem, angles=ANGLES, output_speeds_rpm=(-1.0,))


def _cycle():
    return DutyCycle("test", (DutyStep(0.5, 15.0, 784.0), DutyStep(0.3, 30.0, 300.0), DutyStep(0.2, 0.0, 500.0)))


def test_thermal_balance_root_and_allowable_duty(problem, lm):
    r = thermal_balance(lm, _cycle())
    th = problem.design.thermal
    heat = fr.housing_heat_flow_w(r.steady_temperature_c, th.ambient_c, r.housing_area_m2, th.convection_w_m2k,
                                  th.emissivity, th.flange_conductance_w_k)
    assert heat == pytest.approx(cycle_loss_w(lm, _cycle(), r.steady_temperature_c), rel=1e-6)
    assert r.steady_temperature_c > th.ambient_c and 0.0 < r.time_constant_min < math.inf
    # at the allowable duty the case sits at the limit: f P(T_lim) = Q(T_lim)
    assert r.allowable_duty_at_limit * r.loss_at_limit_w == pytest.approx(r.heat_at_limit_w, rel=1e-12)
    # a cycle that only holds makes no heat: the case stays at the ambient
    hold = thermal_balance(lm, DutyCycle("hold", (DutyStep(1.0, 0.0, 784.0),)))
    assert hold.steady_temperature_c == th.ambient_c


def test_equal_expansion_coefficients_leave_the_clearances(problem, lm):
    th = with_equal_expansion(problem.design.thermal, 12e-6)
    c = clearance_change(problem, th, 80.0)
    # only the designed modifications' own growth (5 um x 12e-6 x 60 K = 0.0036 um): rounding
    for v in (c.moving_distance_modification_um, c.equidistance_modification_um, c.pin_hole_clearance_um,
              c.crank_bearing_clearance_um, c.support_bearing_clearance_um):
        assert abs(v) < 0.005
    ref = precision_at_temperature(problem, lm.model, th, 20.0)
    hot = precision_at_temperature(problem, lm.model, th, 80.0)
    assert hot.lost_motion_arcmin == pytest.approx(ref.lost_motion_arcmin, abs=2e-3)
    assert hot.torsional_rigidity_nm_per_arcmin == pytest.approx(ref.torsional_rigidity_nm_per_arcmin, rel=1e-3)
    # the default coefficients (housing 11e-6 below the discs' 12.5e-6) close the pins' clearance as it warms
    warm = precision_at_temperature(problem, lm.model, problem.design.thermal, 60.0)
    assert warm.clearance.moving_distance_modification_um == pytest.approx(77.5 * 1.5e-6 * 40 * 1e3, abs=0.02)
    assert warm.lost_motion_arcmin < ref.lost_motion_arcmin
    # the support bearings (32005X, d_m 36 mm, D_w 5.5 mm): the steel journal and rollers outgrow the iron
    # carrier's seat: (11.0 x 41.5 - 12.5 x 30.5 - 12.5 x 11) e-6 x 40 K = -2.49 um (a preload), stiffer
    assert warm.clearance.support_bearing_clearance_um == pytest.approx(
        (11.0e-6 * 41.5 - 12.5e-6 * 30.5 - 12.5e-6 * 11.0) * 40 * 1e3, rel=1e-9)
    base = precision_at_temperature(problem, lm.model, problem.design.thermal, 20.0)
    assert warm.torsional_rigidity_nm_per_arcmin > base.torsional_rigidity_nm_per_arcmin


def test_bearing_friction_lies_in_the_makers_published_range(problem, lm):
    # JTEKT (Koyo) "Bearing knowledge" 8-4, Table 8-1: M = mu P d / 2 with mu 0.0020-0.0030 for a needle roller
    # and cage assembly and 0.0017-0.0025 for a tapered roller bearing in stable operation. rv80e's Palmgren
    # moments at the rated point (40 degC, 15 r/min output: 600 r/min) over the mean load, as that mu:
    b = lm.point(784.0, 15.0, 40.0)
    loads = lm.unit.loads(784.0)
    w_crank = 40 * 15.0 * 2 * math.pi / 60
    for element, load, bore, (lo, hi) in (("crank needle bearings", loads.crank_bearing_load_magnitude_n, 30.0,
                                           (0.0020, 0.0030)),
                                          ("crank support bearings", loads.support_bearing_load_magnitude_n, 25.0,
                                           (0.0017, 0.0025))):
        moment_nmm = b.loss_w[ELEMENTS.index(element)] / 6 / w_crank * 1e3
        mu = moment_nmm / fr.makers_friction_moment_nmm(1.0, float(load.mean()), bore)
        assert lo <= mu <= hi, (element, mu)


def test_a_production_runs_efficiency_is_seeded_and_its_yield_counts_its_units(problem):
    from rvbacklash.analysis.losses.production import efficiency_run

    a = efficiency_run(problem, units=4, seed=3, angles=4, spec_min_efficiency=0.8)
    b = efficiency_run(problem, units=4, seed=3, angles=4, spec_min_efficiency=0.8)
    assert [u.efficiency for u in a.per_unit] == [u.efficiency for u in b.per_unit]
    effs = [u.efficiency for u in a.per_unit]
    assert a.yield_ == sum(e >= 0.8 for e in effs) / 4 and a.min == min(effs) and a.max == max(effs)
    assert all(0.0 < e < 1.0 for e in effs)
    # each unit's preload or play as its run recorded it: one of the two
    assert all((u.cycloid_preload_um > 0) != (u.cycloid_play_arcmin == u.cycloid_play_arcmin) for u in a.per_unit)
    with pytest.raises(InputError, match="units"):
        efficiency_run(problem, units=0)


def test_a_production_runs_efficiency_over_torque_per_unit(problem):
    """heat40 (issue 40, per-unit maps beyond the rated point): every unit of the run at the map's
    torques, the same units and numbers as the rated point's run; efficiency falls towards low torque
    for every unit (the load-independent losses' share grows)."""
    from rvbacklash.analysis.losses.efficiency import LossModel
    from rvbacklash.analysis.losses.production import efficiency_run
    from rvbacklash.analysis.simulation import simulate

    run = efficiency_run(problem, units=3, seed=3, angles=4, spec_min_efficiency=0.8, torque_fractions=(0.25, 1.0))
    assert [b.output_torque_nm for b in run.by_torque] == [196.0, 784.0] and len(run.unit_map) == 6
    rated = run.by_torque[-1]
    assert (rated.mean, rated.min, rated.max, rated.yield_) == (run.mean, run.min, run.max, run.yield_)
    low = {c.unit: c.efficiency for c in run.unit_map if c.output_torque_nm == 196.0}
    assert all(low[u.unit] < u.efficiency for u in run.per_unit)
    # unit 1 at 25 % T_R by hand: its own LossModel at that point
    r, _, _ = simulate(problem, model="elastic", samples=3, seed=3, save_units=3, workers=1).units[1]
    lm = LossModel(problem, 4, realization=r, crank_clearance_um=r.crank_clearance_um)
    t = problem.design.lubrication.temperature_c
    assert low[1] == pytest.approx(lm.point(196.0, run.output_speed_rpm, t).efficiency, rel=1e-12)
    assert run.to_dict()["by_torque"][0]["yield"] == run.by_torque[0].yield_
    with pytest.raises(InputError, match="torque_fractions"):
        efficiency_run(problem, units=1, torque_fractions=(1.5,))
