"""The one Jinja2 environment of the report's templates (templates/*.j2), with its filters:
``fmt`` (a number in a format spec, "–" for None) and ``unit`` (a field-name unit as printed)."""

from __future__ import annotations

import jinja2

from rvbacklash.units import display_unit


def _fmt(value, spec: str = ".4f") -> str:
    return "–" if value is None else format(value, spec)


def environment() -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.PackageLoader("rvbacklash.report", "templates"),
                             autoescape=jinja2.select_autoescape(["html", "j2"]), undefined=jinja2.StrictUndefined)
    env.filters["fmt"] = _fmt
    env.filters["unit"] = display_unit
    return env
