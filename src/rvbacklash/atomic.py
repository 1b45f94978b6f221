"""Atomic file writes: a file is either its old self or completely the new content, never half
written (a temporary sibling, then a rename), also on Ctrl-C or a full disk."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from rvbacklash.errors import InputError
from rvbacklash.interrupt import writing


def atomic_write(field: str, path: Path, content: str | bytes) -> None:
    """Write ``content`` to ``path`` through a temporary sibling and ``os.replace``; text as UTF-8
    without newline translation. An OSError becomes an InputError naming ``field`` (the parameter
    or flag that gave the path)."""
    with writing():  # a Ctrl-C waits for the rename (rvbacklash.interrupt): no temporary file is left behind
        _write(field, path, content)


def _write(field: str, path: Path, content: str | bytes) -> None:
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
    except BaseException as e:  # includes Ctrl-C: never leave the temporary file behind
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(e, OSError):
            raise InputError(field, str(path), f"cannot write ({e.strerror or e})") from None
        raise
