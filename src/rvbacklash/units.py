"""Unit constants. Lengths of geometry are in [mm], tolerances and backlash in [um],
angles at the output in [arcmin]."""

import math

ARCMIN_PER_RAD = 10800.0 / math.pi  # 180 * 60 / pi, the "180 x 60 / pi" of Eq. (1)
MM_PER_UM = 1e-3
UM_PER_MM = 1e3

# Units as field names spell them -> as people write them (reports, tables, figures)
DISPLAY = {"arcmin": "arcmin", "um": "µm", "mm": "mm", "nm": "N·m", "nm_per_arcmin": "N·m/arcmin", "h": "h",
           "mpa": "MPa"}


def display_unit(unit: str) -> str:
    """A unit as printed (``nm_per_arcmin`` -> ``N·m/arcmin``), never a field-name suffix."""
    return DISPLAY.get(unit, unit.replace("_per_", "/").replace("_", " "))
