"""The nominal design through the exact contact geometry (``rvbacklash contact``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rvbacklash.factors.catalog import FACTOR_KEYS, Stage
from rvbacklash.geometry.cycloid import ContactGeometry, profile_points, rotate
from rvbacklash.models.contact import MeshPlay, Realization, exact_gaps_um, exact_play
from rvbacklash.problem import Problem
from rvbacklash.results import EXPORT, Result
from rvbacklash.units import ARCMIN_PER_RAD

TIE_RAD = 1e-9  # pins closer than this to the first contact count as touching together
ASSUMPTIONS = ("rigid bodies, no load; exact signed distances between profile and pins; no manufacturing errors; "
               "designed clearances (modifications, pin/hole fit) at their nominal values; involute and crank "
               "stages at their linear means")


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
    """Play of the error-free design from the exact cycloid-pin geometry at one crank angle."""

    design_name: str
    crank_angle_deg: float
    cycloid_stage_arcmin: float  # lost motion of the stage (0 when preloaded)
    cycloid_stage_preloaded: bool
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
        state = "preloaded" if self.cycloid_stage_preloaded else f"{self.cycloid_stage_arcmin:.4f} arcmin"
        return [f"{self.design_name} at crank angle {self.crank_angle_deg:g} deg: cycloid stage {state}, "
                f"output lost motion {self.lost_motion_arcmin:.4f} arcmin"]


def disc_contacts(g: ContactGeometry, r: Realization, play: MeshPlay) -> tuple[DiscContact, ...]:
    out = []
    for d, disc in enumerate(play.discs):
        pins = {}
        for name, beta, sign in (("ccw", disc.play_ccw_rad, 1), ("cw", disc.play_cw_rad, -1)):
            gp = exact_gaps_um(g, r, d, sign * beta)
            pins[name] = tuple(int(j) for j in np.nonzero(gp <= gp.min() + TIE_RAD * g.pitch_radius_um)[0])
        out.append(DiscContact(d + 1, disc.play_ccw_rad * ARCMIN_PER_RAD, disc.play_cw_rad * ARCMIN_PER_RAD,
                               pins["ccw"], pins["cw"]))
    return tuple(out)


def nominal_contact(problem: Problem, crank_angle_deg: float = 0.0) -> NominalContact:
    """Play of the error-free design: nominal modifications and the pin/hole clearance at its zone mean."""
    g = problem.cycloid
    s2 = problem.design.second_stage
    chi = math.radians(crank_angle_deg)
    clearance = float(problem.means_um[FACTOR_KEYS.index("pin_hole_clearance")])
    r = Realization.nominal(g, s2.equidistance_modification_um, s2.moving_distance_modification_um, clearance, chi)
    play = exact_play(g, r)
    gaps = np.stack([exact_gaps_um(g, r, d) for d in range(g.discs)])
    sens, mu = problem.sensitivities_arcmin_per_um, problem.means_um
    other = {s.label: float(sens[problem.stage_mask(s)] @ mu[problem.stage_mask(s)])
             for s in (Stage.INVOLUTE, Stage.CRANK)}
    cyc = float(sens[problem.stage_mask(Stage.CYCLOID)] @ mu[problem.stage_mask(Stage.CYCLOID)])
    prof = profile_points(g.a_mm, g.rp_mm, g.rrp_mm, g.zc, s2.moving_distance_modification_um,
                          s2.equidistance_modification_um)
    centre = g.a_mm * np.array([math.cos(chi), math.sin(chi)])
    prof = rotate(prof, -chi / g.zc) + centre
    psi = g.pin_angles
    stage = play.lost_motion_arcmin
    return NominalContact(
        problem.name, float(crank_angle_deg), stage, play.total_rad < 0, play.total_arcmin, stage + sum(other.values()),
        cyc, other, disc_contacts(g, r, play), float(s2.equidistance_modification_um),
        float(s2.moving_distance_modification_um), clearance, ASSUMPTIONS, g, prof,
        g.rp_mm * np.stack([np.cos(psi), np.sin(psi)], axis=1), (float(centre[0]), float(centre[1])), gaps)
