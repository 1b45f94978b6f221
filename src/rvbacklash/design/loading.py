"""Load a Design from a TOML file, a built-in example name, or a dict; turn every
validation failure into one InputError naming the field, the value and the allowed range."""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from rvbacklash.design.bounds import bounds_text
from rvbacklash.design.schema import Design
from rvbacklash.errors import InputError
from rvbacklash.paths import is_file

_EXAMPLES_PACKAGE = "rvbacklash.examples"


def available_examples() -> tuple[str, ...]:
    """Names of the built-in example designs (``sun2014``, ``rv80e``, ...)."""
    files = resources.files(_EXAMPLES_PACKAGE).iterdir()
    return tuple(sorted(p.name.removesuffix(".toml") for p in files if p.name.endswith(".toml")))


def example_text(name: str) -> str:
    """The TOML text of a built-in example."""
    if name not in available_examples():
        raise InputError("design", name, _source_help())
    return resources.files(_EXAMPLES_PACKAGE).joinpath(f"{name}.toml").read_text(encoding="utf-8")


def _source_help() -> str:
    return f"allowed: a path to an existing .toml file or a built-in example ({', '.join(available_examples())})"


def read_design_text(source: str | Path) -> tuple[str, str]:
    """(TOML text, origin label) for a path or example name."""
    path = Path(source)
    if is_file("design", source):
        try:
            return path.read_text(encoding="utf-8-sig"), str(path)  # -sig: a UTF-8 BOM is not content
        except (OSError, UnicodeDecodeError) as e:
            raise InputError("design", str(source), f"cannot read file ({e})") from None
    if str(source) in available_examples():
        return example_text(str(source)), f"example:{source}"
    raise InputError("design", str(source), _source_help())


def load_design(source: str | Path) -> Design:
    """Validated Design from a TOML path or a built-in example name."""
    text, origin = read_design_text(source)
    return design_from_toml(text, origin)


def load_design_source(source: str | Path) -> tuple[Design, str, str]:
    """(validated Design, origin label, TOML text) for a path or example name; the text is what
    a report fingerprints (sha256)."""
    text, origin = read_design_text(source)
    return design_from_toml(text, origin), origin, text


def design_from_toml(text: str, origin: str = "<string>") -> Design:
    try:
        data = tomllib.loads(text.removeprefix("\ufeff"))
    except tomllib.TOMLDecodeError as e:
        raise InputError(origin, allowed=f"malformed TOML: {e}") from None
    return design_from_dict(data)


def design_from_dict(data: dict[str, Any]) -> Design:
    try:
        return Design.model_validate(data)
    except ValidationError as e:
        raise validation_to_input_error(e, Design) from None


# --- turning pydantic errors into one clear line ------------------------------------------

def _submodel(model: type[BaseModel], loc: tuple) -> type[BaseModel] | None:
    """The nested model class reached by following ``loc`` from ``model`` (None if not a model)."""
    cur: type[BaseModel] | None = model
    for part in loc:
        if isinstance(part, int):  # an index into a list of models: the same model
            continue
        if cur is None or part not in cur.model_fields:
            return None
        ann = cur.model_fields[part].annotation
        cur = next((c for c in (*getattr(ann, "__args__", ()), ann)
                    if isinstance(c, type) and issubclass(c, BaseModel)), None)
    return cur


def _field(model: type[BaseModel], loc: tuple) -> Any:
    """FieldInfo at ``loc`` or None."""
    parent = _submodel(model, loc[:-1]) if loc else None  # loc without list indices
    if parent is None or not loc or loc[-1] not in parent.model_fields:
        return None
    return parent.model_fields[loc[-1]]


def _allowed_range(info: Any) -> str:
    """'allowed: finite number > 0 and <= 50 (module m [mm])' from a field's constraints."""
    if info is None:
        return ""
    kind = "integer" if info.annotation is int else "finite number" if info.annotation in (float, float | None) else ""
    spec = " ".join(p for p in (kind, bounds_text(info)) if p)
    desc = f" ({info.description})" if info.description else ""
    return f"allowed: {spec}{desc}" if spec else (info.description or "")


def validation_to_input_error(err: ValidationError, model: type[BaseModel]) -> InputError:
    """The first validation problem as an InputError (the count of the others appended)."""
    # A misspelt key shows up as "unknown" and as "missing": report the unknown one first.
    errors = sorted(err.errors(include_url=False), key=lambda e: e["type"] != "extra_forbidden")
    first = errors[0]
    loc = tuple(first["loc"])
    field = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in loc).lstrip(".") or "design"
    n = len(errors) - 1
    more = f" (and {n} more problem{'s' if n > 1 else ''})" if n else ""
    info = _field(model, tuple(p for p in loc if not isinstance(p, int)))
    kind = first["type"]
    if kind == "missing":
        return InputError(field, allowed="missing required field; " + (_allowed_range(info) or "required") + more)
    if kind == "extra_forbidden":
        holder = _submodel(model, loc[:-1])
        names = ", ".join(holder.model_fields) if holder is not None else "none"
        allowed = f"unknown field; allowed fields here: {names}{more}"
        value = first.get("input")
        return InputError(field, allowed=allowed) if isinstance(value, dict) else InputError(field, value, allowed)
    msg = first["msg"].removeprefix("Value error, ")
    cause = (first.get("ctx") or {}).get("error")
    if isinstance(cause, InputError):  # a rule over several fields that names the one it refuses
        name = cause.field if field == "design" else f"{field}.{cause.field}"
        return InputError(name, cause.value, cause.allowed + more) if cause.has_value else \
            InputError(name, allowed=cause.allowed + more)
    if info is None or isinstance(first.get("input"), dict):  # a rule over several fields: the message names them
        return InputError(field, allowed=msg + more)
    rng = _allowed_range(info)
    return InputError(field, first.get("input"), msg + (f"; {rng}" if rng else "") + more)
