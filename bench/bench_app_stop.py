"""Workbench benchmark: how fast a cancelled job stops, per job kind; prints figures, asserts
nothing.

    .venv/bin/python bench/bench_app_stop.py [--wait 60] [--tiny] [--only KIND,...]

Each job is sent to a real workbench server (uvicorn on a loopback port) as the page sends it,
at the largest size the workbench accepts for it (its cap); once it has run for a while (it
reports progress, or 1.5 s have passed), ``POST /api/cancel`` asks it to stop. Printed: the time
from the cancel to the job's answer (409), or that it ran on; beside it the process's CPU time
after the cancel (the machine here is shared: wall times drift with the load, CPU time less).
``--wait``: how long to wait for the answer. (The hysteresis loop, the TE curve and the elastic
section are single steps of about a second at their caps: not timed here.)
"""

from __future__ import annotations

import argparse
import os
import threading
import time

from bench_app import start_server  # this directory: the same workbench on a free loopback port

# job kind -> (endpoint, body): each at the workbench's cap for it (SAMPLE_CAPS in
# src/rvbacklash/app/requests.py; explicit here, so that an older workbench runs the same jobs)
JOBS = {
    "simulate contact": ("/api/simulate", {"model": "contact", "samples": 10_000_000}),
    "simulate elastic": ("/api/simulate", {"model": "elastic", "samples": 2_000_000}),
    "simulate transmission": ("/api/simulate", {"model": "transmission", "samples": 20_000}),
    "elastic section": ("/api/elastic-section", {"samples": 10_000}),
    "sensitivity contact": ("/api/sensitivity", {"model": "contact", "samples": 1 << 19}),
    "sensitivity elastic": ("/api/sensitivity", {"model": "elastic", "samples": 1 << 16}),
    "sensitivity transmission": ("/api/sensitivity", {"model": "transmission", "samples": 1 << 10}),
    "report elastic": ("/api/report", {"model": "elastic", "samples": 2_000_000}),
    "report transmission": ("/api/report", {"model": "transmission", "samples": 20_000}),
    "allocate contact": ("/api/allocate", {"model": "contact", "spec_arcmin": 3, "yield": 0.99, "samples": 1 << 16}),
    "allocate elastic": ("/api/allocate", {"model": "elastic", "spec_arcmin": 1.5, "yield": 0.99, "samples": 10_000}),
}
TINY = 1000


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--wait", type=float, default=60.0)
    ap.add_argument("--finish", type=float, default=600.0, help="how much longer to wait for a job that ran on")
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    ap.add_argument("--only", default="", help="comma-separated job kinds (default: all)")
    a = ap.parse_args()
    import httpx2

    server, url = start_server()
    kinds = [k for k in JOBS if not a.only or k in a.only.split(",")]
    if a.tiny:
        kinds = ["simulate contact", "sensitivity contact"]
        print("tiny sizes (--tiny): the figures below say little about a real job")
    with httpx2.Client(base_url=url, timeout=600) as client:
        # warm: the kernels of every model loaded before any timing
        for m in ("contact",) if a.tiny else ("contact", "elastic", "transmission"):
            client.post("/api/simulate", json={"design": "rv80e", "model": m, "samples": 256})
        for n, kind in enumerate(kinds):
            path, body = JOBS[kind]
            body = {"design": "rv80e", **body, "request_id": f"stop-{n}"}
            if a.tiny:
                body["samples"] = TINY if path != "/api/sensitivity" else 1024
            answer: dict = {}

            def send(body=body, answer=answer):
                with httpx2.Client(base_url=url, timeout=a.wait + 600) as own:
                    answer["response"] = own.post(path, json=body)
                answer["t"] = time.perf_counter()

            sender = threading.Thread(target=send, daemon=True)
            started = time.perf_counter()
            sender.start()
            while sender.is_alive() and time.perf_counter() - started < 30:
                p = client.get("/api/progress", params={"id": body["request_id"]})
                if p.status_code == 200 and p.json()["state"] == "running" and \
                        (p.json()["done"] or time.perf_counter() - started > 1.5):
                    break
                time.sleep(0.05)
            time.sleep(0.2)
            if not sender.is_alive():
                r = answer["response"]
                print(f"{kind:24s} samples {body['samples']:>9}: finished before the cancel "
                      f"({r.status_code}, {answer['t'] - started:.2f} s)")
                continue
            cpu0 = time.process_time()
            t0 = time.perf_counter()
            client.post("/api/cancel", json={"id": body["request_id"]})
            sender.join(a.wait)
            if sender.is_alive():
                print(f"{kind:24s} samples {body['samples']:>9}: still running {a.wait:.0f} s after the cancel "
                      f"(CPU {time.process_time() - cpu0:.1f} s)", end="", flush=True)
                sender.join(a.finish)  # the jobs after it would wait for it
                if sender.is_alive():
                    print(f"; still running {a.wait + a.finish:.0f} s after: stopping here", flush=True)
                    os._exit(0)  # the worker thread would keep the process alive
                print(f"; answered {answer['t'] - t0:.0f} s after (HTTP {answer['response'].status_code})", flush=True)
                continue
            r = answer["response"]
            print(f"{kind:24s} samples {body['samples']:>9}: cancel -> answer {answer['t'] - t0:6.2f} s "
                  f"(HTTP {r.status_code}; ran {t0 - started:.1f} s before; CPU after the cancel "
                  f"{time.process_time() - cpu0:.2f} s)")
    server.should_exit = True


if __name__ == "__main__":
    main()
