"""The design workbench (``rvbacklash app``): a local web page where every what-if input of a
design is a control and the production run's figures answer live (docs/workbench.md).

Built on Starlette (served by uvicorn) with one static page and plotly's JavaScript, both served
from the installed packages: it works with no network. Every figure on the page comes from a JSON
endpoint (``rvbacklash.app.endpoints``) that runs the same API and the same JSON rendering as the
command line.
"""

from __future__ import annotations

from rvbacklash.app.endpoints import create_app

__all__ = ["create_app"]
