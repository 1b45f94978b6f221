"""Where the carrier's cranks and pillars stand: one placement for every part that reads it (the
carrier's finite-element body, mechanics/carrier_mesh.py; the discs' crank bores and pillar holes,
geometry/disc_holes.py; the design's checks, design/structure.py), so that every pillar passes
through its holes in the discs (issue 36: the discs and the carrier once placed the pillars by two
formulas that agreed only for as many pillars as cranks).

Angles [rad] about the reducer's axis in the carrier's frame, crank 0 at angle 0.
"""

from __future__ import annotations

import math


def crank_angle_rad(k: int, cranks: int) -> float:
    """Crank k of ``cranks`` equally spaced on the crank circle: 2 pi k / n_c [rad] (the carrier's
    crank seats, ``models.kinematics.crank_fit``'s holes)."""
    return 2.0 * math.pi * k / cranks


def pillar_angle_rad(k: int, cranks: int, pillars: int) -> float:
    """Pillar k of ``pillars`` equally spaced, turned as far from the cranks as equal spacing allows:

        phi_k = pi / lcm(n_c, n_p) + 2 pi k / n_p   [rad]

    Source: ours (geometry). The angles between a pillar and a crank, 2 pi (k / n_p - j / n_c) +
    phi_0, are phi_0 plus the multiples of 2 pi / lcm(n_c, n_p); their smallest magnitude is largest,
    pi / lcm, for phi_0 = pi / lcm. So pillars sit midway between cranks when n_p = n_c (rv80e:
    60 degrees from them), on both sides of each crank when n_p is a multiple of n_c (2 cranks, 4
    pillars: 45, 135, 225, 315 degrees; 3 and 6: 30 degrees either side), and never on a crank.
    Written 2 pi (k + n_p / (2 lcm)) / n_p: for n_p a multiple of n_c the carrier's 2 pi (k + 1/2) / n_p
    to the bit (its sector's cut through the pillars, and so its mesh, are as before).
    Validity: n_c, n_p >= 1."""
    return 2.0 * math.pi * (k + 0.5 * pillars / math.lcm(cranks, pillars)) / pillars


def pillar_angles_rad(cranks: int, pillars: int) -> tuple[float, ...]:
    """Every pillar's angle (``pillar_angle_rad``) [rad]."""
    return tuple(pillar_angle_rad(k, cranks, pillars) for k in range(pillars))


def crank_angles_rad(cranks: int) -> tuple[float, ...]:
    """Every crank's angle (``crank_angle_rad``) [rad]."""
    return tuple(crank_angle_rad(k, cranks) for k in range(cranks))
