"""Results of per-design finite-element models, computed once: kept in process and on disk,
keyed by everything the model reads (its inputs and the model's version), so that a production
run, a sweep or the next command of the same design never meshes or solves again.

The disk cache lives in ``$RVBACKLASH_CACHE_DIR`` (default ``~/.cache/rvbacklash``), one JSON file
per result under ``fe/``; a cache that cannot be read or written is skipped (the result is
computed again), never an error: it only saves time.
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
    """``compute()`` (a JSON-able dict) for ``inputs``, from memory, else from disk, else computed
    and stored in both. ``version``: the model's version (raise it when the model changes what it
    computes: older files are then never read)."""
    key = cache_key(kind, version, inputs)
    hit = _MEMORY.get(key)
    if hit is not None:
        return hit
    path = cache_dir() / "fe" / f"{key}.json"
    if disk:
        try:
            hit = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            hit = None
        if isinstance(hit, dict) and hit.get("inputs") == json.loads(json.dumps(inputs)):
            _MEMORY[key] = hit["result"]
            return hit["result"]
    result = compute()
    _MEMORY[key] = result
    if disk:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            atomic_write("cache", path, json.dumps({"inputs": inputs, "result": result}, sort_keys=True))
        except (OSError, InputError):
            pass  # a cache that cannot be written only costs the next run the computation
    return result


def clear_memory() -> None:
    """Forget the in-process results (tests: force the disk cache or a fresh computation)."""
    _MEMORY.clear()
