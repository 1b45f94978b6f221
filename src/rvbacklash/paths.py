"""Paths a user names (a design file, an output file, a results directory), looked at without an
OSError escaping as a traceback.

``Path.is_file()`` and its kind answer False for a missing file but raise for a name the file
system refuses (``File name too long``), a loop of symlinks or a directory that may not be
searched. Every command reads its paths through ``path_stat`` here, so such a name is bad input:
one line naming the flag or field, the path and what is allowed.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from rvbacklash.errors import InputError

# errors that mean "nothing is there": no such entry, or a component of the path is a file
_ABSENT = (errno.ENOENT, errno.ENOTDIR)


def _limit(path: Path, name: str, default: int) -> int:
    """A pathconf limit (PC_NAME_MAX, PC_PATH_MAX) of the file system of ``path``'s nearest existing
    directory."""
    for parent in (path, *path.parents):
        try:
            return os.pathconf(parent, name)
        except (OSError, ValueError):
            continue
    return default


def unusable(field: str, path: str | Path, e: OSError) -> InputError:
    """The InputError for a path the operating system refused with ``e``."""
    if e.errno == errno.ENAMETOOLONG:
        where = Path(path).absolute()
        longest = max((len(os.fsencode(p)) for p in Path(path).parts), default=0)
        name_max = _limit(where, "PC_NAME_MAX", 255)
        if longest > name_max:
            return InputError(field, str(path), f"file name too long ({longest} bytes); allowed: names of at most "
                                                f"{name_max} bytes (the file system's limit)")
        return InputError(field, str(path), f"path too long ({len(os.fsencode(str(where)))} bytes); allowed: at "
                                            f"most {_limit(where, 'PC_PATH_MAX', 4096)} bytes")
    return InputError(field, str(path), f"cannot be used ({e.strerror or e}); allowed: a path this user can reach")


def path_stat(field: str, path: str | Path, follow_symlinks: bool = True) -> os.stat_result | None:
    """``os.stat`` of ``path`` (of the link itself with ``follow_symlinks=False``); None when
    nothing is there; any other refusal of the operating system is an InputError naming ``field``."""
    try:
        return os.stat(path, follow_symlinks=follow_symlinks)
    except OSError as e:
        if e.errno in _ABSENT:
            return None
        raise unusable(field, path, e) from None


def is_file(field: str, path: str | Path) -> bool:
    """A regular file (symlinks followed) is at ``path``."""
    st = path_stat(field, path)
    return st is not None and stat.S_ISREG(st.st_mode)


def is_dir(field: str, path: str | Path) -> bool:
    """A directory (symlinks followed) is at ``path``."""
    st = path_stat(field, path)
    return st is not None and stat.S_ISDIR(st.st_mode)


def is_symlink(field: str, path: str | Path) -> bool:
    st = path_stat(field, path, follow_symlinks=False)
    return st is not None and stat.S_ISLNK(st.st_mode)
