"""The JSON Schema of each command's JSON output, generated from the typed results.

A result is a frozen dataclass whose ``to_dict()`` is ``results.plain``: its exported fields in
order (``KEY`` renames one, ``EXPORT: False`` leaves it out), numpy arrays as lists, tuples as
arrays, non-finite floats as null. This module walks the same fields with their type hints and
writes what ``plain`` writes, so a field added to a result is in its schema the moment it exists;
``tests/report/test_schemas.py`` validates real outputs of every command against these schemas.

Every JSON file the CLI writes also carries ``schema_version`` (``rvbacklash._version.SCHEMA_VERSION``,
recorded in CHANGELOG.md) and ``rvbacklash_version`` at its top level (``report.files.stamped``).
"""

from __future__ import annotations

import dataclasses
import enum
import types
import typing
from collections.abc import Mapping
from typing import Any, Callable

import numpy as np

from rvbacklash._version import SCHEMA_VERSION
from rvbacklash.analysis.allocation import AllocationResult
from rvbacklash.analysis.bench import BenchResult
from rvbacklash.analysis.calibration import CalibrationResult
from rvbacklash.analysis.capacity import CapacityResult
from rvbacklash.analysis.losses import EfficiencyResult
from rvbacklash.analysis.service_life.results import ServiceLifeResult
from rvbacklash.analysis.contact import NominalContact
from rvbacklash.analysis.hysteresis import HysteresisResult
from rvbacklash.analysis.sensitivity_global import SensitivityResult
from rvbacklash.analysis.selection.assembly import AssemblySheet
from rvbacklash.analysis.selection.run import SelectionResult
from rvbacklash.analysis.simulation import SimulationResult
from rvbacklash.analysis.stackup import FactorResult, StageResult, TotalResult
from rvbacklash.analysis.sweep import SweepResult
from rvbacklash.analysis.transmission import TransmissionErrorResult
from rvbacklash.geometry.reducer import DerivedGeometry
from rvbacklash.results import EXPORT, KEY

DIALECT = "https://json-schema.org/draft/2020-12/schema"


class _Generator:
    """JSON Schema of the plain form of types; each dataclass once, in ``$defs``."""

    def __init__(self) -> None:
        self.defs: dict[str, dict] = {}

    def of(self, tp: Any) -> dict:
        origin, args = typing.get_origin(tp), typing.get_args(tp)
        if tp is Any or tp is object:
            return {}
        if tp is type(None):
            return {"type": "null"}
        if origin in (typing.Union, types.UnionType):
            parts = [self.of(a) for a in args]
            return parts[0] if len(parts) == 1 else {"anyOf": parts}
        if origin is typing.Literal:
            return {"enum": list(args)}
        if isinstance(tp, type) and dataclasses.is_dataclass(tp):
            return self.dataclass_ref(tp)
        if isinstance(tp, type) and issubclass(tp, enum.Enum):
            return {"enum": [m.value for m in tp]}
        if tp is bool:
            return {"type": "boolean"}
        if tp is int or tp is np.integer:
            return {"type": "integer"}
        if tp is float or tp is np.floating:  # a non-finite float is written as null
            return {"type": ["number", "null"]}
        if tp is str or tp is bytes:
            return {"type": "string"}
        if tp is np.ndarray or origin is np.ndarray:  # numbers, or nested lists of them
            return {"type": "array"}
        if origin in (tuple, list, typing.Sequence) or tp in (tuple, list):
            if origin is tuple and args and args[-1] is not Ellipsis:  # a fixed-length tuple
                return {"type": "array", "prefixItems": [self.of(a) for a in args], "minItems": len(args),
                        "maxItems": len(args)}
            return {"type": "array", "items": self.of(args[0])} if args else {"type": "array"}
        if origin in (dict, Mapping, typing.Mapping) or tp in (dict, Mapping):
            return {"type": "object", "additionalProperties": self.of(args[1])} if args else {"type": "object"}
        raise TypeError(f"no JSON schema for {tp!r}")

    def dataclass_ref(self, cls: type) -> dict:
        name = cls.__name__
        if name not in self.defs:
            self.defs[name] = {}  # a placeholder: recursive types end here
            self.defs[name] = self.dataclass_schema(cls)
        return {"$ref": f"#/$defs/{name}"}

    def dataclass_schema(self, cls: type) -> dict:
        hints = typing.get_type_hints(cls)
        props = {f.metadata.get(KEY, f.name): self.of(hints[f.name]) for f in dataclasses.fields(cls)
                 if f.metadata.get(EXPORT, True)}
        doc = (cls.__doc__ or "").strip().split("\n\n")[0]
        return {"type": "object", "description": " ".join(doc.split()), "properties": props,
                "required": list(props), "additionalProperties": False}


def _stackup(g: _Generator) -> dict:
    """``StackupResult.to_dict``: the design's name beside its derived geometry."""
    geometry = g.dataclass_schema(DerivedGeometry)
    design = {**geometry, "properties": {"name": {"type": "string"}, **geometry["properties"]},
              "required": ["name", *geometry["required"]]}
    props = {"design": design, "factors": g.of(tuple[FactorResult, ...]), "stages": g.of(dict[str, StageResult]),
             "total": g.of(TotalResult), "notes": g.of(dict[str, str])}
    return {"type": "object", "description": "The linear stack-up (the paper's Table 2, extended).",
            "properties": props, "required": list(props), "additionalProperties": False}


def _result(cls: type) -> Callable[[_Generator], dict]:
    return lambda g: g.dataclass_schema(cls)


def _contact(g: _Generator) -> dict:
    """``contact --json``: one unit's ``NominalContact``, or with several measured units (``--measured``
    without ``--unit``) the design's name and every unit's."""
    one = g.dataclass_schema(NominalContact)
    many = {"type": "object", "description": "Every unit of a file of measured units.",
            "properties": {"design": {"type": "string"}, "units": {"type": "array", "items": g.of(NominalContact)}},
            "required": ["design", "units"], "additionalProperties": False}
    return {"anyOf": [one, many]}


# command -> (the schema of its result, what the JSON is)
OUTPUTS: dict[str, tuple[Callable[[_Generator], dict], str]] = {
    "simulate": (lambda g: {"anyOf": [g.dataclass_schema(SimulationResult), g.dataclass_schema(SelectionResult)]},
                 "rvbacklash simulate --json: a Monte-Carlo run (or the exact distribution); figures under "
                 "outputs.<quantity>; with --select, the run with random and with selective assembly side by side "
                 "(random_run, selected_run, yields, classes; issue 39)"),
    "analyze": (_stackup, "rvbacklash analyze --json: the linear stack-up"),
    "hysteresis": (_result(HysteresisResult),
                   "rvbacklash hysteresis --json: the test bench's hysteresis loop of one unit"),
    "allocate": (_result(AllocationResult),
                 "rvbacklash allocate --json: the cheapest grades that meet the spec"),
    "sensitivity": (_result(SensitivityResult),
                    "rvbacklash sensitivity --json: Sobol indices per factor"),
    "sweep": (_result(SweepResult),
              "rvbacklash sweep --format json: one row per design point"),
    "transmission-error": (_result(TransmissionErrorResult),
                           "rvbacklash transmission-error --json: one unit's transmission error and rigid lost "
                           "motion over a full output revolution, its spectrum"),
    "bench": (_result(BenchResult),
              "rvbacklash bench --json: measured units (hysteresis loops, TE curves) read by the model's definitions, "
              "each unit's figures under the hysteresis / transmission-error field names"),
    "calibrate": (_result(CalibrationResult),
                  "rvbacklash calibrate --json: the design's unknowns fitted to measured loops, with 95 % intervals"),
    "capacity": (_result(CapacityResult),
                 "rvbacklash capacity --json: the nominal unit's capacity and life: each bearing's load, rating and "
                 "L10, the reducer's life, the derived rated torque, momentary maximum and acceleration torques, the "
                 "main bearings, the loads over a revolution (issue 37)"),
    "efficiency": (_result(EfficiencyResult),
                   "rvbacklash efficiency --json: the nominal unit's losses per element at the rated point, the "
                   "efficiency map, no-load running, starting and back-driving torques, a duty cycle's thermal "
                   "balance with lost motion and backlash at its temperature (issue 40)"),
    "assemble": (_result(AssemblySheet),
                 "rvbacklash assemble --json: the assembly sheet of a measured batch, one row per unit (issue 39)"),
    "service-life": (_result(ServiceLifeResult),
                     "rvbacklash service-life --json: the nominal unit's lost motion, backlash and rigidity over the "
                     "hours of a duty cycle, its contacts' wear rates and worn flank, the production run's yield and "
                     "accuracy life (issue 38)"),
    "contact": (_contact, "rvbacklash contact --json: the play of one unit (or of every measured unit) from the "
                          "exact cycloid-pin geometry"),
}


def output_schema(output: str) -> dict:
    """The JSON Schema (draft 2020-12) of the JSON that ``rvbacklash <output>`` writes."""
    g = _Generator()
    body = OUTPUTS[output][0](g)
    stamps = {"schema_version": {"const": SCHEMA_VERSION, "description": "version of the output formats "
                                                                           "(CHANGELOG.md)"},
              "rvbacklash_version": {"type": "string", "description": "the rvbacklash that wrote the file"}}

    def stamped(form: dict) -> dict:
        return {"properties": {**stamps, **form["properties"]}, "required": [*stamps, *form["required"]],
                "additionalProperties": False}

    schema = {"$schema": DIALECT, "$id": f"https://rvbacklash.invalid/schema/{SCHEMA_VERSION}/{output}.json",
              "title": f"rvbacklash {output} output", "description": OUTPUTS[output][1], "type": "object",
              **({"anyOf": [{"type": "object", **stamped(form)} for form in body["anyOf"]]} if "anyOf" in body
                 else stamped(body))}
    if g.defs:
        schema["$defs"] = dict(sorted(g.defs.items()))
    return schema
