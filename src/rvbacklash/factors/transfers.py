"""Transfers from a raw error quantity to circumferential backlash, one function per formula.

Every transfer returns the *total* circumferential backlash (both directions of rotation
together, i.e. lost motion) at the pitch circle of its stage, in [um], for a raw quantity in
[um]. All are linear and pass through zero, so each factor's gain is ``transfer(1)``.
The derivations are in ``docs/model.md``; where a formula differs from the paper's Table 1
the reason is in ``docs/paper-errata.md``.

Functions accept floats or numpy arrays (element-wise).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike


def _arr(x: ArrayLike) -> np.ndarray:
    return np.asarray(x, dtype=float)


# --- first stage: involute spur mesh --------------------------------------------------------

def base_tangent_length_backlash_um(deviation_um: ArrayLike, pressure_angle_deg: float):
    """Backlash from the base tangent length deviation, j = -dE_s / cos(alpha).

    A base tangent length (span) deviation dE_s is a thinning (dE_s < 0) of the teeth
    measured along the base tangent, i.e. along the line of action. Circumferential
    (transverse, at the reference circle) backlash is the normal one over cos(alpha).

    Source: Sun et al. 2014, Eq. (3) and Table 1 row 1; ISO/TR 10064-2:1996, 4.2
    (j_wt = j_bn / (cos alpha_wt cos beta_b)).
    Parameters: deviation_um dE_s [um], negative = thinner teeth; pressure_angle_deg alpha
    [deg]. Returns j [um], > 0 for thinned teeth. Validity: spur gears, 0 < alpha < 45 deg.
    """
    return -_arr(deviation_um) / math.cos(math.radians(pressure_angle_deg))


def radial_shift_backlash_um(shift_um: ArrayLike, pressure_angle_deg: float):
    """Backlash from a radial shift of the mesh (centre distance), j = 2 dr tan(alpha).

    Moving two involute gears apart by dr opens the normal backlash by 2 dr sin(alpha)
    (both flanks), i.e. 2 dr tan(alpha) circumferentially. Used for the centre-distance
    deviation (row 2) and the bearing eccentricity e_g (row 9, ``2 e_g tan alpha``).

    Source: ISO/TR 10064-2:1996, 4.3 (j_r = j_bn / (2 sin alpha)); Sun et al. 2014, Table 1
    row 9 and Table 3 rows 2-3 (the factor 2).
    Parameters: shift_um dr [um], positive = apart; pressure_angle_deg [deg].
    Returns j [um]. Validity: small shifts (dr << module), spur gears.
    """
    return 2.0 * _arr(shift_um) * math.tan(math.radians(pressure_angle_deg))


def gear_runout_backlash_um(runout_um: ArrayLike, pressure_angle_deg: float):
    """Backlash from radial run-out, j = F_r tan(alpha).

    The run-out F_r is a total indicator reading, twice the eccentricity e. At the mesh,
    the eccentricity shows as a radial shift e cos(theta) = (F_r / 2) cos(theta) of phase
    theta, hence j = 2 (F_r/2) cos(theta) tan(alpha). The raw quantity is the signed,
    phase-weighted reading x = F_r cos(theta) in [-F_r, F_r].

    Source: Sun et al. 2014, Table 1 row 3; ISO 1328-2:1997 (F_r definition).
    Parameters: runout_um x [um]; pressure_angle_deg [deg]. Returns j [um].
    """
    return radial_shift_backlash_um(0.5 * _arr(runout_um), pressure_angle_deg)


def axis_parallelism_in_plane_backlash_um(deviation_um: ArrayLike, pressure_angle_deg: float):
    """Backlash from the in-plane axis parallelism deviation f_x, j = f_x tan(alpha).

    An in-plane (x) misalignment f_x over the face width displaces the mesh radially by
    +-f_x/2 at the two face ends, i.e. up to 2 (f_x / 2) tan(alpha) circumferentially.
    The raw quantity is a magnitude in [0, f_x]; its mean gives the paper's (1/2) f_x tan(alpha).

    Source: Sun et al. 2014, Table 1 row 4 (mean), Table 3 row 4 (gain tan alpha);
    ISO/TR 10064-3:1996 (f_Sigma_delta, in-plane deviation).
    Parameters: deviation_um [um] >= 0; pressure_angle_deg [deg]. Returns j [um].
    """
    return _arr(deviation_um) * math.tan(math.radians(pressure_angle_deg))


def axis_parallelism_out_of_plane_backlash_um(deviation_um: ArrayLike):
    """Backlash from the out-of-plane axis parallelism deviation f_y, j = f_y.

    An out-of-plane (y) misalignment displaces the mesh tangentially by +-f_y/2 at the face
    ends: 2 (f_y / 2) circumferentially, no tan(alpha) because the displacement is already
    along the pitch circle. Raw quantity is a magnitude in [0, f_y].

    Source: Sun et al. 2014, Table 1 row 5 (mean (1/2) f_y), Table 3 row 5 (gain 1);
    ISO/TR 10064-3:1996 (f_Sigma_beta).
    Parameters: deviation_um [um] >= 0. Returns j [um].
    """
    return _arr(deviation_um)


def profile_backlash_um(deviation_um: ArrayLike, pressure_angle_deg: float):
    """Backlash from the tooth profile (form) deviation, j = 2 f_f / cos(alpha).

    The profile form deviation f_f is measured normal to the flank; material missing on the
    drive flank and on the coast flank each open the normal gap, hence 2 f_f, and /cos(alpha)
    converts normal to circumferential. Raw quantity in [0, f_f].

    Source: Sun et al. 2014, Table 3 row 6 (gain 2 / cos alpha); Table 1 row 6 and Table 2
    row 6 print the mean f_f / cos(alpha) of a zone [0, f_f].
    Parameters: deviation_um [um] >= 0; pressure_angle_deg [deg]. Returns j [um].
    """
    return 2.0 * _arr(deviation_um) / math.cos(math.radians(pressure_angle_deg))


def circumferential_backlash_um(deviation_um: ArrayLike):
    """Backlash from a deviation already measured along the pitch circle, j = x.

    Single pitch deviation f_pt and helix (tooth alignment) deviation f_beta are measured
    in the transverse plane along the reference circle; they move the contact
    circumferentially one for one.

    Source: Sun et al. 2014, Table 1 rows 7, 8; ISO 1328-1:1995, 3.1.1 and 3.3.
    Parameters: deviation_um [um]. Returns j [um].
    """
    return _arr(deviation_um)


# --- second stage: cycloid-pin mesh (critical contact at cos(phi) = K1, docs/model.md) ------

def equidistance_modification_backlash_um(modification_um: ArrayLike):
    """Backlash from an equidistance modification (or pin-radius change), j = 2 dr_rp.

    An equidistance modification dr_rp (disc generated by a pin of radius r_rp + dr_rp,
    positive = thinner teeth) opens a uniform normal gap dr_rp at every pin. The disc turns
    until the pin with the largest lever arm touches; the lever arm is at most a z_c (at
    cos(phi) = K1), so the play is dr_rp/(a z_c) each way, 2 dr_rp/(a z_c) in all: 2 dr_rp
    at the radius a z_c of Eq. (1). A pin smaller by d has the same effect as +d here.

    Source: Sun et al. 2014, Table 1 row 11; the play of modified cycloid profiles, e.g.
    Blanche & Yang, J. Mech. Trans. Autom. Des. 111 (1989) 337.
    Parameters: modification_um [um]. Returns j [um] at the disc pitch circle.
    """
    return 2.0 * _arr(modification_um)


def moving_distance_modification_backlash_um(modification_um: ArrayLike, k1: float):
    """Backlash from a moving-distance modification, j = -2 dr_p sqrt(1 - K1^2).

    The disc is generated with the pin circle at r_p + dr_p (positive = teeth moved out =
    less clearance). At pin phase phi the normal gap is -dr_p (1 - K1 cos phi) / sqrt(S),
    S = 1 + K1^2 - 2 K1 cos phi; divided by the lever arm a z_c sin(phi)/sqrt(S) and
    minimised over phi it gives -dr_p sqrt(1 - K1^2) / (a z_c) each way. A pin circle larger
    by d in the housing has the effect of a moving distance -d.

    Source: Sun et al. 2014, Table 1 row 12 (sign convention kept).
    Parameters: modification_um dr_p [um]; k1 K1 [-], 0 < K1 < 1. Returns j [um].
    """
    return -2.0 * _arr(modification_um) * math.sqrt(1.0 - k1 * k1)


def pitch_circle_tangential_backlash_um(deviation_um: ArrayLike, k1: float):
    """Backlash from a tangential position error at the pin circle, j = K1 x.

    A tangential displacement x of a pin (radius r_p) moves it along the contact normal by
    x times the normal's lever arm about the housing axis over r_p, K1 sin(phi)/sqrt(S),
    which equals K1 at the critical contact cos(phi) = K1. Used for the cumulative pitch
    deviation of the pins (row 17) and of the disc teeth (row 10, referred to the pin circle).

    Source: Sun et al. 2014, Table 1 rows 10 and 17.
    Parameters: deviation_um [um]; k1 K1 [-]. Returns j [um].
    """
    return k1 * _arr(deviation_um)


def disc_runout_backlash_um(runout_um: ArrayLike):
    """Backlash from the cycloid disc's radial run-out, j = F_r / 4.

    Run-out F_r = 2 e (profile centre offset e). Its radial component along the contact
    normal vanishes at the critical pin (cos phi = K1, docs/model.md); the paper's factor
    1/4 on the signed, phase-weighted reading x = F_r cos(theta) is kept and checked by the
    contact model.

    Source: Sun et al. 2014, Table 1 row 13 and Table 2 row 13.
    Parameters: runout_um x [um] in [-F_r, F_r]. Returns j [um].
    """
    return 0.25 * _arr(runout_um)


def clearance_backlash_um(clearance_um: ArrayLike):
    """Backlash from a diametral clearance, j = c.

    A part sitting with diametral clearance c can shift c/2 each way along the direction of
    the force: c in all. Used for the pin in its housing hole (row 16) and the crankshaft
    bearings (row 20).

    Source: Sun et al. 2014, Table 1 rows 16, 20 (Table 3 gains 1).
    Parameters: clearance_um c [um] >= 0. Returns j [um].
    """
    return _arr(clearance_um)


def crank_eccentricity_backlash_um(deviation_um: ArrayLike, transfer_coefficient: float):
    """Backlash from the crank eccentricity error, j = 2 k_n da.

    A common eccentricity error da moves the disc centre radially along the line of
    centres; that direction is perpendicular to the contact normal at the critical pin
    ((cos phi - K1)/sqrt(S) = 0), so its first-order effect vanishes and only a small
    fraction k_n remains (the paper's Table 3 weight implies k_n of order 1e-4).

    Source: Sun et al. 2014, Table 1 row 21.
    Parameters: deviation_um da [um]; transfer_coefficient k_n [-], 0 <= k_n <= 1.
    Returns j [um] at the crank circle.
    """
    return 2.0 * transfer_coefficient * _arr(deviation_um)
