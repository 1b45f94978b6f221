"""Serving the workbench: uvicorn on 127.0.0.1 unless told otherwise, the browser opened once
the server listens."""

from __future__ import annotations

import ipaddress
import sys
import threading
import time
import webbrowser

LOOPBACK_NAMES = ["127.0.0.1", "localhost", "::1", "[::1]"]


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def serve(design: str = "rv80e", origin: str | None = None, *, host: str = "127.0.0.1", port: int = 8765,
          open_browser: bool = True, log_level: str = "warning") -> None:
    """Run the workbench until Ctrl-C. ``design``: an example name or a design's TOML text (the
    command line reads a file given to it and passes its text)."""
    import uvicorn

    from rvbacklash.app.endpoints import create_app

    local = is_loopback(host)
    # on loopback only the loopback names are accepted as Host: a page of another site cannot reach
    # the workbench through a name that resolves to 127.0.0.1 (DNS rebinding)
    app = create_app(design, origin, allowed_hosts=LOOPBACK_NAMES if local else None, warm=True)
    server = uvicorn.Server(uvicorn.Config(app, host=host, port=port, log_level=log_level, access_log=False))

    def announce() -> None:
        while not server.started and not server.should_exit:
            time.sleep(0.05)
        if not server.started:
            return
        bound = server.servers[0].sockets[0].getsockname() if server.servers else (host, port)
        shown = "127.0.0.1" if local and host != "localhost" else host
        url = f"http://{'[' + shown + ']' if ':' in shown else shown}:{bound[1]}/"
        sys.stdout.write(f"rvbacklash workbench: {url}  (Ctrl-C stops it)\n")
        sys.stdout.flush()
        if open_browser:
            webbrowser.open(url)

    threading.Thread(target=announce, name="rvb-announce", daemon=True).start()
    server.run()
