"""The studio in real headless Chromium (Debian's `chromium`, driven by Playwright): build a level by clicks and
keys (a green ball, a blue target, a thruster), play it until solved, keep the episode as its solution, save it,
and check the saved file with `kinetix validate --play`. A screenshot of the canvas must show the level."""

from __future__ import annotations

import io
import json
import shutil

import numpy as np
import pytest
from PIL import Image

from helpers.cli import kinetix
from kinetix_cli.studio.server import serve_in_background
from kinetix_cli.studio.service import Studio

CHROMIUM = shutil.which("chromium")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="needs Debian's chromium (apt install chromium; .ci/run does)")
TOKEN = "browser-test-token"
SCALE = 780 / 5.2  # canvas pixels per metre (studio.js: the world x in [-0.1, 5.1] on a 780-pixel canvas)


@pytest.fixture(scope="module")
def studio_url(tmp_path_factory):
    folder = tmp_path_factory.mktemp("studio-browser")
    studio = Studio(folder)
    studio.warm(("s",))
    server, port = serve_in_background(studio, TOKEN)
    yield f"http://127.0.0.1:{port}/?token={TOKEN}", folder
    server.should_exit = True


def test_build_play_solve_and_save_a_level_in_chromium(studio_url, capsys, tmp_path):
    sync_api = pytest.importorskip("playwright.sync_api")
    url, folder = studio_url
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        page = browser.new_page(viewport={"width": 1500, "height": 950})
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(url)
        message = page.locator("#message")
        sync_api.expect(message).to_contain_text("valid level of size s")
        canvas = page.locator("#canvas").bounding_box()

        def at(x: float, y: float) -> tuple[float, float]:  # a world point [m] on the page
            return canvas["x"] + (x + 0.1) * SCALE, canvas["y"] + (5.1 - y) * SCALE

        def click(x: float, y: float) -> None:
            page.mouse.click(*at(x, y))

        def drag(start: tuple[float, float], end: tuple[float, float]) -> None:
            page.mouse.move(*at(*start))
            page.mouse.down()
            page.mouse.move(*at(*end), steps=8)
            page.mouse.up()

        def settle() -> None:
            sync_api.expect(message).to_contain_text("valid level")

        # a green ball at (1, 2.5) in place of the new level's default ball at (2.5, 2.5)
        tool = lambda name: page.locator(f"#tools [data-tool={name}]").click()  # noqa: E731
        tool("circle")
        click(1.0, 2.5)
        settle()
        page.locator("#selection-form select").first.select_option("green")  # role: the first choice of a body
        settle()
        tool("select")
        click(2.5, 2.5)
        page.keyboard.press("Delete")
        settle()
        # a fixed blue target at (4, 2.5), no gravity
        tool("box")
        click(4.0, 2.5)
        settle()
        page.locator("#selection-form select").first.select_option("blue")
        settle()
        page.locator("#selection-form input[type=checkbox]").first.check()  # fixed
        settle()
        # turned a quarter turn by its rotate handle (0.3 m above its top), then scaled up by its corner handle
        tool("select")
        drag((4.0, 2.75 + 0.3), (3.45, 2.5))
        settle()
        drag((4.25 + 0.12, 2.25 - 0.12), (4.48, 2.02))
        settle()
        gravity_y = page.locator("#level-form input[type=number]").nth(1)
        gravity_y.fill("0")
        gravity_y.dispatch_event("change")
        settle()
        # a thruster on the ball pushing right (binding T0)
        tool("thruster")
        click(1.0, 2.5)
        settle()
        sync_api.expect(page.locator("#selection-form")).to_contain_text("direction_deg")  # the thruster's form
        direction = page.locator("#selection-form input[type=number]").nth(2)  # anchor x, anchor y, direction
        direction.fill("0")
        direction.dispatch_event("change")
        settle()
        sync_api.expect(page.locator("#selection-form input[type=number]").nth(2)).to_have_value("0")
        shot = page.locator("#canvas").screenshot()

        # play: hold J (thruster T0) until the ball reaches the target
        page.locator("#modes button[data-mode=play]").click()
        page.keyboard.down("j")
        sync_api.expect(page.locator("#play-readout")).to_contain_text("solved", timeout=30_000)
        page.keyboard.up("j")
        page.locator("#play-keep").click()
        sync_api.expect(message).to_contain_text("solution")
        page.once("dialog", lambda dialog: dialog.accept("built.json"))
        page.locator("#modes button[data-mode=edit]").click()
        page.locator("#save-as").click()
        sync_api.expect(message).to_contain_text("saved built.json")
        browser.close()
    assert not errors

    pixels = np.asarray(Image.open(io.BytesIO(shot)).convert("RGB")).astype(int)
    green = (abs(pixels - [0, 204, 0]).sum(axis=2) < 30).mean()
    blue = (abs(pixels - [0, 51, 102]).sum(axis=2) < 30).mean()  # fixed blue: the role colour x 0.5
    assert green > 0.002 and blue > 0.002  # the ball and the target are drawn
    Image.open(io.BytesIO(shot)).save(folder / "built.png")  # kept for a person to look at (pytest's basetemp)

    target = next(body for body in json.loads((folder / "built.json").read_text())["bodies"] if body["role"] == "blue")
    assert target["angle_deg"] == 90 and 0.6 < target["size"][0] < 0.7 and target["size"][0] == target["size"][1]
    checked = kinetix(capsys, "validate", "--play", folder / "built.json")
    assert checked.code == 0 and "solution solves in" in checked.out, checked.out
