"""The workbench's designs: a built-in example or TOML text sent in a request (never a path),
what-if edits applied to that text with its comments kept, and the controls the page shows.

An edit is a dotted path into the design file and a new value (``"grades.cycloid": 4``,
``"factors.pin_hole_clearance.upper_um": 6.0``); ``null`` removes the key (so that
``plus_minus_um`` can give way to ``lower_um``/``upper_um``). The edited text is what the
analyses prepare, what is downloaded and what the command line re-runs.
"""

from __future__ import annotations

import functools
import json
import re
from collections import OrderedDict
from dataclasses import dataclass
from threading import Lock
from typing import Any, Mapping

import tomlkit
from tomlkit.items import Comment, Table, Whitespace

from rvbacklash.design.loading import available_examples, design_from_toml, example_text
from rvbacklash.errors import InputError
from rvbacklash.factors.catalog import CATALOG
from rvbacklash.problem import Problem, prepare
from rvbacklash.problem.zones import NOMINAL_MODIFICATION

MAX_EDITS = 200  # more than every control of a design at once
_KEY = re.compile(r"^[A-Za-z0-9_]{1,64}$")
MODIFICATIONS = tuple(f"second_stage.{field}" for field in NOMINAL_MODIFICATION.values())
MODELS = ("linear", "contact", "elastic", "transmission")


@dataclass(frozen=True)
class EditedDesign:
    """A design as the workbench runs it: its edited TOML text and the prepared problem."""

    text: str
    origin: str
    problem: Problem


def source_text(design: Any, origin: Any = None) -> tuple[str, str]:
    """(TOML text, origin label) of a request's ``design``: a built-in example's name or the text
    of a design file. A path is never opened: any other string is read as TOML (a path is then
    refused as malformed TOML, as any other text that is not a design)."""
    if not isinstance(design, str) or not design.strip():
        raise InputError("design", design if not isinstance(design, str) else design[:40],
                         f"allowed: TOML text of a design or a built-in example ({', '.join(available_examples())})")
    if design in available_examples():
        return example_text(design), f"example:{design}"
    label = origin if isinstance(origin, str) and origin.strip() else "design"
    return design, label[:200]


def _check_edits(edits: Any) -> dict[str, Any]:
    if edits is None:
        return {}
    if not isinstance(edits, Mapping) or len(edits) > MAX_EDITS:
        raise InputError("edits", type(edits).__name__ if not isinstance(edits, Mapping) else f"{len(edits)} edits",
                         f"allowed: an object of at most {MAX_EDITS} 'dotted.path': value pairs")
    for path, value in edits.items():
        keys = str(path).split(".")
        if not 1 <= len(keys) <= 4 or not all(_KEY.match(k) for k in keys):
            raise InputError("edits", path, "allowed: a dotted path of design-file keys, e.g. grades.cycloid")
        if not (value is None or isinstance(value, (bool, int, float, str))):
            raise InputError(str(path), value, "allowed: a number, a string, true/false or null (remove the key)")
    return dict(edits)


def _append(table, key: str, value: Any) -> None:
    """Add a key to a table before the comments and blank lines that end it (they belong to what
    follows: the next table's heading comment), so an edited file reads as the original."""
    body = table.value.body if isinstance(table, Table) else table.body
    last = max((i for i, (k, item) in enumerate(body) if k is not None or not isinstance(item, (Comment, Whitespace))),
               default=-1)
    container = table.value if isinstance(table, Table) else table
    try:
        container._insert_at(last + 1, key, value)  # tomlkit keeps its items in order: no public insert-at
    except Exception:  # pragma: no cover - a tomlkit without it: appended (the same file, comments moved)
        table[key] = value


@functools.lru_cache(maxsize=8)
def _checked(text: str, origin: str) -> None:
    """Validate a design's text once (a what-if loop edits the same text again and again)."""
    design_from_toml(text, origin)


def _trailing(body: list) -> int:
    """How many items at the end of a table's body are comments and blank lines."""
    n = 0
    while n < len(body) and body[-1 - n][0] is None and isinstance(body[-1 - n][1], (Comment, Whitespace)):
        n += 1
    return n


def _new_table(parent, key: str) -> None:
    """A new table ``key`` in ``parent``, placed before the comments that end the table before it
    (they head what follows it: they move below the new table)."""
    new = tomlkit.table()
    siblings = parent.value.body if isinstance(parent, Table) else parent.body
    last = next((item for k, item in reversed(siblings) if isinstance(item, Table)), None)
    moved = []
    if last is not None and _trailing(last.value.body):
        n = _trailing(last.value.body)
        moved = last.value.body[-n:]
        del last.value.body[-n:]
        if not any(isinstance(item, Whitespace) for _, item in moved[:1]):
            moved.insert(0, (None, tomlkit.ws("\n")))
    parent[key] = new
    for _, item in moved:
        new.value.body.append((None, item))


def edited_text(text: str, edits: Mapping[str, Any], origin: str = "design") -> str:
    """``text`` with ``edits`` applied, comments and layout kept (tomlkit)."""
    edits = _check_edits(edits)
    if not edits:
        return text
    _checked(text, origin)  # the text itself first: its own error before any edit's
    doc = tomlkit.parse(text.removeprefix("\ufeff"))
    for path, value in edits.items():
        *parents, leaf = path.split(".")
        table = doc
        for key in parents:
            if key not in table:
                if value is None:
                    break
                _new_table(table, key)
            table = table[key]
            if not hasattr(table, "get"):
                raise InputError(path, value, f"'{key}' is a value, not a table; allowed: a path to a field")
        else:
            if value is None:
                table.pop(leaf, None) if hasattr(table, "pop") else None
            elif leaf in table:
                table[leaf] = value
            else:
                _append(table, leaf, value)
    return tomlkit.dumps(doc)


class DesignCache:
    """The last few edited designs, prepared once (a what-if loop goes back and forth)."""

    def __init__(self, size: int = 16):
        self._items: OrderedDict[str, EditedDesign] = OrderedDict()
        self._size, self._lock = size, Lock()

    def get(self, design: Any, edits: Any = None, origin: Any = None) -> EditedDesign:
        text, label = source_text(design, origin)
        key = json.dumps([text, label, edits], sort_keys=True, default=str)
        with self._lock:
            if key in self._items:
                self._items.move_to_end(key)
                return self._items[key]
        new = edited_text(text, edits or {}, label)
        d = design_from_toml(new, label)
        item = EditedDesign(new, label, prepare(d, label, new))
        with self._lock:
            self._items[key] = item
            while len(self._items) > self._size:
                self._items.popitem(last=False)
        return item


def controls(item: EditedDesign) -> dict:
    """What the page shows a control for: the grades, every factor's zone (resolved: from its
    grade or explicit, with its origin), the modifications, the models this design can run."""
    p = item.problem
    d = p.design
    grades = d.grades
    factors = []
    for f, zone in zip(CATALOG, p.zones):
        if f.key in NOMINAL_MODIFICATION:
            continue
        explicit = getattr(d.factors, f.key)
        factors.append({"key": f.key, "id": f.id, "name": f.name, "symbol": f.symbol, "stage": f.stage.label,
                        "lower_um": zone.lower_um, "upper_um": zone.upper_um, "distribution": zone.distribution,
                        "origin": zone.origin, "explicit": explicit is not None and explicit.has_zone,
                        "plus_minus": explicit is not None and explicit.plus_minus_um is not None})
    return {
        "name": p.name, "origin": item.origin, "text": item.text,
        "grades": None if grades is None else {"edition": grades.edition, "involute": grades.involute,
                                               "cycloid": grades.cycloid, "crank": grades.crank,
                                               "range": [0, 12] if grades.edition == "1995" else [1, 11]},
        "factors": factors,
        "modifications": {path: getattr(d.second_stage, path.split(".")[1]) for path in MODIFICATIONS},
        "models": [m for m in MODELS if m != "elastic" or d.elastic is not None],
        "examples": list(available_examples()),
    }
