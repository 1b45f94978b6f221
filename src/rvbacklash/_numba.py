"""numba for the compiled kernels, with its on-disk cache keyed by the package's source.

numba reuses a cached kernel as long as the kernel's own file is unchanged; it does not see a
change in another module's kernel that it calls (the Monte-Carlo kernel of sampling/ calls the
contact geometry of models/). The cache therefore lives in a directory named after a hash of
every source file of the package: any change starts a fresh cache, a user never runs stale
machine code. ``NUMBA_CACHE_DIR``, when set, is the base of that directory; else the user's
cache directory (``$XDG_CACHE_HOME`` or ``~/.cache``). Compile kernels with ``njit`` from here.

``njit`` is numba's with ``error_model="numpy"``: a float division by zero gives inf or NaN as
IEEE 754 says instead of raising ZeroDivisionError; every other division gives the same bits. The
kernels never divide by zero on purpose. The point is speed. numba keeps two atomic operations
(a reference count up, then down) for every array a function binds: its arguments, the arrays of
a tuple it unpacks, every view. It removes them only where it can prove them redundant, which it
cannot in a function that may raise, and under numba's default every division may raise. Those
counts cost ~5 ns each; the elastic model paid ~6 us per unit for them (docs/elastic.md,
performance). ``njit_borrowing`` goes further for the per-unit kernels that allocate nothing.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numba as nb
from numba.core.cpu import CPUTargetOptions

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


def njit_borrowing(**options):
    """``njit`` for a per-unit kernel that allocates nothing and only reads and writes arrays its
    caller holds (``unit_draw.draw_unit``, ``contact.stage_play``, ``elastic.chain.loop_figures``),
    compiled without numba's runtime (its ``_nrt=False`` option): its own code keeps no reference
    counts. Each call of such a kernel binds a few dozen arrays (its scratch records, its
    arguments), two atomic operations each that numba could not prune in a function this size:
    ~1 us of the contact model's ~4.9 us per unit (draw_unit alone went from 1.75 to 1.0 us),
    ~2 us of the elastic model's ~23 us of evaluation.

    A function it calls is compiled without the runtime too when this kernel compiles it first;
    one that another caller compiled first (same argument types) is linked as it is, with its own
    counts. Either way is safe as long as no function under such a kernel returns an array or
    keeps one beyond the call (none does: they return scalars; a callee that allocated would make
    numba refuse to compile when compiled from here). ``_nrt`` is a private option of numba (there
    since 0.40, checked here): without it, this is plain ``njit``."""
    if hasattr(CPUTargetOptions, "_nrt"):
        options["_nrt"] = False
    return njit(**options)


__all__ = ["nb", "njit", "njit_borrowing"]
