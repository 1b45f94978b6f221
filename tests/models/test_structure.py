"""The whole torque path (issue 16; models/compliance.py, models/elastic/ with [structure]):
each formula against an independent closed form or a numeric solve, the chain's invariants, its
rigid limit (today's numbers), the disc's sideways motion, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rvbacklash.errors import InputError
from rvbacklash.models import compliance as cm
from rvbacklash.models import elastic as el
from rvbacklash.models.elastic import chain as ch
from rvbacklash.models.elastic import solver as sv
from rvbacklash.problem import prepare
from rvbacklash.units import ARCMIN_PER_RAD

from helpers import example_text, one_line_error, run_cli

E, NU = 206.0, 0.3


@pytest.fixture(scope="module")
def rv80e(rv80e):
    """rv80e with the stated 2 N m of friction (the example's until heat40): these tests compare chains
    built different ways, and the contacts' friction law (the default) is derived per design from each
    chain's share of the pins, and reads into the element stiffnesses by its slope (1 + lambda)."""
    return rv80e.model_copy(update={"elastic": rv80e.elastic.model_copy(update={"friction_torque_nm": 2.0})})


@pytest.fixture(scope="module")
def problem(rv80e):
    return prepare(rv80e)


@pytest.fixture(scope="module")
def model(problem):
    return el.elastic_model(problem)


# --- beams: against superposition of Roark's general point-load case --------------------------------

def point_load_deflection(span, a, x, ei):
    """Roark (7th ed.) Table 8.1 case 1e: simply supported, unit load at a; deflection at x [mm/N]."""
    b = span - a
    if x <= a:
        return b * x * (span ** 2 - b ** 2 - x ** 2) / (6 * ei * span)
    return point_load_deflection(span, span - a, span - x, ei)


@pytest.mark.parametrize("span, c, d", [(45.0, 16.0, 25.0), (120.0, 30.0, 40.0), (60.0, 29.0, 12.0)])
def test_crank_bending_is_two_point_loads_superposed(span, c, d):
    ei = E * 1e3 * math.pi * d ** 4 / 64
    sym = point_load_deflection(span, c, c, ei) + point_load_deflection(span, span - c, c, ei)
    anti = point_load_deflection(span, c, c, ei) - point_load_deflection(span, span - c, c, ei)
    area, g = math.pi * d ** 2 / 4, E * 1e3 / (2 * (1 + NU))
    kappa = 6 * (1 + NU) / (7 + 6 * NU)  # Cowper (1966), solid circle: 0.886 for nu = 0.3
    assert kappa == pytest.approx(0.8864, abs=1e-4)
    # shear: the shear force between support and load is P (two loads alike) or P (L - 2c) / L (opposite)
    assert cm.crank_symmetric_deflection_um_per_n(span, c, d, E, NU) == pytest.approx(
        (sym + c / (kappa * g * area)) * 1e3, rel=1e-12)
    assert cm.crank_antisymmetric_deflection_um_per_n(span, c, d, E, NU) == pytest.approx(
        (anti + c * (span - 2 * c) / (span * kappa * g * area)) * 1e3, rel=1e-12)


def test_pillar_is_a_cantilever_held_straight_at_its_end():
    # fixed-guided = cantilever under W (W l^3 / 3EI) less the end moment W l / 2 that keeps the end
    # straight (M l^2 / 2EI): W l^3 / 12EI; shear with Cowper's rectangle 10 (1 + nu) / (12 + 11 nu)
    length, w, h = 27.0, 20.0, 20.0
    ei = E * 1e3 * h * w ** 3 / 12
    bend = length ** 3 / (3 * ei) - (length / 2) * length ** 2 / (2 * ei)
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    shear = length / (kappa * E * 1e3 / (2 * (1 + NU)) * w * h)
    assert cm.pillar_deflection_um_per_n(length, w, h, E, NU) == pytest.approx((bend + shear) * 1e3, rel=1e-12)


def test_shaft_torsion_against_the_polar_moment_integrated():
    # J = int r^2 dA over the disc of diameter d, numerically; phi / T = L / (G J)
    d, length = 25.0, 40.0
    r = np.linspace(0, d / 2, 200001)
    polar = np.trapezoid(2 * math.pi * r ** 3, r)
    g = E * 1e3 / (2 * (1 + NU))
    assert cm.shaft_torsion_compliance_rad_per_nm(length, d, E, NU) == pytest.approx(length / (g * polar) * 1e3,
                                                                                        rel=1e-8)


def test_output_compliances_by_virtual_work():
    # a tangential element at the cranks and the carrier: compliance = (force per torque)^2 x spring, summed
    k, nb, a0 = 0.9687, 6, 42.0
    spring = 1.7e-3  # um/N
    force = k / (nb * a0 * 1e-3)  # N per N m at each of the n_b points
    assert cm.tangential_output_compliance_rad_per_nm(spring, k, nb, a0) == pytest.approx(
        nb * force ** 2 * spring * 1e-6, rel=1e-12)
    pillars, radius = 3, 42.0
    shear = k / 2 / (pillars * radius * 1e-3)  # the pillars carry k T / 2
    assert cm.carrier_output_compliance_rad_per_nm(spring, pillars, radius, k) == pytest.approx(
        pillars * shear ** 2 * spring * 1e-6, rel=1e-12)
    # crank torsion: n cranks each carrying r2 T / (i r1 n)
    twist, r2, r1, i, n = 1.3e-5, 33.25, 8.75, 153.0, 3
    assert cm.crank_torsion_output_compliance_rad_per_nm(twist, r2, r1, i, n) == pytest.approx(
        n * (r2 / (i * r1 * n)) ** 2 * twist, rel=1e-12)


# --- the disc on three bearings: the closed form against a numeric 3-DOF solve ---------------------

@pytest.mark.parametrize("a0, rho, angle", [(42.0, 58.5, 0.0), (42.0, 58.5, 0.7), (30.0, 80.0, 2.0)])
def test_translation_factor_is_the_three_spring_equilibrium(a0, rho, angle):
    # a rigid disc on three equal isotropic springs at a0 (120 degrees apart), loaded by a force F across the
    # eccentric acting at the pitch point P (rho along it): how far P moves, free against held disc centre
    kb, force = 1.0, 1.0
    e = np.array([math.cos(angle), math.sin(angle)])
    perp = np.array([-e[1], e[0]])
    p = rho * e
    k = np.zeros((3, 3))
    for i in range(3):
        c = a0 * np.array([math.cos(2 * math.pi * i / 3 + 0.3), math.sin(2 * math.pi * i / 3 + 0.3)])
        jac = np.array([[1.0, 0.0, -c[1]], [0.0, 1.0, c[0]]])  # hole displacement from (ux, uy, beta)
        k += kb * jac.T @ jac
    f = np.array([*(force * perp), force * (p[0] * perp[1] - p[1] * perp[0])])
    ux, uy, beta = np.linalg.solve(k, f)
    moved = (np.array([ux, uy]) + beta * np.array([-p[1], p[0]])) @ perp
    held = force * rho * rho / (3 * kb * a0 * a0)  # u = 0: beta = F rho / (3 kb a0^2), P moves rho beta
    assert moved / held == pytest.approx(cm.disc_translation_factor(a0, rho), rel=1e-12)


def test_pin_radial_closure_against_the_exact_geometry(problem):
    # translate each disc along its eccentric (its profile offset) by 1e-3 um: every pin closes by M
    g = problem.cycloid
    for chi in (0.0, 0.9):
        r = el.nominal_realization(problem, chi)
        base = el.unit_from_realization(problem, r, 0.0, 0.0).gap_um
        moved = r.runout_um.copy()
        moved[:, 0] += 1e-3
        closure = -(el.unit_from_realization(problem, r.with_(runout_um=moved), 0.0, 0.0).gap_um - base) / 1e-3
        m = np.array([[cm.pin_radial_closure(ch.pin_phase(d * g.zp + j, chi, g.zp, g.discs), g.K1)
                       for j in range(g.zp)] for d in range(g.discs)])
        # the clearance offsets the contact normal slightly from the nominal one
        np.testing.assert_allclose(closure, m, atol=5e-3)
        assert np.abs(m).max() == pytest.approx(1.0, abs=1e-3)


# --- support bearings: Harris & Kotzalas's load zone ---------------------------------------------

def support_set(model, clearance_um=0.0):
    return ch.prepare_support(model.chain._replace(support_clearance_um=clearance_um))


def support_deflection(model, load_n, clearance_um=0.0):
    cs = support_set(model, clearance_um).contacts
    return sv.solve_set(cs, sv.ContactLaw(0.0, cm.PALMGREN_EXPONENT, 1.0), load_n, 1.0, np.nan,
                        (np.nan, np.nan)).x, (cs.gaps, cs.levers, cs.law_a)


def test_support_bearing_peak_roller_load_is_stribecks(model):
    # zero clearance, line contact: Q_max = F_r / (Z J_r cos alpha), 1/J_r(0.5) = 4.08 (Harris & Kotzalas, 5th
    # ed., the load distribution integral of a line contact; anchors.md); a discrete set of 17 rollers within 2 %
    c = model.chain
    fr = 3000.0
    dr, (g, lv, la) = support_deflection(model, fr)
    q = np.array([sv.law_force(x, la[0], 0.0, cm.PALMGREN_EXPONENT, 0.0)[0] if x > 0 else 0.0 for x in lv * dr - g])
    assert float(q @ lv) == pytest.approx(fr, rel=1e-10)  # the radial balance
    assert q.max() == pytest.approx(4.08 * fr / (c.support_rollers * c.support_cos_alpha), rel=0.02)
    # the heaviest roller's approach (Palmgren, two contacts) is the bearing's radial deflection times cos alpha
    assert dr * c.support_cos_alpha == pytest.approx(cm.law_approach_um(q.max(), la[0], 0.0, cm.PALMGREN_EXPONENT),
                                                     rel=1e-9)


def test_support_clearance_is_a_dead_band_and_preload_stiffens(model):
    fr = 3000.0
    free, _ = support_deflection(model, 1e-9, clearance_um=8.0)
    assert free == pytest.approx(4.0, rel=1e-6)  # half the clearance on the side with a roller on the load line
    loose, _ = support_deflection(model, fr, clearance_um=8.0)
    tight, _ = support_deflection(model, fr, clearance_um=0.0)
    preloaded, _ = support_deflection(model, fr, clearance_um=-4.0)
    assert loose - 4.0 > tight > preloaded  # the load zone narrows with a clearance, widens with a preload


# --- the chain -----------------------------------------------------------------------------------

def test_rigid_limit_reproduces_the_chain_without_structure(problem, model, rv80e):
    # every new stiffness -> infinity and no translation: the numbers of the chain without [structure] (1e-9)
    rigid = prepare(rv80e.model_copy(update={"structure": None}))
    m0 = el.elastic_model(rigid)
    c = model.chain._replace(crank_compliance_rad_per_nm=model.chain.crank_compliance_rad_per_nm * 1e-15,
                             carrier_compliance_rad_per_nm=model.chain.carrier_compliance_rad_per_nm * 1e-15,
                             support_a=model.chain.support_a * 1e-18, translation_factor=1.0,
                             disc_body_compliance_rad_per_nm=model.chain.disc_body_compliance_rad_per_nm * 1e-15)
    stiff = el.ElasticModel(model.inputs, model.geometry, c, model.roller_cos, model.bearings,
                            model.crank_circle_radius_mm, model.raceway_diameter_mm)
    for u in (el.nominal_unit(problem), el.nominal_unit(problem, 0.4)):
        a, b = el.PreparedUnit(stiff, u).figures(), el.PreparedUnit(m0, u).figures()
        np.testing.assert_allclose(a[:el.SHARES], b[:el.SHARES], rtol=1e-9, atol=1e-12)
    # and without the structure's rows, the pins' seats and the needles' profile (the model before issue 28),
    # rv80e's figures are those tests/models/test_elastic.py pins
    bare = prepare(rv80e.model_copy(update={"structure": None, "elastic": rv80e.elastic.model_copy(
        update={"pin_seating": "none", "crank_bearing_roller_profile": "straight"})}))
    assert el.PreparedUnit(el.elastic_model(bare), el.nominal_unit(bare)).figures()[el.RIGIDITY] == pytest.approx(
        1723.64, rel=1e-5)


def test_compliance_shares_and_element_stiffnesses(problem, model):
    from rvbacklash.analysis.hysteresis import hysteresis

    h = hysteresis(problem)
    assert h.structure_model == "derived" and h.disc_translation == "across"
    shares = h.compliance_share
    assert sum(shares.values()) == pytest.approx(1.0, abs=1e-12)
    for name in ("crankshafts", "support_bearings", "carrier", "crank_bearings", "cycloid_pins", "involute_stage"):
        assert shares[name] > 0.0, name
    assert shares["main_bearings"] == 0.0 and shares["structure"] == 0.0  # unloaded by a pure torque; not stated
    # springs in series: 1/K = sum 1/K_e
    inv = sum(1.0 / k for k in h.element_stiffness_nm_per_arcmin.values() if k is not None)
    assert 1.0 / inv == pytest.approx(h.torsional_rigidity_nm_per_arcmin, rel=1e-10)
    # the linear elements' stiffness is their formula's
    assert h.element_stiffness_nm_per_arcmin["crankshafts"] == pytest.approx(
        1.0 / model.chain.crank_compliance_rad_per_nm / ARCMIN_PER_RAD, rel=1e-10)
    assert h.element_stiffness_nm_per_arcmin["carrier"] == pytest.approx(
        1.0 / model.chain.carrier_compliance_rad_per_nm / ARCMIN_PER_RAD, rel=1e-10)
    assert h.wind_up_arcmin == pytest.approx(h.lost_motion_arcmin - sum(h.dead_band_arcmin.values()), rel=1e-12)
    assert h.torsional_rigidity_nm_per_arcmin < 0.5 * 1723.6  # the structure is the soft part of the chain


def test_translation_across_scales_the_bearings_elastic_part_only(problem, model):
    # rigid pins, no friction: the needle bearings' element is its dead band plus f times its wind-up
    none = el.elastic_model(prepare(problem.design.model_copy(update={"structure": problem.design.structure.model_copy(
        update={"disc_translation": "none"})})))
    u = el.nominal_unit(problem)
    for t in (50.0, 700.0):
        a = el.PreparedUnit(model, u).chain(t, 1.0)[ch.CRANK_BEARINGS]
        b = el.PreparedUnit(none, u).chain(t, 1.0)[ch.CRANK_BEARINGS]
        edge = el.PreparedUnit(none, u).chain(0.0, 1.0)[ch.CRANK_BEARINGS]
        assert a - edge == pytest.approx(model.chain.translation_factor * (b - edge), rel=1e-12)
    assert model.chain.translation_factor == pytest.approx(1 + (42 / 58.5) ** 2, rel=1e-12)


def test_full_translation_balances_the_pins_radial_resultant(problem):
    full = el.elastic_model(prepare(problem.design.model_copy(update={"structure": problem.design.structure.model_copy(
        update={"disc_translation": "full"})})))
    c = full.chain
    assert math.isfinite(c.radial_stiffness_n_per_um) and c.radial_stiffness_n_per_um > 0
    u = el.nominal_unit(problem)
    pu = el.PreparedUnit(full, u)
    for t in (23.52, 784.0):
        a = pu.chain(t, 1.0)
        x = a[ch.PINS] + a[ch.PIN_SEATING]  # the pins' angle: flanks and seats
        y = pu.translation_um()
        f = pu.pin_forces_n(x)
        g = problem.cycloid
        m = np.array([[cm.pin_radial_closure(ch.pin_phase(d * g.zp + j, u.chi_rad, g.zp, g.discs), g.K1)
                       for j in range(g.zp)] for d in range(g.discs)])
        radial = (f * m).sum(axis=1) + c.radial_stiffness_n_per_um * y
        assert np.abs(radial).max() < 1e-6 * f.sum()  # each disc's pins balance its bearings along the eccentric
        torque = 1e-6 * float((f * u.lever_um_per_rad / c.lever_factor).sum())
        assert torque == pytest.approx(t, rel=1e-8)
    # following the radial resultant changes the nominal figures by about a per cent, no more
    across = el.PreparedUnit(el.elastic_model(problem), u).figures()
    np.testing.assert_allclose(pu.figures()[:3], across[:3], rtol=0.03)


def test_stated_structure_wins_over_the_derivation(problem):
    d = problem.design
    stated = d.model_copy(update={"elastic": d.elastic.model_copy(update={"structure_stiffness_nm_per_arcmin": 300.0})})
    m = el.elastic_model(prepare(stated))
    assert not m.derived and m.chain.crank_compliance_rad_per_nm == 0.0 and m.chain.support_rollers == 0.0
    assert m.structure_stiffness_nm_per_arcmin == pytest.approx(300.0)


# --- bad input -----------------------------------------------------------------------------------

@pytest.mark.parametrize("line, field", [
    ("disc_spacing_mm = 50.0", "disc_spacing_mm"),
    ("pillar_width_mm = -1.0", "structure.pillar_width_mm"),
    ("support_bearing_rollers = 2", "structure.support_bearing_rollers"),
    ("support_bearing_contact_angle_deg = 60.0", "structure.support_bearing_contact_angle_deg"),
    ("disc_translation = \"sideways\"", "structure.disc_translation"),
])
def test_bad_structure_is_a_one_line_error(tmp_path, line, field):
    key = line.split(" = ")[0]
    lines = [x for x in example_text("rv80e").splitlines() if not x.startswith(f"{key} = ")]
    lines.insert(lines.index("[structure]") + 1, line)
    f = tmp_path / "bad.toml"
    f.write_text("\n".join(lines) + "\n")
    one_line_error(run_cli("hysteresis", f), field)
    assert not (tmp_path / "h.json").exists()


def test_three_discs_keep_what_holds_for_any_number_of_discs(problem):
    """Issue 36: with three discs the derived crankshafts, support bearings and carrier (two discs
    symmetric about the crank's mid-span) were refused with the advice to remove [structure], which
    also dropped the disc bodies' FE and the discs' sideways motion (the chain then read ~1.4x
    stiffer, without a word). Now: the three derived elements must be stated, and the message says so
    and what [structure] still gives; with them stated, the disc bodies and the translation stay."""
    d = problem.design
    three = d.model_copy(update={"second_stage": d.second_stage.model_copy(update={"discs": 3})})
    with pytest.raises(InputError, match="second_stage.discs") as e:
        el.elastic_model(prepare(three))
    for words in ("structure_stiffness_nm_per_arcmin", "disc bodies", "sideways motion", "stiffer"):
        assert words in str(e.value)
    stated = three.model_copy(update={"elastic": three.elastic.model_copy(
        update={"structure_stiffness_nm_per_arcmin": 1000.0})})
    stated_problem = prepare(stated)
    model = el.elastic_model(stated_problem)
    assert model.disc_body is not None and len(model.disc_body.discs) == 3
    g = problem.cycloid
    assert model.chain.translation_factor == cm.disc_translation_factor(problem.geometry.crank_circle_radius_mm,
                                                                        g.a_mm * g.zc)
    assert model.chain.structure_stiffness_nm_per_rad == pytest.approx(1000.0 * ARCMIN_PER_RAD)
    bare_problem = prepare(stated.model_copy(update={"structure": None}))
    bare = el.elastic_model(bare_problem)
    assert bare.disc_body is None and bare.chain.translation_factor == 1.0
    rigidity = [el.PreparedUnit(m, el.nominal_unit(p)).figures()[el.RIGIDITY]
                for m, p in ((model, stated_problem), (bare, bare_problem))]
    assert rigidity[0] < 0.8 * rigidity[1]  # measured 463 against 646 N m/arcmin
    full = stated.model_copy(update={"structure": stated.structure.model_copy(update={"disc_translation": "full"})})
    with pytest.raises(InputError, match="structure.disc_translation"):
        el.elastic_model(prepare(full))


def test_hysteresis_table_names_the_structure_table():
    # "[structure]" is rich markup unless escaped: the table once printed "derived from  (disc ...)"
    p = run_cli("hysteresis", "rv80e")
    assert p.returncode == 0 and "derived from [structure]" in " ".join(p.stdout.split()), p.stdout[-800:]
