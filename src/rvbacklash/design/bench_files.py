"""Test-bench files (``rvbacklash bench``, ``calibrate``; docs/bench-data.md): a CSV, TSV or .xlsx
table of a hysteresis test (torque and output angle, optionally time) or of a transmission-error
test (output angle and TE, or input and output angle with the ratio; one run, or the forward and
backward runs of one unit side by side or marked by a direction column), read into canonical
units, as rigs write them.

The header names each column and its unit in brackets: ``torque [N·m]`` (also ``[N m]``,
``[Nm]``, ``[N*m]``, ``[kN m]``), ``angle [arcmin]`` (``arcsec``, ``deg``, ``rad``, ``mrad``,
``urad``), ``time [s]`` (``ms``, ``min``), ``te [arcsec]``; common spellings are recognised
(``SPELLINGS``: ``Output_Position``, ``Transmission_Error_Fw``, ``Torque_Nm`` ...), a ``_Fw`` /
``_Bw`` ending names the run; a column map (``--columns te=Name,...`` or a format profile, a small
TOML: ``load_format_profile``) names any other header. A column without a unit takes the unit
given by a flag (``--torque-unit``, ``--angle-unit``, ``--te-unit``) or the profile, or is
refused. Lines starting with ``#`` are comments. Lines before the header (a rig's metadata) are
kept (``BenchTable.metadata``); the header is the first line naming two known columns.
Separators: comma, semicolon or tab (detected from the data lines); decimal commas with
``--decimal ,``, or read as such in a file separated by semicolons or tabs. Canonical units:
torque [N m], output angle [arcmin] (hysteresis) or [deg] (TE), TE [arcsec], time [s].

Bad data is one InputError naming the file and the column: a path that is no regular file (a FIFO,
a device, a directory) or larger than MAX_FILE_BYTES, an empty file, an unrecognised header (the
columns found and how to map them), a missing or unknown unit, a non-numeric cell (its row; a hint
for a decimal comma), a value beyond MAX_MAGNITUDE once converted, a time that goes back, a run of
more than MAX_GAP missing or NaN cells (shorter runs are dropped and said in the notes).
"""

from __future__ import annotations

import csv
import dataclasses
import errno
import io
import math
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from rvbacklash.errors import InputError
from rvbacklash.paths import unusable

# unit -> factor to the canonical unit of its quantity
TORQUE_UNITS = {"n·m": 1.0, "n m": 1.0, "nm": 1.0, "n*m": 1.0, "n.m": 1.0, "n-m": 1.0, "kn·m": 1e3, "kn m": 1e3,
                "knm": 1e3}
ANGLE_TO_ARCMIN = {"arcmin": 1.0, "arcsec": 1.0 / 60.0, "deg": 60.0, "°": 60.0, "rad": 10800.0 / math.pi,
                   "mrad": 10.8 / math.pi, "urad": 0.0108 / math.pi, "µrad": 0.0108 / math.pi}
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0}
# header spellings of each role, normalised (lower case; '_', '-', '.' as spaces): rigs' own names
SPELLINGS = {
    "time": ("time", "elapsed time", "time elapsed"),  # not "t": rigs write T for torque
    "torque": ("torque", "output torque", "torque out", "torque output", "output torque reducer",
               "torque output reducer", "load torque", "torque reducer"),
    "angle": ("angle", "output angle", "angle out", "angle output", "out angle", "theta", "theta out", "position",
              "output position", "position output", "position out", "output position reducer",
              "position output reducer", "poisition output reducer",  # the public RV rig's spelling, typo kept
              "output shaft angle", "output shaft position", "angle output reducer"),
    "input_angle": ("input angle", "angle in", "angle input", "in angle", "theta in", "input position",
                    "position input", "position in", "input position reducer", "position input reducer",
                    "motor angle", "motor position", "input shaft angle", "angle input reducer"),
    "te": ("te", "transmission error", "trans error", "transmission error reducer", "angular transmission error",
           "kinematic error"),
}
QUANTITIES = {  # column role -> (names it goes by, unit table, canonical unit, scale of the canonical unit)
    "time": (SPELLINGS["time"], TIME_UNITS, "s", 1.0),
    "torque": (SPELLINGS["torque"], TORQUE_UNITS, "N m", 1.0),
    "angle": (SPELLINGS["angle"], ANGLE_TO_ARCMIN, "arcmin", 1.0),
    "input_angle": (SPELLINGS["input_angle"], ANGLE_TO_ARCMIN, "arcmin", 1.0),
    "te": (SPELLINGS["te"], ANGLE_TO_ARCMIN, "arcsec", 60.0),
}
UNIT_FLAGS = {"torque": "torque_unit", "angle": "angle_unit", "input_angle": "angle_unit", "te": "te_unit",
              "time": "time_unit"}
# a header's run: a last (or first) word of these names the forward or the backward run
RUN_WORDS = {"fw": "forward", "fwd": "forward", "forward": "forward", "bw": "backward", "bwd": "backward",
             "backward": "backward", "back": "backward"}
# the values of a direction column that name each run (a profile's [directions] adds its own)
DIRECTION_VALUES = {"forward": ("fw", "fwd", "forward", "f", "+", "+1", "1", "1.0", "+1.0"),
                    "backward": ("bw", "bwd", "backward", "b", "back", "-", "-1", "-1.0")}
DIRECTION_NAMES = ("direction", "dir", "run direction", "rotation direction", "direction of rotation")
TWO_RUN_ROLES = ("angle", "input_angle", "te")  # roles a backward run has its own column of (role_bw)
MAP_ROLES = ("time", "torque", "angle", "input_angle", "te", "angle_bw", "input_angle_bw", "te_bw", "direction")
# a rig's known header (normalised) -> units of its columns without one; said in the notes
KNOWN_LAYOUTS = {
    ("poisition output reducer fw", "transmission error fw", "position output reducer bw", "transmission error bw"):
        ("the public RV test rig's two-run TE layout: angles and TE in degrees, as that rig writes them",
         {"angle_unit": "deg", "te_unit": "deg"}),
}
MAX_GAP = 3  # rows: a longer run of missing cells is an error, a shorter one is dropped (and said)
MAX_FILE_BYTES = 100_000_000  # a bench file: 1 kHz for an hour of four columns is ~150 MB of text, 10 min ~25 MB
MAX_PROFILE_BYTES = 1_000_000
MAX_HEADER_LINE = 200  # lines searched for the header (metadata above it)
MAX_MAGNITUDE = 1e15  # in canonical units: beyond any bench's range, and squares of it overflow in the fits
_HEADER = re.compile(r"^\s*(?P<name>[^\[\(]*?)\s*(?:[\[\(](?P<unit>[^\]\)]*)[\]\)])?\s*$")
_DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+(?:[eE][+-]?\d+)?$")


@dataclass(frozen=True)
class FileFormat:
    """How a rig writes its files (a column map, units, decimal mark, separator, sheet): the flags
    ``--columns``, ``--decimal``, the unit flags and a format profile (``load_format_profile``),
    merged by ``file_format`` (a flag wins over the profile)."""

    columns: tuple[tuple[str, str], ...] = ()  # (role in MAP_ROLES, the column's header text)
    units: tuple[tuple[str, str], ...] = ()  # (torque_unit | angle_unit | te_unit | time_unit, unit)
    decimal: str | None = None  # "." or ","; None: detected
    delimiter: str | None = None  # None: detected
    sheet: str | None = None  # .xlsx: the sheet (None: the first)
    forward: tuple[str, ...] = ()  # direction-column values of the forward run, beyond DIRECTION_VALUES
    backward: tuple[str, ...] = ()
    name: str | None = None  # the profile's name (said in the notes)


@dataclass(frozen=True)
class BenchTable:
    """One test-bench file in canonical units: ``kind`` hysteresis (torque, angle [arcmin], maybe
    time) or te (angle = output angle [arcmin], te [arcsec] or input_angle [arcmin]; a file of two
    runs also angle_bw and te_bw or input_angle_bw, the backward run's samples)."""

    path: str
    kind: str  # hysteresis | te
    columns: dict[str, np.ndarray]  # role -> values in the canonical unit, rows with gaps dropped
    headers: dict[str, str]  # role -> the column as the header wrote it (for messages)
    notes: tuple[str, ...] = field(default=())
    metadata: tuple[str, ...] = field(default=())  # the lines before the header, as written

    @property
    def two_runs(self) -> bool:
        """Forward and backward runs of one unit (TE)."""
        return "angle_bw" in self.columns


# --- the format: a column map, a profile, flags ------------------------------------------------------

def _norm(text: str) -> str:
    """A header name compared: lower case, '_', '-', '.' and runs of blanks as one space."""
    return " ".join(re.sub(r"[_\-.]", " ", text.strip().lower()).split())


def _unit_key(text: str) -> str:
    return " ".join(text.strip().lower().replace("\u00b7", "·").replace("⋅", "·").split())


def _map_role(text: str) -> str | None:
    role = text.strip().lower().replace("-", "_").replace(" ", "_")
    role = {"output_angle": "angle", "output_angle_bw": "angle_bw"}.get(role, role)
    if role.endswith("_fw"):
        role = role[:-3]
    return role if role in MAP_ROLES else None


def parse_columns(text: str | Mapping[str, str] | None) -> dict[str, str]:
    """``--columns te=Transmission_Error_Fw,angle=Position`` -> {role: header}; a header with a comma
    in double quotes. Roles: MAP_ROLES (``_fw`` is the same as none)."""
    if text is None:
        return {}
    items = list(text.items()) if isinstance(text, Mapping) else None
    if items is None:
        cells = next(csv.reader([text], skipinitialspace=True), [])
        items = []
        for cell in (c.strip() for c in cells):
            if not cell:
                continue
            if "=" not in cell:
                raise InputError("columns", cell, f"allowed: ROLE=COLUMN pairs separated by commas, e.g. "
                                                  f"te=Transmission_Error_Fw; roles: {', '.join(MAP_ROLES)}")
            k, v = cell.split("=", 1)
            items.append((k, v))
    out: dict[str, str] = {}
    for k, v in items:
        role = _map_role(str(k))
        if role is None:
            raise InputError("columns", f"{k}={v}", f"unknown role '{k}'; allowed: {', '.join(MAP_ROLES)}")
        if not isinstance(v, str) or not v.strip():
            raise InputError("columns", f"{k}={v}", "no column named; allowed: ROLE=COLUMN, the column as the header "
                                                   "writes it")
        if role in out:
            raise InputError("columns", f"{k}={v}", f"a second {role}; allowed: one column per role")
        out[role] = v.strip()
    return out


def check_decimal(value: str | None, field_name: str = "decimal") -> str | None:
    if value is None:
        return None
    if value not in (".", ","):
        raise InputError(field_name, value, "allowed: '.' or ',' (the decimal mark of the files' numbers)")
    return value


DELIMITERS = {",": ",", ";": ";", "\t": "\t", "tab": "\t", "|": "|"}
PROFILE_KEYS = ("name", "decimal", "delimiter", "sheet", "columns", "units", "directions")


def load_format_profile(path: str | Path) -> FileFormat:
    """A format profile: a small TOML naming how a rig writes its files (docs/bench-data.md, "Rig
    files"): ``name``, ``decimal`` ("." or ","), ``delimiter`` (",", ";", "tab", "|"), ``sheet``
    (.xlsx), ``[columns]`` role = "header" (MAP_ROLES), ``[units]`` torque/angle/te/time = unit
    (for columns without one), ``[directions]`` forward/backward = values of a direction column."""
    import tomllib

    where = str(path)
    data = read_input_bytes(Path(path), "a TOML format profile", MAX_PROFILE_BYTES)
    try:
        doc = tomllib.loads(data.decode("utf-8-sig"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise InputError(where, allowed=f"not a TOML file ({' '.join(str(e).split())}); allowed: a format profile "
                                        "(docs/bench-data.md, 'Rig files')") from None
    for key in doc:
        if key not in PROFILE_KEYS:
            raise InputError(f"{where}: {key}", allowed=f"unknown key; allowed: {', '.join(PROFILE_KEYS)}")

    def text(key: str, value) -> str:
        if not isinstance(value, str):
            raise InputError(f"{where}: {key}", value, "allowed: a string")
        return value

    def table(key: str) -> dict:
        value = doc.get(key, {})
        if not isinstance(value, dict):
            raise InputError(f"{where}: {key}", value, f"allowed: a table [{key}]")
        return value

    name = text("name", doc["name"]) if "name" in doc else None
    decimal = check_decimal(text("decimal", doc["decimal"]), f"{where}: decimal") if "decimal" in doc else None
    delimiter = None
    if "delimiter" in doc:
        d = text("delimiter", doc["delimiter"])
        if d.lower() not in DELIMITERS:
            raise InputError(f"{where}: delimiter", d, "allowed: ',', ';', 'tab', '|'")
        delimiter = DELIMITERS[d.lower()]
    sheet = text("sheet", doc["sheet"]) if "sheet" in doc else None
    try:
        columns = parse_columns({str(k): v for k, v in table("columns").items()})
    except InputError as e:
        raise InputError(f"{where}: columns", e.value, e.allowed) from None
    units = {}
    for k, v in table("units").items():
        role = _map_role(k)
        base = role.removesuffix("_bw") if role else None
        if base not in UNIT_FLAGS:
            raise InputError(f"{where}: units.{k}", allowed=f"unknown quantity; allowed: {', '.join(QUANTITIES)}")
        units_of = QUANTITIES[base][1]
        if _unit_key(text(f"units.{k}", v)) not in units_of:
            raise InputError(f"{where}: units.{k}", v, f"unknown unit; allowed: {', '.join(sorted(units_of))}")
        units[UNIT_FLAGS[base]] = v
    runs = {}
    for k, v in table("directions").items():
        if k not in ("forward", "backward"):
            raise InputError(f"{where}: directions.{k}", allowed="unknown run; allowed: forward, backward")
        values = [v] if isinstance(v, str) else v
        if not isinstance(values, list) or not values or not all(isinstance(x, (str, int)) for x in values):
            raise InputError(f"{where}: directions.{k}", v, "allowed: a value or a list of values of the direction "
                                                            "column")
        runs[k] = tuple(str(x).strip().lower() for x in values)
    return FileFormat(tuple(columns.items()), tuple(units.items()), decimal, delimiter, sheet,
                      runs.get("forward", ()), runs.get("backward", ()), name)


def file_format(columns: str | Mapping[str, str] | None = None, profile: str | Path | None = None,
                decimal: str | None = None, units: Mapping[str, str | None] | None = None) -> FileFormat:
    """The format of a batch of files: ``profile`` (a TOML, ``load_format_profile``) with the flags
    over it (``columns`` as ``--columns``, ``decimal``, ``units``: {"angle_unit": "deg", ...})."""
    base = load_format_profile(profile) if profile is not None else FileFormat()
    cols = dict(base.columns)
    cols.update(parse_columns(columns))
    merged = dict(base.units)
    merged.update({k: v for k, v in (units or {}).items() if v is not None})
    return dataclasses.replace(base, columns=tuple(cols.items()), units=tuple(merged.items()),
                               decimal=check_decimal(decimal) if decimal is not None else base.decimal)


def as_format(units: Mapping[str, str | None] | FileFormat | None) -> FileFormat:
    """A FileFormat, or the unit flags alone as one."""
    if isinstance(units, FileFormat):
        return units
    return FileFormat(units=tuple((k, v) for k, v in (units or {}).items() if v is not None))


# --- the file's bytes and rows -------------------------------------------------------------------

_KINDS = ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISDIR, "a directory"), (stat.S_ISSOCK, "a socket"))


def read_input_bytes(path: Path, what: str, limit: int = MAX_FILE_BYTES) -> bytes:
    """The bytes of an input file: a regular file of at most ``limit`` bytes, else one InputError
    naming the path. Opened without blocking (a FIFO with no writer does not hang) and checked on
    the open file (no window between the check and the read); read to ``limit`` at most (a file
    that grows meanwhile, or a device, does not fill memory)."""
    where = str(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except OSError as e:
        if e.errno in (errno.ENOENT, errno.ENOTDIR):
            raise InputError(where, allowed=f"no such file; allowed: {what}") from None
        if e.errno == errno.ENAMETOOLONG:  # in the words output paths use (paths.unusable)
            raise InputError(where, allowed=unusable("file", path, e).allowed) from None
        raise InputError(where, allowed=f"cannot be read ({e.strerror or type(e).__name__}); allowed: {what} this "
                                        f"user can read") from None
    too_big = f"allowed: at most {limit / 1e6:g} MB (split a longer record into files)"
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        raise InputError(where, allowed=f"{kind}, not a regular file; allowed: {what} (a regular file)")
    with os.fdopen(fd, "rb") as f:
        if st.st_size > limit:
            raise InputError(where, allowed=f"{st.st_size / 1e6:.1f} MB; {too_big}")
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise InputError(where, allowed=f"cannot be read ({e.strerror or type(e).__name__}); allowed: "
                                            f"{what}") from None
    if len(data) > limit:  # it grew while read
        raise InputError(where, allowed=f"more than {limit / 1e6:g} MB; {too_big}")
    return data


def _decode(data: bytes, where: str) -> tuple[str, str | None]:
    """The text of a text file and a note when it was not UTF-8."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            return data.decode("utf-16"), "read as UTF-16 (its byte-order mark)"
        except UnicodeDecodeError:
            pass
    if b"\x00" in data[:65536]:
        raise InputError(where, allowed="a binary file (NUL bytes); allowed: a CSV or TSV text file, or .xlsx")
    try:
        return data.decode("utf-8-sig"), None
    except UnicodeDecodeError:
        return data.decode("cp1252", errors="replace"), "not UTF-8: read as Windows-1252"


def _cell_text(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    if hasattr(value, "isoformat"):
        return value.isoformat()
    return str(value).strip()


def _xlsx_rows(data: bytes, where: str, sheet: str | None) -> list[tuple[int, list[str]]]:
    """(row number, cells as text) of a worksheet (openpyxl, read-only: streamed); numbers as their
    shortest exact text, blank rows left out."""
    import zipfile

    import openpyxl
    from openpyxl.utils.exceptions import InvalidFileException

    try:
        book = openpyxl.load_workbook(io.BytesIO(data), read_only=True, data_only=True)
    except (zipfile.BadZipFile, InvalidFileException, KeyError, ValueError, OSError, TypeError) as e:
        raise InputError(where, allowed=f"not a readable .xlsx workbook ({type(e).__name__}); allowed: an Excel "
                                        f".xlsx file, or CSV/TSV") from None
    try:
        if sheet is None:
            ws = book.worksheets[0]
        elif sheet in book.sheetnames:
            ws = book[sheet]
        else:
            raise InputError(where, sheet, f"no such sheet; allowed: {', '.join(book.sheetnames)}")
        rows = []
        for k, row in enumerate(ws.iter_rows(values_only=True), start=1):
            cells = [_cell_text(v) for v in row]
            while cells and cells[-1] == "":
                cells.pop()
            if cells:
                rows.append((k, cells))
        return rows
    finally:
        book.close()


def _delimiter(lines: list[str]) -> str:
    """The separator of the data lines (the file's last lines: below any metadata): the first of
    tab, semicolon, comma, bar found the same number of times (> 0) on each of them."""
    tail = lines[-50:]
    for d in ("\t", ";", ",", "|"):
        counts = {line.count(d) for line in tail}
        if len(counts) == 1 and counts.pop() > 0:
            return d
    for d in ("\t", ";", ","):  # uneven counts (quoted cells, a shorter run): the most frequent
        if all(d in line for line in tail):
            return d
    return ","


def _text_rows(text: str, fmt: FileFormat) -> tuple[list[tuple[int, list[str]]], list[tuple[int, str]],
                                                    dict[int, str], str]:
    """(row number, cells) of the lines that are neither blank nor comments, the comment lines,
    the first lines as written (metadata when above the header) and the separator."""
    numbered, comments = [], []
    for k, line in enumerate(text.splitlines(), start=1):
        s = line.strip()
        if not s:
            continue
        if s.startswith("#"):
            comments.append((k, s.lstrip("#").strip()))
            continue
        numbered.append((k, line))
    delimiter = fmt.delimiter or _delimiter([line for _, line in numbered])
    cells = csv.reader((line for _, line in numbered), delimiter=delimiter)
    rows = [(k, [c.strip() for c in row]) for (k, _), row in zip(numbered, cells)]
    first = {k: line.strip() for k, line in numbered[:MAX_HEADER_LINE]}
    return rows, comments, first, delimiter


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


# --- the header ----------------------------------------------------------------------------------------

def _recognise(text: str) -> tuple[str, str | None] | None:
    """(role, unit written in the name or None) of a header cell by its spelling; a run's word
    (``_Fw``, ``_Bw``) makes the role ``<role>_bw`` for the backward run; a last word that is a unit
    of the role (``Torque_Nm``, ``angle_deg``) is its unit; None: not a known quantity."""
    m = _HEADER.match(text)
    if m is None:
        return None
    words = _norm(m.group("name")).split()
    if " ".join(words) in DIRECTION_NAMES:
        return "direction", None
    run = "forward"
    for at in (-1, 0):
        if len(words) > 1 and words[at] in RUN_WORDS:
            run = RUN_WORDS[words.pop(at)]
            break
    candidates = [(" ".join(words), m.group("unit"), False)]
    if len(words) > 1 and m.group("unit") is None:
        candidates.append((" ".join(words[:-1]), words[-1], True))
    for name, unit, from_name in candidates:
        for role, (names, table, *_rest) in QUANTITIES.items():
            if name not in names or (from_name and _unit_key(unit) not in table):
                continue
            if run == "backward":
                if role not in TWO_RUN_ROLES:
                    return None
                role = f"{role}_bw"
            return role, unit
    return None


def _matches(cell: str, name: str) -> bool:
    m = _HEADER.match(cell)
    return _norm(cell) == _norm(name) or (m is not None and _norm(m.group("name")) == _norm(name))


def _header_index(rows: list[tuple[int, list[str]]], mapped: dict[str, str]) -> int:
    """The header row: the first naming two known (or mapped) columns among the first
    MAX_HEADER_LINE rows; else the row above the first row of numbers (a file of unknown
    columns: the error lists them), or the first row."""
    for i, (_, cells) in enumerate(rows[:MAX_HEADER_LINE]):
        known = sum(1 for c in cells if c and (_recognise(c) is not None or any(_matches(c, n)
                                                                                  for n in mapped.values())))
        if known >= 2:
            return i
    for i, (_, cells) in enumerate(rows[:MAX_HEADER_LINE]):
        filled = [c for c in cells if c]
        if len(filled) >= 2 and all(_is_number(c) or _is_number(c.replace(",", ".")) for c in filled):
            return max(i - 1, 0)
    return 0


def _found(header: list[str]) -> str:
    shown = [f"'{c[:40]}'" for c in header if c][:12]
    more = len([c for c in header if c]) - len(shown)
    return ", ".join(shown) + (f" and {more} more" if more > 0 else "")


def _layout_units(header: list[str]) -> tuple[str | None, dict[str, str]]:
    names = {_norm(c) for c in header if c}
    for layout, (note, units) in KNOWN_LAYOUTS.items():
        if set(layout) <= names:
            return note, units
    return None, {}


# --- reading a file -------------------------------------------------------------------------------

def read_bench_table(path: str | Path, units: Mapping[str, str | None] | FileFormat | None = None) -> BenchTable:
    """The file's columns in canonical units (module docstring). ``units``: {"torque_unit": "N m",
    "angle_unit": "deg", "te_unit": "arcsec", "time_unit": "s"} for columns whose header has none
    (a unit in the header wins), or a FileFormat (``file_format``: a column map, units, decimal
    mark, separator, sheet). Columns of no known role are ignored (said in the notes)."""
    path = Path(path)
    fmt = as_format(units)
    where = str(path)
    data = read_input_bytes(path, "a CSV, TSV or .xlsx file of a test")
    notes: list[str] = [f"format profile '{fmt.name}'"] if fmt.name else []
    if path.suffix.lower() in (".xls",) or data.startswith(b"\xd0\xcf\x11\xe0"):
        raise InputError(where, allowed="an Excel 97-2003 .xls workbook; allowed: .xlsx, CSV or TSV (save it as "
                                        ".xlsx)")
    comments: list[tuple[int, str]] = []
    if path.suffix.lower() in (".xlsx", ".xlsm") or data.startswith(b"PK\x03\x04"):
        rows = _xlsx_rows(data, where, fmt.sheet)
        first = {k: ", ".join(c for c in cells if c) for k, cells in rows[:MAX_HEADER_LINE]}
        delimiter = None
    else:
        text, note = _decode(data, where)
        if note:
            notes.append(note)
        rows, comments, first, delimiter = _text_rows(text, fmt)
        del text
    del data
    if not rows:
        raise InputError(where, allowed="the file is empty; allowed: a header row (e.g. 'torque [N m], angle "
                                        "[arcmin]') and rows of numbers")
    mapped = dict(fmt.columns)
    h = _header_index(rows, mapped)
    header_row, header = rows[h]
    above = sorted([(k, c) for k, c in comments if k < header_row and c] + [(k, first[k]) for k, _ in rows[:h]])
    metadata = tuple(line[:500] for _, line in above[:MAX_HEADER_LINE])
    if h:  # (comment lines are kept too, without a note)
        notes.append(f"{h} line{'s' if h > 1 else ''} above the header kept as metadata")
    body = rows[h + 1:]
    roles, headers, unit_of = _assign(header, mapped, where)
    layout_note, layout_units = _layout_units(header)
    flag_units = dict(fmt.units)
    kind = "hysteresis" if "torque" in roles else "te"
    if kind == "hysteresis" and "direction" in roles and "direction" not in mapped:  # a loop has no runs to split
        notes.append(f"column '{headers.pop('direction')}' ignored (a direction column in a hysteresis file)")
        del roles["direction"], unit_of["direction"]
    _check_roles(roles, kind, header, where)
    scales: dict[str, float] = {}
    for key in roles:
        if key == "direction":
            continue
        role = key.removesuffix("_bw")
        names, table, canonical, to_canonical = QUANTITIES[role]
        flag = UNIT_FLAGS[role]
        unit = unit_of[key] if unit_of[key] is not None else flag_units.get(flag, layout_units.get(flag))
        if unit is None:
            raise InputError(f"{where}: column '{headers[key]}'",
                             allowed=f"no unit; allowed: a unit in the header, e.g. '{names[0]} [{canonical}]', or "
                                     f"--{flag.replace('_', '-')} (or [units] {flag.removesuffix('_unit')} in a "
                                     f"--format-profile)")
        if unit_of[key] is None and flag not in flag_units and layout_note:
            notes.append(layout_note)
            layout_note = None
        ukey = _unit_key(unit)
        if ukey not in table:
            raise InputError(f"{where}: column '{headers[key]}'", unit,
                             f"unknown unit; allowed: {', '.join(sorted(table))}")
        scales[key] = table[ukey] * to_canonical
    if not body:
        raise InputError(where, allowed="a header and no data rows; allowed: rows of numbers below the header")
    comma = _decimal_comma(fmt, delimiter, body, roles)
    if comma and fmt.decimal is None:
        notes.append("decimal commas read" + (" (separated by semicolons)" if delimiter == ";" else ""))
    linenos = np.array([k for k, _ in body])
    values, direction = _parse(body, roles, headers, where, comma, fmt.decimal)
    columns = _clean(values, direction, roles, scales, headers, linenos, where, fmt, notes)
    named = {k: headers[k] if k in headers else headers[k.removesuffix("_bw")] for k in columns}  # a shared column
    return BenchTable(where, kind, columns, named, tuple(notes), tuple(metadata))


def _assign(header: list[str], mapped: dict[str, str], where: str):
    """role -> column index, role -> the header's text, role -> the unit its header writes (None)."""
    roles: dict[str, int] = {}
    headers: dict[str, str] = {}
    unit_of: dict[str, str | None] = {}
    for role, name in mapped.items():
        hits = [j for j, c in enumerate(header) if c and _matches(c, name)]
        if not hits:
            raise InputError(f"{where}: column map", f"{role}={name}", f"no such column (columns found: "
                                                                      f"{_found(header)}); allowed: a column of the "
                                                                      f"header")
        j = hits[0]
        m = _HEADER.match(header[j])
        known = _recognise(header[j])
        roles[role], headers[role] = j, header[j]
        unit_of[role] = m.group("unit") if m and m.group("unit") else (known[1] if known else None)
    for j, text in enumerate(header):
        if not text or j in roles.values():
            continue
        known = _recognise(text)
        if known is None:
            if _is_number(text) or _is_number(text.replace(",", ".")):
                raise InputError(f"{where}: header", text, "a number where the header should be; allowed: a first "
                                                           "row naming the columns, e.g. 'torque [N m], angle "
                                                           "[arcmin]'")
            continue
        role, unit = known
        if role in mapped:
            continue  # the map chose another column for it
        if role in roles:
            raise InputError(f"{where}: column '{text}'", allowed=f"a second {role} column (after "
                                                                  f"'{headers[role]}'); allowed: one, or a column map "
                                                                  f"naming the one to read: --columns {role}=NAME")
        roles[role], headers[role], unit_of[role] = j, text, unit
    return roles, headers, unit_of


def _check_roles(roles: dict[str, int], kind: str, header: list[str], where: str) -> None:
    found = f"columns found: {_found(header)}"
    hint = "or a column map: --columns ROLE=NAME (or --format-profile FILE)"
    if not roles:
        raise InputError(where, allowed=f"no column of a known quantity ({found}); allowed: headers such as "
                                        f"'torque [N m]', 'angle [arcmin]', 'te [arcsec]', 'time [s]', {hint}, e.g. "
                                        f"--columns angle=NAME,te=NAME")
    runs = any(k.endswith("_bw") for k in roles) or "direction" in roles
    if kind == "hysteresis":
        need = ("torque", "angle")
        if runs:
            raise InputError(f"{where}: column '{header[roles['torque']]}'",
                             allowed="a torque column beside columns of a backward run or a direction; allowed: a "
                                     "hysteresis loop (torque, angle) or a TE file of one or two runs")
    else:
        need = ("angle",)
    for role in need:
        if role not in roles:
            raise InputError(f"{where}: column '{role}'", allowed=f"missing ({found}); allowed: a header with "
                                                                  f"{' and '.join(need)} columns and their units, "
                                                                  f"{hint.replace('ROLE', role)}")
    if kind == "te" and "te" not in roles and "input_angle" not in roles:
        raise InputError(f"{where}: column 'torque' or 'te'", allowed=f"missing ({found}); allowed: torque and angle "
                                                                      f"columns (a hysteresis loop), or output angle "
                                                                      f"with te or with input angle (a TE curve), "
                                                                      f"{hint}")
    if any(k.endswith("_bw") for k in roles):
        if "direction" in roles:
            raise InputError(f"{where}: column '{header[roles['direction']]}'",
                             allowed="a direction column beside columns of a backward run; allowed: one of them")
        if "te_bw" not in roles and "input_angle_bw" not in roles:
            raise InputError(f"{where}: column 'te_bw'", allowed=f"missing: a backward run's angle and no TE "
                                                                 f"({found}); allowed: te_bw or input_angle_bw "
                                                                 f"beside it, {hint}")
        if "te_bw" in roles and "te" not in roles or "input_angle_bw" in roles and "input_angle" not in roles:
            raise InputError(f"{where}: column 'te'", allowed=f"the backward run's TE has no forward one ({found}); "
                                                              f"allowed: te and te_bw (or input_angle and "
                                                              f"input_angle_bw), {hint}")


def _decimal_comma(fmt: FileFormat, delimiter: str | None, body, roles) -> bool:
    """Are commas decimal marks? --decimal says; else yes in a file separated by semicolons or tabs
    whose first data rows write one."""
    if fmt.decimal is not None:
        return fmt.decimal == ","
    if delimiter in (None, ","):
        return delimiter is None and any(_DECIMAL_COMMA.match(c) for _, cells in body[:50] for c in cells)
    return any(_DECIMAL_COMMA.match(c) for _, cells in body[:50] for c in cells)


_MISSING_CELLS = ("", "nan", "na", "n/a", "null", "-nan", "none")


def _parse(body, roles, headers, where, comma: bool, decimal: str | None):
    """Numbers of every numeric role (NaN where missing) and the direction column's text."""
    n = len(body)
    numeric = {k: j for k, j in roles.items() if k != "direction"}
    values = {k: np.full(n, np.nan) for k in numeric}
    direction = [""] * n if "direction" in roles else None
    jd = roles.get("direction")
    for i, (lineno, row) in enumerate(body):
        if direction is not None:
            direction[i] = row[jd].strip().lower() if jd < len(row) else ""
        for key, j in numeric.items():
            cell = row[j] if j < len(row) else ""
            if cell.lower() in _MISSING_CELLS:
                continue  # missing: a NaN, checked below
            try:
                values[key][i] = float(cell.replace(",", ".") if comma else cell)
            except ValueError:
                hint = ""
                if not comma and _DECIMAL_COMMA.match(cell):
                    hint = " (a decimal comma? give --decimal ,)" if decimal is None else \
                        " (a decimal comma, and the decimal mark is '.')"
                raise InputError(f"{where}: column '{headers[key]}'", cell,
                                 f"row {lineno}: not a number{hint}; allowed: numbers") from None
    for key, v in values.items():
        inf = np.isinf(v)
        if inf.any():
            raise InputError(f"{where}: column '{headers[key]}'",
                             allowed=f"row {body[int(np.argmax(inf))][0]}: infinite; allowed: finite numbers")
    return values, direction


def _check_time(seconds: np.ndarray, linenos: np.ndarray, header: str, where: str) -> None:
    """A time column never goes back: the rows in the order recorded (the drift is fitted against
    it). Refused, not sorted: a time that restarts (two records in one file) would be interleaved."""
    t, rows = seconds, linenos
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        k = int(back[0])
        raise InputError(f"{where}: column '{header}'",
                         allowed=f"row {rows[k + 1]}: the time goes back ({t[k]:.6g} s, then {t[k + 1]:.6g} s; "
                                 f"{back.size} such step{'s' if back.size > 1 else ''}); allowed: times that never "
                                 f"decrease, the rows in the order recorded")


def _runs(direction: list[str], header: str, where: str, fmt: FileFormat) -> np.ndarray:
    """0 forward, 1 backward for each row of a direction column (an empty cell: -1, a gap)."""
    fwd = set(DIRECTION_VALUES["forward"]) | set(fmt.forward)
    bwd = set(DIRECTION_VALUES["backward"]) | set(fmt.backward)
    out = np.full(len(direction), -1)
    unknown: dict[str, None] = {}
    for i, v in enumerate(direction):
        if v in fwd:
            out[i] = 0
        elif v in bwd:
            out[i] = 1
        elif v not in _MISSING_CELLS:
            unknown[v] = None
    if unknown:
        shown = ", ".join(f"'{v}'" for v in list(unknown)[:6])
        raise InputError(f"{where}: column '{header}'", allowed=f"values {shown} name no run; allowed: fw/forward/+1 "
                                                                f"and bw/backward/-1, or a --format-profile with "
                                                                f"[directions] forward = [...], backward = [...]")
    for run, name in ((0, "forward"), (1, "backward")):
        if not np.any(out == run):
            raise InputError(f"{where}: column '{header}'", allowed=f"no row of the {name} run; allowed: rows of both "
                                                                    f"runs")
    return out


def _clean(values, direction, roles, scales, headers, linenos, where, fmt, notes) -> dict[str, np.ndarray]:
    """Each run's rows with gaps dropped (a run of more than MAX_GAP missing cells refused), in
    canonical units, every value finite and within MAX_MAGNITUDE after the conversion."""
    n = linenos.size
    if direction is not None:  # one file, a direction column: the runs' rows
        run = _runs(direction, headers["direction"], where, fmt)
        own = [k for k in roles if k not in ("direction", "time")]
        groups = [(run != 1, {k: k for k in own}, "forward", False),
                  (run != 0, {f"{k}_bw": k for k in own}, "backward", False)]
        if (run == -1).any():
            values = dict(values, _direction=np.where(run == -1, np.nan, 0.0))
            headers = dict(headers, _direction=headers["direction"])
            for _, keys, _, _ in groups:
                keys["_direction"] = "_direction"
    elif any(k.endswith("_bw") for k in roles):  # two runs side by side (their lengths may differ)
        fwd = [k for k in roles if not k.endswith("_bw") and k != "time"]
        bwd = {k: k for k in roles if k.endswith("_bw")}
        bwd.setdefault("angle_bw", "angle")  # one position column for both runs
        groups = [(np.ones(n, bool), {k: k for k in fwd}, "forward", True), (np.ones(n, bool), bwd, "backward", True)]
    else:
        groups = [(np.ones(n, bool), {k: k for k in roles}, "", False)]
    out: dict[str, np.ndarray] = {}
    for rows, keys, name, trim in groups:
        sel = np.flatnonzero(rows)
        v = {k: values[src][sel] for k, src in keys.items()}
        if trim:  # a shorter run leaves blank cells at its end (or start): not gaps
            present = np.zeros(sel.size, bool)
            for k, src in keys.items():
                if src == k:
                    present |= ~np.isnan(v[k])
            if not present.any():
                raise InputError(where, allowed=f"no row of the {name} run; allowed: rows of both runs")
            lo, hi = int(np.argmax(present)), int(present.size - np.argmax(present[::-1]))
            sel, v = sel[lo:hi], {k: x[lo:hi] for k, x in v.items()}
        bad = np.zeros(sel.size, bool)
        for k, x in v.items():
            gap = np.isnan(x)
            start, length = _longest_run(gap)
            if length > MAX_GAP:
                raise InputError(f"{where}: column '{headers[keys[k]]}'",
                                 allowed=f"rows {linenos[sel[start]]}-{linenos[sel[start + length - 1]]}: {length} "
                                         f"missing or NaN cells in a row; allowed: gaps of at most {MAX_GAP} rows "
                                         f"(they are dropped)")
            bad |= gap
        if bad.all():
            raise InputError(where, allowed="no row with every column given" + (f" in the {name} run" if name else "")
                             + "; allowed: rows of numbers")
        if bad.any():
            notes.append(f"{int(bad.sum())} rows with missing or NaN cells dropped" + (f" ({name} run)" if name
                                                                                        else ""))
        for k, x in v.items():
            if k == "_direction":
                continue
            src = keys[k]
            with np.errstate(over="ignore"):  # refused just below
                converted = x[~bad] * scales[src]
            wild = ~(np.abs(converted) <= MAX_MAGNITUDE)
            if wild.any():
                i = int(np.flatnonzero(~bad)[np.argmax(wild)])
                canonical = QUANTITIES[src.removesuffix("_bw")][2]
                raise InputError(f"{where}: column '{headers[src]}'", float(x[i]),
                                 f"row {linenos[sel[i]]}: {converted[np.argmax(wild)]:.4g} {canonical} once "
                                 f"converted; allowed: values within +-{MAX_MAGNITUDE:g} {canonical} (no bench reads "
                                 f"more)")
            if k == "time":
                _check_time(converted, linenos[sel[~bad]], headers[src], where)
            out[k] = converted
    return out


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
