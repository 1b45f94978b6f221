"""A burst of 200 changes in 10 s (a hand dragging through a control): the server answers the
last change with its own result, leaves no computation behind and gives its memory back."""

from __future__ import annotations

import ctypes
import threading
import time
from pathlib import Path

import httpx2


def rss_mb() -> float:
    """The resident memory [MiB] once the allocator has given back what it holds free (so the
    figure follows what is kept, not the high-water mark of however many jobs overlapped). No
    garbage collection first: data kept in reference cycles (a superseded job's traceback held its
    arrays so) counts, as it does for the server."""
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except OSError:  # not glibc: the raw figure
        pass
    return int(Path("/proc/self/statm").read_text().split()[1]) * 4096 / 2**20


SIZES = 200  # changes per burst; the k-th change of either burst asks for the same samples


def samples(k: int) -> int:
    return 20000 + 997 * (1000 + k % SIZES)


def change(client: httpx2.Client, request_id: int, k: int) -> httpx2.Response:
    # the linear model (cheap), a grade and the samples moving as a hand would move them
    return client.post("/api/simulate", json={
        "design": "rv80e", "edits": {"grades.cycloid": 3 + k % 5}, "model": "linear", "samples": samples(k),
        "seed": 1, "specs": {"arcmin": 3}, "request_id": request_id, "channel": "burst"}, timeout=60)


def burst(url: str, first_id: int) -> dict[int, int]:
    """200 changes from 4 senders, 50 each, one every 0.2 s (request ids from ``first_id``): the
    status of each answer."""
    answers: dict[int, int] = {}
    lock = threading.Lock()

    def sender(first: int) -> None:
        with httpx2.Client(base_url=url) as own:
            for k in range(first, SIZES, 4):
                status = change(own, first_id + k, k).status_code
                with lock:
                    answers[k] = status
                time.sleep(0.2)

    senders = [threading.Thread(target=sender, args=(i,)) for i in range(4)]
    for t in senders:
        t.start()
    for t in senders:
        t.join(300)  # a guard against a hang, not a time limit
    return answers


def settle(client: httpx2.Client, jobs, request_id: int) -> None:
    """The change after a burst gets its own result; then no computation is left behind."""
    last = change(client, request_id, SIZES - 1)
    assert last.status_code == 200 and last.headers["x-request-id"] == str(request_id)
    assert last.json()["samples"] == samples(SIZES - 1)
    deadline = time.monotonic() + 60  # a guard: the superseded jobs stop between blocks
    while jobs.active() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert jobs.active() == 0  # no zombie computation
    assert client.get("/api/status").json()["active_jobs"] == 0


def test_a_burst_of_200_changes_in_10_s(workbench_server):
    """Two identical bursts (the same 200 sizes and grades, new request ids): memory after the
    second is compared with its level after the first, both read once the burst has settled and
    the allocator has returned its free memory; a cache or job kept per change would grow it."""
    jobs = workbench_server.app.state.jobs
    with httpx2.Client(base_url=workbench_server.url) as client:
        for k in range(5):  # warm: kernels, caches, thread pools
            assert change(client, k, k).status_code == 200
        threads_before = threading.active_count()
        first = burst(workbench_server.url, 1000)
        settle(client, jobs, 4000)
        rss_after_first = rss_mb()
        answers = burst(workbench_server.url, 1200)
        settle(client, jobs, 5000)
    for a in (first, answers):
        assert len(a) == 200 and set(a.values()) <= {200, 409}, set(a.values())
    assert threading.active_count() <= threads_before + 1
    assert rss_mb() < rss_after_first + 150, (rss_after_first, rss_mb())  # caches are bounded
