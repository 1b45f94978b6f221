"""Derived geometry of an RV reducer, one function per formula.

Symbols follow Sun et al. 2014 (the reference paper, ``../shared/reference``): z1 centre
gear, z2 planet gear, z_c cycloid disc, z_p pins, m module, a eccentricity, r_p pin-circle
radius, a0 crank-circle radius.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass


def reduction_ratio(z1: int, z2: int, zp: int) -> float:
    """Overall ratio of an RV reducer with fixed pin housing, output on the carrier.

    i = 1 + z_p * z2 / z1

    Source: standard 2K-V kinematics (Willis equation of the first stage combined with
    the cycloid stage, disc orientation tied to the carrier); the ``i_16^5`` of Sun et
    al. 2014, Eq. (1).

    Parameters: z1 centre-gear teeth [-], z2 planet teeth [-], zp pins [-].
    Returns: ratio input/output [-]. Validity: z1, z2, zp >= 1.
    Example: RV-80E, z1=10, z2=38, zp=40 -> 153.
    """
    return 1.0 + zp * z2 / z1


def pitch_radius_mm(module_mm: float, teeth: int) -> float:
    """Reference (pitch) radius of a spur gear, r = m * z / 2.

    Source: ISO 21771:2007, 4.3 (reference diameter d = m_n z / cos beta, beta = 0).
    Parameters: module_mm [mm], teeth [-]. Returns [mm]. Validity: spur gears.
    """
    return module_mm * teeth / 2.0


def centre_distance_mm(module_mm: float, z1: int, z2: int) -> float:
    """Reference centre distance of an external spur pair, a = m (z1 + z2) / 2.

    In an RV reducer the planet gears sit on the crankshafts, so this is also the
    crank-circle radius a0 of Eq. (1) when the pair has no profile shift.

    Source: ISO 21771:2007, 5.2 (zero-shift pair). Parameters: module_mm [mm], z1, z2 [-].
    Returns [mm]. Example: m=1.75, z1=10, z2=38 -> 42 mm.
    """
    return module_mm * (z1 + z2) / 2.0


def short_amplitude_coefficient(eccentricity_mm: float, zp: int, pin_circle_radius_mm: float) -> float:
    """Short-amplitude (curtate) coefficient of the cycloid, K1 = a * z_p / r_p.

    Source: Sun et al. 2014, Tables 1 and 3 (K1); standard cycloid-drive theory.
    Parameters: eccentricity_mm a [mm], zp [-], pin_circle_radius_mm r_p [mm].
    Returns K1 [-]. Validity: 0 < K1 < 1 (a curtate epicycloid; K1 >= 1 gives a looped,
    unusable profile). Example: a=1.5, zp=40, r_p=77.5 -> 0.7742.
    """
    return eccentricity_mm * zp / pin_circle_radius_mm


def cycloid_pitch_radius_mm(eccentricity_mm: float, zc: int) -> float:
    """Pitch (rolling) circle radius of the cycloid disc, r_c' = a * z_c.

    The disc's rotational play at its critical contact (cos phi = K1, see docs/model.md)
    acts at this lever arm, hence the a z_c of Eq. (1).

    Source: Sun et al. 2014, Eq. (1). Parameters: eccentricity_mm [mm], zc [-]. Returns [mm].
    """
    return eccentricity_mm * zc


def pin_gap_mm(pin_circle_radius_mm: float, pin_radius_mm: float, zp: int) -> float:
    """Free space between neighbouring pins, 2 r_p sin(pi / z_p) - 2 r_rp.

    Validity check only: the pins must not overlap (result > 0).
    Parameters: pin_circle_radius_mm [mm], pin_radius_mm [mm], zp [-]. Returns [mm].
    """
    return 2.0 * pin_circle_radius_mm * math.sin(math.pi / zp) - 2.0 * pin_radius_mm


@dataclass(frozen=True)
class DerivedGeometry:
    """Everything the transfers and Eq. (1) need, in the units of the field names."""

    ratio: float
    K1: float
    centre_gear_pitch_radius_mm: float
    planet_pitch_radius_mm: float
    centre_distance_mm: float
    cycloid_pitch_radius_mm: float
    crank_circle_radius_mm: float
    crank_circle_radius_is_default: bool
    pressure_angle_deg: float
    crank_eccentricity_coefficient: float

    @property
    def k1(self) -> float:
        return self.K1

    def to_dict(self) -> dict:
        return asdict(self)
