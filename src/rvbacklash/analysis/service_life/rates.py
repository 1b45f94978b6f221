"""Wear rates of one unit at one output torque, contact by contact (docs/service-life.md): from the
elastic solution's loads over a crank revolution (``analysis.capacity.revolution``) and each
contact's sliding (``models.wear``), the wear depth per output revolution

- of each disc's flank, as a function of the position along the tooth (the phase phi of the pin
  that meets it: PHASE_BINS places over both flanks of a tooth), averaged over the teeth and pins;
- of each pin where it meets the flanks (spread round the pin when it turns in its seat, else at
  the direction of the contact normal) and of its seat in the housing's groove (at the direction of
  the normal: DIRECTION_BINS places), per disc (each disc bears on its own stretch of pin and seat);
- of the crank needle bearings' raceways and needles, as the growth of their radial clearance.

How each sliding is obtained:

- *flank on pin*: relative to the pins the disc turns about the pitch point P (models.wear.
  flank_sliding_per_phase_mm), |v_rel| = |omega| |P P_c|; the pin's turning takes up
  ``pin_rolling_fraction`` rho of it: the flank slides (1 - rho) |v_rel|;
- *pin in its seat*: the pin's surface turns against its groove at rho |v_rel|;
- *needles*: their rolling distance per revolution of the rings against each other
  (models.wear.needle_rolling_per_revolution_mm) times ``needle_slip_fraction``; the rings turn z_p
  times per output revolution against each other (the cranks against the carrier).

Per output revolution every pin meets every tooth once (z_p passes over each tooth point), and
every pin's stretch on a disc meets every phase z_c times.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rvbacklash.analysis.capacity.revolution import RevolutionLoads
from rvbacklash.design.wear import WearInputs
from rvbacklash.models import wear as wr
from rvbacklash.models.elastic import ElasticModel
from rvbacklash.problem import Problem

PHASE_BINS = 720  # places along a tooth (both flanks) where the flank's wear depth is kept
DIRECTION_BINS = 90  # directions of the contact normal at a pin (its seat and, if it does not turn, its surface)


@dataclass(frozen=True, eq=False)
class WearGeometry:
    """What the wear rates read of a design, once: the phase grid along a tooth and each place's
    flank arc and sliding, the direction bins at a pin, the needle bearings' sizes, the wear
    coefficients k [mm^3/(N m)]."""

    zp: int
    zc: int
    discs: int
    k1: float
    pin_radius_mm: float
    contact_length_mm: float  # one pin on one disc
    phase_rad: np.ndarray  # (PHASE_BINS,) bin centres over [0, 2 pi)
    flank_arc_per_phase_mm: np.ndarray  # (PHASE_BINS,)
    sliding_per_phase_mm: np.ndarray  # (PHASE_BINS,) relative sliding of flank and pin, non-turning pin
    direction_rad: np.ndarray  # (PHASE_BINS,) the contact normal's direction at each phase
    direction_edges_rad: np.ndarray  # (DIRECTION_BINS + 1,)
    raceway_diameter_mm: float
    roller_diameter_mm: float
    roller_length_mm: float
    rollers: int
    k_flank: float
    k_seat: float
    k_needle: float
    inputs: WearInputs

    @property
    def direction_bin(self) -> np.ndarray:
        """(PHASE_BINS,) the direction bin of each phase."""
        return np.clip(np.searchsorted(self.direction_edges_rad, self.direction_rad) - 1, 0, DIRECTION_BINS - 1)

    @property
    def direction_centres_rad(self) -> np.ndarray:
        e = self.direction_edges_rad
        return 0.5 * (e[1:] + e[:-1])


def wear_geometry(problem: Problem, model: ElasticModel, inputs: WearInputs | None = None) -> WearGeometry:
    """The WearGeometry of a design's elastic model (``inputs``: the [wear] table; None: the design's)."""
    w = inputs or problem.design.wear
    g, c = model.geometry, model.chain
    phase = (np.arange(PHASE_BINS) + 0.5) * 2.0 * math.pi / PHASE_BINS
    arc = wr.flank_arc_per_phase_mm(phase, g.rp_mm, g.K1, float(g.zp), float(g.zc), c.generating_radius_mm)
    slide = wr.flank_sliding_per_phase_mm(phase, g.rp_mm, g.K1, g.rrp_mm, float(g.zc))
    limit = math.asin(min(g.K1, 1.0))
    e = model.inputs
    return WearGeometry(int(g.zp), int(g.zc), int(g.discs), float(g.K1), float(g.rrp_mm), float(c.contact_length_mm),
                        phase, np.maximum(arc, 1e-9), slide, wr.contact_direction_rad(phase, g.K1),
                        np.linspace(-limit, limit, DIRECTION_BINS + 1), float(model.raceway_diameter_mm),
                        float(e.crank_bearing_roller_diameter_mm), float(e.crank_bearing_roller_length_mm),
                        int(e.crank_bearing_rollers), wr.dimensional_wear_coefficient(w.flank_wear_coefficient,
                                                                                      w.hardness_hv),
                        wr.dimensional_wear_coefficient(w.seat_wear_coefficient, w.hardness_hv),
                        wr.dimensional_wear_coefficient(w.needle_wear_coefficient, w.hardness_hv), w)


@dataclass(frozen=True, eq=False)
class WearIncrement:
    """Wear depths [um] (per output revolution, or accumulated: ``WearState``): each disc's flank at
    each phase, each disc's pin stretch uniformly (a turning pin) and at each direction (a pin that
    does not turn), each disc's seat at each direction, the needle bearings' clearance growth (the
    mean and the largest over the bearings) and their inner raceway, outer raceway and needle depths."""

    flank_um: np.ndarray  # (discs, PHASE_BINS)
    pin_um: np.ndarray  # (discs,)
    pin_local_um: np.ndarray  # (discs, DIRECTION_BINS)
    seat_um: np.ndarray  # (discs, DIRECTION_BINS)
    clearance_um: float
    clearance_max_um: float
    needle_depths_um: np.ndarray  # (3,) inner, outer, needle (the mean bearing)

    def scaled(self, factor: float) -> "WearIncrement":
        return WearIncrement(self.flank_um * factor, self.pin_um * factor, self.pin_local_um * factor,
                             self.seat_um * factor, self.clearance_um * factor, self.clearance_max_um * factor,
                             self.needle_depths_um * factor)

    def plus(self, other: "WearIncrement") -> "WearIncrement":
        return WearIncrement(self.flank_um + other.flank_um, self.pin_um + other.pin_um,
                             self.pin_local_um + other.pin_local_um, self.seat_um + other.seat_um,
                             self.clearance_um + other.clearance_um, self.clearance_max_um + other.clearance_max_um,
                             self.needle_depths_um + other.needle_depths_um)

    def largest_depth_um(self) -> float:
        """The largest wear depth of any contact (the time step's bound reads it)."""
        return float(max(self.flank_um.max(initial=0.0), self.pin_um.max(initial=0.0),
                         (self.pin_local_um + self.seat_um).max(initial=0.0), self.clearance_max_um))

    @classmethod
    def zero(cls, discs: int) -> "WearIncrement":
        return cls(np.zeros((discs, PHASE_BINS)), np.zeros(discs), np.zeros((discs, DIRECTION_BINS)),
                   np.zeros((discs, DIRECTION_BINS)), 0.0, 0.0, np.zeros(3))


def pin_force_by_phase(loads: RevolutionLoads, geo: WearGeometry) -> np.ndarray:
    """(discs, PHASE_BINS): the pins' normal force [N] at each phase of the grid, from the loads'
    samples (every pin at every crank angle, phi = psi_j - chi_d), mean over the pins met at one
    phase, linear between phases (periodic)."""
    forces = loads.pin_force_n  # (K, discs, z_p)
    k_n, discs, zp = forces.shape
    out = np.empty((discs, PHASE_BINS))
    psi = 2.0 * math.pi * np.arange(zp) / zp
    for d in range(discs):
        chi_d = loads.crank_angle_rad[:, None] + 2.0 * math.pi * d / discs
        phi = np.mod(psi[None, :] - chi_d, 2.0 * math.pi).ravel()
        f = forces[:, d, :].ravel()
        key = np.round(phi, 9)
        uniq, inv = np.unique(key, return_inverse=True)
        mean = np.bincount(inv, weights=f) / np.bincount(inv)
        out[d] = np.interp(geo.phase_rad, uniq, mean, period=2.0 * math.pi)
    return out


def wear_per_revolution(loads: RevolutionLoads, geo: WearGeometry) -> WearIncrement:
    """Every contact's wear depth [um] per output revolution at the loads' torque with the steady
    coefficients (module docstring)."""
    rho = geo.inputs.pin_rolling_fraction
    q = pin_force_by_phase(loads, geo) / geo.contact_length_mm  # (discs, PHASE_BINS) [N/mm]
    # flank: z_p passes over each tooth point per output revolution (models.wear.pass_depth_um)
    flank = geo.zp * wr.pass_depth_um(geo.k_flank, q, (1.0 - rho) * geo.sliding_per_phase_mm
                                      / geo.flank_arc_per_phase_mm)
    # pins and seats: each stretch meets every phase z_c times; its wear volume per unit length is
    # k q ds (ds the sliding over a phase bin), laid on the surface where the normal points
    dphi = 2.0 * math.pi / PHASE_BINS
    slide = geo.zc * q * geo.sliding_per_phase_mm * dphi  # (discs, PHASE_BINS) [N/mm x mm]
    discs = q.shape[0]
    widths = geo.pin_radius_mm * np.diff(geo.direction_edges_rad)  # [mm] of pin (and seat) surface per bin
    bins = geo.direction_bin
    pin = np.zeros(discs)
    pin_local = np.zeros((discs, DIRECTION_BINS))
    seat = np.zeros((discs, DIRECTION_BINS))
    for d in range(discs):
        v_pin = geo.k_flank * 1e-3 * (1.0 - rho) * slide[d]  # [mm^3/mm] per phase bin (k per mm of sliding)
        v_seat = geo.k_seat * 1e-3 * rho * slide[d]
        if rho > 0.0:  # a turning pin spreads its wear round its circumference
            pin[d] = v_pin.sum() / (2.0 * math.pi * geo.pin_radius_mm) * 1e3
        else:
            pin_local[d] = np.bincount(bins, weights=v_pin, minlength=DIRECTION_BINS) / widths * 1e3
        seat[d] = np.bincount(bins, weights=v_seat, minlength=DIRECTION_BINS) / widths * 1e3
    # needles: sum of the needles' loads per bearing, mean over the crank angles
    sum_q = loads.crank_bearing_roller_load_n.sum(axis=-1).mean(axis=0)  # (discs, cranks) [N]
    sliding_m = geo.inputs.needle_slip_fraction * wr.needle_rolling_per_revolution_mm(
        geo.raceway_diameter_mm, geo.roller_diameter_mm) * 1e-3 * geo.zp  # per output revolution [m]
    volume = geo.k_needle * sum_q * sliding_m  # per raceway [mm^3]
    d_i, big_d, length = geo.raceway_diameter_mm, geo.roller_diameter_mm, geo.roller_length_mm
    inner = volume / (math.pi * d_i * length) * 1e3
    outer = volume / (math.pi * (d_i + 2.0 * big_d) * length) * 1e3
    roller = 2.0 * volume / geo.rollers / (math.pi * big_d * length) * 1e3  # both contacts of each needle
    growth = wr.clearance_growth_um(inner, outer, roller)
    return WearIncrement(flank, pin, pin_local, seat, float(growth.mean()), float(growth.max()),
                         np.array([inner.mean(), outer.mean(), roller.mean()]))


def pin_wear_at(state: WearIncrement, geo: WearGeometry, phase_rad: np.ndarray) -> np.ndarray:
    """The gap's growth [um] at pins of the given phases (discs, n) from the pins' and seats' wear
    (uniform, and at the direction of the normal at each phase)."""
    theta = wr.contact_direction_rad(np.mod(phase_rad, 2.0 * math.pi), geo.k1)
    centres = geo.direction_centres_rad
    out = np.empty(np.shape(phase_rad))
    for d in range(out.shape[0]):
        local = state.pin_local_um[d] + state.seat_um[d]
        out[d] = state.pin_um[d] + np.interp(theta[d], centres, local)
    return out


def flank_wear_at(flank_um: np.ndarray, geo: WearGeometry, phase_rad: np.ndarray) -> np.ndarray:
    """Each disc's flank wear [um] at the given phases (discs, n): linear between the grid's places
    (periodic)."""
    out = np.empty(np.shape(phase_rad))
    for d in range(out.shape[0]):
        out[d] = np.interp(np.mod(phase_rad[d], 2.0 * math.pi), geo.phase_rad, flank_um[d], period=2.0 * math.pi)
    return out
