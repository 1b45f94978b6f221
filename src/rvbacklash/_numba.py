"""numba for the compiled kernels, with its on-disk cache keyed by the package's source.

numba reuses a cached kernel as long as the kernel's own file is unchanged; it does not see a
change in another module's kernel that it calls (the Monte-Carlo kernel of sampling/ calls the
contact geometry of models/). The cache therefore lives in a directory named after a hash of
every source file of the package: any change starts a fresh cache, a user never runs stale
machine code. ``NUMBA_CACHE_DIR``, when set, is the base of that directory; else the user's
cache directory (``$XDG_CACHE_HOME`` or ``~/.cache``). Import kernels' numba from here:
``from rvbacklash._numba import nb``.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numba as nb

_PACKAGE = Path(__file__).resolve().parent


def source_hash() -> str:
    """First 16 hex digits of the sha256 of every .py file of the package (paths and contents)."""
    h = hashlib.sha256()
    for path in sorted(_PACKAGE.rglob("*.py")):
        h.update(str(path.relative_to(_PACKAGE)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _cache_dir() -> str:
    base = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "rvbacklash")
    return os.path.join(base, f"numba-{source_hash()}")


nb.config.CACHE_DIR = _cache_dir()


def njit(**options):
    """``numba.njit(**options)`` with ``error_model="numpy"`` (module docstring)."""
    return nb.njit(error_model="numpy", **options)


__all__ = ["nb", "njit"]
