"""The geometric contact model: validation against closed forms and the Table 1 transfers,
the linearisation against the exact geometry, and the Monte-Carlo through the engine."""

import math

import numpy as np
import pytest

from helpers import example_with
from rvbacklash.analysis.simulation import simulate
from rvbacklash.design.loading import design_from_toml
from rvbacklash.factors.catalog import factor_by_key
from rvbacklash.geometry.cycloid import PinCentreCurve, rotate
from rvbacklash.models.contact import exact_play, kernel_play, mesh_table
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import derive_geometry, prepare


@pytest.fixture(scope="module")
def geo(sun2014_problem):
    return sun2014_problem.cycloid


@pytest.fixture(scope="module")
def azc_um(geo):
    return geo.a_mm * geo.zc * 1e3


CRANK_ANGLES = [0.0, 0.05, 0.11, 1.0, 2.5]


@pytest.mark.parametrize("chi", CRANK_ANGLES)
def test_zero_errors_zero_modification_zero_play(geo, chi):
    play = exact_play(geo, Realization.nominal(geo, chi_rad=chi))
    assert abs(play.total_rad) < 1e-12
    assert all(abs(d.play_ccw_rad) < 1e-12 and abs(d.play_cw_rad) < 1e-12 for d in play.discs)


@pytest.mark.parametrize("chi", CRANK_ANGLES)
def test_pure_equidistance_modification(geo, azc_um, chi):
    """Table 1 row 11: 2 dr_rp / (a z_c) rad in total. Discrete pins can only make it larger,
    by at most (1 / cos(4.5 deg) - 1)-ish at the flat minimum: 0.5 %."""
    play = exact_play(geo, Realization.nominal(geo, equidistance_um=5.0, chi_rad=chi)).total_rad
    expected = 2 * 5.0 / azc_um
    assert expected * (1 - 1e-9) <= play <= expected * 1.005


@pytest.mark.parametrize("chi", CRANK_ANGLES)
def test_pure_moving_distance_modification(geo, azc_um, chi):
    """Table 1 row 12: -2 dr_p sqrt(1 - K1^2) / (a z_c) for dr_p < 0 (teeth moved in)."""
    play = exact_play(geo, Realization.nominal(geo, moving_distance_um=-5.0, chi_rad=chi)).total_rad
    assert play == pytest.approx(2 * 5.0 * math.sqrt(1 - geo.K1 ** 2) / azc_um, rel=0.01)


def test_interference_is_preload_not_lost_motion(geo):
    """Teeth moved out (dr_p > 0): every pin interferes, no rotation frees them: the stage is
    preloaded; its lost motion is 0 (the linear model would say -2 dr_p sqrt(1 - K1^2)). The
    preload is the interference no rotation can relieve: dr_p (1 - K1 cos phi)/sqrt(S) is dr_p at
    the pin on the eccentric's line (phi = 0, no lever arm), pin 0 at crank angle 0."""
    play = exact_play(geo, Realization.nominal(geo, moving_distance_um=5.0))
    assert play.preloaded and play.total_rad < 0 and play.lost_motion_rad == 0.0
    assert play.preload_um == pytest.approx(5.0, rel=1e-6)


def test_negative_equidistance_is_preload_of_that_depth(geo):
    """An equidistance modification of -3 um (fatter teeth) interferes by 3 um at every pin."""
    play = exact_play(geo, Realization.nominal(geo, equidistance_um=-3.0, chi_rad=0.3))
    assert play.preloaded and play.preload_um == pytest.approx(3.0, rel=1e-6)


@pytest.mark.parametrize("change", [("equidistance_modification_um = 5.0", "equidistance_modification_um = -20.0"),
                                    ("moving_distance_modification_um = 3.0", "moving_distance_modification_um = 40.0")])
def test_a_valid_design_never_crashes_the_exact_play(change):
    """Regression (issue 9): rv80e with Δr_rp = -20 um or Δr_p = 40 um ended in 'ArithmeticError:
    exact play: no root near the linear estimate'; the stage is preloaded."""
    from rvbacklash.analysis.contact import nominal_contact

    r = nominal_contact(prepare(example_with("rv80e", change)))
    assert r.cycloid_stage_preloaded and r.cycloid_stage_arcmin == 0.0 and r.play_total_arcmin < 0


def test_analytic_contact_normal_is_the_curve_normal(geo):
    """The linearisation's normal (c - P)/|c - P| through the pitch point equals the exact
    normal of the pin-centre curve at every pin (docs/contact.md)."""
    curve = PinCentreCurve(geo.a_mm, geo.rp_mm, geo.zc)
    chi = 0.37
    psi = geo.pin_angles
    centres = geo.rp_mm * np.stack([np.cos(psi), np.sin(psi)], axis=1)
    q = rotate(centres - geo.a_mm * np.array([math.cos(chi), math.sin(chi)]), chi / geo.zc)
    _, t = curve.signed_distance(q, chi - psi + 2 * math.pi * np.arange(geo.zp))
    n_exact = rotate(curve.outward_normal(t), -chi / geo.zc)
    pitch = geo.a_mm * geo.zp * np.array([math.cos(chi), math.sin(chi)])
    n_pitch = (centres - pitch) / np.linalg.norm(centres - pitch, axis=1, keepdims=True)
    np.testing.assert_allclose(n_exact, n_pitch, atol=1e-9)


BASE_CLEARANCE = 10.0  # um of equidistance modification, so that small errors do not interfere


def _delta_play_um(geo, azc_um, **changes) -> float:
    """Change of total play from the base, as circumferential backlash at a z_c [um]."""
    base = Realization.nominal(geo, equidistance_um=BASE_CLEARANCE, chi_rad=0.2)
    moved = base.with_(**changes)
    return (exact_play(geo, moved).total_rad - exact_play(geo, base).total_rad) * azc_um


@pytest.mark.parametrize("key,changes", [
    ("pin_circle_radius", lambda g, x: {"pin_radial_um": np.full(g.zp, x)}),
    ("pin_radius", lambda g, x: {"pin_radius_um": np.full(g.zp, x)}),
    ("pin_hole_clearance", lambda g, x: {"pin_clearance_um": np.full(g.zp, x)}),
    ("equidistance_modification_error", lambda g, x: {"equidistance_um": np.full(g.discs, BASE_CLEARANCE + x)}),
    ("moving_distance_modification_error", lambda g, x: {"moving_distance_um": np.full(g.discs, x)}),
])
def test_catalog_transfers_match_within_2_percent(geo, azc_um, sun2014, key, changes):
    """Every catalog factor with a common-mode counterpart here matches its Table 1 transfer."""
    gain = factor_by_key(key).gain(derive_geometry(sun2014))
    x = 1.0
    assert _delta_play_um(geo, azc_um, **changes(geo, x)) == pytest.approx(gain * x, rel=0.02)


def test_differences_from_table1_are_the_derived_ones(geo, azc_um, sun2014):
    """Findings (docs/contact.md), at a 10 um clearance:
    - a disc profile offset (run-out) across the eccentric is a rotation: no effect;
    - along the eccentric (and a crank eccentricity error, the same displacement) it has no
      first-order effect at the critical pin (normal perpendicular to it) but always reduces the
      play, quadratically, as pins nearer the tooth tips take over: -0.12 um at 1 um, -0.43 um
      at 2 um; Table 1 row 13 reads it as a zero-mean linear term (F_r / 4 = 0.5 um at 1 um);
    - a pitch error of one pin moves only that pin and saturates once the next pin takes over,
      bounded by the linear transfer K1 x."""
    g = derive_geometry(sun2014)
    across = _delta_play_um(geo, azc_um, runout_um=np.tile([0.0, 2.0], (geo.discs, 1)))
    assert abs(across) < 0.01
    along1 = _delta_play_um(geo, azc_um, runout_um=np.tile([1.0, 0.0], (geo.discs, 1)))
    along2 = _delta_play_um(geo, azc_um, runout_um=np.tile([2.0, 0.0], (geo.discs, 1)))
    table1 = factor_by_key("disc_runout").gain(g) * 2 * 1.0  # F_r = 2 e
    assert -table1 < along1 < 0 and 3.0 < along2 / along1 < 5.0
    ecc = _delta_play_um(geo, azc_um, eccentricity_error_um=np.full(geo.discs, 1.0))
    assert ecc == pytest.approx(along1, abs=1e-6)
    base = Realization.nominal(geo, equidistance_um=BASE_CLEARANCE, chi_rad=0.2)
    first = exact_play(geo, base).discs[0].contact_pin_ccw
    tangential = np.zeros(geo.zp)
    tangential[first] = 2.0
    delta = _delta_play_um(geo, azc_um, pin_tangential_um=tangential)
    assert 0 <= delta <= factor_by_key("pin_cumulative_pitch").gain(g) * 2.0 * 1.02


def test_tip_pins_are_not_ignored():
    """Regression (issue 10): pins with a lever arm below 10 % of a z_c were skipped, so a pin
    that interferes at the tooth tip went unseen. One disc, equidistance +10 um, crank angle 0,
    pin 20 (on the eccentric's line, no lever arm) oversized by 11 um: gap -1 um that no
    rotation can relieve. The old code said 3.424e-4 rad of play; the stage is preloaded by 1 um."""
    from rvbacklash.geometry.cycloid import ContactGeometry

    g = ContactGeometry(39, 40, 1.5, 77.5, 4.0, 1)
    radius = np.zeros(g.zp)
    radius[20] = 11.0
    r = Realization.nominal(g, equidistance_um=10.0).with_(pin_radius_um=radius)
    for play in (exact_play(g, r), kernel_play(g, r)):
        assert play.preloaded and play.lost_motion_rad == 0.0
        assert play.preload_um == pytest.approx(1.0, abs=0.02)


def test_osculating_table_is_the_curve_geometry(geo):
    """The kernel's osculating circles: every nominal pin centre lies on its circle (distance RHO
    from the centre), and the radius is C's radius of curvature |C'|^3 / |C' x C''|."""
    from rvbacklash.models import contact as C

    t = mesh_table(geo, np.array([0.0, 0.07]))
    chi_d = np.array([0.0, 0.07])[:, None] + np.array([0.0, np.pi])[None, :]
    psi = geo.pin_angles
    q = rotate(geo.rp_mm * np.stack([np.cos(psi), np.sin(psi)], -1)[None, None]
               - geo.a_mm * np.stack([np.cos(chi_d), np.sin(chi_d)], -1)[:, :, None], (chi_d / geo.zc)[:, :, None])
    dist = np.hypot(q[..., 0] - t[:, C.OX], q[..., 1] - t[:, C.OY])  # the table is (chis, column, discs, pins)
    tight = t[:, C.RHO] < C.RHO_MAX_MM
    np.testing.assert_allclose(dist[tight], t[:, C.RHO][tight], rtol=1e-9)
    assert t[:, C.RHO].min() == pytest.approx(0.13, abs=0.02)  # near the tips C bends with ~0.1 mm radius


def test_undercut_profile_is_rejected(sun2014_toml):
    from rvbacklash.errors import InputError
    with pytest.raises(InputError, match="undercut"):
        design_from_toml(sun2014_toml.replace("eccentricity_mm = 1.5", "eccentricity_mm = 1.9"))


# --- Monte-Carlo through the engine --------------------------------------------------------

def _only(toml: str, keep: dict) -> str:
    """sun2014 with every factor fixed at 0 except the ones in ``keep`` (key -> TOML body)."""
    from rvbacklash.factors.catalog import CATALOG
    head, _, _ = toml.partition("[factors.")
    body = "\n".join(f"[factors.{f.key}]\n" + keep.get(f.key, "distribution = \"fixed\"\nvalue_um = 0.0")
                     for f in CATALOG)
    return head + body


def test_contact_mc_min_over_two_discs_oracle(sun2014_toml, geo, azc_um):
    """Only the equidistance-modification error is random, per disc, N(0, 1): the discs are tied
    by the cranks, so play = 2 (eq + min(e1, e2)) / (a z_c); E[min of two N(0,1)] = -1/sqrt(pi)."""
    d = design_from_toml(_only(sun2014_toml, {
        "equidistance_modification": "distribution = \"fixed\"\nvalue_um = 10.0",
        "equidistance_modification_error": "plus_minus_um = 3.0"}))
    r = simulate(prepare(d), samples=1 << 18, seed=5, model="contact")
    arcmin_per_um = 60 * 180 / math.pi / azc_um
    expected = 2 * (10.0 - 1 / math.sqrt(math.pi)) * arcmin_per_um
    # the discrete-pin effect adds at most 0.5 % of the play on top
    assert r.output.mean_ci95_low <= expected * 1.005 and r.output.mean_ci95_high >= expected
    assert r.sigma_arcmin == pytest.approx(2 * math.sqrt(1 - 1 / math.pi) * arcmin_per_um, rel=0.02)


def test_contact_mc_reproducible_and_chunk_invariant(rv80e_problem):
    a = simulate(rv80e_problem, samples=3 * 65536 + 7, seed=9, model="contact", workers=1, chunk_blocks=1)
    b = simulate(rv80e_problem, samples=3 * 65536 + 7, seed=9, model="contact", workers=2, chunk_blocks=2)
    assert a.to_dict()["outputs"] == b.to_dict()["outputs"]
