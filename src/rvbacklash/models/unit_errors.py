"""One unit's part errors: the record every kernel reads (docs/architecture.md, "One unit's path").

A unit of a production run, or a unit measured on a CMM, is its parts' deviations from nominal.
Python code holds it as a ``Realization`` (a dataclass, with the crank angle of its measurement
and the parts only some models read); the compiled kernels take the same deviations as one
``UnitErrors`` record of contiguous float arrays. The sampler draws into a ``UnitErrors``, the
contact model's play, the elastic model's pin gaps and the transmission error's curve read it,
and a saved unit is written from it: one record, the same field names everywhere.

A batch of units (the transmission-error source's chunks, the saved units of a run) is a
``UnitErrors`` whose arrays have one more, leading axis: the unit (``unit_at``, ``store_unit``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from rvbacklash._numba import njit
from rvbacklash.geometry.cycloid import ContactGeometry


@dataclass
class Realization:
    """One set of errors [um] (angles [rad]); arrays per pin (z_p) and per disc."""

    chi_rad: float
    pin_radial_um: np.ndarray
    pin_tangential_um: np.ndarray
    pin_radius_um: np.ndarray
    pin_clearance_um: np.ndarray
    tooth_pitch_um: np.ndarray  # (discs, z_c): cumulative pitch error of each tooth space, arc at r_p
    runout_um: np.ndarray  # (discs, 2): profile-centre offset along / across the eccentric
    eccentricity_error_um: np.ndarray  # (discs,)
    equidistance_um: np.ndarray  # (discs,) total dr_rp of each disc
    moving_distance_um: np.ndarray  # (discs,) total dr_p of each disc
    # the rest of the unit, for the elastic model (None: the stage's nominal value)
    crank_clearance_um: float | None = None  # radial clearance of the crank needle bearings
    involute_backlash_rad: float | None = None  # the involute stage's backlash at the output, >= 0
    # the kinematic errors of the transmission-error model (models.kinematics; None: zero)
    centre_gear_eccentricity_um: np.ndarray | None = None  # (2,) in the centre gear's frame
    planet_eccentricity_um: np.ndarray | None = None  # (planets, 2) each in its planet's frame
    disc_crank_hole_um: np.ndarray | None = None  # (discs, planets, 2) hole position errors, disc frame
    carrier_crank_hole_um: np.ndarray | None = None  # (planets, 2) hole position errors, carrier frame

    @classmethod
    def nominal(cls, g: ContactGeometry, equidistance_um: float = 0.0, moving_distance_um: float = 0.0,
                clearance_um: float = 0.0, chi_rad: float = 0.0) -> "Realization":
        z = np.zeros(g.zp)
        return cls(chi_rad, z.copy(), z.copy(), z.copy(), np.full(g.zp, clearance_um),
                   np.zeros((g.discs, g.zc)), np.zeros((g.discs, 2)), np.zeros(g.discs),
                   np.full(g.discs, float(equidistance_um)), np.full(g.discs, float(moving_distance_um)))

    def with_(self, **changes) -> "Realization":
        return replace(self, **changes)


class UnitErrors(NamedTuple):
    """A unit's part errors as the compiled kernels read them [um] (``Realization``'s, one array
    per field; vectors (x, y) in the last axis). Per pin (z_p): its radial and tangential position,
    its radius, its hole's diametral clearance; per disc: every tooth space's cumulative pitch
    (discs, z_c), the modifications (each disc's total), the profile's run-out along and across
    the eccentric, the crank eccentricity error; the transmission-error model's: the centre gear's
    and each planet's eccentricity, the crank holes of each disc (discs, planets, 2) and of the
    carrier (planets, 2)."""

    pin_radial_um: np.ndarray
    pin_tangential_um: np.ndarray
    pin_radius_um: np.ndarray
    pin_clearance_um: np.ndarray
    tooth_pitch_um: np.ndarray
    equidistance_um: np.ndarray
    moving_distance_um: np.ndarray
    runout_along_um: np.ndarray
    runout_across_um: np.ndarray
    eccentricity_error_um: np.ndarray
    centre_gear_eccentricity_um: np.ndarray
    planet_eccentricity_um: np.ndarray
    disc_crank_hole_um: np.ndarray
    carrier_crank_hole_um: np.ndarray


def unit_errors(r: Realization, planets: int = 0) -> UnitErrors:
    """The record of a Realization (contiguous float arrays) with its kinematic errors for
    ``planets`` cranks (those it leaves out are zero); ``planets`` = 0 for the models that do not
    read them: none are kept, whatever the unit has."""
    discs = np.shape(r.tooth_pitch_um)[0]

    def arr(v) -> np.ndarray:  # writable too: a read-only array is another type to numba (a kernel compiled again)
        return np.require(np.asarray(v, dtype=float), requirements=("C", "W"))

    def kinematic(v, shape) -> np.ndarray:
        if v is None or planets == 0:
            return np.zeros(shape)
        return np.require(np.broadcast_to(np.asarray(v, dtype=float), shape), requirements=("C", "W"))

    runout = np.asarray(r.runout_um, dtype=float)
    return UnitErrors(
        pin_radial_um=arr(r.pin_radial_um), pin_tangential_um=arr(r.pin_tangential_um),
        pin_radius_um=arr(r.pin_radius_um), pin_clearance_um=arr(r.pin_clearance_um),
        tooth_pitch_um=arr(r.tooth_pitch_um), equidistance_um=arr(r.equidistance_um),
        moving_distance_um=arr(r.moving_distance_um), runout_along_um=arr(runout[:, 0]),
        runout_across_um=arr(runout[:, 1]), eccentricity_error_um=arr(r.eccentricity_error_um),
        centre_gear_eccentricity_um=kinematic(r.centre_gear_eccentricity_um, (2,)),
        planet_eccentricity_um=kinematic(r.planet_eccentricity_um, (planets, 2)),
        disc_crank_hole_um=kinematic(r.disc_crank_hole_um, (discs, planets, 2)),
        carrier_crank_hole_um=kinematic(r.carrier_crank_hole_um, (planets, 2)))


def empty_units(n: int, zp: int, zc: int, discs: int, planets: int) -> UnitErrors:
    """A batch of n units to draw into (``store_unit``)."""
    pins, per_disc = (lambda: np.empty((n, zp))), (lambda: np.empty((n, discs)))
    return UnitErrors(
        pin_radial_um=pins(), pin_tangential_um=pins(), pin_radius_um=pins(), pin_clearance_um=pins(),
        tooth_pitch_um=np.empty((n, discs, zc)), equidistance_um=per_disc(), moving_distance_um=per_disc(),
        runout_along_um=per_disc(), runout_across_um=per_disc(), eccentricity_error_um=per_disc(),
        centre_gear_eccentricity_um=np.empty((n, 2)), planet_eccentricity_um=np.empty((n, planets, 2)),
        disc_crank_hole_um=np.empty((n, discs, planets, 2)), carrier_crank_hole_um=np.empty((n, planets, 2)))


@njit(nogil=True, cache=True)
def empty_unit(zp, zc, discs, planets):
    """One unit's record to draw into."""
    return UnitErrors(np.empty(zp), np.empty(zp), np.empty(zp), np.empty(zp), np.empty((discs, zc)), np.empty(discs),
                      np.empty(discs), np.empty(discs), np.empty(discs), np.empty(discs), np.zeros(2),
                      np.zeros((planets, 2)), np.zeros((discs, planets, 2)), np.zeros((planets, 2)))


@njit(nogil=True, cache=True)
def unit_at(batch, s):
    """Unit s of a batch (views: writing to it writes to the batch)."""
    return UnitErrors(batch.pin_radial_um[s], batch.pin_tangential_um[s], batch.pin_radius_um[s],
                      batch.pin_clearance_um[s], batch.tooth_pitch_um[s], batch.equidistance_um[s],
                      batch.moving_distance_um[s], batch.runout_along_um[s], batch.runout_across_um[s],
                      batch.eccentricity_error_um[s], batch.centre_gear_eccentricity_um[s],
                      batch.planet_eccentricity_um[s], batch.disc_crank_hole_um[s], batch.carrier_crank_hole_um[s])


@njit(nogil=True, cache=True)
def with_disc_errors(unit, tooth_pitch_um, runout_along_um, runout_across_um):
    """``unit`` with other arrays for its discs' tooth pitch errors and run-outs (numba has no
    NamedTuple._replace)."""
    return UnitErrors(unit.pin_radial_um, unit.pin_tangential_um, unit.pin_radius_um, unit.pin_clearance_um,
                      tooth_pitch_um, unit.equidistance_um, unit.moving_distance_um, runout_along_um, runout_across_um,
                      unit.eccentricity_error_um, unit.centre_gear_eccentricity_um, unit.planet_eccentricity_um,
                      unit.disc_crank_hole_um, unit.carrier_crank_hole_um)


@njit(nogil=True, cache=True)
def _copy(to, values):
    """to <- values, element by element in C order (contiguous arrays of one shape; a plain loop
    compiles in a fraction of the time of numba's broadcasting slice assignment)."""
    t, v = to.reshape(to.size), values.reshape(values.size)
    for i in range(t.size):
        t[i] = v[i]


@njit(nogil=True, cache=True)
def store_unit(batch, s, unit):
    """Copy ``unit`` into unit s of ``batch``."""
    to = unit_at(batch, s)
    _copy(to.pin_radial_um, unit.pin_radial_um)
    _copy(to.pin_tangential_um, unit.pin_tangential_um)
    _copy(to.pin_radius_um, unit.pin_radius_um)
    _copy(to.pin_clearance_um, unit.pin_clearance_um)
    _copy(to.tooth_pitch_um, unit.tooth_pitch_um)
    _copy(to.equidistance_um, unit.equidistance_um)
    _copy(to.moving_distance_um, unit.moving_distance_um)
    _copy(to.runout_along_um, unit.runout_along_um)
    _copy(to.runout_across_um, unit.runout_across_um)
    _copy(to.eccentricity_error_um, unit.eccentricity_error_um)
    _copy(to.centre_gear_eccentricity_um, unit.centre_gear_eccentricity_um)
    _copy(to.planet_eccentricity_um, unit.planet_eccentricity_um)
    _copy(to.disc_crank_hole_um, unit.disc_crank_hole_um)
    _copy(to.carrier_crank_hole_um, unit.carrier_crank_hole_um)


def realization_at(batch: UnitErrors, s: int, chi_rad: float, **rest) -> Realization:
    """Unit s of a batch as a Realization (copies), at crank angle chi_rad; ``rest``: the
    Realization's other fields (e.g. crank_clearance_um)."""
    u = UnitErrors(*(np.array(a[s]) for a in batch))
    kinematic = u.planet_eccentricity_um.shape[0] > 0  # drawn (the transmission model's units)
    return Realization(
        chi_rad=chi_rad, pin_radial_um=u.pin_radial_um, pin_tangential_um=u.pin_tangential_um,
        pin_radius_um=u.pin_radius_um, pin_clearance_um=u.pin_clearance_um, tooth_pitch_um=u.tooth_pitch_um,
        runout_um=np.stack([u.runout_along_um, u.runout_across_um], axis=1),
        eccentricity_error_um=u.eccentricity_error_um, equidistance_um=u.equidistance_um,
        moving_distance_um=u.moving_distance_um,
        centre_gear_eccentricity_um=u.centre_gear_eccentricity_um if kinematic else None,
        planet_eccentricity_um=u.planet_eccentricity_um if kinematic else None,
        disc_crank_hole_um=u.disc_crank_hole_um if kinematic else None,
        carrier_crank_hole_um=u.carrier_crank_hole_um if kinematic else None, **rest)
