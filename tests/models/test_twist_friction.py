"""The hysteresis loop's friction from the contacts (models/elastic/twist_friction.py; issue 40 item 3):
closed forms of its terms and of the loop's area, the kinematics against the contact model's levers,
metamorphic checks (no friction: no loop; the coefficient doubled: the load-dependent part doubled and
the loop's area grows), a stated value winning over the model's."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rvbacklash.analysis.hysteresis import build_loop, hysteresis, loop_area_j
from rvbacklash.models import compliance as cm
from rvbacklash.models import elastic as el
from rvbacklash.models.elastic.twist_friction import CURVE_FRACTIONS, tangential_lever_mm, twist_friction
from rvbacklash.problem import prepare

from helpers import example_with

MESH = "mesh_stiffness_n_per_mm_um = 20.0"
CONTACTS = (MESH, MESH + '\nfriction_model = "contacts"')


def contacts_design(*lubrication: str, stated: str | None = None):
    lines = "\n".join(lubrication)
    replacements = [CONTACTS if stated is None else
                    (MESH, MESH + f'\nfriction_model = "contacts"\nfriction_torque_nm = {stated}')]
    if lines:
        replacements.append(("[capacity]", f"[lubrication]\n{lines}\n\n[capacity]"))
    return example_with("rv80e", *replacements)


@pytest.fixture(scope="module")
def problem():
    return prepare(contacts_design())


@pytest.fixture(scope="module")
def model(problem):
    return el.elastic_model(problem)


def test_the_normal_lever_is_the_contact_models(problem, model):
    # the rotation about the disc's centre moves each contact along its normal by the contact model's lever
    # (its exact geometry with the modifications: within 1 % of the largest)
    u = el.nominal_unit(problem)
    g = model.geometry
    s, lever = tangential_lever_mm(g.rp_mm, g.rrp_mm, g.a_mm, g.zp, g.discs, float(u.chi_rad))
    reference = np.abs(u.lever_um_per_rad) * 1e-3
    assert np.max(np.abs(lever - reference)) < 0.01 * reference.max()
    # by hand, pin 10 of disc 0 at chi = 0 (psi = 90 deg): Q = (0, 77.5), P = (60, 0), O = (1.5, 0)
    q, p, o = np.array([0.0, 77.5]), np.array([60.0, 0.0]), np.array([1.5, 0.0])
    n = (p - q) / np.linalg.norm(p - q)
    c = q + 4.0 * n - o
    assert s[0, 10] == pytest.approx(abs(c @ n), rel=1e-12)
    assert lever[0, 10] == pytest.approx(abs(c[0] * n[1] - c[1] * n[0]), rel=1e-12)


def test_loaded_pins_slide_beyond_mindlins_partial_slip(problem, model):
    # the docstring's argument for Coulomb sliding: every pin loaded at T_R moves along its tangent by
    # s beta, beyond Mindlin's full-slip displacement mu (2 - nu) / (4 (1 - nu)) delta_n <= that of its
    # normal closure L beta (Johnson 1985, Sec. 7.2) by a wide margin
    u = el.nominal_unit(problem)
    pu = el.PreparedUnit(model, u)
    forces = pu.pin_forces_n(pu.pins_angle_rad(model.chain.rated_torque_nm, el.RISE))
    g = model.geometry
    s, lever = tangential_lever_mm(g.rp_mm, g.rrp_mm, g.a_mm, g.zp, g.discs, float(u.chi_rad))
    loaded = forces > 0.0
    ratio = s[loaded] / lever[loaded]
    assert 0.5 < ratio.min() and ratio.max() < 5.0
    mu, nu = problem.design.lubrication.static_friction_coefficient, 0.3
    assert ratio.min() > 5 * mu * (2 - nu) / (4 * (1 - nu))


def test_the_terms_in_closed_form(problem, model):
    tf = twist_friction(problem, model)
    lube = problem.design.lubrication
    t_r = 784.0
    k = cm.cycloid_lever_factor(39, 40, 10, 38, kinematic=True)
    per_bearing = k * 1e3 / (6 * 42.0)  # each of the 6 needle bearings' load per N m (T k / (n a0))
    # Palmgren M1 = f1 P dm on each, turning (z1/z2) per output radian; dm = 30 + 4 mm (needles), 36 mm (32005X)
    needles = 0.0005 * per_bearing * t_r * 34.0 * 6 * (10 / 38) * 1e-3
    support = 0.0004 * per_bearing * t_r * 36.0 * 6 * (10 / 38) * 1e-3
    assert tf.terms_at_rated_nm["crank needle bearings"] == pytest.approx(needles, rel=1e-12)
    assert tf.terms_at_rated_nm["crank support bearings"] == pytest.approx(support, rel=1e-12)
    # the mesh: mu H_V T / R; the seal as stated; the main bearings' two rows at the preload
    from rvbacklash.models import friction as fr
    hv = fr.mesh_geometry(problem).loss_factor
    assert tf.terms_at_rated_nm["involute mesh"] == pytest.approx(0.12 * hv * t_r / 153.0, rel=1e-12)
    assert tf.terms_at_rated_nm["output seal"] == lube.output_seal_torque_nm == 1.0
    main = 2 * fr.palmgren_load_moment_nmm(0.001 * (0.26 * 1000 / (12.3 * 38 * 9.525 ** 2 * math.cos(math.radians(40))))
                                           ** 0.33, 1000.0, 154.0) * 1e-3
    assert tf.terms_at_rated_nm["main bearings"] == pytest.approx(main, rel=1e-12)
    assert tf.constant_nm == pytest.approx(1.0 + main, rel=1e-12)
    # the chain reads the linear law: T_0 and lambda = mu a + b
    assert model.chain.friction_nm == pytest.approx(tf.constant_nm, rel=1e-15)
    assert model.chain.friction_fraction == pytest.approx(0.12 * tf.load_fraction_per_coefficient
                                                          + tf.load_fraction_bearings, rel=1e-12)


def test_the_linear_law_follows_the_models_curve(problem, model):
    tf = twist_friction(problem, model)
    t = np.array(tf.torque_nm)
    assert t == pytest.approx(np.array(CURVE_FRACTIONS) * 784.0)
    curve = np.array(tf.curve_nm)
    linear = np.array([tf.torque_at_nm(x) for x in t])
    fit = t >= 0.03 * 784.0
    assert np.max(np.abs(curve[fit] - linear[fit]) / curve[fit]) < 0.1
    assert np.all(np.diff(curve) > 0)  # more torque, more friction
    # rv80e (issue 40): 1.06 N m + 0.0081 |T|, 7.4 N m at T_R; the pins' flanks 6.0 of it (not 146 N m: the
    # running reducer's kinematic sliding)
    assert tf.constant_nm == pytest.approx(1.063, abs=0.01)
    assert tf.load_fraction == pytest.approx(0.0081, abs=0.0005)
    assert tf.terms_at_rated_nm["pins (flanks or seats)"] == pytest.approx(6.0, abs=0.3)


def test_no_friction_gives_no_loop():
    zero = contacts_design("static_friction_coefficient = 0.0", "needle_bearing_f1 = 0.0",
                           "support_bearing_f1 = 0.0", "main_bearing_f1_scale = 0.0", "output_seal_torque_nm = 0.0")
    h = hysteresis(prepare(zero))
    assert h.friction_torque_nm == 0.0 and h.friction_load_fraction == 0.0
    assert h.hysteresis_loss_j == pytest.approx(0.0, abs=1e-9)
    assert h.friction_model == "contacts"


def test_doubling_the_coefficient_doubles_the_load_dependent_part_and_widens_the_loop(problem, model):
    doubled = prepare(contacts_design("static_friction_coefficient = 0.24"))
    m2 = el.elastic_model(doubled)
    one, two = model.twist_friction, m2.twist_friction
    assert two.constant_nm == one.constant_nm
    assert two.load_fraction_per_coefficient == pytest.approx(one.load_fraction_per_coefficient, rel=1e-12)
    assert two.load_fraction - two.load_fraction_bearings == pytest.approx(
        2 * (one.load_fraction - one.load_fraction_bearings), rel=1e-12)
    h1, h2 = hysteresis(problem), hysteresis(doubled)
    assert h2.hysteresis_loss_j > h1.hysteresis_loss_j
    assert h2.friction_at_rated_nm > h1.friction_at_rated_nm


def test_a_stated_friction_wins_over_the_models():
    m = el.elastic_model(prepare(contacts_design(stated="2.0")))
    assert m.chain.friction_nm == 2.0
    assert m.chain.friction_fraction == pytest.approx(m.twist_friction.load_fraction, rel=1e-15)


def test_the_loops_area_in_closed_form(rv80e):
    # rigid contacts, a dead band D and linear springs K, a constant Coulomb friction T_f (mu = 0): the loop
    # is a parallelogram of torque width 2 T_f over the angle 2 (T_R - T_f) / K plus the dead band's
    # rectangle 2 T_f D: area = 4 T_f (T_R - T_f) / K + 2 T_f D
    problem = prepare(rv80e.model_copy(update={"structure": None}))
    model = el.elastic_model(problem)
    k1, ks, tf = 3.0e6, 2.0e5, 4.0
    c = model.chain._replace(law_b=0.0, law_n=cm.PALMGREN_EXPONENT, johnson=False, palmgren_a=1e-14, roller_a=1e-14,
                             roller_b=0.0, involute_stiffness_nm_per_rad=k1, structure_stiffness_nm_per_rad=ks,
                             friction_nm=tf, friction_fraction=0.0)
    m = el.ElasticModel(model.inputs, model.geometry, c, model.roller_cos, model.bearings,
                        model.crank_circle_radius_mm, model.raceway_diameter_mm)
    pu = el.PreparedUnit(m, el.nominal_unit(problem))
    dead = float((pu.chain(0.0, 1.0) - pu.chain(0.0, -1.0)).sum())
    k = 1.0 / (1 / k1 + 1 / ks)
    loop, _ = build_loop(pu, 21)
    t_r = c.rated_torque_nm
    assert loop_area_j(loop) == pytest.approx(4 * tf * (t_r - tf) / k + 2 * tf * dead, rel=1e-6)


def test_the_contacts_friction_is_the_default_and_a_stated_constant_overrides_it(rv80e):
    """heat40 (issue 40 item 3): a design that states no friction gets the contacts' (rv80e: 1.063 N m +
    0.00814 |T|); a stated friction_torque_nm without friction_model keeps its old meaning (the constant,
    no load-dependent part); friction_model = "stated" with nothing stated is no friction; "contacts" with a
    stated T_0 takes it with the model's slope."""
    assert rv80e.elastic.friction_model is None and rv80e.elastic.loop_friction_model == "contacts"
    h = hysteresis(prepare(rv80e))
    assert h.friction_model == "contacts"
    assert h.friction_torque_nm == pytest.approx(1.063, abs=0.01) and h.friction_load_fraction > 0.0
    assert h.backlash_arcmin == pytest.approx(1.5588, abs=5e-4)  # 1.5870 with the former stated 2 N m
    old = example_with("rv80e", (MESH, MESH + "\nfriction_torque_nm = 2.0"))
    assert old.elastic.loop_friction_model == "stated"
    m = el.elastic_model(prepare(old))
    assert (m.chain.friction_nm, m.chain.friction_fraction, m.twist_friction) == (2.0, 0.0, None)
    none = example_with("rv80e", (MESH, MESH + '\nfriction_model = "stated"'))
    c = el.elastic_model(prepare(none)).chain
    assert (c.friction_nm, c.friction_fraction) == (0.0, 0.0)
