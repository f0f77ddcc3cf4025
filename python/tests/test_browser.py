"""The pages of the `penumbra` binary in a real browser: headless Chromium,
driven through Selenium, opens the live preview of `render --preview` and
checks what a person would: the image refines pass by pass, the exposure and
zoom controls act on it, the Stop button ends the render cleanly, and the
browser's console stays free of errors.

The harness is two fixtures that any page of the binary can use: `serve`
starts a `penumbra` command that prints `LABEL: http://...` on stderr and
returns its URL and process, and `browser` gives a Chromium driver. Both are
torn down after each test.

Chromium and its driver come from Debian's `chromium` and `chromium-driver`
(which `scripts/test` installs); without them these tests skip. Selenium is
given the driver's path, so it never downloads one. With
`PENUMBRA_UPDATE_DOCS=1` the screenshot goes to `docs/images/preview.png`.
"""

from __future__ import annotations

import base64
import os
import re
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
CHROMIUM = Path("/usr/bin/chromium")
CHROMEDRIVER = Path("/usr/bin/chromedriver")
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--window-size=1000,640",
]

#: Generous bounds for anything the tests wait for: the machine may be busy.
TIMEOUT = 60.0

#: A render whose passes come a few a second and which lasts far longer than
#: any test, so that the page is always live while a test looks at it (the
#: tests stop it, and the time limit ends it should a test fail to).
LONG_RENDER = ["--width", "320", "--height", "240", "--spp", "512", "--passes", "256",
               "--time-limit", "300"]


# ---------------------------------------------------------------- harness


def wait_for(condition: Callable[[], object], what: str, timeout: float = TIMEOUT):
    """Polls `condition` until it returns something true, and returns that."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout:.0f} s waiting for {what}")
        time.sleep(0.05)


@dataclass
class Server:
    """A running `penumbra` command that serves a page."""

    proc: subprocess.Popen
    url: str
    stderr_path: Path
    stdout_path: Path

    def stderr(self) -> str:
        return self.stderr_path.read_text(errors="replace")

    def wait(self, timeout: float = TIMEOUT) -> int:
        return self.proc.wait(timeout=timeout)


@pytest.fixture
def serve(cli: Path, tmp_path: Path):
    """Starts `penumbra ARGS` and waits for it to print `LABEL: URL` on
    stderr; returns a `Server`. Whatever is still running at the end of the
    test is interrupted (as Ctrl-C would), then killed if it lingers."""
    started: list[Server] = []

    def start(*args: str, label: str = "preview") -> Server:
        n = len(started)
        out, err = tmp_path / f"server{n}.stdout", tmp_path / f"server{n}.stderr"
        with out.open("wb") as o, err.open("wb") as e:
            proc = subprocess.Popen([str(cli), *args], stdout=o, stderr=e,
                                    stdin=subprocess.DEVNULL, cwd=tmp_path)
        pattern = re.compile(rf"^{re.escape(label)}: (http://\S+)$", re.M)

        def url():
            m = pattern.search(err.read_text(errors="replace"))
            if m:
                return m.group(1)
            if proc.poll() is not None:
                raise AssertionError(f"penumbra exited with {proc.returncode} before "
                                     f"printing its URL:\n{err.read_text(errors='replace')}")
            return None

        server = Server(proc, wait_for(url, f"the '{label}:' line"), err, out)
        started.append(server)
        return server

    yield start
    for s in started:
        if s.proc.poll() is None:
            s.proc.send_signal(signal.SIGINT)
            try:
                s.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                s.proc.kill()
                s.proc.wait()


@pytest.fixture
def browser(tmp_path: Path):
    """Headless Chromium through chromedriver, with a fresh profile and the
    console's messages kept for `console_errors`."""
    missing = [str(p) for p in (CHROMIUM, CHROMEDRIVER) if not os.access(p, os.X_OK)]
    if missing:
        pytest.skip(f"no {' and no '.join(missing)}: install Debian's chromium and "
                    "chromium-driver (scripts/test does) to run the browser tests")
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service

    options = Options()
    options.binary_location = str(CHROMIUM)
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    profile = tmp_path / "chromium-profile"
    profile.mkdir()
    options.add_argument(f"--user-data-dir={profile}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # A driver path given here means Selenium Manager never runs.
    driver = webdriver.Chrome(service=Service(executable_path=str(CHROMEDRIVER)),
                              options=options)
    driver.set_script_timeout(TIMEOUT)
    try:
        yield driver
    finally:
        driver.quit()


def console_errors(driver) -> list[str]:
    """The console's SEVERE messages since the last call."""
    return [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def screenshot_path(tmp_path: Path, name: str) -> Path:
    if os.environ.get("PENUMBRA_UPDATE_DOCS") == "1":
        return REPO / "docs" / "images" / name
    return tmp_path / name


# ---------------------------------------------------------------- the preview page


def text(driver, element_id: str) -> str:
    return driver.find_element("id", element_id).text


def shown_pass(driver) -> int:
    """The pass the page says it shows (0 before the first frame)."""
    m = re.fullmatch(r"pass (\d+)/(\d+)", text(driver, "pass"))
    return int(m.group(1)) if m else 0


def canvas_pixels(driver) -> np.ndarray:
    """The canvas's RGB bytes, height x width x 3, as the page drew them."""
    data = driver.execute_script("""
        const c = document.getElementById("image");
        const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
        let s = "";
        for (let i = 0; i < d.length; i += 0x8000)
          s += String.fromCharCode.apply(null, d.subarray(i, i + 0x8000));
        return [c.width, c.height, btoa(s)];
    """)
    w, h, b64 = data
    return np.frombuffer(base64.b64decode(b64), np.uint8).reshape(h, w, 4)[:, :, :3]


def open_preview(driver, server: Server, width: int = 320, height: int = 240):
    """Opens the page and waits until it shows a frame of the render."""
    driver.get(server.url)
    wait_for(lambda: driver.execute_script(
        "const c = document.getElementById('image'); return [c.width, c.height];")
        == [width, height], "the first frame")
    wait_for(lambda: shown_pass(driver) >= 1, "the pass counter")


def stable_pixels(driver, quiet: float = 0.5) -> np.ndarray:
    """The canvas once it has not changed for `quiet` seconds (a frame that
    was on its way has been drawn)."""
    state = {"pixels": canvas_pixels(driver), "since": time.monotonic()}

    def settled():
        now = canvas_pixels(driver)
        if not np.array_equal(now, state["pixels"]):
            state.update(pixels=now, since=time.monotonic())
        return time.monotonic() - state["since"] >= quiet

    wait_for(settled, "the canvas to settle")
    return state["pixels"]


def pixels_other_than(driver, base: np.ndarray, what: str) -> np.ndarray:
    """Waits for the canvas to show other pixels than `base`; returns them."""

    def changed():
        now = canvas_pixels(driver)
        return None if np.array_equal(now, base) else [now]

    return wait_for(changed, what)[0]


def stop_and_wait(driver, server: Server) -> int:
    """Presses Stop; returns the process's exit status."""
    driver.find_element("id", "stop").click()
    rc = server.wait()
    wait_for(lambda: text(driver, "status").startswith("stopped")
             and not text(driver, "status").startswith("stopping"), "the page to say it stopped")
    return rc


def test_preview_page_loads(serve, browser, tmp_path):
    server = serve("render", "showcase", "-o", "out.png", *LONG_RENDER, "--preview", "0")
    assert re.fullmatch(r"http://127\.0\.0\.1:\d+/\?token=[0-9A-Za-z_-]+", server.url)
    open_preview(browser, server)
    assert browser.title.endswith("penumbra preview")
    assert browser.find_element("id", "image").tag_name == "canvas"
    assert text(browser, "status") == "rendering"
    assert text(browser, "p-size") == "320 × 240"
    # The ray statistics are listed, with rays counted.
    assert int(re.sub(r"\D", "", text(browser, "p-rays")) or 0) > 0
    assert browser.find_elements("css selector", "#stats tr")
    assert console_errors(browser) == []


def test_preview_image_refines_pass_by_pass(serve, browser, tmp_path):
    server = serve("render", "showcase", "-o", "out.png", *LONG_RENDER, "--preview", "0")
    open_preview(browser, server)
    first_pass, first = shown_pass(browser), canvas_pixels(browser)
    assert first.max() > 0, "the first frame is black"
    later = wait_for(lambda: shown_pass(browser) > first_pass and shown_pass(browser),
                     "a later pass")
    wait_for(lambda: not np.array_equal(canvas_pixels(browser), first),
             f"the image to change after pass {first_pass} (now {later})")
    assert console_errors(browser) == []


def test_preview_exposure_scales_the_displayed_image(serve, browser, tmp_path):
    from selenium.webdriver.common.keys import Keys

    server = serve("render", "showcase", "-o", "out.png", *LONG_RENDER, "--preview", "0")
    open_preview(browser, server)
    # Stop first, so that only the exposure changes what the canvas shows.
    assert stop_and_wait(browser, server) == 0
    base = stable_pixels(browser)
    slider = browser.find_element("id", "exposure")

    slider.send_keys(*[Keys.ARROW_RIGHT] * 10)
    wait_for(lambda: text(browser, "exposure-value") == "+1.0", "the exposure to read +1.0")
    brighter = pixels_other_than(browser, base, "the canvas to brighten")
    assert (brighter >= base).all(), "a pixel darkened at a higher exposure"
    assert brighter.mean() > base.mean() + 10

    browser.find_element("id", "exposure-reset").click()
    wait_for(lambda: np.array_equal(canvas_pixels(browser), base),
             "exposure 0 to show the first pixels again")

    slider.send_keys(*[Keys.ARROW_LEFT] * 10)
    wait_for(lambda: text(browser, "exposure-value") == "-1.0", "the exposure to read -1.0")
    darker = pixels_other_than(browser, base, "the canvas to darken")
    assert (darker <= base).all(), "a pixel brightened at a lower exposure"
    assert darker.mean() < base.mean() - 10
    assert console_errors(browser) == []


def test_preview_zoom_changes_the_scale(serve, browser, tmp_path):
    server = serve("render", "showcase", "-o", "out.png", *LONG_RENDER, "--preview", "0")
    open_preview(browser, server)

    def shown_width() -> float:
        return browser.execute_script(
            "return document.getElementById('image').getBoundingClientRect().width;")

    def zoom_percent() -> float:
        return float(text(browser, "zoom-value").rstrip("%"))

    # At first the image fits the window: larger than its pixels here.
    fitted, fitted_zoom = shown_width(), zoom_percent()
    view = browser.execute_script("return document.getElementById('view').getBoundingClientRect();")
    assert fitted == pytest.approx(min(view["width"] / 320, view["height"] / 240) * 320, rel=1e-3)
    assert fitted == pytest.approx(320 * fitted_zoom / 100, rel=1e-2)

    browser.find_element("id", "zoom-one").click()
    wait_for(lambda: text(browser, "zoom-value") == "100%", "the zoom to read 100%")
    assert shown_width() == pytest.approx(320, rel=1e-6)
    browser.find_element("id", "zoom-in").click()
    wait_for(lambda: text(browser, "zoom-value") == "200%", "the zoom to read 200%")
    assert shown_width() == pytest.approx(640, rel=1e-6)
    browser.find_element("id", "zoom-out").click()
    browser.find_element("id", "zoom-out").click()
    wait_for(lambda: text(browser, "zoom-value") == "50%", "the zoom to read 50%")
    assert shown_width() == pytest.approx(160, rel=1e-6)
    browser.find_element("id", "zoom-fit").click()
    wait_for(lambda: zoom_percent() == fitted_zoom, "the zoom to fit again")
    assert shown_width() == pytest.approx(fitted, rel=1e-6)
    assert console_errors(browser) == []


def test_preview_stop_button_ends_the_render_cleanly(serve, browser, tmp_path):
    server = serve("render", "showcase", "-o", "out.png", "--checkpoint", "run.ckpt",
                   *LONG_RENDER, "--preview", "0")
    open_preview(browser, server)
    started = time.monotonic()
    assert stop_and_wait(browser, server) == 0, server.stderr()
    took = time.monotonic() - started
    stderr = server.stderr()
    assert "stopped from the preview" in stderr
    assert (tmp_path / "out.png").stat().st_size > 0
    assert (tmp_path / "run.ckpt").stat().st_size > 0
    # It stopped after a pass, long before its 256 passes.
    assert shown_pass(browser) < 256
    assert took < 30, f"the render took {took:.1f} s to stop"
    assert browser.find_element("id", "stop").get_attribute("disabled") is not None
    assert console_errors(browser) == []


def test_preview_screenshot(serve, browser, tmp_path):
    """Halfway through a render, as the docs show it."""
    server = serve("render", "showcase", "-o", "out.png", "--width", "320", "--height", "240",
                   "--spp", "64", "--passes", "16", "--preview", "0")
    open_preview(browser, server)
    wait_for(lambda: shown_pass(browser) >= 8, "pass 8 of 16")
    path = screenshot_path(tmp_path, "preview.png")
    assert browser.save_screenshot(str(path))
    assert path.stat().st_size > 10_000
    assert console_errors(browser) == []


# ---------------------------------------------------------------- the explorer page


def open_explorer(driver, server: Server) -> np.ndarray:
    """Opens the explorer and waits for its form and a first frame; returns
    the canvas once it has settled."""
    driver.get(server.url)
    wait_for(lambda: driver.find_elements("id", "c-integrator"), "the generated controls")
    wait_for(lambda: shown_pass(driver) >= 1, "the first frame")
    return stable_pixels(driver, quiet=1.0)


def test_explorer_controls_come_from_the_schema_and_change_the_render(serve, browser, tmp_path):
    server = serve("explore", "--width", "96", "--height", "72", "--spp", "4", "--threads", "1",
                   "--port", "0", label="explore")
    before = open_explorer(browser, server)
    # Every control the server's schema names is on the page, and nothing else.
    schema = browser.execute_async_script("""
        const done = arguments[arguments.length - 1];
        const token = new URLSearchParams(location.search).get("token");
        fetch("/schema?token=" + token).then(r => r.json()).then(s => done(s.controls.map(c => c.name)));
    """)
    ids = [e.get_attribute("id") for e in browser.find_elements("css selector", "#controls [id^='c-']")]
    assert ids == [f"c-{name}" for name in schema]
    # Choosing another pixel distribution re-renders: another run, other pixels.
    from selenium.webdriver.support.ui import Select

    Select(browser.find_element("id", "c-pixel_distribution")).select_by_value("random")
    after = pixels_other_than(browser, before, "the image to change with the pixel distribution")
    assert after.shape == before.shape
    assert console_errors(browser) == []


def test_explorer_dragging_orbits_the_camera(serve, browser, tmp_path):
    from selenium.webdriver.common.action_chains import ActionChains

    server = serve("explore", "--width", "96", "--height", "72", "--spp", "1", "--threads", "1",
                   "--port", "0", label="explore")
    before = open_explorer(browser, server)
    view = browser.find_element("id", "image")
    ActionChains(browser).click_and_hold(view).move_by_offset(40, 0).release().perform()
    pixels_other_than(browser, before, "the orbited camera's image")
    assert console_errors(browser) == []


def test_explorer_screenshot(serve, browser, tmp_path):
    """The explorer after a control was changed, as the docs show it."""
    from selenium.webdriver.support.ui import Select

    server = serve("explore", "--width", "320", "--height", "240", "--spp", "16", "--port", "0",
                   label="explore")
    before = open_explorer(browser, server)
    Select(browser.find_element("id", "c-shadow_distribution")).select_by_value("poisson")
    pixels_other_than(browser, before, "the render with poisson shadow sets")
    wait_for(lambda: re.fullmatch(r"pass (\d+)/\1", text(browser, "pass")), "the last pass")
    path = screenshot_path(tmp_path, "explore.png")
    assert browser.save_screenshot(str(path))
    assert path.stat().st_size > 10_000
    assert console_errors(browser) == []
