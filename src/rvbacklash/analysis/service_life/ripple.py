"""The nominal unit's transmission error over its service life (docs/service-life.md, "Transmission
error over the life"): the rigid, unloaded flank curve of the worn unit, from its pins' gaps and levers
as the contact model gives them (``worn.worn_unit``: the flank wear along the tooth at each pin's
phase, the pins' and seats' wear at the normal's direction), over one pin pitch of the crank angle.

The nominal unit's teeth all wear alike (the wear is averaged over the teeth and pins), so its flank
curve repeats every pin pitch of chi: its peak-to-peak over one pitch is the whole revolution's. Each
flank's output position is the edge of the free interval every pin allows (``models.contact.
free_interval_bounds``: the first pin to close on that side, linearised at the assembled position);
at 0 h it is the transmission-error model's own ripple of the error-free unit
(``TransmissionErrorResult.nominal_ripple_arcsec``: 0.0707 against 0.0701 arcsec for rv80e; tested within 2 %). The ripple is the
modifications' (an equidistance and a moving-distance modification tilt the flank against the
conjugate one): a uniform wear w is w more equidistance modification and changes it as that
modification does (tested against the TE model of that design); wear that varies along the tooth
changes it further.
"""

from __future__ import annotations

import math

import numpy as np

from rvbacklash.analysis.service_life.rates import WearGeometry, WearIncrement
from rvbacklash.analysis.service_life.results import LifeRipple
from rvbacklash.analysis.service_life.worn import worn_unit
from rvbacklash.models.contact import PinGaps, free_interval_bounds
from rvbacklash.models.elastic import nominal_realization, other_stages_nominal
from rvbacklash.problem import Problem
from rvbacklash.units import ARCMIN_PER_RAD

RIPPLE_ANGLES = 64  # crank angles over one pin pitch


def worn_ripple(problem: Problem, hours: float, wear: WearIncrement, geo: WearGeometry,
                angles: int = RIPPLE_ANGLES) -> LifeRipple:
    """The LifeRipple of the nominal unit after ``wear`` (module docstring)."""
    inv, clr = other_stages_nominal(problem)
    g = problem.cycloid
    chis = 2.0 * math.pi / g.zp * (np.arange(angles) + 0.5) / angles
    ccw = np.empty(angles)
    cw = np.empty(angles)
    for i, chi in enumerate(chis):
        u = worn_unit(problem, nominal_realization(problem, float(chi)), inv, clr, wear, geo)
        lo, hi, _ = free_interval_bounds(PinGaps(u.gap_um, u.lever_um_per_rad), g.stage_geometry.pitch_radius_um)
        ccw[i], cw[i] = hi, lo
    to_arcsec = 60.0 * ARCMIN_PER_RAD
    return LifeRipple(float(hours), float((ccw.max() - ccw.min()) * to_arcsec),
                      float((cw.max() - cw.min()) * to_arcsec), float((ccw - cw).mean() * ARCMIN_PER_RAD))
