"""ISO 286 limits and fits: standard tolerance grades IT1..IT12 and the fundamental
deviations needed for the pin/hole and crank-bearing fits, sizes up to 500 mm.

The lookup uses the standard's tables (``data/iso286-1_2010_it.csv``,
``data/iso286-2_2010_shaft_deviations.csv``): ISO 286 rounds its formula values by rules of
its own, so the tables are the data and the formulas below are what tests hold them to.
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass

from rvbacklash.errors import InputError
from rvbacklash.standards.tables import read_table

IT_TABLE = "iso286-1_2010_it.csv"
SHAFT_TABLE = "iso286-2_2010_shaft_deviations.csv"
MAX_SIZE_MM = 500.0
IT_GRADES = range(1, 13)
SHAFT_LETTERS = ("f", "g", "h", "js", "k", "m", "n", "p")
HOLE_LETTERS = ("F", "G", "H", "JS")


def _step(size_mm: float, option: str) -> dict[str, str]:
    if not (isinstance(size_mm, (int, float)) and math.isfinite(size_mm) and 0 < size_mm <= MAX_SIZE_MM):
        raise InputError(option, size_mm, f"ISO 286-1 tables here cover 0 < size <= {MAX_SIZE_MM:g} mm")
    for row in read_table(IT_TABLE):
        if float(row["over_mm"]) < size_mm <= float(row["to_mm"]):
            return row
    raise AssertionError("unreachable")


def size_step_mm(size_mm: float) -> tuple[float, float]:
    """(over, to) of the ISO 286-1 nominal size step holding ``size_mm`` [mm]."""
    row = _step(size_mm, "size_mm")
    return float(row["over_mm"]), float(row["to_mm"])


def step_geometric_mean_mm(over_mm: float, to_mm: float) -> float:
    """D = sqrt(over * to), with over = 1 for the first step (ISO 286-1, calculation of the
    standard tolerances). [mm]"""
    return math.sqrt(max(over_mm, 1.0) * to_mm)


def standard_tolerance_factor_um(d_mm: float) -> float:
    """i = 0.45 D^(1/3) + 0.001 D [um], D [mm] the step's geometric mean. ISO 286-1, for IT5..IT18."""
    return 0.45 * d_mm ** (1.0 / 3.0) + 0.001 * d_mm


IT_MULTIPLIERS = {5: 7, 6: 10, 7: 16, 8: 25, 9: 40, 10: 64, 11: 100, 12: 160}


def it_formula_um(grade: int, d_mm: float) -> float:
    """Unrounded standard tolerance [um]: IT5..IT12 = (7, 10, 16, 25, 40, 64, 100, 160) i;
    IT1 = 0.8 + 0.020 D; IT2..IT4 geometric steps between IT1 and IT5. ISO 286-1."""
    if grade in IT_MULTIPLIERS:
        return IT_MULTIPLIERS[grade] * standard_tolerance_factor_um(d_mm)
    it1 = 0.8 + 0.020 * d_mm
    if grade == 1:
        return it1
    it5 = 7 * standard_tolerance_factor_um(d_mm)
    return it1 * (it5 / it1) ** ((grade - 1) / 4.0)


def it_um(grade: int, size_mm: float, option: str = "grade") -> float:
    """Standard tolerance IT<grade> [um] for nominal size ``size_mm`` [mm], from the table."""
    if grade not in IT_GRADES:
        raise InputError(option, f"IT{grade}", "allowed: IT1 to IT12 (ISO 286-1)")
    return float(_step(size_mm, "size_mm")[f"IT{grade}"])


def parse_it(text: str) -> int:
    m = re.fullmatch(r"(?i)IT(\d{1,2})", text.strip())
    if not m or int(m.group(1)) not in IT_GRADES:
        raise InputError("grade", text, "allowed: IT1 to IT12")
    return int(m.group(1))


@dataclass(frozen=True)
class Zone:
    """Limit deviations [um] of a hole or shaft: upper and lower."""

    letter: str
    grade: int
    upper_um: float
    lower_um: float


def shaft_zone(letter: str, grade: int, size_mm: float) -> Zone:
    """Shaft tolerance zone, e.g. g6: es from the table, ei = es - IT (or ei from the table
    for k..p, es = ei + IT; js: +-IT/2). ISO 286-1/-2."""
    if letter not in SHAFT_LETTERS:
        raise InputError("fit", letter, f"allowed shaft letters: {', '.join(SHAFT_LETTERS)}")
    it = it_um(grade, size_mm, "fit")
    if letter == "js":
        return Zone(letter, grade, it / 2, -it / 2)
    row = next(r for r in read_table(SHAFT_TABLE) if float(r["over_mm"]) < size_mm <= float(r["to_mm"]))
    dev = float(row[letter])
    if letter in ("f", "g", "h"):
        return Zone(letter, grade, dev, dev - it)
    if letter == "k" and not 4 <= grade <= 7:
        dev = 0.0  # ISO 286-1: k has ei = 0 outside IT4..IT7
    return Zone(letter, grade, dev + it, dev)


def hole_zone(letter: str, grade: int, size_mm: float) -> Zone:
    """Hole tolerance zone, e.g. H7: EI = -es of the same shaft letter for F, G, H, ES = EI + IT;
    JS: +-IT/2. ISO 286-1."""
    if letter not in HOLE_LETTERS:
        raise InputError("fit", letter, f"allowed hole letters: {', '.join(HOLE_LETTERS)}")
    it = it_um(grade, size_mm, "fit")
    if letter == "JS":
        return Zone(letter, grade, it / 2, -it / 2)
    ei = 0.0 - shaft_zone(letter.lower(), grade, size_mm).upper_um  # 0.0 - 0.0 is +0.0, not -0.0
    return Zone(letter, grade, ei + it, ei)


@dataclass(frozen=True)
class Fit:
    fit: str
    size_mm: float
    hole_upper_um: float
    hole_lower_um: float
    shaft_upper_um: float
    shaft_lower_um: float
    clearance_min_um: float  # negative = interference
    clearance_max_um: float

    def to_dict(self) -> dict:
        return asdict(self)


def fit(spec: str, size_mm: float) -> Fit:
    """Clearance range of a hole/shaft fit such as 'H7/g6' [um]: min = EI - es, max = ES - ei."""
    m = re.fullmatch(r"\s*(JS|[A-Z])(\d{1,2})\s*/\s*(js|[a-z])(\d{1,2})\s*", spec)
    if not m:
        raise InputError("fit", spec, "allowed: hole/shaft like H7/g6 (holes F G H JS, shafts f g h js k m n p)")
    hole = hole_zone(m.group(1), int(m.group(2)), size_mm)
    shaft = shaft_zone(m.group(3), int(m.group(4)), size_mm)
    return Fit(spec.strip(), size_mm, hole.upper_um, hole.lower_um, shaft.upper_um, shaft.lower_um,
               hole.lower_um - shaft.upper_um, hole.upper_um - shaft.lower_um)
