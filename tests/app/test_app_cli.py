"""`rvbacklash app`: serves the page on 127.0.0.1 (a warning when --host exposes it), refuses a
bad design or port in one line before any server starts, stops on Ctrl-C."""

from __future__ import annotations

import signal
import socket
import subprocess
import sys
import threading
import time

import httpx2

from helpers import one_line_error, run_cli


def test_app_serves_the_page_and_stops_on_ctrl_c():
    p = subprocess.Popen([sys.executable, "-m", "rvbacklash", "app", "rv80e", "--no-browser", "--port", "0"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = p.stdout.readline()
        assert line.startswith("rvbacklash workbench: http://127.0.0.1:"), (line, p.stderr.read() if p.poll() else "")
        url = line.split()[2]
        with httpx2.Client(base_url=url, timeout=60) as c:
            assert c.get("/api/status").json()["active_jobs"] >= 0
            assert "rvbacklash workbench" in c.get("/").text
            # another name for 127.0.0.1 is refused (DNS rebinding): only the loopback names
            assert c.get("/api/status", headers={"Host": "attacker.example"}).status_code == 400
    finally:
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
    assert p.returncode in (0, 130), err
    assert "Traceback" not in err


def test_app_refuses_a_bad_design_or_port_in_one_line(tmp_path):
    one_line_error(run_cli("app", "no-such-design", "--no-browser"), "error: design = 'no-such-design'")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = 1\n")
    one_line_error(run_cli("app", bad, "--no-browser"), "error: ")
    one_line_error(run_cli("app", "rv80e", "--port", "70000", "--no-browser"), "error: --port = 70000")


def test_app_warns_when_its_host_exposes_it(monkeypatch):
    calls, bound = [], []
    monkeypatch.setattr("rvbacklash.app.server.serve", lambda *a, **k: calls.append((a, k)))
    # no real port: the test must not depend on 8765 being free
    monkeypatch.setattr("rvbacklash.app.server.listening_socket", lambda host, port: bound.append((host, port)) or "S")
    p = run_cli("app", "rv80e", "--host", "0.0.0.0", "--no-browser")
    assert p.returncode == 0 and "warning: --host 0.0.0.0 exposes the workbench" in p.stderr
    assert "no authentication" in p.stderr
    assert calls == [(("rv80e", None), {"host": "0.0.0.0", "port": 8765, "open_browser": False, "sock": "S"})]
    assert bound == [("0.0.0.0", 8765)]
    p = run_cli("app", "rv80e", "--no-browser")
    assert p.returncode == 0 and p.stderr == "" and calls[-1][1]["host"] == "127.0.0.1"


def test_a_busy_port_or_an_unknown_host_is_one_line_before_any_server_starts():
    """They used to end in uvicorn's own message and exit 3 (issue 35, 2.9). The busy port is one
    this test holds (bound to port 0: any free port, never a fixed one)."""
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        line = one_line_error(run_cli("app", "rv80e", "--port", port, "--no-browser"), f"error: --port = {port}: ")
        assert "in use" in line and "0 (any free port)" in line
    line = one_line_error(run_cli("app", "rv80e", "--host", "no-such-host.invalid", "--no-browser"),
                          "error: --host = 'no-such-host.invalid': cannot be resolved")
    assert "warning" not in line  # refused before the warning about a non-loopback host


def test_ctrl_c_stops_the_app_and_the_jobs_under_way():
    """Ctrl-C while computations run: every job cancelled, the process gone with exit 130 (it used
    to wait for the jobs to end: still alive after a minute, issue 35, 2.7). The two jobs would take
    a minute and a half together on two idle cores; the bounds below are upper bounds for a loaded
    machine, not the expected times (about a second when idle)."""
    p = subprocess.Popen([sys.executable, "-m", "rvbacklash", "app", "rv80e", "--no-browser", "--port", "0"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    answers: dict[str, object] = {}
    jobs = {"live": ("/api/simulate", {"model": "elastic", "samples": 2_000_000}),
            "sobol": ("/api/sensitivity", {"model": "elastic", "samples": 1 << 16})}
    senders = []
    try:
        line = p.stdout.readline()  # the server says when it listens: no sleeping
        assert line.startswith("rvbacklash workbench: http://127.0.0.1:"), (line, p.stderr.read() if p.poll() else "")
        url = line.split()[2]

        def send(job_id: str) -> None:
            path, body = jobs[job_id]
            try:
                with httpx2.Client(base_url=url, timeout=1200) as own:
                    answers[job_id] = own.post(path, json={"design": "rv80e", **body, "request_id": job_id}).status_code
            except httpx2.HTTPError as e:  # the connection closed as the server stopped
                answers[job_id] = type(e).__name__

        with httpx2.Client(base_url=url, timeout=60) as c:
            for job_id in jobs:  # one after the other: the live one waits for the warm-up (the kernels load)
                senders.append(threading.Thread(target=send, args=(job_id,), daemon=True))
                senders[-1].start()
                deadline = time.monotonic() + 900  # an upper bound for a loaded machine (seconds when idle)
                while c.get("/api/progress", params={"id": job_id}).json().get("state") != "running":
                    assert time.monotonic() < deadline and not answers, answers
                    time.sleep(0.1)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    assert p.returncode == 130, (p.returncode, err)
    assert "Traceback" not in err and err.strip().splitlines()[-1] == "interrupted: nothing was written", err
    for t in senders:
        t.join(60)
    # each request was answered "cancelled" (409) or "the workbench is stopping" (503), or its connection closed
    assert set(answers) == set(jobs) and all(a in (409, 503) or isinstance(a, str) for a in answers.values()), answers
