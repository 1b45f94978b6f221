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
MAX_DEPTH = 16  # nesting of a body's objects and lists (the page sends 3: {"edits": {"path": value}})
MAX_LABEL = 200  # characters of request_id and channel (a label; ids are kept for progress and cancel)
# The most samples each job accepts, by model: what it finishes in about a minute on a 2-core machine
# (CPU per unit: linear 0.1 us, contact 8 us, elastic 50 us, transmission 530 us sampled, ~5 ms with its TE refined
# between positions since schema 9.0: its caps cut tenfold; bench/bench_app_stop.py).
# A Sobol run evaluates N (D + 2) units (D ~ 20 groups); an allocation up to 200 candidates of `samples`
# each. Beyond: the command line, which has no such limit (and Ctrl-C).
SAMPLE_CAPS = {
    "simulate": {"linear": 10_000_000, "contact": 10_000_000, "elastic": 2_000_000, "transmission": 20_000},
    "sensitivity": {"linear": 1 << 20, "contact": 1 << 19, "elastic": 1 << 16, "transmission": 1 << 10},
    "allocate": {"contact": 1 << 16, "elastic": 10_000, "transmission": 1000},
    "elastic-section": {"elastic": 10_000},  # one draw and evaluation, then four loops: not interruptible, ~0.5 CPU-s
    "service-life": {"elastic": 10_000},  # each unit worn step by step: 10 000 units to 6000 h ~15 CPU-s
}
SAMPLE_CAPS["report"] = SAMPLE_CAPS["simulate"]
MAX_SAMPLES = max(SAMPLE_CAPS["simulate"].values())
# "specs" keys of a request -> the parameter (and --spec-... flag) of the command line
SPEC_KEYS = {"arcmin": "spec_arcmin", "lost_motion_arcmin": "spec_lost_motion_arcmin",
             "rigidity_nm_per_arcmin": "spec_rigidity_nm_per_arcmin", "preload_um": "spec_preload_um",
             "te_arcsec": "spec_te_arcsec"}
SPEC_FIELDS = {param: f"specs.{key}" for key, param in SPEC_KEYS.items()}
# API parameter -> the request's field, per endpoint where they differ (the command line's cli.common.FLAGS
# maps them to its flags): an error names what the request (and the page's control) calls it
REQUEST_FIELDS = {"simulate": SPEC_FIELDS, "report": SPEC_FIELDS, "selection": SPEC_FIELDS,
                  "allocate": {"yield_target": "yield"}}
COMMON_FIELDS = {"design", "origin", "edits", "request_id", "channel"}


def samples_cap(job: str, model: str) -> int:
    """The most samples ``job`` (an endpoint's name) accepts with ``model``."""
    return SAMPLE_CAPS[job][model]


def nesting_depth(data) -> int:
    """How deep lists and objects nest in parsed JSON (iterative: any depth)."""
    deepest, todo = 0, [(data, 1)]
    while todo:
        item, depth = todo.pop()
        if isinstance(item, (dict, list)):
            deepest = max(deepest, depth)
            todo.extend((v, depth + 1) for v in (item.values() if isinstance(item, dict) else item))
    return deepest


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
    too_deep = InputError("body", allowed=f"nested too deep; allowed: a JSON object nested at most {MAX_DEPTH} deep")
    try:
        data = json.loads(body or b"{}")
    except RecursionError:  # the parser's own limit (~1000 levels)
        raise too_deep from None
    except (ValueError, UnicodeDecodeError):
        raise InputError("body", allowed="allowed: a JSON object") from None
    if not isinstance(data, dict):
        raise InputError("body", type(data).__name__, "allowed: a JSON object")
    if nesting_depth(data) > MAX_DEPTH:  # what is read from it later (edits, the cache's key) recurses too
        raise too_deep
    for name in ("request_id", "channel"):
        if name in data and (not isinstance(data[name], (str, int)) or isinstance(data[name], bool)
                             or len(str(data[name])) > MAX_LABEL):
            raise InputError(name, str(data[name])[:40] + "...", f"allowed: a string or whole number of at most "
                                                                 f"{MAX_LABEL} characters")
    return data


def check_fields(body: dict, allowed: set[str]) -> None:
    for key in body:
        if key not in allowed | COMMON_FIELDS:
            raise InputError(str(key), allowed=f"unknown field; allowed: {', '.join(sorted(allowed | COMMON_FIELDS))}")


def whole(body: dict, name: str, default: int, low: int, high: int, why: str = "") -> int:
    value = body.get(name, default)
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(name, value, f"allowed: a whole number {low} to {high}{why}")
    return value


def samples(body: dict, job: str, model: str, default: int, low: int = 1) -> int:
    """The request's ``samples``, within what ``job`` finishes with ``model`` (SAMPLE_CAPS); a
    Sobol run's a power of two."""
    high = samples_cap(job, model)
    where = f" for the {model} model in the workbench (the command line has no limit)"
    n = whole(body, "samples", min(default, high), low, high, where)
    if job == "sensitivity" and n & (n - 1):
        raise InputError("samples", n, f"allowed: a power of two {low} to {high}{where}")
    return n


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
    return {"samples": samples(body, "simulate", model, api.DEFAULT_SAMPLES),
            "seed": whole(body, "seed", 0, 0, 2**63 - 1), "method": choice(body, "method", "default",
                                                                           ("default", "box-muller", "sobol")),
            "model": model, "spec_arcmin": limits["spec_arcmin"], "specs": by_output}
