"""Rounding rules of the gear accuracy standards."""

from __future__ import annotations

import math


def round_half_up(x: float, step: float) -> float:
    """Nearest multiple of ``step``, halves away from zero (x >= 0)."""
    return math.floor(x / step + 0.5 + 1e-9) * step


def round_iso1328_1(value_um: float) -> float:
    """ISO 1328-1:1995 and ISO 1328-1:2013 rounding: values above 10 um to the nearest
    1 um, from 5 to 10 um to the nearest 0.5 um, below 5 um to the nearest 0.1 um.
    Parameters: value_um [um] >= 0. Returns [um]."""
    if value_um > 10.0:
        return round_half_up(value_um, 1.0)
    if value_um >= 5.0:
        return round_half_up(value_um, 0.5)
    return round(round_half_up(value_um, 0.1), 1)


def round_iso1328_2(value_um: float) -> float:
    """ISO 1328-2:1997 (radial run-out table, Annex B): above 10 um to the nearest 1 um, up to
    10 um to the nearest 0.5 um (the printed run-out tables use 0.5 um steps down to grade 0,
    e.g. 1.5, 2.5, 3.0 for 5 <= d <= 20, 0.5 <= m <= 2). Parameters: value_um [um]."""
    if value_um > 10.0:
        return round_half_up(value_um, 1.0)
    return round_half_up(value_um, 0.5)
