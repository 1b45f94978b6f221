"""Start-up and exact-path benchmark: prints figures, asserts nothing.

    .venv/bin/python bench/bench_startup.py [--repeat 7]

1. wall time of `rvbacklash --help` and of `rvbacklash analyze rv80e` (fresh interpreters,
   median of --repeat runs): what a user waits for;
2. the exact distribution of the linear model once the problem is prepared, in process
   (`simulate --method exact` without the interpreter and the file loading), for an all-normal
   design (closed form) and for a design with non-normal factors (FFT convolution);
3. which heavy modules `--help` loads (none should be).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

CLI = [str(Path(sys.executable).with_name("rvbacklash"))]


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


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    many, few = (1, 1) if a.tiny else (50, 5)
    if a.tiny:
        a.repeat = 1
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
    code = ("import sys\nfrom rvbacklash.cli import main\nsys.argv=['rvbacklash','--help']\n"
            "try:\n    main()\nexcept SystemExit:\n    pass\n"
            "print('|'.join(m for m in ('numpy', 'scipy', 'numba', 'pydantic', 'matplotlib') if m in sys.modules))")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.splitlines()[-1]
    print(f"heavy modules loaded by --help: {loaded or 'none'}")


if __name__ == "__main__":
    main()
