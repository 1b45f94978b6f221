"""Test-bench files (``rvbacklash bench``, ``calibrate``; docs/bench-data.md): a CSV or TSV table
of a hysteresis test (torque and output angle, optionally time) or of a transmission-error test
(output angle and TE, or input and output angle with the ratio), read into canonical units.

The header names each column and its unit in brackets: ``torque [N·m]`` (also ``[N m]``,
``[Nm]``, ``[N*m]``, ``[kN m]``), ``angle [arcmin]`` (``arcsec``, ``deg``, ``rad``, ``mrad``,
``urad``), ``time [s]`` (``ms``, ``min``), ``te [arcsec]``; a column without a unit takes the unit
given by a flag (``--torque-unit``, ``--angle-unit``, ``--te-unit``) or is refused. Lines starting
with ``#`` are comments. Canonical units: torque [N m], output angle [arcmin] (hysteresis) or
[deg] (TE), TE [arcsec], time [s].

Bad data is one InputError naming the file and the column: an empty file, a missing or unknown
unit, a non-numeric cell, a run of more than MAX_GAP missing or NaN cells (shorter runs are
dropped and said in the notes).
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from rvbacklash.errors import InputError

# unit -> factor to the canonical unit of its quantity
TORQUE_UNITS = {"n·m": 1.0, "n m": 1.0, "nm": 1.0, "n*m": 1.0, "n.m": 1.0, "n-m": 1.0, "kn·m": 1e3, "kn m": 1e3,
                "knm": 1e3}
ANGLE_TO_ARCMIN = {"arcmin": 1.0, "arcsec": 1.0 / 60.0, "deg": 60.0, "°": 60.0, "rad": 10800.0 / math.pi,
                   "mrad": 10.8 / math.pi, "urad": 0.0108 / math.pi, "µrad": 0.0108 / math.pi}
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0}
QUANTITIES = {  # column role -> (names it goes by, unit table, canonical unit, scale of the canonical unit)
    "time": (("time",), TIME_UNITS, "s", 1.0),
    "torque": (("torque", "output torque", "output_torque", "torque_out"), TORQUE_UNITS, "N m", 1.0),
    "angle": (("angle", "output angle", "output_angle", "theta", "angle_out"), ANGLE_TO_ARCMIN, "arcmin", 1.0),
    "input_angle": (("input angle", "input_angle", "angle_in"), ANGLE_TO_ARCMIN, "arcmin", 1.0),
    "te": (("te", "transmission error", "transmission_error"), ANGLE_TO_ARCMIN, "arcsec", 60.0),
}
UNIT_FLAGS = {"torque": "torque_unit", "angle": "angle_unit", "input_angle": "angle_unit", "te": "te_unit",
              "time": "time_unit"}
MAX_GAP = 3  # rows: a longer run of missing cells is an error, a shorter one is dropped (and said)
_HEADER = re.compile(r"^\s*(?P<name>[^\[\(]*?)\s*(?:[\[\(](?P<unit>[^\]\)]*)[\]\)])?\s*$")


@dataclass(frozen=True)
class BenchTable:
    """One test-bench file in canonical units: ``kind`` hysteresis (torque, angle [arcmin], maybe
    time) or te (angle = output angle [arcmin], te [arcsec] or input_angle [arcmin])."""

    path: str
    kind: str  # hysteresis | te
    columns: dict[str, np.ndarray]  # role -> values in the canonical unit, rows with gaps dropped
    headers: dict[str, str]  # role -> the column as the header wrote it (for messages)
    notes: tuple[str, ...] = field(default=())


def _unit_key(text: str) -> str:
    return " ".join(text.strip().lower().replace("\u00b7", "·").replace("⋅", "·").split())


def _role(name: str) -> str | None:
    n = " ".join(name.strip().lower().replace("-", " ").split())
    for role, (names, *_rest) in QUANTITIES.items():
        if n in names or n.replace(" ", "_") in names:
            return role
    return None


def _read_rows(path: Path) -> list[list[str]]:
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError(str(path), allowed="no such file; allowed: a CSV or TSV file of a test") from None
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(str(path), allowed=f"cannot be read ({type(e).__name__}); allowed: a UTF-8 CSV or TSV "
                                            "file") from None
    lines = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise InputError(str(path), allowed="the file is empty; allowed: a header row (e.g. 'torque [N m], angle "
                                            "[arcmin]') and rows of numbers")
    delimiter = "\t" if "\t" in lines[0] else ";" if ";" in lines[0] and "," not in lines[0] else ","
    return [[c.strip() for c in row] for row in csv.reader(lines, delimiter=delimiter)]


def read_bench_table(path: str | Path, units: Mapping[str, str | None] | None = None) -> BenchTable:
    """The file's columns in canonical units (module docstring). ``units``: {"torque_unit": "N m",
    "angle_unit": "deg", "te_unit": "arcsec", "time_unit": "s"} for columns whose header has none
    (a unit in the header wins). Columns of no known role are ignored (said in the notes)."""
    path = Path(path)
    units = {k: v for k, v in (units or {}).items() if v is not None}
    rows = _read_rows(path)
    header, body = rows[0], rows[1:]
    where = str(path)
    roles: dict[str, int] = {}
    headers: dict[str, str] = {}
    scales: dict[str, float] = {}
    notes = []
    for j, text in enumerate(header):
        m = _HEADER.match(text)
        role = _role(m.group("name")) if m else None
        if role is None:
            if text and not _is_number(text):
                notes.append(f"column '{text}' ignored (not a known quantity)")
                continue
            raise InputError(f"{where}: header", text, "a number where the header should be; allowed: a first row "
                                                       "naming the columns, e.g. 'torque [N m], angle [arcmin]'")
        if role in roles:
            raise InputError(f"{where}: column '{text}'", allowed=f"a second {role} column; allowed: one")
        names, table, canonical, to_canonical = QUANTITIES[role]
        unit = m.group("unit") if m.group("unit") is not None else units.get(UNIT_FLAGS[role])
        flag = "--" + UNIT_FLAGS[role].replace("_", "-")
        if unit is None:
            raise InputError(f"{where}: column '{text}'", allowed=f"no unit; allowed: a unit in the header, e.g. "
                                                                  f"'{names[0]} [{canonical}]', or {flag}")
        key = _unit_key(unit)
        if key not in table:
            raise InputError(f"{where}: column '{text}'", unit, f"unknown unit; allowed: {', '.join(sorted(table))}")
        roles[role], headers[role], scales[role] = j, text, table[key] * to_canonical
    kind = "hysteresis" if "torque" in roles else "te"
    need = ("torque", "angle") if kind == "hysteresis" else ("angle",)
    for role in need:
        if role not in roles:
            raise InputError(f"{where}: column '{role}'", allowed=f"missing; allowed: a header with "
                                                                  f"{' and '.join(need)} columns and their units")
    if kind == "te" and "te" not in roles and "input_angle" not in roles:
        raise InputError(f"{where}: column 'torque' or 'te'", allowed="missing; allowed: torque and angle columns (a "
                                                                      "hysteresis loop), or output angle with te or "
                                                                      "with input angle (a TE curve)")
    if not body:
        raise InputError(where, allowed="a header and no data rows; allowed: rows of numbers below the header")
    values = {role: np.full(len(body), np.nan) for role in roles}
    for i, row in enumerate(body):
        for role, j in roles.items():
            cell = row[j] if j < len(row) else ""
            if cell == "" or cell.lower() in ("nan", "na", "n/a", "null"):
                continue  # missing: a NaN, checked below
            try:
                values[role][i] = float(cell)
            except ValueError:
                raise InputError(f"{where}: column '{headers[role]}'", cell,
                                 f"row {i + 2}: not a number; allowed: numbers") from None
    bad = np.zeros(len(body), bool)
    for role, v in values.items():
        if np.isinf(v).any():
            raise InputError(f"{where}: column '{headers[role]}'", allowed=f"row {int(np.argmax(np.isinf(v))) + 2}: "
                                                                           "infinite; allowed: finite numbers")
        gap = np.isnan(v)
        run = _longest_run(gap)
        if run[1] > MAX_GAP:
            raise InputError(f"{where}: column '{headers[role]}'",
                             allowed=f"rows {run[0] + 2}-{run[0] + run[1] + 1}: {run[1]} missing or NaN cells in a "
                                     f"row; allowed: gaps of at most {MAX_GAP} rows (they are dropped)")
        bad |= gap
    if bad.any():
        notes.append(f"{int(bad.sum())} rows with missing or NaN cells dropped")
    if bad.all():
        raise InputError(where, allowed="no row with every column given; allowed: rows of numbers")
    cols = {role: values[role][~bad] * scales[role] for role in roles}
    return BenchTable(where, kind, cols, headers, tuple(notes))


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def _longest_run(mask: np.ndarray) -> tuple[int, int]:
    """(start, length) of the longest run of True."""
    best, start, i = (0, 0), None, 0
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        if not m and start is not None:
            best = max(best, (start, i - start), key=lambda r: r[1])
            start = None
    if start is not None:
        best = max(best, (start, len(mask) - start), key=lambda r: r[1])
    return best
