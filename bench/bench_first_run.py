"""First run on a fresh machine: where `make example`'s time goes. Prints figures, asserts nothing.

    .venv/bin/python bench/bench_first_run.py [--base REV] [--install] [--tiny]

1. ``--install``: creating a virtual environment and installing the package as the Makefile does
   (`pip install -e .` for `make example`, then the test and sweep extras for `make test`), into a
   temporary directory; pip's own download cache is used as it is (a machine that never
   downloaded the wheels waits for its network on top).
2. The example's command (the Makefile's `example` target) with empty caches (a temporary
   NUMBA_CACHE_DIR and RVBACKLASH_CACHE_DIR: nothing compiled, no finite-element result on disk),
   then again with those caches filled (warm): wall and CPU time of the process, split into
   numba's compilation (wall time inside numba's compiler, outermost calls: a kernel's callees are
   part of its compilation), each kind of cached computation (the finite-element models, the
   roller law's fit, the part calibration: their computations when not found in a cache), and
   the rest (imports, sampling, the report); one line of wall times, one of CPU times (the
   process's, and each part's in the thread that ran it: the compilations and the FE solves run
   on one thread each, the sampling on every core). ``--base``: the same for a commit (a
   temporary git worktree run with this virtual environment), side by side.
``--tiny`` runs a small linear command with the user's caches as they are (the test suite runs
every bench; its figures mean nothing).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DETAIL = False  # --detail: every compiled kernel (outermost calls), on stderr


def example_args() -> list[str]:
    """The arguments of `make example`'s command, read from the Makefile (one source of truth)."""
    lines = (ROOT / "Makefile").read_text().split("\nexample:", 1)[1].splitlines()
    line = next(x for x in lines if "rvbacklash report" in x)
    args = line.split("rvbacklash", 1)[1].split()
    return [a.replace("out/", "") for a in args]


# Runs the command in this process with numba's compiler and the cached computations timed.
RUNNER = r"""
import json, resource, sys, threading, time
t0 = time.perf_counter()
acc = {"numba compilation": 0.0}
cpu = {"numba compilation": 0.0}
kernels = {}
from numba.core import dispatcher
_compile = dispatcher._FunctionCompiler.compile
_depth = threading.local()

def compile(self, args, return_type):
    d = getattr(_depth, "n", 0)
    _depth.n = d + 1
    t, c = time.perf_counter(), time.thread_time()
    try:
        return _compile(self, args, return_type)
    finally:
        _depth.n = d
        if d == 0:
            acc["numba compilation"] += time.perf_counter() - t
            cpu["numba compilation"] += time.thread_time() - c
            name = self.py_func.__module__.rsplit(".", 1)[-1] + "." + self.py_func.__name__
            kernels.setdefault(name, []).append(round(time.perf_counter() - t, 2))

dispatcher._FunctionCompiler.compile = compile
from rvbacklash.mechanics import fe_cache
_cached = fe_cache.cached

def cached(kind, version, inputs, compute, disk=True):
    def timed():
        t, c = time.perf_counter(), time.thread_time()
        try:
            return compute()
        finally:
            acc[kind] = acc.get(kind, 0.0) + time.perf_counter() - t
            cpu[kind] = cpu.get(kind, 0.0) + time.thread_time() - c
    return _cached(kind, version, inputs, timed, disk)

fe_cache.cached = cached  # before the modules that import it by name are imported
from rvbacklash.cli.entry import main
code = 0
try:
    main(sys.argv[1:])
except SystemExit as e:
    code = e.code
r = resource.getrusage(resource.RUSAGE_SELF)
acc["total wall"] = time.perf_counter() - t0
acc["total CPU"] = r.ru_utime + r.ru_stime
print("FIRST-RUN " + json.dumps({"exit": code, "cpu": cpu, **acc}), file=sys.stderr)
print("KERNELS " + json.dumps(kernels), file=sys.stderr)
"""


def run_example(src: Path, args: list[str], cwd: Path, caches: Path | None) -> dict:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(src)
    if caches is not None:
        env.update(NUMBA_CACHE_DIR=str(caches / "numba"), RVBACKLASH_CACHE_DIR=str(caches / "rvbacklash"))
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", RUNNER, *args], cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t
    line = next((x for x in p.stderr.splitlines() if x.startswith("FIRST-RUN ")), None)
    if line is None or json.loads(line[10:])["exit"] not in (0, None):
        raise SystemExit(f"{src}: `rvbacklash {' '.join(args)}` failed: {p.stderr.strip()[-600:]}")
    figures = json.loads(line[10:])
    figures["process wall (interpreter included)"] = wall
    kernels = next((x for x in p.stderr.splitlines() if x.startswith("KERNELS ")), None)
    if DETAIL and kernels:
        for name, times in sorted(json.loads(kernels[8:]).items(), key=lambda kv: -sum(kv[1])):
            print(f"      compiled {name}: {len(times)} signature(s), {sum(times):.1f} s", file=sys.stderr)
    return figures


def specialisations(cache: Path) -> str:
    """The functions numba's cache holds more than one compiled signature of, and how many."""
    counts: dict[str, int] = {}
    for f in cache.rglob("*.nbc"):
        name = f.name.split(".py")[0].rsplit("-", 1)[0]  # contact.stage_play-587.py311.2.nbc
        counts[name] = counts.get(name, 0) + 1
    return ", ".join(f"{k} x{v}" for k, v in sorted(counts.items()) if v > 1)


def print_split(name: str, f: dict) -> None:
    """One line of wall times, one of CPU times: the whole process, then its parts and the rest."""
    skip = ("exit", "cpu", "total wall", "total CPU", "process wall (interpreter included)")
    parts = {k: v for k, v in f.items() if k not in skip}
    for label, total, split in (("wall", f["process wall (interpreter included)"], parts),
                                ("CPU", f["total CPU"], f["cpu"])):
        rest = total - sum(split.values())
        cells = "  ".join(f"{k} {v:6.1f}" for k, v in split.items() if v >= 0.05)
        print(f"  {name if label == 'wall' else '':<34} {label:<4} {total:6.1f}  |  {cells}  rest {rest:6.1f}")


def time_install(tmp: Path) -> None:
    """A fresh virtual environment with the package, as the Makefile makes it [s]."""
    venv = tmp / "venv"
    py = venv / "bin" / "python"
    steps = [("venv + pip upgrade", [[sys.executable, "-m", "venv", str(venv)],
                                     [str(py), "-m", "pip", "install", "--quiet", "--upgrade", "pip"]]),
             ("pip install -e . (make example)", [[str(py), "-m", "pip", "install", "--quiet", "-e", str(ROOT)]]),
             ("the test and sweep extras (make test)",
              [[str(py), "-m", "pip", "install", "--quiet", "-e", f"{ROOT}[test,sweep]"]])]
    print("install (pip's download cache as it is) [s]:")
    for label, commands in steps:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t = time.perf_counter()
        for c in commands:
            subprocess.run(c, check=True, capture_output=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
        print(f"  {label:<40} wall {time.perf_counter() - t:6.1f}  CPU {cpu:6.1f}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--base", help="a commit to compare with (e.g. bd2a342, issue 35's start)")
    ap.add_argument("--install", action="store_true", help="also time a fresh virtual environment's install")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    ap.add_argument("--detail", action="store_true", help="list every compiled kernel and its compilation time")
    a = ap.parse_args()
    global DETAIL
    DETAIL = a.detail
    with tempfile.TemporaryDirectory(prefix="rvb-bench-first-run-") as t:
        tmp = Path(t)
        if a.install:
            time_install(tmp)
        sides = {"this checkout": ROOT / "src"}
        if a.base:
            wt = tmp / "base"
            subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-f", str(wt), a.base], check=True,
                           capture_output=True)
            sides = {f"base {a.base}": wt / "src", **sides}
        try:
            if a.tiny:
                args = ["simulate", "sun2014", "-n", "1000", "--json", "out.json", "--force"]
                print(f"`rvbacklash {' '.join(args)}` with the caches as they are [s]:")
                print_split("this checkout", run_example(ROOT / "src", args, tmp, None))
                return
            args = example_args()
            print(f"`rvbacklash {' '.join(args)}` [s]:")
            for name, src in sides.items():
                caches = tmp / f"caches-{len(name)}-{abs(hash(name))}"
                print_split(f"{name}, empty caches", run_example(src, args, tmp, caches))
                if DETAIL:  # a function compiled for several signatures compiles its body once for each
                    print(f"      several signatures: {specialisations(caches / 'numba') or 'none'}", file=sys.stderr)
                print_split(f"{name}, warm", run_example(src, args, tmp, caches))
                shutil.rmtree(caches, ignore_errors=True)
        finally:
            if a.base:
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(wt)], capture_output=True)


if __name__ == "__main__":
    main()
