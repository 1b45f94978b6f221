"""Reading a workbench request: the body (size-limited as it arrives), its fields checked one by
one with the project's one-line errors, and the simulation's inputs checked as the command line
checks its flags (``api.output_specs``, ``api.te_model_and_specs``: the same functions)."""

from __future__ import annotations

import json
import math
from typing import Callable

from starlette.requests import Request

import rvbacklash.api as api
from rvbacklash.app.designs import MODELS
from rvbacklash.errors import InputError

MAX_BODY_BYTES = 1 << 20  # a design file is ~10 kB; nothing the page sends comes near
MAX_SAMPLES = 10_000_000  # per run of the workbench (the command line has no such limit)
# "specs" keys of a request -> the parameter (and --spec-... flag) of the command line
SPEC_KEYS = {"arcmin": "spec_arcmin", "lost_motion_arcmin": "spec_lost_motion_arcmin",
             "rigidity_nm_per_arcmin": "spec_rigidity_nm_per_arcmin", "preload_um": "spec_preload_um",
             "te_arcsec": "spec_te_arcsec"}
SPEC_FIELDS = {param: f"specs.{key}" for key, param in SPEC_KEYS.items()}
COMMON_FIELDS = {"design", "origin", "edits", "request_id", "channel"}


class BodyTooLarge(Exception):
    pass


async def read_body(request: Request) -> dict:
    """The request's JSON object, at most MAX_BODY_BYTES (checked as it arrives)."""
    kind = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if kind != "application/json":  # a page of another site cannot send this without the workbench's consent (CORS)
        raise InputError("Content-Type", kind or None, "allowed: application/json")
    length = request.headers.get("content-length")
    if length is not None and length.isdigit() and int(length) > MAX_BODY_BYTES:
        raise BodyTooLarge(int(length))
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_BODY_BYTES:
            raise BodyTooLarge(len(body))
    try:
        data = json.loads(body or b"{}")
    except (ValueError, UnicodeDecodeError):
        raise InputError("body", allowed="allowed: a JSON object") from None
    if not isinstance(data, dict):
        raise InputError("body", type(data).__name__, "allowed: a JSON object")
    return data


def check_fields(body: dict, allowed: set[str]) -> None:
    for key in body:
        if key not in allowed | COMMON_FIELDS:
            raise InputError(str(key), allowed=f"unknown field; allowed: {', '.join(sorted(allowed | COMMON_FIELDS))}")


def whole(body: dict, name: str, default: int, low: int, high: int) -> int:
    value = body.get(name, default)
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(name, value, f"allowed: a whole number {low} to {high}")
    return value


def number_or_none(body: dict, name: str, field: str | None = None) -> float | None:
    value = body.get(name)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(field or name, value, "allowed: a finite number")
    return float(value)


def choice(body: dict, name: str, default: str, allowed: tuple[str, ...]) -> str:
    value = body.get(name, default)
    if value not in allowed:
        raise InputError(name, value, f"allowed: {', '.join(allowed)}")
    return value


def renamed_spec_errors(fn: Callable):
    """Errors of the spec checks name the request's ``specs.<key>``, not the Python parameter."""
    try:
        return fn()
    except InputError as e:
        raise e.renamed(SPEC_FIELDS.get(e.field, e.field)) from None


def simulation_inputs(body: dict) -> dict:
    """The keyword arguments of ``api.simulate`` for a request, checked as the command line
    checks its flags (``api.output_specs``, ``api.te_model_and_specs``: the same functions)."""
    check_fields(body, {"model", "samples", "seed", "specs", "method", "format"})
    model = choice(body, "model", "linear", MODELS)
    specs = body.get("specs") or {}
    if not isinstance(specs, dict) or any(k not in SPEC_KEYS for k in specs):
        raise InputError("specs", specs if not isinstance(specs, dict) else sorted(set(specs) - set(SPEC_KEYS)),
                         f"allowed: an object with keys {', '.join(SPEC_KEYS)}")
    limits = {param: number_or_none(specs, key, f"specs.{key}") for key, param in SPEC_KEYS.items()}
    model, by_output = renamed_spec_errors(lambda: api.te_model_and_specs(
        model, limits["spec_te_arcsec"],
        api.output_specs(model, limits["spec_arcmin"], limits["spec_lost_motion_arcmin"],
                         limits["spec_rigidity_nm_per_arcmin"], limits["spec_preload_um"])))
    return {"samples": whole(body, "samples", api.DEFAULT_SAMPLES, 1, MAX_SAMPLES),
            "seed": whole(body, "seed", 0, 0, 2**63 - 1), "method": choice(body, "method", "default",
                                                                           ("default", "box-muller", "sobol")),
            "model": model, "spec_arcmin": limits["spec_arcmin"], "specs": by_output}
