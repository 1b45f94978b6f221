"""Serving the workbench: uvicorn on 127.0.0.1 unless told otherwise, the browser opened once
the server listens."""

from __future__ import annotations

import errno
import ipaddress
import socket
import sys
import threading
import time
import webbrowser

from rvbacklash.errors import InputError

LOOPBACK_NAMES = ["127.0.0.1", "localhost", "::1", "[::1]"]


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def listening_socket(host: str, port: int) -> socket.socket:
    """The socket the workbench listens on, bound here (uvicorn is given it): a name that does not
    resolve, a port in use or an address not of this machine is the command line's one line
    (``--host`` / ``--port``), before any server starts."""
    try:
        found = socket.getaddrinfo(host.strip("[]"), port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
        # IPv4 first where a name has both (localhost), as uvicorn binds a name
        family, kind, proto, _, address = min(found, key=lambda f: f[0] != socket.AF_INET)
    except (socket.gaierror, UnicodeError) as e:
        reason = e.strerror if isinstance(e, socket.gaierror) else "not a valid name"
        raise InputError("--host", host, f"cannot be resolved ({reason}); allowed: an address or a name of this "
                                         f"machine, e.g. 127.0.0.1") from None
    sock = socket.socket(family, kind, proto)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as uvicorn binds: no wait after a restart
        sock.bind(address)
    except OSError as e:
        sock.close()
        if e.errno == errno.EADDRINUSE:
            raise InputError("--port", port, "is in use by another program; allowed: a free port, or 0 (any free "
                                             "port)") from None
        if e.errno == errno.EACCES:
            raise InputError("--port", port, "needs privileges to listen on; allowed: a port above 1023, or 0 "
                                             "(any free port)") from None
        raise InputError("--host", host, f"cannot be listened on ({e.strerror}); allowed: an address of this "
                                         f"machine, e.g. 127.0.0.1") from None
    sock.set_inheritable(True)
    return sock


def server_for(app, sock_host: str, log_level: str = "warning"):
    """A uvicorn server of the workbench ``app`` whose stop (Ctrl-C, SIGTERM) first cancels every
    job: a running computation stops within a second, its request answers 409 and the connection
    closes, so the graceful shutdown does not wait for it (it used to wait for an allocation's end)."""
    import uvicorn

    class Server(uvicorn.Server):
        def handle_exit(self, sig, frame) -> None:
            app.state.jobs.cancel_all("server stopping")
            super().handle_exit(sig, frame)

    # the graceful shutdown waits at most this long for requests under way (a step no job can
    # interrupt, such as the FE of a new geometry); requests are bounded (413 beyond MAX_BODY_BYTES)
    return Server(uvicorn.Config(app, host=sock_host, log_level=log_level, access_log=False,
                                 timeout_graceful_shutdown=GRACEFUL_S, limit_concurrency=MAX_CONNECTIONS))


GRACEFUL_S = 3
MAX_CONNECTIONS = 64  # connections and requests at once (503 beyond): a page uses a handful


def serve(design: str = "rv80e", origin: str | None = None, *, host: str = "127.0.0.1", port: int = 8765,
          open_browser: bool = True, log_level: str = "warning", sock: socket.socket | None = None) -> None:
    """Run the workbench until Ctrl-C. ``design``: an example name or a design's TOML text (the
    command line reads a file given to it and passes its text). ``sock``: the socket bound to
    host and port (``listening_socket``: a host that does not resolve or a port in use is an
    ``InputError`` there, before any server starts); bound here if not given."""
    from rvbacklash.app.endpoints import create_app

    sock = sock if sock is not None else listening_socket(host, port)
    local = is_loopback(host)
    # on loopback only the loopback names are accepted as Host: a page of another site cannot reach
    # the workbench through a name that resolves to 127.0.0.1 (DNS rebinding)
    app = create_app(design, origin, allowed_hosts=LOOPBACK_NAMES if local else None, warm=True)
    server = server_for(app, host, log_level)

    def announce() -> None:
        while not server.started and not server.should_exit:
            time.sleep(0.05)
        if not server.started:
            return
        bound = sock.getsockname()
        shown = "127.0.0.1" if local and host != "localhost" else host
        url = f"http://{'[' + shown + ']' if ':' in shown else shown}:{bound[1]}/"
        sys.stdout.write(f"rvbacklash workbench: {url}  (Ctrl-C stops it)\n")
        sys.stdout.flush()
        if open_browser:
            webbrowser.open(url)

    threading.Thread(target=announce, name="rvb-announce", daemon=True).start()
    server.run(sockets=[sock])
