"""Start-up benchmark: prints figures, asserts nothing.

    .venv/bin/python bench/bench_startup.py [--base REV] [--repeat 5] [--tiny]

1. The warm start-up of a small what-if on the command line, `rvbacklash simulate rv80e --model
   contact -n 1000` (issue 35: <= 1.5 s), and the same with the elastic model: wall time and CPU
   time (user + sys of the process and its threads) of a fresh process whose compiled kernels are
   in numba's cache. This checkout (its working tree) side by side with ``--base`` (a commit,
   checked out into a temporary git worktree and run with this virtual environment and its own
   source on PYTHONPATH, as tools/compare_outputs.py does), alternated ``--repeat`` times after
   one warm-up run each (which compiles the kernels into the cache if they are not there: minutes
   for a base never run before). Median and best of each; on a shared machine the CPU time is the
   figure to compare (the wall time waits for the other processes). Python writes its bytecode
   files as a user's would (PYTHONDONTWRITEBYTECODE is dropped for the runs).
2. Wall time of `rvbacklash --help` and of `rvbacklash analyze rv80e` (fresh interpreters, median
   of --repeat runs): what a user waits for.
3. The exact distribution of the linear model once the problem is prepared, in process
   (`simulate --method exact` without the interpreter and the file loading), for an all-normal
   design (closed form) and for a design with non-normal factors (FFT convolution).
4. Which heavy modules `--help` loads (none should be).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CLI = [str(Path(sys.executable).with_name("rvbacklash"))]
WHAT_IFS = {"contact": ["simulate", "rv80e", "--model", "contact", "-n", "1000", "-q"],
            "elastic": ["simulate", "rv80e", "--model", "elastic", "-n", "1000", "-q"]}


def wall(args: list[str], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(CLI + args, capture_output=True, check=True)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def in_process(fn, repeat: int) -> float:
    fn()  # first call: imports
    t = time.perf_counter()
    for _ in range(repeat):
        fn()
    return (time.perf_counter() - t) / repeat


def timed_run(src: Path, args: list[str]) -> tuple[float, float]:
    """(wall, CPU) [s] of `python -m rvbacklash ARGS` with ``src`` first on the path."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(src)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "rvbacklash", *args], capture_output=True, text=True, env=env)
    seconds = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        raise SystemExit(f"{src}: `rvbacklash {' '.join(args)}` failed ({p.returncode}): {p.stderr.strip()[-300:]}")
    return seconds, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def side_by_side(sides: dict[str, Path], args: list[str], repeat: int) -> dict[str, list[tuple[float, float]]]:
    """Every side once to warm its caches, then ``repeat`` alternations."""
    for src in sides.values():
        timed_run(src, args)
    runs: dict[str, list[tuple[float, float]]] = {name: [] for name in sides}
    for _ in range(repeat):
        for name, src in sides.items():
            runs[name].append(timed_run(src, args))
    return runs


def startup_table(sides: dict[str, Path], repeat: int, models: list[str]) -> None:
    print(f"warm start-up, fresh process, {repeat} alternated run(s) per side after a warm-up "
          f"(median / best) [s]:")
    for model in models:
        args = WHAT_IFS[model]
        runs = side_by_side(sides, args, repeat)
        print(f"  `rvbacklash {' '.join(args)}`")
        for name, rs in runs.items():
            w, c = [r[0] for r in rs], [r[1] for r in rs]
            print(f"    {name:<28} wall {statistics.median(w):6.2f} / {min(w):6.2f}    "
                  f"CPU {statistics.median(c):6.2f} / {min(c):6.2f}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--base", help="a commit to compare the start-up with (e.g. bd2a342, issue 35's start)")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    many, few = (1, 1) if a.tiny else (50, 5)
    if a.tiny:
        a.repeat = 1
    with tempfile.TemporaryDirectory(prefix="rvb-bench-startup-") as tmp:
        sides = {"this checkout": ROOT / "src"}
        if a.base:
            wt = Path(tmp) / "base"
            subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-f", str(wt), a.base], check=True,
                           capture_output=True)
            sides = {f"base {a.base}": wt / "src", **sides}
        try:
            startup_table(sides, a.repeat, ["contact"] if a.tiny else ["contact", "elastic"])
        finally:
            if a.base:
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(wt)], capture_output=True)

    print(f"rvbacklash --help           {wall(['--help'], a.repeat) * 1e3:8.0f} ms (median of {a.repeat})")
    print(f"rvbacklash analyze rv80e    {wall(['analyze', 'rv80e'], a.repeat) * 1e3:8.0f} ms")

    import rvbacklash as rb
    from rvbacklash.design.loading import design_from_toml, example_text

    normal = rb.prepare("rv80e")
    text = example_text("sun2014").replace("[factors.disc_cumulative_pitch]\n",
                                           "[factors.disc_cumulative_pitch]\ndistribution = \"uniform\"\n", 1)
    mixed = rb.prepare(design_from_toml(text))
    print(f"exact, all-normal (closed form), prepared: {in_process(lambda: rb.exact(normal, spec_arcmin=3.0), many) * 1e3:8.2f} ms")
    print(f"exact, one uniform factor (FFT), prepared: "
          f"{in_process(lambda: rb.exact(mixed, spec_arcmin=3.0), few) * 1e3:8.2f} ms")
    code = ("import atexit, sys\nfrom rvbacklash.cli import main\nsys.argv=['rvbacklash','--help']\n"
            "atexit.register(lambda: print('|'.join(m for m in ('numpy', 'scipy', 'numba', 'pydantic', 'matplotlib') "
            "if m in sys.modules)))\n"
            "main()\n")  # read in an exit handler: the console script's main() ends the process itself
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.splitlines()[-1]
    print(f"heavy modules loaded by --help: {loaded or 'none'}")


if __name__ == "__main__":
    main()
