"""Tolerances of the cycloid stage from a grade: a documented ASSUMPTION, not a standard.

The paper takes cycloid-stage tolerances from JB/T 10419-2005 (cycloid pin-wheel reducers);
no public text of it is available. rvbacklash therefore reads the disc and the pin wheel as
gears of an *equivalent module* and applies ISO 1328-1 at their pitch diameters, and ISO 286
to the radii and fits. Every output that uses this mapping says so. Override any factor with
an explicit zone when the supplier's data are known.
"""

from __future__ import annotations

ASSUMPTION = "assumption (no public JB/T 10419-2005): cycloid as a gear of equivalent module 2 r_p / z_p"


def equivalent_module_mm(pin_circle_radius_mm: float, pins: int) -> float:
    """m_c = 2 r_p / z_p [mm]: the module of a gear with z_p teeth on the pin circle.
    Parameters: pin_circle_radius_mm r_p [mm], pins z_p [-]. Example: 2*77.5/40 = 3.875 mm."""
    return 2.0 * pin_circle_radius_mm / pins


def disc_pitch_diameter_mm(pin_circle_radius_mm: float, pins: int, cycloid_teeth: int) -> float:
    """d_c = m_c z_c [mm]: the disc's equivalent pitch diameter (2 r_p z_c / z_p).
    Example: 3.875 * 39 = 151.1 mm."""
    return equivalent_module_mm(pin_circle_radius_mm, pins) * cycloid_teeth
