"""A design as a TOML design file (``allocate --write-design``): the same tables and fields as
the schema, loadable by ``rvbacklash.load_design`` to an equal Design.

Only what a Design holds is written: tables (nested models and dicts), strings, booleans,
integers, floats, lists (of scalars or lists); None fields are left out (they take their
defaults again on loading)."""

from __future__ import annotations

import json
import math
import re
from typing import Any

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"a design holds finite numbers only; got {v}")
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # JSON escapes are TOML basic-string escapes
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(str(k))} = {_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _emit(table: dict, path: list[str], out: list[str]) -> None:
    scalars = {k: v for k, v in table.items() if not isinstance(v, dict)}
    subs = {k: v for k, v in table.items() if isinstance(v, dict) and v}
    if path and scalars:
        out.append("")
        out.append("[" + ".".join(_key(p) for p in path) + "]")
    for k, v in scalars.items():
        out.append(f"{_key(str(k))} = {_value(v)}")
    for k, v in subs.items():
        _emit(v, path + [str(k)], out)


def design_toml(design, header: str = "") -> str:
    """TOML text of a Design; ``header`` lines are written first as comments."""
    data = design.model_dump(exclude_none=True)
    out = [f"# {line}".rstrip() for line in header.splitlines()]
    _emit(data, [], out)
    return "\n".join(out).lstrip("\n") + "\n"
