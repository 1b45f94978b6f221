"""Screenshot of the workbench (docs/workbench.png) with Debian's chromium (headless, playwright):
a workbench server on a free loopback port, the rv80e example, the elastic model at 20 000 units,
the cycloid grade moved from 5 to 4.

    python tools/screenshot_workbench.py OUT.png
"""

from __future__ import annotations

import sys
import threading
import time

from playwright.sync_api import sync_playwright

CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def main() -> None:
    import uvicorn

    from rvbacklash.app import create_app

    server = uvicorn.Server(uvicorn.Config(create_app("rv80e"), host="127.0.0.1", port=0, log_level="warning"))
    threading.Thread(target=server.run, daemon=True).start()
    while not server.started:
        time.sleep(0.05)
    url = f"http://127.0.0.1:{server.servers[0].sockets[0].getsockname()[1]}/"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1400, "height": 1250})
        page.goto(url)
        page.wait_for_function("document.body.dataset.shown", timeout=300_000)
        page.wait_for_selector("#fig-loop .main-svg", timeout=300_000)
        # a change, as a designer makes it: the cycloid stage one grade finer (the timing shown is this change's)
        shown = page.evaluate("window.workbench.seq")
        page.select_option("#grade-cycloid", "4")
        page.wait_for_function(f"document.body.dataset.shown > {shown}", timeout=300_000)
        time.sleep(1.5)
        page.screenshot(path=sys.argv[1])
        browser.close()
    server.should_exit = True
    print(f"wrote {sys.argv[1]}")


if __name__ == "__main__":
    main()
