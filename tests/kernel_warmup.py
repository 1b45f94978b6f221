"""Compile numba's kernels once, before the suite's two xdist workers start (tests/conftest.py).

From an empty numba cache (a fresh clone: the cache is keyed by the package's source and its
folder, src/rvbacklash/_numba.py) each worker compiled a kernel the first time one of its tests
needed it, and both workers start with tests of the same models (the Ctrl-C tests and the benches
run the contact and elastic models first): the same kernels were compiled by both at once, and
every Ctrl-C test that stopped a process while it compiled threw its work away. Here they are
compiled once, two processes side by side, in two phases: the contact model's kernels (which the
elastic and transmission models call: ~50 s of CPU of ~135 s) beside the linear model's, then the
elastic model's (and what reads its solution: hysteresis, capacity, service life) beside the
transmission model's. The workers then load them from the cache. A kernel not compiled here is
compiled where it is first needed, as before: this only moves work, it never decides what runs.

    python tests/kernel_warmup.py GROUP      # one group (GROUPS), in this process
"""

from __future__ import annotations

import hashlib
import subprocess
import sys
import time
from pathlib import Path

PHASES = (("contact", "linear"), ("elastic", "transmission"))  # each phase's groups side by side
GROUPS = tuple(g for phase in PHASES for g in phase)


def run_group(group: str) -> None:
    """The small calls that compile (or load) the kernels of ``group``."""
    import rvbacklash as rb

    rv80e = rb.prepare("rv80e")
    if group == "linear":
        rb.simulate(rb.prepare("sun2014"), samples=1000, seed=1)
    elif group == "contact":
        rb.simulate(rv80e, samples=64, seed=1, model="contact")
    elif group == "elastic":
        rb.simulate(rv80e, samples=64, seed=1, model="elastic")
        rb.hysteresis(rv80e)
        rb.capacity(rv80e)
        rb.service_life(rv80e, duty_cycle="robot-joint", hours=(0.0, 1000.0), samples=16, seed=1)
    elif group == "transmission":
        rb.simulate(rv80e, samples=16, seed=1, model="transmission")
    else:
        raise SystemExit(f"unknown group {group!r}: one of {', '.join(GROUPS)}")


def stamp() -> Path:
    """The file that says this checkout's kernels were compiled for this source (the cache's own
    folder is named after a hash of the package's source; numba's entries in it are per source
    folder, hence the folder's hash in the name)."""
    from rvbacklash import _numba

    where = hashlib.sha1(str(_numba._PACKAGE).encode()).hexdigest()[:16]
    return Path(_numba._cache_dir()) / f"suite-warm-up-{where}"


def warm_up(write) -> None:
    """Compile the kernels in one process per group, side by side, unless the stamp says it was
    done; ``write(line)`` reports. A group that fails is reported and left to the tests (they
    compile what they need themselves and show the real error)."""
    done = stamp()
    if done.exists():
        return
    write("numba's cache is empty for this source: compiling the kernels once for both workers "
          f"({' then '.join(' beside '.join(phase) for phase in PHASES)}) ...")
    t = time.perf_counter()
    failed = []
    for phase in PHASES:
        procs = {g: subprocess.Popen([sys.executable, __file__, g], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True) for g in phase}
        for g, p in procs.items():
            _, err = p.communicate()
            if p.returncode:
                failed.append(g)
                write(f"kernel warm-up {g!r} failed (exit {p.returncode}); the tests compile what they need: "
                      + " | ".join(err.strip().splitlines()[-3:]))
    write(f"kernels compiled in {time.perf_counter() - t:.0f} s")
    if not failed:
        done.parent.mkdir(parents=True, exist_ok=True)
        done.write_text(f"{time.strftime('%Y-%m-%d %H:%M:%S')} {' '.join(GROUPS)}\n")


if __name__ == "__main__":
    run_group(sys.argv[1])
