"""A measured unit (UNIT.toml): the deviations of one assembled reducer's cycloid-stage parts
from nominal [um], as a manufacturer inspects them, in the frame of docs/contact.md (pin j at
angle 2 pi j / z_p, counter-clockwise; tooth space k of a disc as the contact model numbers it).
Any array may be left out (zeros). A file holds one unit (``[pins]``, ``[[discs]]``) or several
(``[[unit]]``, as ``simulate --save-units`` writes them).

    [pins]
    radius_um = [...]               # z_p values, + = larger pin
    radial_position_um = [...]      # + = away from the pin-wheel axis
    tangential_position_um = [...]  # + = counter-clockwise
    hole_clearance_um = [...]       # diametral clearance of each pin in its hole
    [[discs]]                       # one table per disc, in disc order
    cumulative_pitch_um = [...]     # z_c values, tooth space k
    equidistance_error_um = 0.0     # optional: this disc's modification errors, run-out offset
    moving_distance_error_um = 0.0  #   (along, across the eccentric) and crank eccentricity error
    runout_um = [0.0, 0.0]
    eccentricity_error_um = 0.0

    [kinematics]                    # optional: the transmission-error model's errors [um]
    centre_gear_eccentricity_um = [x, y]       # in the centre gear's frame
    planet_eccentricity_um = [[x, y], ...]     # one per planet, each in its own frame
    carrier_crank_holes_um = [[x, y], ...]     # crank k's seat in the carrier (k at 2 pi k / P)
    disc_crank_holes_um = [[[x, y], ...], ...] # per disc, per crank hole

Optional per unit: ``crank_angle_deg``, ``other_stages_arcmin`` (the involute and crank stages'
lost motion, Eq. (1)), ``crank_bearing_clearance_um`` (the elastic model's needle-bearing dead
band; with ``other_stages_arcmin`` it also fixes the involute stage's share).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from rvbacklash.design.loading import validation_to_input_error
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.paths import is_file

LIMIT_UM = 1000.0  # a deviation beyond a millimetre is not a measurement of this part


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


Values = list[float]


class MeasuredPins(_Strict):
    radius_um: Values | None = Field(None, description="z_p values [um], + = larger pin")
    radial_position_um: Values | None = Field(None, description="z_p values [um], + = away from the axis")
    tangential_position_um: Values | None = Field(None, description="z_p values [um], + = counter-clockwise")
    hole_clearance_um: Values | None = Field(None, description="z_p values [um], diametral clearance in the hole")


class MeasuredDisc(_Strict):
    cumulative_pitch_um: Values | None = Field(None, description="z_c values [um], tooth space k")
    equidistance_error_um: float = Field(0.0, ge=-LIMIT_UM, le=LIMIT_UM, description="[um], + = thinner teeth")
    moving_distance_error_um: float = Field(0.0, ge=-LIMIT_UM, le=LIMIT_UM, description="[um], + = teeth moved out")
    runout_um: list[float] | None = Field(None, min_length=2, max_length=2,
                                          description="profile-centre offset [along, across] the eccentric [um]")

    @field_validator("runout_um")
    @classmethod
    def _runout_within_limit(cls, v):
        if v is not None and any(abs(x) > LIMIT_UM for x in v):
            raise ValueError(f"allowed: values within +-{LIMIT_UM:g} um")
        return v
    eccentricity_error_um: float = Field(0.0, ge=-LIMIT_UM, le=LIMIT_UM, description="crank eccentricity error [um]")


Vector = list[float]


class MeasuredKinematics(_Strict):
    """Position errors of the parts that only the transmission-error model reads [um] (x, y)."""

    centre_gear_eccentricity_um: Vector | None = Field(None, min_length=2, max_length=2)
    planet_eccentricity_um: list[Vector] | None = Field(None, description="one [x, y] per planet")
    carrier_crank_holes_um: list[Vector] | None = Field(None, description="one [x, y] per crankshaft")
    disc_crank_holes_um: list[list[Vector]] | None = Field(None, description="per disc, one [x, y] per crankshaft")


class MeasuredUnit(_Strict):
    crank_angle_deg: float | None = Field(None, ge=-360, le=360, description="crank angle of the measurement [deg]")
    cycloid_stage_arcmin: float | None = Field(None, description="the play the Monte-Carlo found (informative)")
    other_stages_arcmin: float | None = Field(None, ge=-60, le=60,
                                              description="lost motion of the involute and crank stages [arcmin] "
                                                          "(Eq. (1)); default: their linear means")
    crank_bearing_clearance_um: float | None = Field(None, ge=0, le=LIMIT_UM,
                                                     description="radial clearance of the crank needle bearings "
                                                                 "[um] (elastic model); default: its zone mean")
    pins: MeasuredPins = MeasuredPins()
    discs: list[MeasuredDisc] = Field(default_factory=list)
    kinematics: MeasuredKinematics = MeasuredKinematics()


class UnitFile(_Strict):
    unit: list[MeasuredUnit] = Field(min_length=1)


def _check_lengths(u: MeasuredUnit, design: Design, where: str) -> None:
    s2 = design.second_stage
    for name in MeasuredPins.model_fields:
        values = getattr(u.pins, name)
        if values is None:
            continue
        if len(values) != s2.pins:
            raise InputError(f"{where}pins.{name}", f"{len(values)} values", f"allowed: z_p = {s2.pins} values")
        bad = next((v for v in values if not (math.isfinite(v) and abs(v) <= LIMIT_UM)), None)
        if bad is not None or (name == "hole_clearance_um" and min(values) < 0):
            raise InputError(f"{where}pins.{name}", bad if bad is not None else min(values),
                             f"allowed: finite values{' >= 0' if name == 'hole_clearance_um' else ''} within "
                             f"+-{LIMIT_UM:g} um")
    if u.discs and len(u.discs) != s2.discs:
        raise InputError(f"{where}discs", f"{len(u.discs)} tables", f"allowed: one [[discs]] table per disc "
                                                                     f"({s2.discs}), or none")
    for i, disc in enumerate(u.discs):
        v = disc.cumulative_pitch_um
        if v is not None and len(v) != s2.cycloid_teeth:
            raise InputError(f"{where}discs[{i}].cumulative_pitch_um", f"{len(v)} values",
                             f"allowed: z_c = {s2.cycloid_teeth} values")
        if v is not None and any(not (math.isfinite(x) and abs(x) <= LIMIT_UM) for x in v):
            raise InputError(f"{where}discs[{i}].cumulative_pitch_um", next(x for x in v if not (
                math.isfinite(x) and abs(x) <= LIMIT_UM)), f"allowed: finite values within +-{LIMIT_UM:g} um")


def _check_kinematics(k: MeasuredKinematics, design: Design, where: str) -> None:
    planets, discs = design.first_stage.planets, design.second_stage.discs
    shapes = {"centre_gear_eccentricity_um": (2,), "planet_eccentricity_um": (planets, 2),
              "carrier_crank_holes_um": (planets, 2), "disc_crank_holes_um": (discs, planets, 2)}
    for name, shape in shapes.items():
        v = getattr(k, name)
        if v is None:
            continue
        field = f"{where}kinematics.{name}"
        try:
            ok = list(_shape(v)) == list(shape)
        except ValueError:
            ok = False
        if not ok:
            raise InputError(field, "the given nesting", f"allowed: an array of shape {list(shape)} (planets = "
                                                         f"{planets}, discs = {discs}) of [x, y] pairs")
        flat = _flatten(v)
        bad = next((x for x in flat if not (math.isfinite(x) and abs(x) <= LIMIT_UM)), None)
        if bad is not None:
            raise InputError(field, bad, f"allowed: finite values within +-{LIMIT_UM:g} um")


def _shape(v) -> tuple[int, ...]:
    if not isinstance(v, list):
        return ()
    inner = {_shape(x) for x in v}
    if len(inner) > 1:
        raise ValueError("ragged")
    return (len(v),) + (inner.pop() if inner else ())


def _flatten(v) -> list[float]:
    return [y for x in v for y in _flatten(x)] if isinstance(v, list) else [float(v)]


def units_from_toml(text: str, design: Design, origin: str = "<string>") -> list[MeasuredUnit]:
    """Every unit of a measured-unit file, validated against the design (lengths z_p, z_c, discs)."""
    try:
        data: dict[str, Any] = tomllib.loads(text.removeprefix("\ufeff"))
    except tomllib.TOMLDecodeError as e:
        raise InputError(origin, allowed=f"malformed TOML: {e}") from None
    try:
        units = list(UnitFile.model_validate(data).unit) if "unit" in data else [MeasuredUnit.model_validate(data)]
    except ValidationError as e:
        raise validation_to_input_error(e, UnitFile if "unit" in data else MeasuredUnit) from None
    for k, u in enumerate(units):
        where = f"unit[{k}]." if "unit" in data else ""
        _check_measures_something(u, where or origin)
        _check_lengths(u, design, where)
        _check_kinematics(u.kinematics, design, where)
    return units


def _check_measures_something(u: MeasuredUnit, where: str) -> None:
    """A unit without a single measured array is not a perfect unit: it is an empty or wrong file
    (e.g. an export that wrote nothing), and reading it as zeros would give a plausible answer."""
    if u.discs or any(getattr(u.pins, name) is not None for name in MeasuredPins.model_fields) or \
            any(getattr(u.kinematics, name) is not None for name in MeasuredKinematics.model_fields):
        return
    raise InputError(where.rstrip("."), "no measured values",
                     "allowed: at least one measured array ([pins] radius_um = [...], ... or [[discs]]); an empty "
                     "unit is not read as a perfect one")


def load_units(path: str | Path, design: Design) -> list[MeasuredUnit]:
    p = Path(path)
    if not is_file("measured", path):
        raise InputError("measured", str(path), "allowed: a path to an existing TOML file of measured units")
    try:
        text = p.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError("measured", str(path), f"cannot read file ({e})") from None
    try:
        return units_from_toml(text, design, str(path))
    except InputError as e:  # name the file: the fields of a unit file are not the command's flags
        raise e.renamed(f"{path}: {e.field}") if not e.field.startswith(str(path)) else e from None


def _nested(v) -> str:
    return "[" + ", ".join(_nested(x) for x in v) + "]" if isinstance(v, list) and v and isinstance(v[0], list) \
        else _array(v)


def _array(values) -> str:
    return "[" + ", ".join(f"{v:.10g}" for v in values) + "]"


def units_to_toml(units: list[MeasuredUnit], header: str = "") -> str:
    """The TOML text of several units (``[[unit]]``), readable by units_from_toml."""
    lines = [f"# {line}" for line in header.splitlines()] + ([""] if header else [])
    for u in units:
        lines.append("[[unit]]")
        for name in ("crank_angle_deg", "cycloid_stage_arcmin", "other_stages_arcmin", "crank_bearing_clearance_um"):
            v = getattr(u, name)
            if v is not None:
                lines.append(f"{name} = {v:.9g}")
        lines.append("[unit.pins]")
        for name in MeasuredPins.model_fields:
            v = getattr(u.pins, name)
            if v is not None:
                lines.append(f"{name} = {_array(v)}")
        for d in u.discs:
            lines.append("[[unit.discs]]")
            if d.cumulative_pitch_um is not None:
                lines.append(f"cumulative_pitch_um = {_array(d.cumulative_pitch_um)}")
            lines += [f"equidistance_error_um = {d.equidistance_error_um:.10g}",
                      f"moving_distance_error_um = {d.moving_distance_error_um:.10g}"]
            if d.runout_um is not None:
                lines.append(f"runout_um = {_array(d.runout_um)}")
            lines.append(f"eccentricity_error_um = {d.eccentricity_error_um:.10g}")
        kin = {name: getattr(u.kinematics, name) for name in MeasuredKinematics.model_fields}
        if any(v is not None for v in kin.values()):
            lines.append("[unit.kinematics]")
            lines += [f"{name} = {_nested(v)}" for name, v in kin.items() if v is not None]
        lines.append("")
    return "\n".join(lines)
