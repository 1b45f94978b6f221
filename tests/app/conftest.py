"""A real workbench server (uvicorn on a free loopback port, in a thread) for the burst and
browser tests."""

from __future__ import annotations

import threading
import time

import pytest


class Running:
    def __init__(self, app, server, thread):
        self.app, self.server, self.thread = app, server, thread
        port = server.servers[0].sockets[0].getsockname()[1]
        self.url = f"http://127.0.0.1:{port}"


@pytest.fixture(scope="module")
def workbench_server():
    import uvicorn

    from rvbacklash.app import create_app
    from rvbacklash.app.server import LOOPBACK_NAMES

    app = create_app("rv80e", allowed_hosts=LOOPBACK_NAMES)
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=0, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started and time.monotonic() < deadline:
        time.sleep(0.02)
    assert server.started, "the workbench server did not start"
    yield Running(app, server, thread)
    server.should_exit = True
    thread.join(30)
