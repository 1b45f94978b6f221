"""A burst of 200 changes in 10 s (a hand dragging through a control): the server answers the
last change with its own result, leaves no computation behind and gives its memory back."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import httpx2


def rss_mb() -> float:
    return int(Path("/proc/self/statm").read_text().split()[1]) * 4096 / 2**20


def change(client: httpx2.Client, k: int) -> httpx2.Response:
    # the linear model (cheap), a grade and the samples moving as a hand would move them
    return client.post("/api/simulate", json={
        "design": "rv80e", "edits": {"grades.cycloid": 3 + k % 5}, "model": "linear", "samples": 20000 + 997 * k,
        "seed": 1, "specs": {"arcmin": 3}, "request_id": k, "channel": "burst"}, timeout=60)


def test_a_burst_of_200_changes_in_10_s(workbench_server):
    jobs = workbench_server.app.state.jobs
    with httpx2.Client(base_url=workbench_server.url) as client:
        for k in range(5):  # warm: kernels, caches, thread pools
            assert change(client, k).status_code == 200
        threads_before, rss_before = threading.active_count(), rss_mb()
        answers: dict[int, int] = {}
        lock = threading.Lock()

        def sender(first: int) -> None:
            with httpx2.Client(base_url=workbench_server.url) as own:
                for k in range(first, 200, 4):  # 4 senders, 50 changes each, one every 0.2 s
                    status = change(own, 1000 + k).status_code
                    with lock:
                        answers[k] = status
                    time.sleep(0.2)

        started = time.monotonic()
        senders = [threading.Thread(target=sender, args=(i,)) for i in range(4)]
        for t in senders:
            t.start()
        for t in senders:
            t.join(60)
        last = change(client, 5000)  # the change after the burst: its own result
        assert last.status_code == 200 and last.headers["x-request-id"] == "5000"
        assert last.json()["samples"] == 20000 + 997 * 5000
        deadline = time.monotonic() + 10
        while jobs.active() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert jobs.active() == 0  # no zombie computation
        assert client.get("/api/status").json()["active_jobs"] == 0
    assert len(answers) == 200 and set(answers.values()) <= {200, 409}, set(answers.values())
    assert time.monotonic() - started < 60
    assert threading.active_count() <= threads_before + 1
    assert rss_mb() < rss_before + 150, (rss_before, rss_mb())  # caches are bounded: back near its level
