"""Workbench benchmark: the time from a change to the updated cards, per model; prints figures,
asserts nothing.

    .venv/bin/python bench/bench_app.py [--samples 20000] [--repeat 5] [--tiny]

A change is a grade moved and a new seed (a new design: read, edited, prepared, simulated; never a
cached result) sent to a real workbench server (uvicorn on a loopback port) as the page sends it; the
time runs until the answer (the JSON the cards show) is parsed. Targets (issue 30): <= 1 s for the
elastic model at 20 000 units, <= 0.3 s for the contact and linear models. The transmission model
has no target (printed for scale at a tenth of the units).
"""

from __future__ import annotations

import argparse
import json
import statistics
import threading
import time

TARGETS_S = {"elastic": 1.0, "contact": 0.3, "linear": 0.3}


def start_server():
    import uvicorn

    from rvbacklash.app import create_app

    server = uvicorn.Server(uvicorn.Config(create_app("rv80e"), host="127.0.0.1", port=0, log_level="warning"))
    threading.Thread(target=server.run, daemon=True).start()
    while not server.started:
        time.sleep(0.02)
    return server, f"http://127.0.0.1:{server.servers[0].sockets[0].getsockname()[1]}"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=float, default=20_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--tiny", action="store_true", help="tiny sizes: the test suite runs every bench so none rots")
    a = ap.parse_args()
    n, repeat = int(a.samples), a.repeat
    if a.tiny:
        n, repeat = 256, 2
        print("tiny sizes (--tiny): the figures below say nothing about the targets")
    import httpx2

    from rvbacklash.analysis.simulation import default_workers

    server, url = start_server()
    specs = {"elastic": {"lost_motion_arcmin": 1.5, "rigidity_nm_per_arcmin": 450.0}, "contact": {"arcmin": 3.0},
             "linear": {"arcmin": 3.0}, "transmission": {"arcmin": 3.0, "te_arcsec": 60.0}}
    change = 0
    # what moves: the involute grade (a new design, prepared again; the cycloid stage's parts keep their
    # tolerances), or the cycloid grade (the discs' and pin holes' tolerances change: the long-wave error
    # model of each indexed part is calibrated again, sampling/part_errors.calibrate, ~0.1-0.3 s a part)
    rows = [(m, "involute") for m in ("elastic", "contact", "linear", "transmission")] + \
        [(m, "cycloid") for m in ("elastic", "contact")]
    with httpx2.Client(base_url=url, timeout=600) as client:
        for model, stage in rows:
            units = n if model != "transmission" else max(64, n // 10)
            times = []
            for k in range(repeat + 1):  # the first loads the kernels: not counted
                change += 1
                grade = (3 + change % 9) if stage == "cycloid" else 3 + change % 5
                body = {"design": "rv80e", "edits": {f"grades.{stage}": grade}, "model": model, "samples": units,
                        "seed": change, "specs": specs[model], "request_id": change, "channel": "bench"}
                t = time.perf_counter()
                r = client.post("/api/simulate", json=body)
                data = json.loads(r.text)
                dt = time.perf_counter() - t
                assert r.status_code == 200, r.text
                if k:
                    times.append((dt, data["elapsed_s"]))
            total = [t for t, _ in times]
            run = statistics.median(s for _, s in times)
            target = TARGETS_S.get(model)
            verdict = "" if target is None or a.tiny else ("  pass" if statistics.median(total) <= target else "  FAIL")
            print(f"change -> cards, {model:12s} {stage:8s} grade, {units:6d} units ({default_workers()} threads): "
                  f"median {statistics.median(total):6.3f} s, max {max(total):6.3f} s (the run {run:6.3f} s)"
                  + (f"; target <= {target:g} s{verdict}" if target is not None else "; no target"))
    server.should_exit = True


if __name__ == "__main__":
    main()
