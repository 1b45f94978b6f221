"""`rvbacklash app`: serves the page on 127.0.0.1 (a warning when --host exposes it), refuses a
bad design or port in one line before any server starts, stops on Ctrl-C."""

from __future__ import annotations

import signal
import subprocess
import sys

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
    calls = []
    monkeypatch.setattr("rvbacklash.app.server.serve", lambda *a, **k: calls.append((a, k)))
    p = run_cli("app", "rv80e", "--host", "0.0.0.0", "--no-browser")
    assert p.returncode == 0 and "warning: --host 0.0.0.0 exposes the workbench" in p.stderr
    assert "no authentication" in p.stderr
    assert calls == [(("rv80e", None), {"host": "0.0.0.0", "port": 8765, "open_browser": False})]
    p = run_cli("app", "rv80e", "--no-browser")
    assert p.returncode == 0 and p.stderr == "" and calls[-1][1]["host"] == "127.0.0.1"
