"""Catalog of the 21 error factors (Sun et al. 2014, Table 1; ids are the Table 2 numbering).

Each factor names its raw quantity (what a tolerance zone is given for), its stage, and its
transfer to circumferential backlash [um] at the stage's pitch circle (``transfers``).
Other parts of the package (model, sampling, standards, report) read this catalog; nothing
else lists the factors.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

import rvbacklash.factors.transfers as t
from rvbacklash.geometry.reducer import DerivedGeometry


class Stage(IntEnum):
    """Stage of Eq. (1): its backlash is referred to the output through its own radius."""

    INVOLUTE = 1  # centre gear / planet gears, radius i * r1
    CYCLOID = 2  # cycloid discs / pins, radius a * z_c
    CRANK = 3  # crankshaft bearings and eccentrics, radius a0

    @property
    def label(self) -> str:
        return {1: "involute", 2: "cycloid", 3: "crank"}[self.value]


Transfer = Callable[[ArrayLike, DerivedGeometry], np.ndarray]


@dataclass(frozen=True)
class Factor:
    """One error factor of Table 1.

    ``raw_quantity`` says what the tolerance zone [um] of the design file describes and its
    sign convention; ``transfer(x_um, geometry)`` gives circumferential backlash [um].
    """

    id: int
    key: str
    name: str
    stage: Stage
    symbol: str
    raw_quantity: str
    paper_table1: str
    transfer: Transfer
    # "signed": any sign; "magnitude": >= 0 by nature (misalignments, form, pin pitch);
    # "phase": a magnitude times the cosine of its phase at the mesh (run-outs, eccentricity);
    # "clearance": a fit's clearance. Decides which input distributions make sense.
    kind: str = "signed"

    def gain(self, geometry: DerivedGeometry) -> float:
        """d(backlash)/d(raw) [um/um]; every transfer is linear through zero."""
        return float(self.transfer(1.0, geometry))


S1, S2, S3 = Stage.INVOLUTE, Stage.CYCLOID, Stage.CRANK

CATALOG: tuple[Factor, ...] = (
    Factor(1, "base_tangent_length", "Deviation of base tangent length", S1, "dE_s",
           "base tangent length deviation; negative = thinner teeth",
           "-(E_ss + E_si) / (2 cos a)",
           lambda x, g: t.base_tangent_length_backlash_um(x, g.pressure_angle_deg)),
    Factor(2, "centre_distance", "Centre distance deviation", S1, "f_a",
           "deviation of the first-stage centre distance; positive = gears apart",
           "f_a tan a",
           lambda x, g: t.radial_shift_backlash_um(x, g.pressure_angle_deg)),
    Factor(3, "gear_runout", "Radial run-out of the gears", S1, "F_r",
           "radial run-out reading weighted by its phase at the mesh, F_r cos(theta), in [-F_r, F_r]",
           "F_r tan a",
           lambda x, g: t.gear_runout_backlash_um(x, g.pressure_angle_deg),
           kind="phase"),
    Factor(4, "axis_parallelism_x", "Axis parallelism, in plane (x)", S1, "f_x",
           "in-plane axis parallelism deviation over the face width (magnitude)",
           "(1/2) f_x tan a",
           lambda x, g: t.axis_parallelism_in_plane_backlash_um(x, g.pressure_angle_deg),
           kind="magnitude"),
    Factor(5, "axis_parallelism_y", "Axis parallelism, out of plane (y)", S1, "f_y",
           "out-of-plane axis parallelism deviation over the face width (magnitude)",
           "(1/2) f_y",
           lambda x, g: t.axis_parallelism_out_of_plane_backlash_um(x),
           kind="magnitude"),
    Factor(6, "tooth_profile", "Tooth profile deviation", S1, "f_f",
           "profile form deviation (magnitude, normal to the flank)",
           "f_f / cos a",
           lambda x, g: t.profile_backlash_um(x, g.pressure_angle_deg),
           kind="magnitude"),
    Factor(7, "single_pitch", "Single pitch deviation", S1, "f_pt",
           "single pitch deviation at the reference circle (paper: 'cumulative pitch error')",
           "f_pt",
           lambda x, g: t.circumferential_backlash_um(x)),
    Factor(8, "tooth_alignment", "Tooth alignment (helix) deviation", S1, "f_beta",
           "helix deviation in the transverse direction",
           "f_beta",
           lambda x, g: t.circumferential_backlash_um(x)),
    Factor(9, "bearing_eccentricity", "Eccentricity of the rolling bearing", S1, "e_g",
           "radial eccentricity of the gear's bearing, signed by its phase at the mesh",
           "2 e_g tan a",
           lambda x, g: t.radial_shift_backlash_um(x, g.pressure_angle_deg),
           kind="phase"),
    Factor(10, "disc_cumulative_pitch", "Total cumulative pitch deviation of the cycloid disc", S2, "F_p",
           "cumulative pitch deviation of the disc teeth, referred to the pin circle",
           "F_p K1",
           lambda x, g: t.pitch_circle_tangential_backlash_um(x, g.k1)),
    Factor(11, "equidistance_modification", "Equidistance modification", S2, "dr_rp",
           "equidistance modification of the disc profile; positive = thinner teeth",
           "2 dr_rp",
           lambda x, g: t.equidistance_modification_backlash_um(x)),
    Factor(12, "moving_distance_modification", "Moving-distance modification", S2, "dr_p",
           "moving-distance modification of the disc profile; positive = teeth moved out (tighter)",
           "-2 dr_p sqrt(1 - K1^2)",
           lambda x, g: t.moving_distance_modification_backlash_um(x, g.k1)),
    Factor(13, "disc_runout", "Radial run-out of the cycloid disc", S2, "F_r",
           "disc run-out reading weighted by its phase, F_r cos(theta), in [-F_r, F_r]",
           "F_r / 4",
           lambda x, g: t.disc_runout_backlash_um(x),
           kind="phase"),
    Factor(14, "pin_circle_radius", "Pin-circle radius deviation", S2, "dr_p",
           "deviation of the housing's pin-circle radius; positive = pins further out",
           "dr_p sqrt(1 - K1^2)",
           lambda x, g: t.moving_distance_modification_backlash_um(-np.asarray(x, float), g.k1)),
    Factor(15, "pin_radius", "Pin radius deviation", S2, "dr_rp",
           "deviation of the pin radius; positive = larger pins (tighter)",
           "dr_rp",
           lambda x, g: t.equidistance_modification_backlash_um(-np.asarray(x, float))),
    Factor(16, "pin_hole_clearance", "Clearance fit of the pins in their holes", S2, "c_j",
           "diametral clearance between pin and housing hole",
           "(d_jmax - d_jmin) / 2",
           lambda x, g: t.clearance_backlash_um(x),
           kind="clearance"),
    Factor(17, "pin_cumulative_pitch", "Total cumulative pitch deviation of the pins", S2, "F_p",
           "cumulative pitch deviation of the pins on the pin circle (magnitude)",
           "F_p K1 / 2",
           lambda x, g: t.pitch_circle_tangential_backlash_um(x, g.k1),
           kind="magnitude"),
    Factor(18, "equidistance_modification_error", "Equidistance modification error", S2, "d(dr_rp)",
           "manufacturing error of the equidistance modification; positive = thinner teeth",
           "d(dr_rp)",
           lambda x, g: t.equidistance_modification_backlash_um(x)),
    Factor(19, "moving_distance_modification_error", "Moving-distance modification error", S2, "d(dr_p)",
           "manufacturing error of the moving-distance modification; positive = tighter",
           "d(dr_p) sqrt(1 - K1^2)",
           lambda x, g: t.moving_distance_modification_backlash_um(x, g.k1)),
    Factor(20, "crank_bearing_clearance", "Clearance of the crankshaft bearings", S3, "du",
           "radial clearance of the crankshaft bearings",
           "(du_max - du_min) / 2",
           lambda x, g: t.clearance_backlash_um(x),
           kind="clearance"),
    Factor(21, "crank_eccentricity", "Eccentricity error of the crankshaft", S3, "da",
           "deviation of the crank eccentricity from a",
           "2 k_n da",
           lambda x, g: t.crank_eccentricity_backlash_um(x, g.crank_eccentricity_coefficient)),
)

FACTOR_KEYS: tuple[str, ...] = tuple(f.key for f in CATALOG)
_BY_KEY = {f.key: f for f in CATALOG}


def factor_by_key(key: str) -> Factor:
    """The catalog entry for ``key``; KeyError names the allowed keys."""
    try:
        return _BY_KEY[key]
    except KeyError:
        raise KeyError(f"unknown factor {key!r}; allowed: {', '.join(FACTOR_KEYS)}") from None


@dataclass(frozen=True)
class KinematicFactor:
    """An error that only the kinematic (transmission-error) model reads: a 2-D position error of
    an element, drawn as an isotropic normal vector whose length stays within the zone's radius
    (``problem.kinematic_errors``). Not part of Table 2's 21 factors: the linear model and its
    paper reproduction do not see it. ``default`` says where its zone comes from when the design
    gives none."""

    key: str
    name: str
    symbol: str
    group: str  # error group of the transmission-error shares (analysis.transmission.GROUPS)
    raw_quantity: str
    default: str


KINEMATIC_FACTORS: tuple[KinematicFactor, ...] = (
    KinematicFactor("centre_gear_eccentricity", "Eccentricity of the centre gear", "e_1", "involute stage",
                    "offset of the centre gear's pitch circle from its axis [um]; zone = its largest length",
                    "F_r / 2 of gear_runout (factor 3): a run-out F_r is twice the eccentricity (ISO 1328-2)"),
    KinematicFactor("planet_eccentricity", "Eccentricity of each planet gear on its crankshaft", "e_2",
                    "involute stage",
                    "offset of a planet's pitch circle from its crankshaft's axis [um]; zone = its largest length",
                    "F_r / 2 of gear_runout (factor 3), as the centre gear"),
    KinematicFactor("disc_crank_hole_position", "Position of the crank holes in the cycloid discs", "t_h",
                    "crank holes",
                    "position tolerance (diameter of the zone, ISO 1101) of each crank hole of a disc [um]",
                    "10 um (ASSUMPTION: jig-bored holes of a precision disc, IT5-class at this size; "
                    "docs/transmission-error.md)"),
    KinematicFactor("carrier_crank_hole_position", "Position of the crank holes in the carrier", "t_c",
                    "crank holes",
                    "position tolerance (diameter of the zone, ISO 1101) of each crankshaft bearing seat of the "
                    "carrier [um]",
                    "10 um (ASSUMPTION, as the disc holes)"),
)
KINEMATIC_KEYS: tuple[str, ...] = tuple(f.key for f in KINEMATIC_FACTORS)
