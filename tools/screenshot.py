"""Screenshot of an HTML report with Debian's chromium (headless, via playwright).

    python tools/screenshot.py REPORT.html OUT.png [--full]
"""

from __future__ import annotations

import sys
from pathlib import Path

from playwright.sync_api import sync_playwright

CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def main() -> None:
    html, png = Path(sys.argv[1]).resolve(), Path(sys.argv[2])
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1200, "height": 1500})
        page.goto(html.as_uri())
        page.screenshot(path=str(png), full_page="--full" in sys.argv)
        browser.close()
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
