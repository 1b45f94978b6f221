"""Results of per-design finite-element models, computed once: kept in process and on disk,
keyed by everything the model reads (its inputs and the model's version), so that a production
run, a sweep or the next command of the same design never meshes or solves again.

The disk cache lives in ``$RVBACKLASH_CACHE_DIR`` (default ``~/.cache/rvbacklash``), one JSON file
per result under ``fe/``; a cache that cannot be read or written is skipped (the result is
computed again), never an error: it only saves time.

The results of the built-in examples ship with the package (``SHIPPED``, the same files, written
by ``tools/ship_fe_results.py``): a fresh install never meshes or solves them (tens of seconds of
a first `make example`), and every machine reads the same numbers for them. They are found by
the same key as any other result, so a change of a model's inputs or of its version simply
misses them (tests/mechanics/test_fe_cache.py says when they are due to be written again).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rvbacklash.atomic import atomic_write
from rvbacklash.errors import InputError

_MEMORY: dict[str, dict[str, Any]] = {}
SHIPPED: Path | None = Path(__file__).resolve().parent / "data" / "fe"  # None: not read (tools, tests)


def cache_dir() -> Path:
    """The folder of the disk cache (``$RVBACKLASH_CACHE_DIR``, default ``~/.cache/rvbacklash``)."""
    root = os.environ.get("RVBACKLASH_CACHE_DIR")
    return Path(root) if root else Path.home() / ".cache" / "rvbacklash"


def cache_key(kind: str, version: int, inputs: dict[str, Any]) -> str:
    """A stable key of a model's inputs: sha256 of their canonical JSON (floats as repr: a change
    in the last bit is another geometry)."""
    text = json.dumps({"kind": kind, "version": version, "inputs": inputs}, sort_keys=True, allow_nan=True)
    return f"{kind}-{hashlib.sha256(text.encode()).hexdigest()[:32]}"


def cached(kind: str, version: int, inputs: dict[str, Any], compute: Callable[[], dict[str, Any]],
           disk: bool = True) -> dict[str, Any]:
    """``compute()`` (a JSON-able dict) for ``inputs``, from memory, else from disk (the user's
    cache, then the results shipped with the package), else computed and stored in memory and in
    the user's cache. ``version``: the model's version (raise it when the model changes what it
    computes: older files are then never read)."""
    key = cache_key(kind, version, inputs)
    hit = _MEMORY.get(key)
    if hit is not None:
        return hit
    path = cache_dir() / "fe" / f"{key}.json"
    if disk:
        for where in (path, SHIPPED and SHIPPED / f"{key}.json"):
            hit = _read(where, inputs) if where else None
            if hit is not None:
                _MEMORY[key] = hit
                return hit
    result = compute()
    _MEMORY[key] = result
    if disk:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            atomic_write("cache", path, json.dumps({"inputs": inputs, "result": result}, sort_keys=True))
        except (OSError, InputError):
            pass  # a cache that cannot be written only costs the next run the computation
    return result


def _read(path: Path, inputs: dict[str, Any]) -> dict[str, Any] | None:
    """The result stored in ``path`` for exactly these inputs, or None."""
    try:
        hit = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if isinstance(hit, dict) and hit.get("inputs") == json.loads(json.dumps(inputs)):
        return hit["result"]
    return None


def clear_memory() -> None:
    """Forget the in-process results (tests: force the disk cache or a fresh computation)."""
    _MEMORY.clear()
