"""Writing result files atomically: everything is rendered first, then each file is written
to a temporary sibling and renamed, so a failure never leaves a half-written file.

A path is a new file or an existing *regular* file (replaced only with ``force``); a symlink is
followed and its target replaced; FIFOs, devices, sockets and directories are refused, and so is
a path that ends in a slash (it names a directory, even one that does not exist yet) or that the
file system cannot hold (a name too long). ``-`` means standard output.
"""

from __future__ import annotations

import csv
import io
import json
import os
import stat
import sys
from pathlib import Path
from typing import Any, Iterable, Mapping

from rvbacklash._version import SCHEMA_VERSION, __version__
from rvbacklash.atomic import atomic_write  # noqa: F401 - part of this module's interface
from rvbacklash.errors import InputError
from rvbacklash.interrupt import writing
from rvbacklash.paths import is_dir, is_symlink, path_stat
from rvbacklash.results import plain

STDOUT = "-"


def stamped(data: Any) -> Any:
    """A JSON output's top level with the versions first: ``schema_version`` (of the output
    formats, CHANGELOG.md) and ``rvbacklash_version`` (the program that wrote it)."""
    if not isinstance(data, Mapping):
        return data
    return {"schema_version": SCHEMA_VERSION, "rvbacklash_version": __version__,
            **{k: v for k, v in data.items() if k not in ("schema_version", "rvbacklash_version")}}


def render_json(data: Any, stamp: bool = True) -> str:
    """An output as JSON, stamped with its versions (``stamp=False``: as it is, e.g. a schema)."""
    data = plain(data)
    return json.dumps(stamped(data) if stamp else data, indent=2, allow_nan=False) + "\n"


def render_csv(rows: Iterable[Mapping[str, Any]]) -> str:
    rows = [plain(r) for r in rows]
    buf = io.StringIO()
    if rows:
        names = list(dict.fromkeys(k for r in rows for k in r))
        w = csv.DictWriter(buf, fieldnames=names, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    return buf.getvalue()


def is_stdout(path: Path | str) -> bool:
    return str(path) == STDOUT


def output_path(option: str, text: str) -> Path:
    """The path of an output file as given on the command line. A trailing slash names a
    directory (``newdir/``), which a file cannot be written as: ``Path`` would drop the slash and
    write a file named ``newdir``, so the text is checked before it becomes a Path."""
    if not is_stdout(text) and text.endswith(tuple({os.sep, os.altsep or os.sep})):
        raise InputError(option, text, "ends in a slash, which names a directory; allowed: a file path (e.g. "
                                       f"{text.rstrip(os.sep + (os.altsep or ''))}{os.sep}result.json)")
    return Path(text)


def target(option: str, path: Path) -> Path:
    """The file a write to ``path`` replaces: symlinks followed."""
    return Path(os.path.realpath(path)) if is_symlink(option, path) else path


def check_writable(option: str, path: Path, force: bool = False) -> None:
    """Fail early (before any work is written) if ``path`` cannot be written."""
    if is_stdout(path):
        return
    real = target(option, path)
    parent = real.parent if str(real.parent) else Path(".")
    st = path_stat(option, real)
    mode = st.st_mode if st is not None else None
    if mode is not None and stat.S_ISDIR(mode):
        raise InputError(option, str(path), "is a directory; allowed: a file path")
    if mode is not None and not stat.S_ISREG(mode):
        raise InputError(option, str(path), "is not a regular file (a FIFO, device or socket); allowed: a new path "
                                            "or a regular file")
    if not is_dir(option, parent):
        raise InputError(option, str(path), f"directory {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK):
        raise InputError(option, str(path), f"directory {str(parent)!r} is not writable")
    if mode is not None and not force:
        raise InputError(option, str(path), "file exists; allowed: a new path, or --force to overwrite")


def check_distinct(paths: Mapping[str, Path | None]) -> None:
    """Two outputs must not name the same file (or both standard output)."""
    seen: dict[str, str] = {}
    for option, path in paths.items():
        if path is None:
            continue
        key = STDOUT if is_stdout(path) else os.path.realpath(path)
        if key in seen:
            raise InputError(option, str(path), f"is also given to {seen[key]}; allowed: a different path for "
                                                f"each output")
        seen[key] = option


def write_files(contents: Mapping[str, tuple[Path, str | bytes]], force: bool = False) -> None:
    """Write several rendered outputs {option: (path, content)}; all paths are checked first,
    an existing file is only replaced with ``force``; ``-`` writes to standard output."""
    check_distinct({option: path for option, (path, _) in contents.items()})
    for option, (path, _) in contents.items():
        check_writable(option, path, force)
    with writing():  # a Ctrl-C lets every file of the command be written first (rvbacklash.interrupt)
        for option, (path, content) in contents.items():
            if is_stdout(path):
                if isinstance(content, bytes):
                    sys.stdout.buffer.write(content)
                else:
                    sys.stdout.write(content)
                sys.stdout.flush()
            else:
                atomic_write(option, target(option, path), content)


