"""The holes of a cycloid disc: its crank bores, the carrier pillars' holes and an optional centre
hole, as circles in the disc's frame [mm] (docs/rigidity-elements.md). Plain numbers in, circles out:
the design's checks (design/structure.py) and the disc's finite elements (mechanics/disc_body.py)
read the same layout.

Frame: the disc frame of geometry/cycloid.py (origin at the disc's centre, turned with the disc).
The holes stand where the carrier's cranks and pillars stand (geometry/carrier_layout.py, the one
placement the carrier's body reads too): crank k's bore on the crank circle a0 at 2 pi k / n_c, as
the carrier's crank seats in models/kinematics.py (``crank_fit``); pillar k's hole at
pi / lcm(n_c, n_p) + 2 pi k / n_p (rv80e: three pillars, 60 degrees from the cranks). Disc d's frame
is turned against the carrier by 2 pi d / (discs z_c) (its orientation is -chi_d / z_c): its holes
are at those angles plus that.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from rvbacklash.geometry.carrier_layout import crank_angle_rad, pillar_angle_rad


class Hole(NamedTuple):
    """A round hole through the disc: centre (x, y) and radius [mm] in the disc frame; ``field``
    names the design field that sets its size (errors), ``kind`` is crank_bore, pillar_hole or
    centre_hole."""

    x_mm: float
    y_mm: float
    radius_mm: float
    kind: str
    field: str


def crank_bore_diameter_mm(raceway_diameter_mm: float, roller_diameter_mm: float) -> float:
    """Bore of the disc around a crank's needle bearing: the needles run directly on the disc
    (the outer raceway is the bore), D_bore = D_e + 2 D_w [mm], D_e the inner raceway (the
    eccentric), D_w the needle diameter. Source: the bearing's geometry (a full complement or caged
    needle set without an outer ring, as in RV reducers). Validity: rollers of one size, no ring."""
    return raceway_diameter_mm + 2.0 * roller_diameter_mm


def pillar_hole_clearance_diameter_mm(pillar_width_mm: float, pillar_depth_mm: float, eccentricity_mm: float) -> float:
    """Smallest round hole that a pillar of section w x h passes through while the disc orbits it
    with the eccentricity a: D_min = sqrt(w^2 + h^2) + 2 a [mm] (the section's circumscribed
    circle swept by the orbit; the pillar is fixed in the carrier, the disc translates on a circle
    of radius a against it). Source: geometry. Validity: a rectangular section centred on the hole."""
    return math.hypot(pillar_width_mm, pillar_depth_mm) + 2.0 * eccentricity_mm


def disc_holes(cranks: int, crank_circle_radius_mm: float, bore_diameter_mm: float, bore_field: str,
               pillars: int, pillar_hole_radius_mm: float, pillar_hole_diameter_mm: float,
               centre_hole_diameter_mm: float | None = None, turn_rad: float = 0.0) -> tuple[Hole, ...]:
    """Every hole of one disc in its frame (module docstring): ``cranks`` bores of diameter
    ``bore_diameter_mm`` on the crank circle, ``pillars`` holes on their circle between the cranks,
    and the centre hole if given; all turned by ``turn_rad`` (disc d: 2 pi d / (discs z_c))."""
    holes = []
    for k in range(cranks):
        angle = turn_rad + crank_angle_rad(k, cranks)
        holes.append(Hole(crank_circle_radius_mm * math.cos(angle), crank_circle_radius_mm * math.sin(angle),
                          0.5 * bore_diameter_mm, "crank_bore", bore_field))
    for k in range(pillars):
        angle = turn_rad + pillar_angle_rad(k, cranks, pillars)
        holes.append(Hole(pillar_hole_radius_mm * math.cos(angle), pillar_hole_radius_mm * math.sin(angle),
                          0.5 * pillar_hole_diameter_mm, "pillar_hole", "structure.disc_pillar_hole_diameter_mm"))
    if centre_hole_diameter_mm is not None:
        holes.append(Hole(0.0, 0.0, 0.5 * centre_hole_diameter_mm, "centre_hole",
                          "structure.disc_centre_hole_diameter_mm"))
    return tuple(holes)
