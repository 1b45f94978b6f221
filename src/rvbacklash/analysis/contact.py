"""The nominal design through the exact contact geometry (`rvbacklash contact`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.analysis.stackup import analyze
from rvbacklash.design.derived import resolve_zones
from rvbacklash.design.schema import Design
from rvbacklash.factors.catalog import FACTOR_KEYS, Stage
from rvbacklash.model.contact import ContactGeometry, MeshPlay, Realization, exact_gaps_um, exact_play
from rvbacklash.sampling.distributions import input_moments

TIE_RAD = 1e-9  # pins closer than this to the first contact count as touching together


@dataclass
class NominalContact:
    design_name: str
    geometry: ContactGeometry
    realization: Realization
    play: MeshPlay
    contact_pins: list[dict]  # per disc: {"ccw": [...], "cw": [...]}
    gaps_um: np.ndarray  # (discs, z_p) gaps at zero rotation
    stage_means_arcmin: dict  # involute and crank stages at their means (linear)
    linear_cycloid_mean_arcmin: float

    @property
    def cycloid_arcmin(self) -> float:
        return self.play.lost_motion_arcmin

    @property
    def preloaded(self) -> bool:
        return self.play.total_rad < 0

    @property
    def lost_motion_arcmin(self) -> float:
        return self.cycloid_arcmin + sum(self.stage_means_arcmin.values())

    def to_dict(self) -> dict:
        return {
            "design": self.design_name,
            "crank_angle_deg": math.degrees(self.realization.chi_rad),
            "lost_motion_arcmin": self.lost_motion_arcmin,
            "cycloid_stage_arcmin": self.cycloid_arcmin,
            "cycloid_stage_preloaded": self.preloaded,
            "linear_cycloid_stage_mean_arcmin": self.linear_cycloid_mean_arcmin,
            "other_stages_mean_arcmin": self.stage_means_arcmin,
            "play_ccw_rad": self.play.play_ccw_rad,
            "play_cw_rad": self.play.play_cw_rad,
            "discs": [{"play_cw_rad": d.play_cw_rad, "play_ccw_rad": d.play_ccw_rad,
                       "contact_pins_cw": pins["cw"], "contact_pins_ccw": pins["ccw"]}
                      for d, pins in zip(self.play.discs, self.contact_pins)],
            "inputs": {"equidistance_modification_um": float(self.realization.equidistance_um[0]),
                       "moving_distance_modification_um": float(self.realization.moving_distance_um[0]),
                       "pin_hole_clearance_um": float(self.realization.pin_clearance_um[0])},
            "assumptions": "rigid bodies, no load; exact signed distances between profile and pins; no "
                           "manufacturing errors; designed clearances (modifications, pin/hole fit) at their "
                           "nominal values; involute and crank stages at their linear means",
        }


def nominal_contact(design: Design, chi_rad: float = 0.0) -> NominalContact:
    """Play of the error-free design: nominal modifications and the pin/hole clearance at its zone mean."""
    g = ContactGeometry.from_design(design)
    zones = resolve_zones(design)
    means, _ = input_moments(zones)
    s2 = design.second_stage
    clearance = float(means[FACTOR_KEYS.index("pin_hole_clearance")])
    r = Realization.nominal(g, s2.equidistance_modification_um, s2.moving_distance_modification_um, clearance, chi_rad)
    play = exact_play(g, r)
    pins = []
    gaps = np.stack([exact_gaps_um(g, r, d) for d in range(g.discs)])
    for d, disc in enumerate(play.discs):
        entry = {}
        for name, beta, sign in (("ccw", disc.play_ccw_rad, 1), ("cw", disc.play_cw_rad, -1)):
            gp = exact_gaps_um(g, r, d, sign * beta)
            entry[name] = [int(j) for j in np.nonzero(gp <= gp.min() + TIE_RAD * g.a_mm * g.zc * 1e3)[0]]
        pins.append(entry)
    stack = analyze(design)
    stage_means = {s.label: stack.stages[s.label].mean_arcmin for s in (Stage.INVOLUTE, Stage.CRANK)}
    cyc = stack.stages["cycloid"].mean_arcmin
    return NominalContact(design.name, g, r, play, pins, gaps, stage_means, cyc)
