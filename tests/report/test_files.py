"""Result files: atomic, never half-written, never a special file, '-' is standard output."""

import json
import os
import stat

import pytest

from rvbacklash.errors import InputError
from rvbacklash.report.files import check_distinct, render_csv, render_json, write_files


def test_new_file_and_force(tmp_path):
    f = tmp_path / "a.json"
    write_files({"--json": (f, "one")})
    with pytest.raises(InputError, match="--force"):
        write_files({"--json": (f, "two")})
    write_files({"--json": (f, "two")}, force=True)
    assert f.read_text() == "two" and [p.name for p in tmp_path.iterdir()] == ["a.json"]
    assert stat.S_IMODE(f.stat().st_mode) & 0o044  # readable by others, like any file


def test_force_refuses_a_fifo(tmp_path):
    """Regression (issue 9): --force turned a FIFO into a regular file."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match="not a regular file"):
        write_files({"--json": (fifo, "x")}, force=True)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)


def test_force_refuses_a_device(tmp_path):
    with pytest.raises(InputError, match="not a regular file"):
        write_files({"--json": (type(tmp_path)("/dev/null"), "x")}, force=True)


def test_force_writes_through_a_symlink_to_its_target(tmp_path):
    """Regression (issue 9): --force replaced the symlink instead of its target."""
    target = tmp_path / "real.json"
    target.write_text("old")
    link = tmp_path / "link.json"
    link.symlink_to(target)
    write_files({"--json": (link, "new")}, force=True)
    assert link.is_symlink() and target.read_text() == "new"


def test_same_path_twice_is_refused(tmp_path):
    f = tmp_path / "x"
    with pytest.raises(InputError, match="also given to --json"):
        check_distinct({"--json": f, "--csv": f})
    with pytest.raises(InputError, match="also given"):
        check_distinct({"--json": "-", "--csv": "-"})


def test_dash_is_standard_output(capsys, tmp_path):
    write_files({"--json": ("-", "{}\n")})
    assert capsys.readouterr().out == "{}\n" and not (tmp_path / "-").exists()


def test_renderers_are_plain():
    import math

    assert render_json({"a": math.nan, "b": (1, 2)}, stamp=False) == '{\n  "a": null,\n  "b": [\n    1,\n    2\n  ]\n}\n'
    assert list(json.loads(render_json({"a": 1}))) == ["schema_version", "rvbacklash_version", "a"]  # every output
    assert render_csv([{"a": 1, "b": 2}, {"a": 3, "c": 4}]) == "a,b,c\n1,2,\n3,,4\n"
