#!/usr/bin/env python3
"""Are two versions of rvbacklash bit-identical in what they write? (issue 27: a refactor changes
no number).

    tools/compare_outputs.py BASE [OTHER]      # OTHER: a commit, or WORKTREE (default): this checkout

Each side is a commit checked out into a temporary git worktree (WORKTREE: this checkout's src/,
uncommitted changes included), run with this checkout's virtual environment and its own source
on PYTHONPATH. Both sides run the same commands (COMMANDS: simulate JSON of the linear, contact,
elastic and transmission models, hysteresis, transmission-error and contact JSON, saved units
and the measured-unit commands on them) and every file they write is compared: JSON after the
fields that time a run are removed (TIMING_KEYS), every other file byte for byte. A JSON float
is written with the shortest repr that reads back to the same double, so equal JSON values are
equal bits. Prints one line per output and exits 1 when any differs.

A commit's outputs are kept in ``.compare-cache/<commit>/`` (a commit does not change); ``--quick``
runs the smaller sizes (a check while working, not the issue's evidence).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PYTHON = ROOT / ".venv" / "bin" / "python"
CACHE = ROOT / ".compare-cache"
TIMING_KEYS = {"elapsed_s", "created_utc", "rvbacklash_version", "units_per_s", "samples_per_s"}  # when, and how fast

# (output file name, arguments), run in the output directory (a file a command reads is named relative to
# it: its name appears in the outputs). Sizes: full|quick.
COMMANDS: list[tuple[str, list[str]]] = [
    ("linear.json", ["simulate", "rv80e", "-n", "1e6|1e5", "--seed", "1", "--spec-arcmin", "3"]),
    ("linear-sun2014.json", ["simulate", "sun2014", "-n", "1e6|1e5", "--seed", "7", "--method", "box-muller",
                             "--spec-arcmin", "3"]),
    ("contact.json", ["simulate", "rv80e", "--model", "contact", "-n", "20000|4000", "--seed", "1", "--spec-arcmin", "3",
                      "--save-units", "4", "contact-units.toml"]),
    ("contact-box-muller.json", ["simulate", "rv80e", "--model", "contact", "--method", "box-muller", "-n", "8000|2000",
                                 "--seed", "4", "--spec-arcmin", "3"]),
    ("contact-independent.json", ["simulate", "rv80e", "--model", "contact", "--error-model", "independent",
                                  "-n", "8000|2000", "--seed", "2", "--spec-preload-um", "10"]),
    ("contact-te.json", ["simulate", "rv80e", "--model", "contact", "-n", "1000|300", "--seed", "3",
                         "--spec-te-arcsec", "60"]),
    ("elastic.json", ["simulate", "rv80e", "--model", "elastic", "-n", "20000|4000", "--seed", "1",
                      "--spec-lost-motion-arcmin", "1", "--spec-rigidity-nm-per-arcmin", "450",
                      "--save-units", "3", "elastic-units.toml"]),
    ("transmission.json", ["simulate", "rv80e", "--model", "transmission", "-n", "2000|400", "--seed", "1",
                           "--spec-te-arcsec", "60"]),
    ("hysteresis.json", ["hysteresis", "rv80e"]),
    ("hysteresis-unit.json", ["hysteresis", "rv80e", "--measured", "elastic-units.toml", "--unit", "1"]),
    ("transmission-error.json", ["transmission-error", "rv80e"]),
    ("transmission-error-fine.json", ["transmission-error", "rv80e", "--positions", "5000"]),  # solved in parts
    ("transmission-error-unit.json", ["transmission-error", "rv80e", "--measured", "contact-units.toml",
                                      "--unit", "2"]),
    ("contact-nominal.json", ["contact", "rv80e", "--crank-angle-deg", "3"]),
    ("contact-unit.json", ["contact", "rv80e", "--measured", "contact-units.toml", "--unit", "0"]),
    ("sensitivity-elastic.json", ["sensitivity", "rv80e", "--model", "elastic", "-n", "512|128", "--seed", "1"]),
    ("report-te.json", ["report", "rv80e", "-n", "2000|1000", "--seed", "1", "--spec-arcmin", "3", "--spec-te-arcsec",
                        "60", "-o", "report-te.html"]),
]


def run_side(src: Path, out: Path, quick: bool) -> None:
    """Every command of COMMANDS with ``src`` first on the path, its files into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_NUM_THREADS="2")
    for name, args in COMMANDS:
        argv = [a.split("|")[1 if quick else 0] if "|" in a else a for a in args]
        cmd = [str(PYTHON), "-m", "rvbacklash", *argv, "--json", name, "-q", "--force"]
        r = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=out)
        if r.returncode != 0:
            raise SystemExit(f"{src}: `rvbacklash {' '.join(argv)}` failed ({r.returncode}): {r.stderr.strip()[-400:]}")
        print(f"  {src.parent.name}: {name}", file=sys.stderr)


def strip_timings(x, ignore: frozenset[str] = frozenset()):
    """The JSON value without the fields that time a run (and those in ``ignore``), at any depth."""
    if isinstance(x, dict):
        return {k: strip_timings(v, ignore) for k, v in x.items() if k not in TIMING_KEYS | ignore}
    if isinstance(x, list):
        return [strip_timings(v, ignore) for v in x]
    return x


def first_difference(a, b, path: str = "") -> str | None:
    """Where two JSON values first differ (bit for bit: NaN equals NaN), or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return f"{path or '/'}: keys {sorted(set(a) ^ set(b))}"
        for k in a:
            d = first_difference(a[k], b[k], f"{path}/{k}")
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{path}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return None
    if type(a) is not type(b) or a != b:
        return f"{path}: {a!r} != {b!r}"
    return None


def compare_dirs(a: Path, b: Path, ignore: frozenset[str] = frozenset()) -> int:
    failures = 0
    names = sorted(({p.name for p in a.iterdir()} | {p.name for p in b.iterdir()}) - {".complete"})
    names = [n for n in names if not n.endswith(".html")]  # a page shows its run's time: its JSON is compared
    for name in names:
        pa, pb = a / name, b / name
        if not (pa.exists() and pb.exists()):
            print(f"DIFFERENT  {name}: only in {'base' if pa.exists() else 'other'}")
            failures += 1
            continue
        if name.endswith(".json"):
            ja = strip_timings(json.loads(pa.read_text(), parse_constant=float), ignore)
            jb = strip_timings(json.loads(pb.read_text(), parse_constant=float), ignore)
            diff = first_difference(ja, jb)
        else:
            diff = None if pa.read_bytes() == pb.read_bytes() else "bytes differ"
        print(f"{'identical ' if diff is None else 'DIFFERENT '} {name}" + ("" if diff is None else f": {diff}"))
        failures += diff is not None
    return failures


def checkout(commit: str, into: Path) -> Path:
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-f", str(into), commit], check=True,
                   capture_output=True)
    return into / "src"


def resolve(rev: str) -> str:
    return subprocess.run(["git", "-C", str(ROOT), "rev-parse", rev], check=True, capture_output=True,
                          text=True).stdout.strip()


def outputs_of(rev: str, quick: bool, tmp: Path) -> Path:
    """The directory of ``rev``'s outputs (run now, or from the cache for a commit)."""
    if rev == "WORKTREE":  # a snapshot of this checkout's source (edits while it runs do not mix in), in
        # one place with its files' times kept, so that numba's cache of an unchanged kernel is reused
        src = CACHE / "worktree" / "src"
        shutil.rmtree(src, ignore_errors=True)
        shutil.copytree(ROOT / "src", src, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        out = tmp / "worktree" / "out"
        run_side(src, out, quick)
        return out
    sha = resolve(rev)
    out = CACHE / (sha + ("-quick" if quick else ""))
    if out.is_dir() and (out / ".complete").exists():
        return out
    if out.exists():
        shutil.rmtree(out)
    wt = tmp / sha
    try:
        run_side(checkout(sha, wt), out, quick)
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(wt)], capture_output=True)
    (out / ".complete").touch()
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("base", help="a commit (e.g. 59154fd)")
    p.add_argument("other", nargs="?", default="WORKTREE", help="a commit, or WORKTREE (this checkout)")
    p.add_argument("--quick", action="store_true", help="smaller runs (a check while working)")
    p.add_argument("--ignore", action="append", default=[], metavar="KEY",
                   help="a JSON key whose change is intended (e.g. schema_version), at any depth; repeatable")
    args = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="rvb-compare-") as t:
        tmp = Path(t)
        a = outputs_of(args.base, args.quick, tmp)
        b = outputs_of(args.other, args.quick, tmp)
        failures = compare_dirs(a, b, frozenset(args.ignore))
    print(f"{'all identical' if not failures else f'{failures} output(s) differ'} "
          f"({args.base} vs {args.other}{', quick sizes' if args.quick else ''}"
          f"{', ignoring ' + ', '.join(args.ignore) if args.ignore else ''})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
