"""``rvbacklash app``: the design workbench in the browser (docs/workbench.md)."""

from __future__ import annotations

import sys

import typer

from rvbacklash.cli.app import app
from rvbacklash.cli.common import command
from rvbacklash.errors import InputError


@app.command("app")
@command
def workbench(
    design: str = typer.Argument("rv80e", help="TOML design file, or a built-in example name (see `rvbacklash "
                                               "examples`); the page opens with it."),
    port: int = typer.Option(8765, "--port", help="TCP port (0: any free port)."),
    host: str = typer.Option("127.0.0.1", "--host", help="Address to listen on. Anything but loopback exposes the "
                                                         "workbench to the network, without authentication."),
    no_browser: bool = typer.Option(False, "--no-browser", help="Do not open the page in a browser."),
) -> None:
    """A local web page where every what-if input of the design is a control and the production
    run's figures (means, tails, yields, histograms, the hysteresis loop, TE) answer live."""
    from rvbacklash.app.server import is_loopback, listening_socket, serve
    from rvbacklash.design.loading import available_examples, load_design_source

    if not 0 <= port <= 65535:
        raise InputError("--port", port, "allowed: 0 to 65535")
    _, origin, text = load_design_source(design)  # a bad design: its one line, before any server starts
    sock = listening_socket(host, port)  # a host that does not resolve, a port in use: one line, exit 2
    if not is_loopback(host):
        sys.stderr.write(f"warning: --host {host} exposes the workbench to the network; it has no authentication: "
                         f"anyone who reaches it can run computations on this machine\n")
    serve(design if design in available_examples() and origin.startswith("example:") else text,
          None if origin.startswith("example:") else origin, host=host, port=port, open_browser=not no_browser,
          sock=sock)
