"""Every performance target of issue 19 in one table: prints figures, asserts nothing.

    .venv/bin/python bench/bench_all.py [--repeat 3] [--no-commands] [--tiny]      (make bench)

Rows, each with its target and pass/fail:
1. contact model production run (rv80e, end to end through the engine, all cores) [units/s];
2. elastic model production run (same) [units/s];
3. wall time of `rvbacklash sensitivity rv80e --model elastic` (default N) [s];
4. wall time of `rvbacklash allocate rv80e --model elastic --spec-arcmin 1.5 --yield 0.8
   --spec-preload-um 10` [s] (a feasible spec since issue 28's chain: rv80e as given reaches 0.76,
   the allocation finds grades at 0.80; at 1 arcmin the best candidate reached 0.45, exit 2, and
   the row timed that refusal);
5. linear engine (sun2014, 21 normal inputs, all cores) [M samples/s];
6. its ratio to numpy generating the same N x 21 normals (one thread), measured in the same run.
The engine and numpy are timed alternately ``--repeat`` times and the best of each is kept: the
machine may be shared, a ratio of two figures taken minutes apart would mean little.
Rows 3-4 take minutes: ``--no-commands`` leaves them out. ``--tiny`` runs everything at a tiny
size in seconds (the test suite does, so that the bench cannot rot); its figures mean nothing.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_montecarlo import engine_rate, numpy_rate  # noqa: E402

SENSITIVITY = ["sensitivity", "rv80e", "--model", "elastic"]
ALLOCATE = ["allocate", "rv80e", "--model", "elastic", "--spec-arcmin", "1.5", "--yield", "0.8", "--spec-preload-um",
            "10"]


@dataclass(frozen=True)
class Row:
    figure: str
    value: float | None  # None: not measured
    unit: str
    target: float
    higher_is_better: bool
    note: str = ""
    failed: bool = False  # the row's command failed: no figure, the note says why

    @property
    def verdict(self) -> str:
        if self.failed:
            return "FAILED"
        if self.value is None:
            return "skipped"
        ok = self.value >= self.target if self.higher_is_better else self.value <= self.target
        return "pass" if ok else "FAIL"

    def cells(self) -> tuple[str, ...]:
        value = "-" if self.value is None else _number(self.value)
        target = f"{'>=' if self.higher_is_better else '<='} {_number(self.target)} {self.unit}"
        return self.figure, f"{value} {self.unit}", target, self.verdict, self.note


def _number(x: float) -> str:
    return f"{x:,.0f}" if abs(x) >= 100 else f"{x:.3g}"


def model_rate(model: str, samples: int) -> float:
    """Units/s of a production run of ``model`` on rv80e through the engine (after a warm-up)."""
    import rvbacklash as rb

    problem = rb.prepare("rv80e")
    rb.simulate(problem, samples=min(samples, 2048), seed=0, model=model)  # compile / load the kernels
    t = time.perf_counter()
    rb.simulate(problem, samples=samples, seed=1, model=model)
    return samples / (time.perf_counter() - t)


def command_row(args: list[str], target_s: float, skip: bool) -> Row:
    """Wall time of one CLI command in a fresh process (start-up included, as a user waits). A
    command that fails (any non-zero exit, e.g. exit 2 "no design confirmed") has no time: the
    row says FAILED and gives the command's message."""
    label = "`rvbacklash " + " ".join(args) + "`"
    if skip:
        return Row(label, None, "s", target_s, False, "left out (--no-commands)")
    t = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "rvbacklash", *args, "--quiet"], capture_output=True, text=True)
    seconds = time.perf_counter() - t
    if p.returncode:
        message = " ".join(p.stderr.strip().splitlines()[-1:])[-100:]
        return Row(label, None, "s", target_s, False, f"exit {p.returncode}: {message}", failed=True)
    return Row(label, seconds, "s", target_s, False, "wall time, fresh process")


def linear_rows(samples: int, numpy_samples: int, repeat: int) -> list[Row]:
    from rvbacklash.analysis.simulation import default_workers

    engine, numpy_ = 0.0, 0.0
    for _ in range(repeat):  # alternated: both see the same machine
        engine = max(engine, engine_rate(samples)[0])
        numpy_ = max(numpy_, numpy_rate(numpy_samples))
    note = f"best of {repeat}, {default_workers()} threads; numpy {numpy_ / 1e6:.2f} M/s (1 thread)"
    return [Row("linear engine (sun2014, 21 normals)", engine / 1e6, "M samples/s", 25.0, True, note),
            Row("linear engine / numpy generation", engine / numpy_, "x", 5.0, True, "same run, alternated")]


def table(rows: list[Row]) -> str:
    head = ("figure", "measured", "target", "result", "note")
    cells = [head] + [r.cells() for r in rows]
    widths = [max(len(c[i]) for c in cells) for i in range(len(head))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(line, widths)).rstrip() for line in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="alternations of the linear engine and numpy")
    ap.add_argument("--no-commands", action="store_true", help="leave out the sensitivity and allocate wall times")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    units, linear, numpy_n = (200_000, 100_000_000, 20_000_000)
    sens, alloc = SENSITIVITY, ALLOCATE
    if a.tiny:
        units, linear, numpy_n, a.repeat = 256, 4096, 4096, 1
        # the linear model's commands: the same code path (a fresh process, wall time) in a second or two
        sens, alloc = ["sensitivity", "rv80e", "-n", "64"], ["allocate", "rv80e", "--spec-arcmin", "3", "--yield", "0.9"]
    rows = [Row("contact model production run (rv80e)", model_rate("contact", units), "units/s", 500e3, True,
                f"{units:,} units"),
            Row("elastic model production run (rv80e)", model_rate("elastic", units // 4), "units/s", 60e3, True,
                f"{units // 4:,} units")]
    rows += [command_row(sens, 20.0, a.no_commands), command_row(alloc, 30.0, a.no_commands)]
    rows += linear_rows(linear, numpy_n, a.repeat)
    if a.tiny:
        print("tiny sizes (--tiny): the figures below say nothing about the targets")
    print(table(rows))


if __name__ == "__main__":
    main()
