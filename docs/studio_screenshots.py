"""The screenshots of docs/studio.md: the studio on the shipped levels in headless Chromium (Playwright driving
Debian's chromium). Run from the repository root: `.venv/bin/python docs/studio_screenshots.py`."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from playwright.sync_api import expect, sync_playwright

from kinetix_cli.studio.server import serve_in_background
from kinetix_cli.studio.service import Studio

TOKEN = "screenshots"
OUT = Path("docs")


def main() -> None:
    studio = Studio("levels")
    studio.warm(("s",))
    server, port = serve_in_background(studio, TOKEN)
    url = f"http://127.0.0.1:{port}/?token={TOKEN}&level=s/rocket-car-jump.json"
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=shutil.which("chromium"), args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1400, "height": 1010})
        page.goto(url)
        expect(page.locator("#message")).to_contain_text("valid level")
        page.wait_for_timeout(1500)  # thumbnails
        page.mouse.click(*_pixel(page, 0.8, 0.6))  # select the chassis
        page.screenshot(path=OUT / "studio-edit.png")
        page.locator("#modes button[data-mode=play]").click()
        page.keyboard.down("e")  # motor M2 forward, with the rocket (T1) from step 16, as the level's solution
        page.wait_for_timeout(500)
        page.keyboard.down("k")
        page.wait_for_timeout(300)
        page.screenshot(path=OUT / "studio-play.png")
        page.keyboard.up("e")
        page.keyboard.up("k")
        page.locator("#modes button[data-mode=watch]").click()
        page.locator("#evaluate").click()
        expect(page.locator("#eval-readout")).to_contain_text("attempts", timeout=120_000)
        page.locator("#watch").click()
        expect(page.locator("#watch-readout")).to_contain_text(re.compile(r"step [1-9]"), timeout=120_000)
        page.wait_for_timeout(1500)
        page.screenshot(path=OUT / "studio-watch.png")
        browser.close()
    server.should_exit = True
    print("wrote docs/studio-edit.png, docs/studio-play.png, docs/studio-watch.png")


def _pixel(page, x: float, y: float) -> tuple[float, float]:
    box = page.locator("#canvas").bounding_box()
    scale = 780 / 5.2
    return box["x"] + (x + 0.1) * scale, box["y"] + (5.1 - y) * scale


if __name__ == "__main__":
    main()
