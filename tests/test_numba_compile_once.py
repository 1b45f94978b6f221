"""A kernel missing from numba's on-disk cache is compiled by one process at a time (rvbacklash._numba:
``_compiled_once``): a second process that needs it meanwhile waits, then loads the first one's
machine code from the cache instead of compiling it again (an empty cache in CI: pytest's two
workers and the commands they run compiled the same large kernels at the same time)."""

from __future__ import annotations

import fcntl
import importlib
import subprocess
import sys
import textwrap

from rvbacklash import _numba

KERNEL = textwrap.dedent("""
    from rvbacklash._numba import njit

    @njit(cache=True)
    def twice(x):
        return 2.0 * x
""")

OTHER = textwrap.dedent("""
    import sys
    sys.path.insert(0, sys.argv[1])
    import kernel_once
    print("ready", flush=True)
    assert kernel_once.twice(1.5) == 3.0
    print(sum(kernel_once.twice.stats.cache_misses.values()), sum(kernel_once.twice.stats.cache_hits.values()))
""")


def test_a_kernel_another_process_is_compiling_is_loaded_from_the_cache_not_compiled_again(tmp_path, monkeypatch):
    (tmp_path / "kernel_once.py").write_text(KERNEL)  # a kernel of its own: an empty cache for it
    monkeypatch.syspath_prepend(str(tmp_path))
    kernel = importlib.import_module("kernel_once").twice
    lock = kernel._cache._cache_file._index_path + ".lock"
    held = getattr(_numba, "_held", set())  # the locks this process holds (its own compile does not wait)
    with open(lock, "w") as f:
        fcntl.flock(f, fcntl.LOCK_EX)  # this process compiles the kernel: the other one must wait
        held.add(lock)
        try:
            other = subprocess.Popen([sys.executable, "-c", OTHER, str(tmp_path)], stdout=subprocess.PIPE, text=True)
            assert other.stdout.readline().strip() == "ready"  # it is about to call the kernel
            assert kernel(2.0) == 4.0  # compiled here (and saved to the cache) while the other process waits
            assert sum(kernel.stats.cache_misses.values()) == 1
        finally:
            held.discard(lock)
    out, _ = other.communicate(timeout=600)
    assert other.returncode == 0
    misses, hits = map(int, out.split())
    assert (misses, hits) == (0, 1)  # loaded from the cache, not compiled a second time
