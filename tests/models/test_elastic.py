"""The elastic hysteresis model (models/compliance.py, models/elastic/): formulas against the
literature and closed forms, the solver against independent balances, the loop's invariants."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rvbacklash.geometry.cycloid import PinCentreCurve
from rvbacklash.models import compliance as cm
from rvbacklash.models import elastic as el
from rvbacklash.models.contact import exact_play, linear_gaps_um
from rvbacklash.models.elastic import chain as ch
from rvbacklash.models.elastic import solver as sv
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import prepare
from rvbacklash.units import ARCMIN_PER_RAD

from helpers import example_with

E_STEEL, NU = 206.0, 0.3


@pytest.fixture(scope="module")
def problem(rv80e):
    # the contacts, needle bearings and mesh as derived before issue 16: the structure rigid (the
    # whole torque path is tests/models/test_structure.py; its rigid limit is these numbers)
    return prepare(rv80e.model_copy(update={"structure": None}))


@pytest.fixture(scope="module")
def model(problem):
    return el.elastic_model(problem)


def rigid(model: el.ElasticModel, **chain) -> el.ElasticModel:
    """The same model with (nearly) rigid contacts: a Palmgren law with a compliance 1e-12 of steel's,
    so that only dead bands and the linear springs (involute mesh, structure) remain."""
    c = model.chain._replace(law_b=0.0, law_n=cm.PALMGREN_EXPONENT, johnson=False, palmgren_a=1e-14,
                             roller_a=1e-14, roller_b=0.0, **chain)
    return el.ElasticModel(model.inputs, model.geometry, c, model.roller_cos, model.bearings,
                           model.crank_circle_radius_mm, model.raceway_diameter_mm)


def preloaded_unit(problem) -> el.ElasticUnit:
    """Teeth moved out (moving-distance modification 14 um instead of 3), no pin/hole clearance: every
    pin interferes; crank bearings preloaded too (clearance -1 um)."""
    s2 = problem.design.second_stage
    r = Realization.nominal(problem.cycloid, s2.equidistance_modification_um, 14.0, 0.0)
    return el.unit_from_realization(problem, r, 0.0, -1.0)


def random_unit(problem, seed: int, scale: float = 1.0) -> Realization:
    """Tolerance-sized per-pin and per-tooth errors (normal, sigma a few um), modifications nominal."""
    g = problem.cycloid
    rng = np.random.default_rng(seed)
    s2 = problem.design.second_stage
    return Realization(rng.uniform(0, 2 * math.pi / g.zp), scale * rng.normal(0, 1.5, g.zp),
                       scale * rng.normal(0, 1.5, g.zp), scale * rng.normal(0, 1.0, g.zp),
                       np.full(g.zp, 12.5) + scale * rng.normal(0, 1.0, g.zp),
                       scale * rng.normal(0, 2.0, (g.discs, g.zc)), scale * rng.normal(0, 1.0, (g.discs, 2)),
                       scale * rng.normal(0, 0.5, g.discs), np.full(g.discs, s2.equidistance_modification_um),
                       np.full(g.discs, s2.moving_distance_modification_um))


# --- formulas ----------------------------------------------------------------------------------

def test_hertz_half_width_and_pressure_against_roark():
    # Oracle: Young & Budynas, Roark's Formulas for Stress and Strain, 7th ed. (2002), Table 14.1,
    # cylinder on a flat plate: full width b = 1.60 sqrt(p K_D C_E), sigma_max = 0.798 sqrt(p / (K_D C_E)),
    # K_D = D, C_E = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (1.60 and 0.798 are rounded: 0.3 % tolerance).
    # Hand-worked: steel pin D = 8 mm on steel, p = 100 N/mm: C_E = 2 * 0.91 / 206000 = 8.835e-6 mm^2/N,
    # b = 1.60 sqrt(100 * 8 * 8.835e-6) = 0.1345 mm, sigma_max = 0.798 sqrt(100 / (8 * 8.835e-6)) = 949 MPa.
    force, length = 1200.0, 12.0
    e_star = cm.contact_modulus_n_per_mm2(E_STEEL, NU, E_STEEL, NU)
    a = cm.line_contact_half_width_mm(force, length, cm.relative_radius_mm(4.0, math.inf), e_star)
    assert 2 * a == pytest.approx(0.1345, rel=3e-3)
    assert cm.line_contact_peak_pressure_mpa(force, length, a) == pytest.approx(949.0, rel=3e-3)
    # a pin in a concave flank of radius 45 mm: R = 4 * 45 / 41
    assert cm.relative_radius_mm(4.0, -45.0) == pytest.approx(4.0 * 45.0 / 41.0, rel=1e-14)


def test_johnson_and_palmgren_agree_for_a_steel_roller():
    # ../shared/reference/anchors.md: "The two agree within ~35 % for a steel roller." A needle roller
    # D_w = 4 mm on a 30 mm raceway, L = 10 mm, loads 200 N - 2 kN; and a pin (r = 4 mm) on a flank.
    for q in (200.0, 700.0, 2000.0):
        pal = cm.palmgren_line_approach_um(q, 10.0)
        r = cm.relative_radius_mm(2.0, 15.0)
        joh = cm.johnson_line_approach_um(q, 10.0, cm.Body(2.0, E_STEEL, NU), cm.Body(15.0, E_STEEL, NU), r)
        assert 0.65 < joh / pal < 1.35, (q, joh, pal)
    joh = cm.johnson_line_approach_um(1000.0, 12.0, cm.Body(4.0, E_STEEL, NU), cm.Body(45.0, E_STEEL, NU),
                                   cm.relative_radius_mm(4, 45))
    assert 0.65 < joh / cm.palmgren_line_approach_um(1000.0, 12.0) < 1.35


def test_johnson_law_is_the_approach_rearranged():
    b = cm.johnson_law_b_um_per_n(12.0, E_STEEL, NU, 210.0, 0.29)
    for r1, r2, rel in ((4.0, 45.0, cm.relative_radius_mm(4, 45)), (4.0, 77.5, 8.0), (2.0, 19.0, 2.3)):
        a = cm.johnson_law_a_um_per_n(12.0, cm.Body(r1, E_STEEL, NU), cm.Body(r2, 210.0, 0.29), rel)
        for f in (10.0, 300.0, 5000.0):
            direct = cm.johnson_line_approach_um(f, 12.0, cm.Body(r1, E_STEEL, NU), cm.Body(r2, 210.0, 0.29), rel)
            assert cm.law_approach_um(f, a, b, 1.0) == pytest.approx(direct, rel=1e-12)
    assert cm.law_approach_um(700.0, cm.palmgren_law_a(10.0), 0.0, 0.9) == \
        pytest.approx(cm.palmgren_line_approach_um(700.0, 10.0), rel=1e-14)


@pytest.mark.parametrize("law", ["johnson", "palmgren"])
def test_contact_force_inverts_the_law(law):
    if law == "johnson":
        a, b, n = cm.johnson_law_a_um_per_n(12.0, cm.Body(4.0, E_STEEL, NU), cm.Body(45.0, E_STEEL, NU), 3.6), \
            cm.johnson_law_b_um_per_n(12.0, E_STEEL, NU, E_STEEL, NU), 1.0
    else:
        a, b, n = cm.palmgren_law_a(12.0), 0.0, 0.9
    for delta in (1e-3, 0.05, 1.0, 3.0, 20.0):
        for start in (0.0, 1.0, 1e5):
            f, df = sv.law_force(delta, a, b, n, start)
            assert cm.law_approach_um(f, a, b, n) == pytest.approx(delta, rel=1e-12)
            h = 1e-6 * f
            slope = (cm.law_approach_um(f + h, a, b, n) - cm.law_approach_um(f - h, a, b, n)) / (2 * h)
            assert df == pytest.approx(1 / slope, rel=1e-6)


def test_pin_centre_curve_radius_against_the_curve(problem):
    g = problem.cycloid
    curve = PinCentreCurve(g.a_mm, g.rp_mm, g.zc)
    for phi in (0.2, 0.5, math.acos(g.K1), 1.2, 2.0, 2.8):
        t = np.array([-phi])
        d1, d2 = curve.d1(t)[0], curve.d2(t)[0]
        cross = d1[0] * d2[1] - d1[1] * d2[0]
        numeric = np.linalg.norm(d1) ** 3 / cross
        assert cm.pin_centre_curve_radius_mm(phi, g.rp_mm, g.K1, g.zp) == pytest.approx(numeric, rel=1e-6)
    # at the critical pin (cos phi = K1) the radius is r_p sqrt(1 - K1^2)
    assert cm.pin_centre_curve_radius_mm(math.acos(g.K1), g.rp_mm, g.K1, g.zp) == \
        pytest.approx(g.rp_mm * math.sqrt(1 - g.K1 ** 2), rel=1e-12)
    assert cm.flank_radius_mm(49.0, 4.0) == 45.0 and cm.flank_radius_mm(-30.0, 4.0) == -34.0


def test_stage_one_stiffness_lever_factor_and_spring_algebra():
    # K_1 = i^2 r_1^2 n b c_gamma cos^2(alpha): RV-80E class i = 153, r_1 = 8.75 mm, 3 planets, b = 15 mm,
    # c_gamma = 20 N/(mm um) = 2e4 N/mm^2: 153^2 * 8.75^2 * 3 * 15 * 2e4 * cos^2(20 deg) N mm/rad.
    k = 153 ** 2 * 8.75 ** 2 * 3 * 15 * 2e4 * math.cos(math.radians(20)) ** 2 / 1e3
    assert cm.mesh_torsional_stiffness_nm_per_rad(20.0, 15.0, 8.75, 153.0, 3, 20.0) == pytest.approx(k, rel=1e-14)
    assert cm.cycloid_lever_factor(39, 40, 10, 38) == pytest.approx(39 / (40 + 10 / 38), rel=1e-15)
    assert cm.cycloid_lever_factor(39, 40, 10, 38, kinematic=False) == 1.0
    assert cm.series_stiffness(100.0, 300.0) == pytest.approx(75.0, rel=1e-15)
    assert cm.series_stiffness(100.0, math.inf) == 100.0 and cm.series_stiffness() == math.inf
    assert cm.parallel_stiffness(100.0, 300.0) == 400.0


def test_friction_branches():
    for t in (-50.0, -3.0, 0.0, 2.0, 7.0, 50.0):
        for inc in (True, False):
            te = cm.elastic_torque_nm(t, inc, 5.0, 0.1)
            assert cm.applied_torque_nm(te, inc, 5.0, 0.1) == pytest.approx(t, abs=1e-12)
            assert cm.elastic_torque_nm(t, inc, 0.0, 0.0) == t


# --- the solver --------------------------------------------------------------------------------

def test_discs_in_parallel_share_the_torque(problem, model):
    # two identical discs in parallel at one rotation: the rotation of one disc under half the torque
    u = el.nominal_unit(problem)
    c = model.chain
    g1, l1 = u.gap_um[0], u.lever_um_per_rad[0] / c.lever_factor
    law = np.empty((problem.cycloid.discs, problem.cycloid.zp))
    ch.fill_pin_law(0.0, c, law)
    a1 = law[0]

    def solve(g, lev, a, load):
        cs = sv.ContactSet(g, lev, a, sv.set_bounds(g, lev, g.size), np.zeros(g.size), -1, 0)
        return sv.solve_set(cs, sv.ContactLaw(c.law_b, c.law_n, 1e-6), load, 1.0, np.nan, (np.nan, np.nan)).x

    for t in (20.0, 400.0, -700.0):
        two = solve(np.concatenate([g1, g1]), np.concatenate([l1, l1]), np.concatenate([a1, a1]), t)
        assert two == pytest.approx(solve(g1, l1, a1, t / 2), rel=1e-10)


def chain_torque(c, torque: float, branch: int) -> float:
    """The torque the chain carries at an applied torque on a branch (held at the turning points
    until friction is overcome)."""
    tr, tf, mu = c.rated_torque_nm, c.friction_nm, c.friction_fraction
    if branch == el.RISE:
        held = cm.elastic_torque_nm(-tr, False, tf, mu)
        return held if torque < cm.applied_torque_nm(held, True, tf, mu) else cm.elastic_torque_nm(torque, True, tf, mu)
    held = cm.elastic_torque_nm(tr, True, tf, mu)
    return held if torque > cm.applied_torque_nm(held, False, tf, mu) else cm.elastic_torque_nm(torque, False, tf, mu)


def balance_residuals(pu: el.PreparedUnit, torque: float, branch: int) -> tuple[float, float]:
    """(pins, rollers) relative residuals of the torque balance at a solved point, recomputed from
    every pin of every disc with the converged contact law; the involute element checked too."""
    c = pu.model.chain
    t_el = chain_torque(c, torque, branch)
    angles = pu.branch(torque, branch)
    if t_el != 0.0:
        assert angles[ch.INVOLUTE] - math.copysign(0.5 * pu.loop.involute_backlash_rad, t_el) == pytest.approx(
            t_el / c.involute_stiffness_nm_per_rad, rel=1e-12)
    lev = (pu.unit.lever_um_per_rad / c.lever_factor).ravel()
    f = pu.pin_forces_n(angles[ch.PINS] + angles[ch.PIN_SEATING]).ravel()
    pins = 1e-6 * float(f @ lev)
    dr = angles[ch.CRANK_BEARINGS] / c.bearing_angle_rad_per_um
    d = dr * pu.model.roller_cos - 0.5 * pu.unit.crank_clearance_um
    q = np.array([sv.law_force(x, c.roller_a, c.roller_b, c.roller_n, 0.0)[0] if x > 0 else 0.0 for x in d])
    rollers = float(q @ pu.model.roller_cos)
    load = t_el * c.bearing_force_n_per_nm
    return abs(pins - t_el) / max(abs(t_el), 1.0), abs(rollers - load) / max(abs(load), 1.0)


def test_torque_balance_at_every_node(problem, model):
    from rvbacklash.analysis.hysteresis import build_loop

    units = [el.nominal_unit(problem), preloaded_unit(problem)] + [
        el.unit_from_realization(problem, random_unit(problem, s), 0.0, 3.0) for s in range(2)]
    for u in units:
        pu = el.PreparedUnit(model, u)
        loop, _ = build_loop(pu, 6)
        kinds = {"load+": el.RISE, "unload-": el.RISE, "load-": el.FALL, "unload+": el.FALL}
        for b in loop:
            for t in b.torque_nm:
                rp, rr = balance_residuals(pu, t, kinds[b.branch])
                assert rp < 1e-8 and rr < 1e-8, (b.branch, t, rp, rr)


# --- the loop ----------------------------------------------------------------------------------

def loop_of(problem, model, unit, points=25):
    from rvbacklash.analysis.hysteresis import build_loop

    return build_loop(el.PreparedUnit(model, unit), points)[0]


def test_branches_are_monotone(problem, model):
    units = [el.nominal_unit(problem), preloaded_unit(problem)] + [
        el.unit_from_realization(problem, random_unit(problem, s, 2.0), 1e-5, 2.0) for s in range(5)]
    for u in units:
        for b in loop_of(problem, model, u):
            t, a = np.array(b.torque_nm), np.array(b.angle_arcmin)
            direction = 1.0 if b.branch in ("load+", "unload-") else -1.0
            assert np.all(direction * np.diff(a) >= -1e-12), b.branch
            assert np.all(direction * np.diff(t) >= 0), b.branch


def test_symmetric_unit_gives_a_symmetric_loop(problem, model):
    # the nominal unit at crank angle 0: gaps even, levers odd in the pin phase; an even number of rollers
    u = el.nominal_unit(problem)
    assert model.roller_cos.size % 2 == 0
    loop = {b.branch: b for b in loop_of(problem, model, u)}
    for a, b in (("load+", "load-"), ("unload+", "unload-")):
        np.testing.assert_allclose(loop[a].torque_nm, -np.array(loop[b].torque_nm), atol=1e-12)
        np.testing.assert_allclose(loop[a].angle_arcmin, -np.array(loop[b].angle_arcmin), atol=1e-9)


def test_zero_friction_branches_coincide(problem, model):
    m = el.ElasticModel(model.inputs, model.geometry, model.chain._replace(friction_nm=0.0, friction_fraction=0.0),
                        model.roller_cos, model.bearings, model.crank_circle_radius_mm, model.raceway_diameter_mm)
    pu = el.PreparedUnit(m, el.unit_from_realization(problem, random_unit(problem, 3), 1e-5, 3.0))
    for t in (-700.0, -20.0, 5.0, 300.0):
        np.testing.assert_allclose(pu.branch(t, el.RISE), pu.branch(t, el.FALL), rtol=1e-12, atol=1e-15)


def test_linear_chain_with_dead_band_in_closed_form(problem, model):
    # rigid contacts: a dead band D (pins + crank bearings + involute backlash) and two linear springs in
    # series (mesh K_1, structure K_s), Coulomb friction T_f + mu |T|. Closed forms (x T_R > T_f):
    #   lost motion = D + [(x T_R - T_f)/(1 + mu) + (x T_R + T_f)/(1 - mu)] / K,  K = 1/(1/K_1 + 1/K_s)
    #   backlash    = D + 2 T_f / ((1 - mu) K),   rigidity = (1 + mu) K
    k1, ks = 3.0e6, 2.0e5  # N m/rad
    tf, mu = 4.0, 0.05
    m = rigid(model, involute_stiffness_nm_per_rad=k1, structure_stiffness_nm_per_rad=ks, friction_nm=tf,
              friction_fraction=mu)
    u = el.nominal_unit(problem)
    u = el.ElasticUnit(u.gap_um, u.lever_um_per_rad, u.chi_rad, 2e-5, 4.0)
    pu = el.PreparedUnit(m, u)
    c = m.chain
    dead = (pu.chain(0.0, 1.0) - pu.chain(0.0, -1.0)).sum()
    # the dead band itself: the pins' rigid play (k times the contact model's), the crank bearings' k G_r / a0
    # (an even number of rollers, one on the load line), the involute backlash
    g, lev = u.gap_um.ravel(), u.lever_um_per_rad.ravel()
    play = np.min(g[lev > 0] / lev[lev > 0]) + np.min(g[lev < 0] / -lev[lev < 0])
    assert dead == pytest.approx(c.lever_factor * play + c.lever_factor * 4.0e-3 / m.crank_circle_radius_mm + 2e-5,
                                 rel=1e-9)
    k = 1.0 / (1 / k1 + 1 / ks)
    xt = c.measuring_fraction * c.rated_torque_nm
    fig = pu.figures()
    assert fig[el.LOST_MOTION] / ARCMIN_PER_RAD == pytest.approx(
        dead + ((xt - tf) / (1 + mu) + (xt + tf) / (1 - mu)) / k, rel=1e-9)
    assert fig[el.BACKLASH] / ARCMIN_PER_RAD == pytest.approx(dead + 2 * tf / ((1 - mu) * k), rel=1e-9)
    assert fig[el.RIGIDITY] * ARCMIN_PER_RAD == pytest.approx((1 + mu) * k, rel=1e-9)
    assert sum(fig[el.ELEMENT_LOST_MOTION:el.SHARES]) == pytest.approx(fig[el.LOST_MOTION], rel=1e-12)


def test_rigid_limit_recovers_the_contact_model(problem, model):
    # stiffness -> infinity, no friction: the loop's width is the sum of the dead bands, and the pins' part
    # is the contact model's rigid play of the same unit, times the lever factor (Eq. (1)'s a z_c: factor 1)
    for lever_arms in ("kinematic", "eq1"):
        k = cm.cycloid_lever_factor(39, 40, 10, 38, kinematic=lever_arms == "kinematic")
        m = rigid(model, lever_factor=k, friction_nm=0.0, friction_fraction=0.0, structure_stiffness_nm_per_rad=math.inf,
                  involute_stiffness_nm_per_rad=1e30)
        for seed in range(3):
            r = random_unit(problem, seed, scale=0.5).with_(pin_clearance_um=np.full(40, 30.0))
            u = el.unit_from_realization(problem, r, 0.0, 0.0)
            pins = (el.PreparedUnit(m, u).chain(0.0, 1.0) - el.PreparedUnit(m, u).chain(0.0, -1.0))[0]
            g, lev = u.gap_um.ravel(), u.lever_um_per_rad.ravel()
            linear = np.min(g[lev > 0] / lev[lev > 0]) + np.min(g[lev < 0] / -lev[lev < 0])
            assert pins == pytest.approx(k * linear, rel=1e-9)
            exact = exact_play(problem.cycloid, r)
            assert not exact.preloaded
            assert pins == pytest.approx(k * exact.total_rad, rel=0.02)  # the linearisation's error (docs/contact.md)
            fig = el.PreparedUnit(m, u).figures()
            assert fig[el.LOST_MOTION] / ARCMIN_PER_RAD == pytest.approx(pins, rel=1e-6)


def test_zero_clearance_and_friction_give_twice_the_angle_at_the_measuring_torque(problem, model):
    # every gap zero (no modification, no clearance), crank bearings without clearance, no involute backlash,
    # no friction: the loop passes through the origin and lost motion = 2 theta(x T_R)
    r = Realization.nominal(problem.cycloid)
    u = el.unit_from_realization(problem, r, 0.0, 0.0)
    assert np.max(np.abs(u.gap_um)) < 1e-9  # the exact geometry's gaps of a perfect unit: 0 to rounding
    m = el.ElasticModel(model.inputs, model.geometry, model.chain._replace(friction_nm=0.0, friction_fraction=0.0),
                        model.roller_cos, model.bearings, model.crank_circle_radius_mm, model.raceway_diameter_mm)
    pu = el.PreparedUnit(m, u)
    c = m.chain
    xt = c.measuring_fraction * c.rated_torque_nm
    assert pu.branch(0.0, el.RISE).sum() == pytest.approx(0.0, abs=1e-15)
    theta = pu.branch(xt, el.RISE).sum()
    assert theta > 0
    assert pu.figures()[el.LOST_MOTION] / ARCMIN_PER_RAD == pytest.approx(2 * theta, rel=1e-10)
    assert pu.figures()[el.BACKLASH] == pytest.approx(0.0, abs=1e-12)


def test_preloaded_unit_is_stiff_at_zero_and_has_no_pin_dead_band(problem, model):
    u = preloaded_unit(problem)
    assert np.max(u.gap_um) < 0
    pu = el.PreparedUnit(model, u)
    assert (pu.chain(0.0, 1.0) - pu.chain(0.0, -1.0))[0] == pytest.approx(0.0, abs=1e-15)
    closed = (pu.pin_closures_um(pu.chain(0.0, 1.0)[0]) > 0).sum()
    assert closed > 10  # preloaded units start in contact
    assert pu.figures()[el.LOST_MOTION] < el.PreparedUnit(model, el.nominal_unit(problem)).figures()[el.LOST_MOTION]


def test_core_equals_the_prepared_unit_and_batches(problem, model):
    from rvbacklash.sampling.elastic_source import evaluate_batch, sample_units

    units = sample_units(problem, 5, 40)
    out = evaluate_batch(el.loop_design(model), units)
    for i in range(0, 40, 7):
        u = el.ElasticUnit(units.gap_um[i], units.lever_um_per_rad[i], float(units.chi_rad[i]),
                           float(units.involute_backlash_rad[i]), float(units.crank_clearance_um[i]))
        fig = el.PreparedUnit(model, u).figures()
        np.testing.assert_allclose(out[:3, i], fig[:3], rtol=1e-9)
        assert np.isnan(out[3, i]) or out[3, i] >= 0  # preload [um]: NaN when the cycloid stage is free
        one = np.empty(el.N_FIGURES)
        el.unit_hysteresis(u, el.loop_design(model), one)
        np.testing.assert_allclose(one, fig, rtol=1e-9)
        assert sum(fig[el.ELEMENT_LOST_MOTION:el.SHARES]) == pytest.approx(fig[0], rel=1e-12)


def test_the_elastic_model_draws_the_contact_models_units(problem):
    """Same seed, same units: the elastic model's sampler is the contact model's (issue 10 kernel),
    and its gaps and levers are the contact kernel's (models.contact.unit_gaps), which agree with
    the first-order gaps (linear_gaps_um) away from the tooth tips."""
    from rvbacklash.analysis.simulation import simulate
    from rvbacklash.models.contact import RHO, PinGaps, mesh_table, stage_work, unit_gaps
    from rvbacklash.models.unit_errors import unit_errors
    from rvbacklash.sampling.elastic_source import sample_units

    e = simulate(problem, samples=50, seed=3, model="elastic", save_units=5, workers=1)
    c = simulate(problem, samples=50, seed=3, model="contact", save_units=5, workers=1)
    batch = sample_units(problem, 3, 5, stream=())
    g = problem.cycloid
    for k, ((re, le, se), (rc, lc, sc)) in enumerate(zip(e.units, c.units)):
        assert re.chi_rad == rc.chi_rad == batch.chi_rad[k] and (le, se) == pytest.approx((lc, sc), rel=1e-12)
        np.testing.assert_array_equal(re.tooth_pitch_um, rc.tooth_pitch_um)
        np.testing.assert_array_equal(re.pin_radius_um, rc.pin_radius_um)
        gap, lever = np.empty((g.discs, g.zp)), np.empty((g.discs, g.zp))
        table = mesh_table(g, np.array([re.chi_rad]))[0]
        unit_gaps(table, g.stage_geometry, unit_errors(re), PinGaps(gap, lever), stage_work(g.discs, g.zp))
        np.testing.assert_array_equal(batch.gap_um[k], gap)
        np.testing.assert_array_equal(batch.lever_um_per_rad[k], lever)
        for d in range(g.discs):
            lin_gap, lin_lever = linear_gaps_um(g, re, d)
            away = table[RHO, d] > 3.0  # C gently bent: second-order terms small
            np.testing.assert_allclose(gap[d][away], lin_gap[away], atol=0.3)  # second-order terms of the errors
            # near a lever's zero (a pin facing the flank's turn) the second-order terms reach ~3e-3 a z_c:
            # seed 3's unit 1, pin 20 of disc 0: 141 against the linear 273 um/rad (issue 19's draws)
            np.testing.assert_allclose(lever[d][away], lin_lever[away], rtol=0.02, atol=4e-3 * g.pitch_radius_um)


def test_the_model_needs_an_elastic_table_and_a_face_width(sun2014):
    from rvbacklash.errors import InputError

    with pytest.raises(InputError) as e:
        el.elastic_model(prepare(sun2014))
    assert e.value.field == "elastic"
    d = example_with("rv80e", ("face_width_mm = 15.0\n", ""))
    with pytest.raises(InputError) as e:
        el.elastic_model(prepare(d))
    assert e.value.field == "first_stage.face_width_mm"


def test_the_pin_law_table_holds_each_units_laws(problem, model):
    """The design's table of contact laws (one row per crank-angle step the contact model draws)
    is the per-unit computation exactly, and a unit at another angle gets its laws computed."""
    from rvbacklash.sampling.contact_source import CRANK_STEPS
    from rvbacklash.sampling.elastic_source import design_pin_laws

    g = model.geometry
    table = design_pin_laws(model)
    assert table.shape == (CRANK_STEPS, g.discs * g.zp)
    law = np.empty((g.discs, g.zp))
    for s in (0, 77, CRANK_STEPS - 1):
        chi = 2.0 * math.pi / g.zp * (s + 0.5) / CRANK_STEPS  # as contact_source draws it
        ch.fill_pin_law(chi, model.chain, law)
        assert np.array_equal(ch.unit_pin_laws(chi, model.chain, g.zp, g.discs, table), law.ravel())
        assert np.shares_memory(ch.unit_pin_laws(chi, model.chain, g.zp, g.discs, table), table)  # the row itself
    off = 0.123  # not on the grid: computed
    ch.fill_pin_law(off, model.chain, law)
    got = ch.unit_pin_laws(off, model.chain, g.zp, g.discs, table)
    assert np.array_equal(got, law.ravel()) and not np.shares_memory(got, table)


def test_contacts_in_closure_order_load_as_in_any_order():
    """set_load over contacts in closure_order, each run stopped at its first open contact, gives
    the load of the same contacts in any order (the closed contacts of a run are a prefix)."""
    rng = np.random.default_rng(5)
    m = 40
    gaps = rng.normal(2.0, 3.0, m)
    levers = rng.normal(0.0, 4e4, m)
    levers[:3] = 0.0  # no lever: checked every time
    law_a = rng.uniform(0.003, 0.005, m)
    order, npos, nneg = sv.closure_order(gaps, levers, m)
    assert sorted(order) == list(range(m)) and npos == int((levers > 0).sum()) and nneg == int((levers < 0).sum())
    g, lv, la = gaps[order], levers[order], law_a[order]
    n_closed = 0
    for x in rng.uniform(-5e-4, 5e-4, 25):
        closed = lv * x - g > 0.0
        n_closed += int(closed.sum())
        assert not np.any(np.diff(closed[:npos].astype(int)) > 0)  # a prefix of each run
        assert not np.any(np.diff(closed[npos:npos + nneg].astype(int)) > 0)
        law = sv.ContactLaw(2.3e-4, 1.0, 1e-6)
        plain = sv.set_load(x, sv.ContactSet(gaps, levers, law_a, sv.set_bounds(gaps, levers, m), np.zeros(m), -1, 0), law, 1)
        runs = sv.set_load(x, sv.ContactSet(g, lv, la, sv.set_bounds(g, lv, m), np.zeros(m), npos, nneg), law, 1)
        np.testing.assert_allclose(runs, plain, rtol=1e-12, atol=1e-15)
    assert n_closed > 100  # the loads are sums over many closed contacts, not zeros


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_closure_prediction_is_the_root_for_linear_contacts(sign):
    """solver.closure_prediction (a solve's start far from the last solution): each closed contact
    on its tangent, each contact closing beyond on the last one's. For linear contacts of one law
    (F = delta / a: Palmgren's form with n = 1) that piecewise-linear load is the set's own, so the
    walked start is the root itself, past the closures of the contacts that close on the way."""
    rng = np.random.default_rng(11)
    m = 16
    gaps = rng.uniform(0.0, 2.0, m)  # a clearance: the other run is open
    levers = rng.uniform(1e4, 5e4, m) * np.where(np.arange(m) % 2 == 0, 1.0, -1.0)
    order, npos, nneg = sv.closure_order(gaps, levers, m)
    g, lv = gaps[order], levers[order]
    law = sv.ContactLaw(0.0, 1.0, 1e-6)
    cs = sv.ContactSet(g, lv, np.full(m, 0.003), sv.set_bounds(g, lv, m), np.zeros(m), npos, nneg)
    x0 = sv.solve_set(cs, law, sign * 5.0, sign, np.nan, (np.nan, np.nan)).x  # leaves its forces in cs
    predicted = sv.closure_prediction(cs, law, sign * 60.0, x0)
    fresh = sv.ContactSet(g, lv, np.full(m, 0.003), sv.set_bounds(g, lv, m), np.zeros(m), npos, nneg)
    root = sv.solve_set(fresh, law, sign * 60.0, sign, np.nan, (np.nan, np.nan)).x
    assert predicted == pytest.approx(root, rel=1e-9)
    assert np.sum(lv * root - g > 0) > np.sum(lv * x0 - g > 0) + 1  # contacts closed on the way
