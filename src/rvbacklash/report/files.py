"""Writing result files atomically: everything is rendered first, then each file is written
to a temporary sibling and renamed, so a failure never leaves a half-written file."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import tempfile
from pathlib import Path
from typing import Any, Iterable, Mapping

from rvbacklash.errors import InputError


def _plain(obj: Any) -> Any:
    """JSON-safe plain numbers: numpy scalars to Python, non-finite floats to None."""
    if isinstance(obj, Mapping):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if hasattr(obj, "item") and not isinstance(obj, (str, bytes)):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def render_json(data: Mapping[str, Any]) -> str:
    return json.dumps(_plain(data), indent=2, allow_nan=False) + "\n"


def render_csv(rows: Iterable[Mapping[str, Any]]) -> str:
    rows = [_plain(r) for r in rows]
    buf = io.StringIO()
    if rows:
        w = csv.DictWriter(buf, fieldnames=list(rows[0].keys()), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    return buf.getvalue()


def check_writable(option: str, path: Path, force: bool = False) -> None:
    """Fail early (before any work is written) if ``path`` cannot be written."""
    parent = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise InputError(option, str(path), "is a directory; allowed: a file path")
    if not parent.is_dir():
        raise InputError(option, str(path), f"directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK):
        raise InputError(option, str(path), f"directory {str(parent)!r} is not writable")
    if path.exists() and not force:
        raise InputError(option, str(path), "file exists; allowed: a new path, or --force to overwrite")


def write_files(contents: Mapping[str, tuple[Path, str | bytes]], force: bool = False) -> None:
    """Write several rendered outputs {option: (path, content)}; all paths are checked first,
    an existing file is only replaced with ``force``."""
    for option, (path, _) in contents.items():
        check_writable(option, path, force)
    for option, (path, content) in contents.items():
        _atomic_write(option, path, content)


def _atomic_write(option: str, path: Path, content: str | bytes) -> None:
    mode = "wb" if isinstance(content, bytes) else "w"
    parent = path.parent if str(path.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=parent)
    try:
        with os.fdopen(fd, mode, **({} if mode == "wb" else {"encoding": "utf-8", "newline": ""})) as fh:
            fh.write(content)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; give the file the usual permissions
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise InputError(option, str(path), f"cannot write ({e.strerror or e})") from None
