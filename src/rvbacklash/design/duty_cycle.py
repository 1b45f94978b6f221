"""A duty cycle (docs/capacity.md, "Duty cycle"): the steps of a reducer's work as the makers'
selection procedures tabulate them — each step's time (or time share), output speed and output
torque, and, for the main bearings, the external moment, thrust and radial load acting meanwhile.
One reader for every analysis that runs a reducer through its work (capacity and life; wear over
the service life and the losses read the same file).

CSV (a header row, one step per row) or TOML (``[[step]]`` tables), with these columns/keys:

- ``time_share`` [-] or ``time_s`` [s] (one of the two, for every step; they are normalised to
  shares of the cycle): >= 0, summing to > 0;
- ``output_speed_rpm`` [r/min] >= 0 (0: a hold, no revolutions);
- ``output_torque_nm`` [N m] (signed: a negative torque loads the other flanks);
- optional ``moment_nm`` [N m] >= 0, ``thrust_n`` [N], ``radial_n`` [N] >= 0: the external loads on
  the output's main bearings (default 0).

Bad input is one line naming the file, the step (1-based row) and the column, the value and what is
allowed (``InputError``).
"""

from __future__ import annotations

import csv
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from rvbacklash.errors import InputError
from rvbacklash.results import Result

REQUIRED = ("output_speed_rpm", "output_torque_nm")
OPTIONAL = ("moment_nm", "thrust_n", "radial_n")
TIMES = ("time_share", "time_s")
MAX_STEPS = 10_000
LIMITS = {"time_share": (0.0, 1e12), "time_s": (0.0, 1e12), "output_speed_rpm": (0.0, 1e5),
          "output_torque_nm": (-1e8, 1e8), "moment_nm": (0.0, 1e9), "thrust_n": (-1e9, 1e9), "radial_n": (0.0, 1e9)}


@dataclass(frozen=True, repr=False)
class DutyStep(Result):
    """One step of a duty cycle: its share of the cycle's time and its loads."""

    time_share: float
    output_speed_rpm: float
    output_torque_nm: float
    moment_nm: float = 0.0
    thrust_n: float = 0.0
    radial_n: float = 0.0


@dataclass(frozen=True, repr=False)
class DutyCycle(Result):
    """A duty cycle's steps (time shares summing to 1) and the file it came from."""

    source: str
    steps: tuple[DutyStep, ...]

    def rows(self) -> list[dict]:
        return [s.to_dict() for s in self.steps]

    def summary(self) -> list[str]:
        return [f"{len(self.steps)} steps from {self.source}", f"mean output speed {self.mean_speed_rpm:.4g} r/min"]

    @property
    def mean_speed_rpm(self) -> float:
        """N_m = sum t_i n_i / sum t_i (the makers' mean output speed)."""
        return sum(s.time_share * s.output_speed_rpm for s in self.steps)

    def mean_torque_nm(self, exponent: float = 10.0 / 3.0) -> float:
        """T_m = (sum t_i n_i |T_i|^p / sum t_i n_i)^(1/p): the life-equivalent mean torque of the makers'
        selection procedure (p = 10/3, the roller bearings'); 0 when the cycle never turns."""
        revs = sum(s.time_share * s.output_speed_rpm for s in self.steps)
        if revs <= 0.0:
            return 0.0
        return (sum(s.time_share * s.output_speed_rpm * abs(s.output_torque_nm) ** exponent for s in self.steps)
                / revs) ** (1.0 / exponent)


def read_duty_cycle(path: str | Path) -> DutyCycle:
    """The DutyCycle of a CSV or TOML file (module docstring)."""
    p = Path(path)
    field = "duty_cycle"
    if not p.is_file():
        raise InputError(field, str(path), "allowed: a readable CSV or TOML file of duty-cycle steps")
    try:
        text = p.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(field, str(path), f"allowed: a readable UTF-8 text file ({type(e).__name__})") from None
    if p.suffix.lower() == ".toml":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise InputError(field, str(path), f"allowed: valid TOML ({e})") from None
        unknown = [k for k in data if k != "step"]
        if unknown:
            raise InputError(f"{p.name}: {unknown[0]}", "given", "allowed: [[step]] tables only")
        rows = data.get("step", [])
        if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
            raise InputError(f"{p.name}: step", "given", "allowed: [[step]] tables")
    else:
        reader = csv.DictReader(line for line in text.splitlines() if line.strip() and not line.startswith("#"))
        rows = [dict(r) for r in reader]
        if reader.fieldnames is None:
            raise InputError(field, str(path), "allowed: a CSV file with a header row "
                                               "(time_share or time_s, output_speed_rpm, output_torque_nm, ...)")
    return DutyCycle(str(path), _steps(p.name, rows))


def _steps(name: str, rows: list[dict]) -> tuple[DutyStep, ...]:
    if not rows:
        raise InputError(name, "no steps", "allowed: at least one step")
    if len(rows) > MAX_STEPS:
        raise InputError(name, f"{len(rows)} steps", f"allowed: at most {MAX_STEPS}")
    columns = set(rows[0])
    times = [t for t in TIMES if t in columns]
    if len(times) != 1:
        raise InputError(f"{name}: time_share", "missing" if not times else "both",
                         "allowed: exactly one of the columns time_share [-] and time_s [s]")
    for key in REQUIRED:
        if key not in columns:
            raise InputError(f"{name}: {key}", "missing", f"allowed: a column {key}")
    known = set(TIMES) | set(REQUIRED) | set(OPTIONAL)
    values = []
    for i, row in enumerate(rows, start=1):
        extra = [k for k in row if k not in known and k is not None]
        if extra or None in row:
            bad = extra[0] if extra else "(a value without a column)"
            raise InputError(f"{name}: step {i}: {bad}", "given",
                             f"allowed columns: {', '.join(TIMES + REQUIRED + OPTIONAL)}")
        v = {}
        for key in (times[0],) + REQUIRED + OPTIONAL:
            raw = row.get(key)
            if raw is None or (isinstance(raw, str) and raw.strip() == ""):
                if key in OPTIONAL:
                    v[key] = 0.0
                    continue
                raise InputError(f"{name}: step {i}: {key}", "missing", "allowed: a number")
            try:
                x = float(raw) if not isinstance(raw, bool) else math.nan
            except (TypeError, ValueError):
                x = math.nan
            lo, hi = LIMITS[key]
            if not (math.isfinite(x) and lo <= x <= hi):
                raise InputError(f"{name}: step {i}: {key}", raw, f"allowed: a number from {lo:g} to {hi:g}")
            v[key] = x
        values.append(v)
    total = sum(v[times[0]] for v in values)
    if not total > 0.0:
        raise InputError(f"{name}: {times[0]}", total, "allowed: times summing to more than 0")
    return tuple(DutyStep(v[times[0]] / total, v["output_speed_rpm"], v["output_torque_nm"], v["moment_nm"],
                          v["thrust_n"], v["radial_n"]) for v in values)
