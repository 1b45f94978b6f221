"""Defects of reading a bench file found by a hostile tryout (issue 35, item 2), each refused in one
line naming the file (and column and row): a FIFO (it hung `bench` and `calibrate`), a device
(/dev/zero grew memory to a MemoryError), a directory, a file beyond the size limit, a file name
too long (said "cannot be read (OSError)"), a finite cell that overflows once converted (gave exit
0 and wrong figures), a time column that goes back (accepted without a note), a decimal comma
without --decimal (said "not a number" with no hint). Only the reader's API of before the fix is
used, so that each test runs, and fails, on the code before it."""

from __future__ import annotations

import os

import numpy as np
import pytest

from helpers import call_beside_fifo
from rvbacklash.design.bench_files import read_bench_table
from rvbacklash.errors import InputError

MAX_FILE_BYTES = 100_000_000  # design.bench_files.MAX_FILE_BYTES: the message says 100 MB


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "rig.csv"
    os.mkfifo(fifo)
    out = call_beside_fifo(fifo, lambda: read_bench_table(fifo))
    assert isinstance(out.get("error"), InputError), out
    assert str(out["error"]) == (f"{fifo}: a FIFO (named pipe), not a regular file; allowed: a CSV, TSV or .xlsx file "
                                 f"of a test (a regular file)")


@pytest.mark.parametrize("path, kind", [("/dev/zero", "a character device"), (".", "a directory")])
def test_devices_and_directories_are_refused(path, kind):
    if not os.path.exists(path):
        pytest.skip(f"no {path}")
    with pytest.raises(InputError, match=f"{kind}, not a regular file"):
        read_bench_table(path)


def test_a_file_beyond_the_size_limit_is_refused(tmp_path):
    f = tmp_path / "huge.csv"
    with open(f, "wb") as out:  # sparse: no disk used
        out.write(b"angle [deg],te [arcsec]\n")
        out.truncate(MAX_FILE_BYTES + 1)
    with pytest.raises(InputError, match=r"100.0 MB; allowed: at most 100 MB \(split a longer record"):
        read_bench_table(f)


def test_a_file_name_too_long_says_so(tmp_path):
    f = tmp_path / ("u" * 300 + ".csv")
    with pytest.raises(InputError, match=r"file name too long \(304 bytes\); allowed: names of at most \d+ bytes"):
        read_bench_table(f)


def test_a_value_that_overflows_once_converted_is_refused(tmp_path):
    f = tmp_path / "huge.csv"
    f.write_text("angle [deg],te [arcsec]\n" + "".join(f"{k},1\n" for k in range(400)) + "1e308,2\n")
    with pytest.raises(InputError) as e:
        read_bench_table(f)
    assert str(e.value) == (f"{f}: column 'angle [deg]' = 1e+308: row 402: inf arcmin once converted; allowed: "
                            f"values within +-1e+15 arcmin (no bench reads more)")


def test_a_time_that_goes_back_is_refused(tmp_path):
    t = np.arange(40) * 0.01
    t[[10, 20]] = t[[20, 10]]  # two rows swapped
    f = tmp_path / "shuffled.csv"
    f.write_text("time [s],torque [N m],angle [arcmin]\n" + "".join(f"{x:.2f},{k},{k / 10}\n" for k, x in enumerate(t)))
    with pytest.raises(InputError, match=r"column 'time \[s\]': row 13: the time goes back \(0.2 s, then 0.11 s; "
                                         r"2 such steps\); allowed: times that never decrease"):
        read_bench_table(f)


def test_a_decimal_comma_without_decimal_says_how_to_read_it(tmp_path):
    f = tmp_path / "quoted.csv"
    f.write_text('angle [deg],te [arcsec]\n"0,5","1,25"\n')
    with pytest.raises(InputError) as e:
        read_bench_table(f)
    assert str(e.value) == (f"{f}: column 'angle [deg]' = '0,5': row 2: not a number (a decimal comma? give "
                            f"--decimal ,); allowed: numbers")
