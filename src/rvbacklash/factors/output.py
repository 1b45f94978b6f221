"""Eq. (1)/(2) of Sun et al. 2014: circumferential backlash of a stage -> output angle."""

from __future__ import annotations

from rvbacklash.geometry.reducer import DerivedGeometry
from rvbacklash.factors.catalog import Stage
from rvbacklash.units import ARCMIN_PER_RAD, MM_PER_UM


def output_angle_arcmin_per_um(radius_mm: float, ratio: float = 1.0) -> float:
    """Output angle of 1 um of circumferential backlash at radius r behind ratio i.

    dphi = (180 * 60 / pi) * j / (i * r), with j in [um] and r in [mm] (factor 1e-3).

    Source: Sun et al. 2014, Eq. (1).
    Parameters: radius_mm r [mm] > 0; ratio i [-] > 0 between that radius's shaft and the
    output. Returns [arcmin/um]. Validity: small angles (j << r).
    """
    return ARCMIN_PER_RAD * MM_PER_UM / (ratio * radius_mm)


def stage_coefficient_arcmin_per_um(stage: Stage, g: DerivedGeometry) -> float:
    """The three coefficients of Eq. (1)/(2).

    involute: 10800 / (pi i r1); cycloid: 10800 / (pi a z_c); crank: 10800 / (pi a0), each
    times 1e-3 for j in [um] and lengths in [mm]. Source: Sun et al. 2014, Eq. (1)-(2).
    Returns [arcmin/um].
    """
    if stage is Stage.INVOLUTE:
        return output_angle_arcmin_per_um(g.centre_gear_pitch_radius_mm, g.ratio)
    if stage is Stage.CYCLOID:
        return output_angle_arcmin_per_um(g.cycloid_pitch_radius_mm)
    return output_angle_arcmin_per_um(g.crank_circle_radius_mm)
