"""Each unit's own wear in the production run (docs/service-life.md, "The production run").

The nominal unit's trajectory (``stepping``) gives, at each time step, every contact's wear from
the nominal loads. A unit's own loads differ: its part deviations close some pins first, its discs
share the torque unequally, its run-outs and modifications move the load along the tooth. Each unit
is followed step by step with a first-order correction of the nominal wear by its own loads:

1. at the step's start its pins are solved at its own crank angle, on its own worn gaps, at each of
   the cycle's torques (``models.elastic.unit_loads``), and so are the nominal unit's at the same
   crank angle with the nominal wear (the nominal part of every unit's wear, ``worn.worn_gaps_um``);
2. the difference of the forces, pin by pin, weighed by each torque's revolutions per hour of the
   cycle, is the unit's excess load at its pins' phases; linear between the pins' phases (z_p places
   per disc), it is the excess of its load profile along the tooth;
3. that excess profile is worn into the flanks, the pins and their seats by the nominal unit's own
   formulas (``profile_wear``: Archard's law with each place's sliding, the same as
   ``rates.wear_per_revolution``), over the step's equivalent hours, and read at the unit's pins
   (flank at each pin's phase, seat at its normal's direction; ``growth_at_pins``). Compiled:
   ``models.wear_kernel.pins_growth_um`` with ``profile_tables``, the same arithmetic.

The unit's wear is then the nominal wear plus this correction: a unit without deviations has none
(its forces are the nominal's, bit for bit), and the whole is linear in the wear coefficients. What
it leaves out: a pin's own deviation is read as a deviation of the tooth place it meets (one crank
angle cannot tell them apart; the full stepping averages over 12), the needle bearings' clearance
grows as the nominal's. Checked against each unit's full stepping at 12 crank angles
(``stepping.nominal_trajectory(..., realization=...)``) on a handful of units
(tests/analysis/test_service_life_units.py).
"""

from __future__ import annotations

import math

import numpy as np

from rvbacklash.analysis.service_life.rates import DIRECTION_BINS, PHASE_BINS, WearGeometry
from rvbacklash.analysis.service_life.stepping import Trajectory
from rvbacklash.analysis.service_life.worn import worn_gaps_um
from rvbacklash.models import wear as wr
from rvbacklash.models.elastic import ElasticUnit, nominal_realization, other_stages_nominal, unit_from_realization
from rvbacklash.models.elastic.unit_loads import pin_forces_n
from rvbacklash.models.wear_kernel import ProfileTables, pins_growth_um
from rvbacklash.problem import Problem

TWO_PI = 2.0 * math.pi


def profile_wear(q_n_per_mm: np.ndarray, geo: WearGeometry) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Wear depths [um] per output revolution of a load profile q (..., discs, PHASE_BINS) [N/mm]
    (``rates.wear_per_revolution``'s formulas, vectorised; q may be negative: a correction):
    (flank (..., discs, PHASE_BINS), pin (..., discs) round a turning pin, pin_local and seat
    (..., discs, DIRECTION_BINS))."""
    rho = geo.inputs.pin_rolling_fraction
    flank = geo.zp * wr.pass_depth_um(geo.k_flank, q_n_per_mm, (1.0 - rho) * geo.sliding_per_phase_mm
                                      / geo.flank_arc_per_phase_mm)
    dphi = TWO_PI / PHASE_BINS
    slide = geo.zc * q_n_per_mm * geo.sliding_per_phase_mm * dphi
    widths = geo.pin_radius_mm * np.diff(geo.direction_edges_rad)
    binning = np.zeros((PHASE_BINS, DIRECTION_BINS))
    binning[np.arange(PHASE_BINS), geo.direction_bin] = 1.0
    v_pin = geo.k_flank * 1e-3 * (1.0 - rho) * slide
    v_seat = geo.k_seat * 1e-3 * rho * slide
    seat = (v_seat @ binning) / widths * 1e3
    if rho > 0.0:
        pin = v_pin.sum(axis=-1) / (TWO_PI * geo.pin_radius_mm) * 1e3
        local = np.zeros_like(seat)
    else:
        pin = np.zeros(q_n_per_mm.shape[:-1])
        local = (v_pin @ binning) / widths * 1e3
    return flank, pin, local, seat


def profile_tables(geo: WearGeometry) -> ProfileTables:
    """The ProfileTables of a WearGeometry: ``profile_wear``'s weights per unit load at each place."""
    rho = geo.inputs.pin_rolling_fraction
    dphi = TWO_PI / PHASE_BINS
    slide = geo.zc * geo.sliding_per_phase_mm * dphi
    flank = geo.zp * geo.k_flank * (1.0 - rho) * geo.sliding_per_phase_mm / geo.flank_arc_per_phase_mm
    pin = geo.k_flank * (1.0 - rho) * slide / (TWO_PI * geo.pin_radius_mm) if rho > 0.0 else np.zeros(PHASE_BINS)
    seat = (geo.k_seat * rho + (geo.k_flank * (1.0 - rho) if rho == 0.0 else 0.0)) * slide
    return ProfileTables(np.ascontiguousarray(geo.phase_rad), np.ascontiguousarray(flank), np.ascontiguousarray(pin),
                         np.ascontiguousarray(seat), np.ascontiguousarray(geo.direction_bin, dtype=np.int64),
                         geo.pin_radius_mm * np.diff(geo.direction_edges_rad),
                         np.ascontiguousarray(geo.direction_centres_rad), float(geo.k1))


def _phases(chi_rad: np.ndarray, geo: WearGeometry) -> np.ndarray:
    """(n, discs, z_p): phi = psi_j - chi - 2 pi d / discs of every pin, in [0, 2 pi)."""
    psi = TWO_PI * np.arange(geo.zp) / geo.zp
    chi_d = np.asarray(chi_rad, float)[:, None] + TWO_PI * np.arange(geo.discs)[None, :] / geo.discs
    return np.mod(psi[None, None, :] - chi_d[:, :, None], TWO_PI)


def samples_to_grid(values: np.ndarray, chi_rad: np.ndarray, geo: WearGeometry) -> np.ndarray:
    """(n, discs, PHASE_BINS): values (n, discs, z_p) given at every pin's phase, linear between the
    pins' phases (periodic), at the grid's phases."""
    n = values.shape[0]
    pitch = TWO_PI / geo.zp
    # pin j's phase is j pitch + c, c = -chi - 2 pi d / discs: place s = (phi - c) / pitch on the pins' row
    c = -(np.asarray(chi_rad, float)[:, None] + TWO_PI * np.arange(geo.discs)[None, :] / geo.discs)
    s = (geo.phase_rad[None, None, :] - c[:, :, None]) / pitch
    lo = np.floor(s)
    w = s - lo
    j0 = np.mod(lo.astype(np.int64), geo.zp)
    j1 = np.mod(j0 + 1, geo.zp)
    a = np.take_along_axis(values, j0.reshape(n, geo.discs, -1), axis=2)
    b = np.take_along_axis(values, j1.reshape(n, geo.discs, -1), axis=2)
    return (1.0 - w) * a + w * b


def _interp_rows(grid: np.ndarray, values: np.ndarray, x: np.ndarray, period: float | None) -> np.ndarray:
    """values (n, discs, G) on the uniform increasing grid (G,), at x (n, discs, m): linear (periodic
    with ``period``, else clamped to the ends)."""
    step = grid[1] - grid[0]
    s = (x - grid[0]) / step
    if period is not None:
        lo = np.floor(s)
        w = s - lo
        i0 = np.mod(lo.astype(np.int64), grid.size)
        i1 = np.mod(i0 + 1, grid.size)
    else:
        s = np.clip(s, 0.0, grid.size - 1.0)
        i0 = np.minimum(np.floor(s).astype(np.int64), grid.size - 2)
        w = s - i0
        i1 = i0 + 1
    return (1.0 - w) * np.take_along_axis(values, i0, axis=2) + w * np.take_along_axis(values, i1, axis=2)


def growth_at_pins(flank: np.ndarray, pin: np.ndarray, local: np.ndarray, chi_rad: np.ndarray,
                   geo: WearGeometry) -> np.ndarray:
    """(n, discs, z_p): every pin's gap growth [um] from wear depths of n units (flank (n, discs,
    PHASE_BINS), pin (n, discs), pin_local + seat (n, discs, DIRECTION_BINS)) at its phase and its
    normal's direction (``rates.flank_wear_at``, ``rates.pin_wear_at``, vectorised)."""
    phases = _phases(chi_rad, geo)
    out = _interp_rows(geo.phase_rad, flank, phases, TWO_PI) + pin[:, :, None]
    theta = wr.contact_direction_rad(phases, geo.k1)
    return out + _interp_rows(geo.direction_centres_rad, local, theta, None)


class NominalAtAngles:
    """The nominal unit's pins at any crank angle (the production run's units' angles), without wear:
    its ElasticUnit there (``models.elastic.unit_from_realization``), kept per angle."""

    def __init__(self, problem: Problem):
        self.problem = problem
        self.inv, self.clr = other_stages_nominal(problem)
        self._units: dict[float, tuple[np.ndarray, np.ndarray]] = {}

    def batch(self, chi_rad: np.ndarray):
        """An ElasticUnit batch of the nominal unit at each crank angle chi_rad (n,) [rad]."""
        for chi in chi_rad:
            key = float(chi)
            if key not in self._units:
                u = unit_from_realization(self.problem, nominal_realization(self.problem, key), self.inv, self.clr)
                self._units[key] = (u.gap_um, u.lever_um_per_rad)
        n = np.size(chi_rad)
        return ElasticUnit(np.array([self._units[float(c)][0] for c in chi_rad]),
                           np.array([self._units[float(c)][1] for c in chi_rad]), np.asarray(chi_rad, float),
                           np.full(n, self.inv), np.full(n, self.clr))


def own_wear_correction(worn, nominal_forces_n: np.ndarray, design, trajectory: Trajectory, k: int) -> np.ndarray:
    """(n, discs, z_p): the gap growth [um] over step k of the units ``worn`` (their gaps at the
    step's start) beyond the nominal unit's wear (module docstring); ``nominal_forces_n`` (n, T, discs,
    z_p): the nominal unit's pins' forces at the same crank angles with the nominal wear, at the
    cycle's torques (``Trajectory.torque_revolutions``); ``design``: the step's LoopDesign."""
    geo = trajectory.geometry
    torques = np.array([t for t, _ in trajectory.torque_revolutions])
    revs = np.array([r for _, r in trajectory.torque_revolutions])
    if torques.size == 0:
        return np.zeros_like(worn.gap_um)
    excess = pin_forces_n(worn, design, torques) - nominal_forces_n  # (n, T, discs, zp)
    per_hour = np.ascontiguousarray(np.tensordot(revs, excess, axes=(0, 1)) / geo.contact_length_mm)
    out = np.zeros_like(worn.gap_um)
    pins_growth_um(per_hour, np.ascontiguousarray(worn.chi_rad, float), profile_tables(geo),
                   float(trajectory.step_equivalent_h[k]), out)
    return out


def worn_units(chunk, trajectory: Trajectory, designs, nominal: NominalAtAngles | None = None):
    """Each time k of the trajectory: (k, the units of ``chunk`` (an ElasticUnit batch) with their wear
    to that time): the nominal unit's wear and, with ``nominal`` (the nominal unit's pins at the units'
    angles), each unit's own correction step by step (module docstring); without it, the nominal
    unit's wear as it is. The nominal unit's forces are solved once per distinct crank angle (a
    production run draws its units' angles from CRANK_STEPS per pin pitch)."""
    geo = trajectory.geometry
    extra = np.zeros_like(chunk.gap_um)
    if nominal is not None:
        angles, index = np.unique(chunk.chi_rad, return_inverse=True)
        base = nominal.batch(angles)
        torques = np.array([t for t, _ in trajectory.torque_revolutions])
    for k, wear in enumerate(trajectory.wear):
        nominal_growth = worn_gaps_um(wear, geo, chunk.chi_rad)
        clearance = chunk.crank_clearance_um + wear.clearance_um
        worn = chunk._replace(gap_um=np.ascontiguousarray(chunk.gap_um + nominal_growth + extra),
                              crank_clearance_um=clearance)
        yield k, worn
        if nominal is not None and k < len(trajectory.step_equivalent_h):
            ref = base._replace(gap_um=np.ascontiguousarray(base.gap_um + worn_gaps_um(wear, geo, angles)))
            forces = pin_forces_n(ref, designs[k], torques)[index]
            extra = extra + own_wear_correction(worn, forces, designs[k], trajectory, k)
