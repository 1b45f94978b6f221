"""The nominal design through the exact contact geometry (``rvbacklash contact``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rvbacklash.design.measured import MeasuredDisc, MeasuredKinematics, MeasuredPins, MeasuredUnit
from rvbacklash.factors.catalog import FACTOR_KEYS, Stage
from rvbacklash.geometry.cycloid import ContactGeometry, profile_points, rotate
from rvbacklash.models.contact import MeshPlay, exact_gaps_um, exact_play
from rvbacklash.models.unit_errors import Realization
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result
from rvbacklash.units import ARCMIN_PER_RAD

TIE_RAD = 1e-9  # pins closer than this to the first contact count as touching together
ASSUMPTIONS = ("rigid bodies, no load; exact signed distances between profile and pins; no manufacturing errors; "
               "designed clearances (modifications, pin/hole fit) at their nominal values; involute and crank "
               "stages at their linear means")
ASSUMPTIONS_MEASURED = ("rigid bodies, no load; exact signed distances between profile and pins; the unit's measured "
                        "deviations (missing ones zero), modifications at their nominal values plus the unit's errors; "
                        "involute and crank stages as given in the unit, else at their linear means")


@dataclass(frozen=True, repr=False)
class DiscContact(Result):
    """One disc's free rotation each way [arcmin at the output] and its first-contact pins (0-based
    pin index j at angle 2 pi j / z_p); discs are numbered from 1."""

    disc: int
    play_ccw_arcmin: float
    play_cw_arcmin: float
    contact_pins_ccw: tuple[int, ...]
    contact_pins_cw: tuple[int, ...]


@dataclass(frozen=True, repr=False)
class NominalContact(Result):
    """Play of one unit from the exact cycloid-pin geometry at one crank angle: the error-free
    design (``unit`` "nominal") or a measured unit."""

    design_name: str
    unit: str  # "nominal", or the measured unit ("unit 3 of units.toml")
    crank_angle_deg: float
    cycloid_stage_arcmin: float  # lost motion of the stage (0 when preloaded)
    cycloid_stage_preloaded: bool
    preload_um: float  # the smallest uniform clearance that would free every pin (0 when free)
    play_total_arcmin: float  # signed: negative = interference (only the sign is meaningful then)
    lost_motion_arcmin: float  # the stage plus the involute and crank stages at their linear means
    linear_cycloid_stage_mean_arcmin: float
    other_stages_mean_arcmin: dict[str, float]
    discs: tuple[DiscContact, ...]
    equidistance_modification_um: float
    moving_distance_modification_um: float
    pin_hole_clearance_um: float
    assumptions: str
    # drawing data for the figure (kept out of to_dict): disc 1's profile and the pin centres in
    # the housing frame [mm], the gaps of every pin at zero rotation (discs, z_p) [um]
    geometry: ContactGeometry = field(metadata={EXPORT: False})
    profile_xy_mm: np.ndarray = field(metadata={EXPORT: False})
    pin_xy_mm: np.ndarray = field(metadata={EXPORT: False})
    disc_centre_xy_mm: tuple[float, float] = field(metadata={EXPORT: False})
    gaps_um: np.ndarray = field(metadata={EXPORT: False})

    def rows(self) -> list[dict]:
        return [{k: v for k, v in d.to_dict().items()} | {
            "contact_pins_ccw": " ".join(map(str, d.contact_pins_ccw)),
            "contact_pins_cw": " ".join(map(str, d.contact_pins_cw))} for d in self.discs]

    def summary(self) -> list[str]:
        state = f"preloaded by {self.preload_um:.3f} um" if self.cycloid_stage_preloaded else \
            f"{self.cycloid_stage_arcmin:.4f} arcmin"
        return [f"{self.design_name}, {self.unit} at crank angle {self.crank_angle_deg:g} deg: cycloid stage {state}, "
                f"output lost motion {self.lost_motion_arcmin:.4f} arcmin"]


def disc_contacts(g: ContactGeometry, r: Realization, play: MeshPlay) -> tuple[DiscContact, ...]:
    out = []
    for d, disc in enumerate(play.discs):
        pins = {}
        for name, beta, sign in (("ccw", disc.play_ccw_rad, 1), ("cw", disc.play_cw_rad, -1)):
            if math.isnan(beta):  # this disc alone cannot be freed
                pins[name] = ()
                continue
            gp = exact_gaps_um(g, r, d, sign * beta)
            pins[name] = tuple(int(j) for j in np.nonzero(gp <= gp.min() + TIE_RAD * g.pitch_radius_um)[0])
        out.append(DiscContact(d + 1, disc.play_ccw_rad * ARCMIN_PER_RAD, disc.play_cw_rad * ARCMIN_PER_RAD,
                               pins["ccw"], pins["cw"]))
    return tuple(out)


def linear_stage_means(problem: Problem) -> tuple[dict[str, float], float]:
    """The involute and crank stages at their linear means, and the cycloid stage's linear mean [arcmin]."""
    sens, mu = problem.sensitivities_arcmin_per_um, problem.means_um
    other = {s.label: float(sens[problem.stage_mask(s)] @ mu[problem.stage_mask(s)])
             for s in (Stage.INVOLUTE, Stage.CRANK)}
    return other, float(sens[problem.stage_mask(Stage.CYCLOID)] @ mu[problem.stage_mask(Stage.CYCLOID)])


def unit_contact(problem: Problem, r: Realization, label: str, other_stages_arcmin: float | None = None) -> NominalContact:
    """The exact play of one unit (errors ``r``) and what the figure needs."""
    g = problem.cycloid
    play = exact_play(g, r)
    gaps = np.stack([exact_gaps_um(g, r, d) for d in range(g.discs)])
    other, cyc = linear_stage_means(problem)
    if other_stages_arcmin is not None:
        other = {"involute and crank (given)": float(other_stages_arcmin)}
    chi = r.chi_rad
    prof = profile_points(g.a_mm, g.rp_mm, g.rrp_mm, g.zc, float(r.moving_distance_um[0]), float(r.equidistance_um[0]))
    centre = g.a_mm * np.array([math.cos(chi), math.sin(chi)])
    prof = rotate(prof, -chi / g.zc) + centre
    psi = g.pin_angles
    stage = play.lost_motion_arcmin
    s2 = problem.design.second_stage
    return NominalContact(
        problem.name, label, math.degrees(chi), stage, play.preloaded, play.preload_um, play.total_arcmin,
        stage + sum(other.values()), cyc, other, disc_contacts(g, r, play), float(s2.equidistance_modification_um),
        float(s2.moving_distance_modification_um), float(np.mean(r.pin_clearance_um)),
        ASSUMPTIONS if label == "nominal" else ASSUMPTIONS_MEASURED, g, prof,
        g.rp_mm * np.stack([np.cos(psi), np.sin(psi)], axis=1), (float(centre[0]), float(centre[1])), gaps)


def nominal_contact(problem: Problem, crank_angle_deg: float = 0.0) -> NominalContact:
    """Play of the error-free design: nominal modifications and the pin/hole clearance at its zone mean."""
    g = problem.cycloid
    s2 = problem.design.second_stage
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    r = Realization.nominal(g, s2.equidistance_modification_um, s2.moving_distance_modification_um, clearance,
                            math.radians(crank_angle_deg))
    return unit_contact(problem, r, "nominal")


def unit_realization(problem: Problem, unit: MeasuredUnit, crank_angle_deg: float | None = None) -> Realization:
    """The errors of a measured unit as the contact model takes them; missing arrays are zeros
    (a missing hole clearance: zero clearance), modifications at the design's nominal values plus
    the unit's errors. The crank angle: ``crank_angle_deg``, else the unit's, else 0."""
    g = problem.cycloid
    s2 = problem.design.second_stage
    z = np.zeros(g.zp)

    def arr(v, n=g.zp):
        return np.array(v, dtype=float) if v is not None else np.zeros(n)

    p = unit.pins
    discs = unit.discs or []
    chi = crank_angle_deg if crank_angle_deg is not None else (unit.crank_angle_deg or 0.0)
    per = lambda name: np.array([getattr(d, name) for d in discs]) if discs else np.zeros(g.discs)  # noqa: E731
    crank = unit.crank_bearing_clearance_um
    involute = None
    if crank is not None and unit.other_stages_arcmin is not None:  # Eq. (1): other stages = involute + crank
        k = FACTOR_KEYS.index("crank_bearing_clearance")
        involute = max(unit.other_stages_arcmin - problem.sensitivities_arcmin_per_um[k] * crank, 0.0) / ARCMIN_PER_RAD
    return Realization(
        math.radians(chi), arr(p.radial_position_um), arr(p.tangential_position_um), arr(p.radius_um),
        arr(p.hole_clearance_um) if p.hole_clearance_um is not None else z.copy(),
        np.stack([arr(d.cumulative_pitch_um, g.zc) for d in discs]) if discs else np.zeros((g.discs, g.zc)),
        np.stack([arr(d.runout_um, 2) for d in discs]) if discs else np.zeros((g.discs, 2)),
        per("eccentricity_error_um"), s2.equidistance_modification_um + per("equidistance_error_um"),
        s2.moving_distance_modification_um + per("moving_distance_error_um"), crank_clearance_um=crank,
        involute_backlash_rad=involute, **kinematic_fields(unit))


def kinematic_fields(unit: MeasuredUnit) -> dict:
    """The transmission-error model's errors of a measured unit as Realization fields (None: zero)."""
    k = unit.kinematics
    return {"centre_gear_eccentricity_um": k.centre_gear_eccentricity_um, "planet_eccentricity_um":
            k.planet_eccentricity_um, "disc_crank_hole_um": k.disc_crank_holes_um,
            "carrier_crank_hole_um": k.carrier_crank_holes_um}


def measured_contact(problem: Problem, unit: MeasuredUnit, label: str = "measured unit",
                     crank_angle_deg: float | None = None) -> NominalContact:
    """Play of one measured unit from the exact geometry."""
    return unit_contact(problem, unit_realization(problem, unit, crank_angle_deg), label, unit.other_stages_arcmin)


def measured_units(problem: Problem, saved: tuple) -> list[MeasuredUnit]:
    """The units a Monte-Carlo run saved (SimulationResult.units) in the measured-unit format (with
    their kinematic errors when the run drew them: the transmission model)."""
    s2 = problem.design.second_stage
    out = []
    for r, linear_arcmin, stage in saved:
        out.append(MeasuredUnit(
            crank_angle_deg=math.degrees(r.chi_rad), cycloid_stage_arcmin=max(stage, 0.0),
            other_stages_arcmin=linear_arcmin, crank_bearing_clearance_um=r.crank_clearance_um,
            pins=MeasuredPins(radius_um=r.pin_radius_um.tolist(), radial_position_um=r.pin_radial_um.tolist(),
                              tangential_position_um=r.pin_tangential_um.tolist(),
                              hole_clearance_um=r.pin_clearance_um.tolist()),
            discs=[MeasuredDisc(cumulative_pitch_um=r.tooth_pitch_um[d].tolist(),
                                equidistance_error_um=float(r.equidistance_um[d] - s2.equidistance_modification_um),
                                moving_distance_error_um=float(r.moving_distance_um[d]
                                                               - s2.moving_distance_modification_um),
                                runout_um=r.runout_um[d].tolist(), eccentricity_error_um=float(r.eccentricity_error_um[d]))
                   for d in range(problem.cycloid.discs)],
            kinematics=MeasuredKinematics() if r.planet_eccentricity_um is None else MeasuredKinematics(
                centre_gear_eccentricity_um=np.asarray(r.centre_gear_eccentricity_um, float).tolist(),
                planet_eccentricity_um=np.asarray(r.planet_eccentricity_um, float).tolist(),
                carrier_crank_holes_um=np.asarray(r.carrier_crank_hole_um, float).tolist(),
                disc_crank_holes_um=np.asarray(r.disc_crank_hole_um, float).tolist())))
    return out
