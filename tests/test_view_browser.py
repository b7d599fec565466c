"""The display in a real browser: headless Chromium opens the page, takes screenshots at known
states and checks what a person sees there (the banner's colour and text by the DOM and by the
screenshot's pixels; the ghosts, the obstacles and the scrubbed pose by the pixels they change
when switched on and off) and that the page asks nothing of any other machine.

Needs the [view] and [browser] extras and Debian's chromium (.ci/run installs all three). Outside
CI a missing piece skips these tests; in CI (CI set) it fails them. The screenshots are kept in
$CRANEPREDICT_SCREENSHOTS when that is set (else in pytest's tmp folder)."""

from __future__ import annotations

import io
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path
from urllib.parse import urlparse

import numpy as np
import pytest

import cranepredict as cp

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--no-first-run",
         # WebGL on the CPU (SwiftShader): Chromium asks for this once there is no GPU
         "--enable-unsafe-swiftshader"]
VIEWPORT = {"width": 1280, "height": 800}


def _need(what: str, ok: bool) -> None:
    if not ok:
        if os.environ.get("CI"):
            pytest.fail(f"{what} is missing: .ci/run installs it")
        pytest.skip(f"{what} is not installed")


def _chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    _need("Debian's chromium", path is not None)
    return path  # type: ignore[return-value]


@pytest.fixture(scope="module")
def browser():
    try:
        import viser  # noqa: F401
        _need("viser ([view] extra)", True)
    except ImportError:
        _need("viser ([view] extra)", False)
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _need("playwright ([browser] extra)", False)
    exe = _chromium()
    # Playwright starts chromium on a fresh temporary profile (its own --user-data-dir)
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=exe, args=FLAGS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def shots(tmp_path_factory) -> Path:
    out = os.environ.get("CRANEPREDICT_SCREENSHOTS")
    if out:
        Path(out).mkdir(parents=True, exist_ok=True)
        return Path(out)
    return tmp_path_factory.mktemp("screenshots")


class Page:
    """A browser tab on the display, recording every request it makes."""

    def __init__(self, browser, url: str,
                 ready: str = "#cp-banner:not([data-signal=FAULT])") -> None:
        self.url = url
        self.requests: list = []
        self.context = browser.new_context(viewport=VIEWPORT)
        self.page = self.context.new_page()
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.page.goto(url)
        self.page.wait_for_selector(ready, timeout=60_000)
        self.page.wait_for_selector("canvas", timeout=60_000)
        # the software-WebGL notice (headless has no GPU) covers part of the scene: close it
        self.settle()
        for button in self.page.locator(".mantine-Notification-closeButton").all():
            button.click()
        self.settle()

    def settle(self, timeout: float = 30.0) -> None:
        """Waits for the scene to be received and drawn: until two screenshots 0.4 s apart are
        the same (software WebGL is slow, and slower on a busy machine)."""
        deadline = time.time() + timeout
        time.sleep(0.4)
        last = self.page.screenshot()
        while time.time() < deadline:
            time.sleep(0.4)
            shot = self.page.screenshot()
            if shot == last:
                return
            last = shot
        pytest.fail(f"the page did not settle within {timeout:g} s")

    def png(self, path: Path) -> np.ndarray:
        data = self.page.screenshot(path=str(path))
        from PIL import Image

        return np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(int)

    def banner(self) -> dict:
        return self.page.eval_on_selector("#cp-banner", """e => {
            const r = e.getBoundingClientRect();
            const f = {};
            e.querySelectorAll('[data-field]').forEach(x => f[x.dataset.field] = x.textContent);
            return {signal: e.dataset.signal, text: e.innerText, fields: f,
                    background: getComputedStyle(e).backgroundColor,
                    box: [r.left, r.top, r.right, r.bottom]};
        }""")

    def changed(self, before: bytes, timeout: float = 30.0) -> None:
        """Waits until the page differs from the screenshot ``before`` (the server's answer to
        an action has arrived), then until it settles."""
        deadline = time.time() + timeout
        while self.page.screenshot() == before:
            if time.time() > deadline:
                pytest.fail(f"the page did not change within {timeout:g} s")
            time.sleep(0.2)
        self.settle()

    def toggle(self, label: str) -> None:
        before = self.page.screenshot()
        self.page.get_by_role("checkbox", name=label).click()
        self.changed(before)

    def foreign_requests(self) -> list:
        """Requests to anything but the display's own server (blob: and data: are in-page)."""
        own = urlparse(self.url).netloc
        return [u for u in self.requests
                if not (u.startswith(("blob:", "data:")) or urlparse(u).netloc == own)]

    def close(self) -> None:
        self.context.close()


def _rgb(css: str) -> tuple:
    return tuple(int(x) for x in re.findall(r"\d+", css)[:3])


def _hex(colour: str) -> tuple:
    return tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))


def _scene_region(img: np.ndarray, banner_box) -> np.ndarray:
    """The 3D view left of the control panel."""
    return img[:, : int(banner_box[0]) - 10]


def _changed(a: np.ndarray, b: np.ndarray) -> int:
    return int(np.count_nonzero(np.abs(a - b).sum(axis=2) > 30))


def _viewer(frame):
    from cranepredict.view import Viewer

    v = Viewer(port=0)
    v.show(frame)
    return v


def _frame(scenario: str, world: str):
    from cranepredict.view import Frame

    sc = cp.scenarios.get(scenario)
    return Frame.predict(sc.crane, cp.worlds.get(world), sc.initial, sc.inputs, sc.horizon)


def _check_banner(page: Page, img: np.ndarray, frame) -> dict:
    from cranepredict.view.scene import SIGNAL_COLOURS

    b = page.banner()
    v = frame.verdict
    assert b["signal"] == v.signal
    assert b["text"].splitlines()[0].strip() == v.signal            # the big word on top
    assert _rgb(b["background"]) == _hex(SIGNAL_COLOURS[v.signal])
    # the screenshot's pixels in the banner are mostly its colour (the text is white)
    x0, y0, x1, y1 = (int(round(c)) for c in b["box"])
    patch = img[y0 + 3:y1 - 3, x0 + 3:x1 - 3].reshape(-1, 3)
    share = np.mean(np.abs(patch - np.array(_hex(SIGNAL_COLOURS[v.signal]))).sum(axis=1) < 12)
    assert share > 0.5, f"banner pixels of the signal's colour: {share:.0%}"
    return b


def test_go_scenario_shows_green_banner_ghosts_and_obstacles(browser, shots):
    frame = _frame("paper-fig4", "cab")
    assert frame.signal == "GO"
    v = _viewer(frame)
    page = Page(browser, v.url)
    try:
        img = page.png(shots / "view-go-paper-fig4-cab.png")
        b = _check_banner(page, img, frame)
        assert "no contact within 2 s" in b["text"]
        assert b["fields"] == {"time to contact": "-", "part": "-", "obstacle": "-",
                               "begin stopping by": "-"}
        scene = _scene_region(img, b["box"])
        # parts clear of everything are green: that colour is on the screen (shaded)
        green = (scene[..., 1] > scene[..., 0] + 40) & (scene[..., 1] > scene[..., 2] + 20)
        assert np.count_nonzero(green) > 2000
        # the ghosts: switching them off changes the picture where they were
        page.toggle("ghosts (the crane ahead)")
        no_ghosts = _scene_region(page.png(shots / "view-go-no-ghosts.png"), b["box"])
        assert _changed(scene, no_ghosts) > 1500
        # the obstacles (the cab, its exhaust stack, the ground): likewise
        page.toggle("obstacles")
        bare = _scene_region(page.png(shots / "view-go-no-obstacles.png"), b["box"])
        assert _changed(no_ghosts, bare) > 5000
        page.toggle("obstacles")
        page.toggle("ghosts (the crane ahead)")
        # both layers drawn again: the same presence tests as above, on the restored page (its
        # pixels need not equal the first render's: the translucent ghosts are blended in the
        # order the renderer sorts them); a software renderer on a loaded machine may take
        # seconds to draw them
        deadline = time.monotonic() + 20.0
        while True:
            again = _scene_region(page.png(shots / "view-go-again.png"), b["box"])
            back = _changed(again, no_ghosts) > 1500 and _changed(again, bare) > 5000
            if back or time.monotonic() > deadline:
                break
            time.sleep(0.5)
        assert _changed(again, no_ghosts) > 1500 and _changed(again, bare) > 5000
        assert page.foreign_requests() == []
        assert any(u.startswith(v.url) for u in page.requests)
    finally:
        page.close()
        v.close()


def test_stop_scenario_shows_red_banner_part_and_obstacle(browser, shots):
    frame = _frame("paper-fig4", "building-edge")
    assert frame.signal == "STOP"
    c = frame.verdict.contact
    v = _viewer(frame)
    page = Page(browser, v.url)
    try:
        img = page.png(shots / "view-stop-paper-fig4-building-edge.png")
        b = _check_banner(page, img, frame)
        assert b["fields"]["part"] == c.part == "load"
        assert b["fields"]["obstacle"] == c.obstacle == "building"
        assert b["fields"]["time to contact"] == "0.00 s"
        assert f"{c.part} - {c.obstacle}" in b["text"]
        scene = _scene_region(img, b["box"])
        # the obstacle in contact is drawn in its own colour (magenta), the load within the
        # margin in red
        magenta = (scene[..., 0] > scene[..., 1] + 60) & (scene[..., 2] > scene[..., 1] + 60)
        red = (scene[..., 0] > scene[..., 1] + 90) & (scene[..., 0] > scene[..., 2] + 90)
        assert np.count_nonzero(magenta) > 2000
        assert np.count_nonzero(red) > 200
        assert page.foreign_requests() == []
    finally:
        page.close()
        v.close()


def test_warn_scenario_scrubbing_the_timeline_moves_the_crane_ahead(browser, shots):
    frame = _frame("paper-fig4", "power-line")
    assert frame.signal == "WARN"
    c = frame.verdict.contact
    v = _viewer(frame)
    page = Page(browser, v.url)
    try:
        img = page.png(shots / "view-warn-paper-fig4-power-line.png")
        b = _check_banner(page, img, frame)
        assert b["fields"]["time to contact"] == f"{c.t:.2f} s"
        assert b["fields"]["begin stopping by"] == f"{frame.verdict.stop.latest:.2f} s"
        assert b["fields"]["obstacle"].startswith("conductor")
        page.toggle("ghosts (the crane ahead)")
        before = _scene_region(page.png(shots / "view-warn-now.png"), b["box"])
        # a person types a time into the timeline's box: the crane at that time appears
        box = page.page.locator("input[type=number], input.mantine-NumberInput-input").first
        shot = page.page.screenshot()
        box.fill("1.5")
        box.press("Enter")
        page.changed(shot)
        after = _scene_region(page.png(shots / "view-warn-scrub-1.5s.png"), b["box"])
        assert abs(v._timeline.value - 1.5) < 0.02
        assert "t = 1.50 s" in page.page.inner_text("body")
        assert _changed(before, after) > 1500
        assert page.foreign_requests() == []
    finally:
        page.close()
        v.close()


def test_replay_position_and_fault(browser, shots):
    """A recording (frames at successive clocks) on the recording slider: the banner follows the
    frame picked; a frame without a verdict shows FAULT."""
    from cranepredict.view import Frame

    sc = cp.scenarios.get("paper-fig4")
    world = cp.worlds.get("power-line")
    go = Frame.predict(sc.crane, world, sc.initial, sc.inputs, 0.3, clock=10.0)
    warn = Frame.predict(sc.crane, world, sc.initial, sc.inputs, sc.horizon, clock=10.1)
    fault = Frame.faulted(sc.crane, sc.initial, world, "no CAN message for 0.25 s", clock=10.2)
    assert (go.signal, warn.signal, fault.signal) == ("GO", "WARN", "FAULT")
    from cranepredict.view import Viewer

    v = Viewer(port=0)
    v.play([go, warn, fault])
    page = Page(browser, v.url)
    try:
        assert page.banner()["signal"] == "GO"
        assert "at 10.00 s" in page.banner()["text"]
        for i, want in ((1, "WARN"), (2, "FAULT")):
            v._log_slider.value = i        # as the slider in the page does
            page.page.wait_for_selector(f"#cp-banner[data-signal={want}]", timeout=20_000)
            page.settle()
        img = page.png(shots / "view-replay-fault.png")
        b = page.banner()
        assert "no CAN message for 0.25 s" in b["text"] and "at 10.20 s" in b["text"]
        from cranepredict.view.scene import SIGNAL_COLOURS

        assert _rgb(b["background"]) == _hex(SIGNAL_COLOURS["FAULT"])
        x0, y0, x1, y1 = (int(round(c)) for c in b["box"])
        patch = img[y0 + 3:y1 - 3, x0 + 3:x1 - 3].reshape(-1, 3)
        assert np.mean(np.abs(patch - np.array(_hex(SIGNAL_COLOURS["FAULT"]))).sum(axis=1) < 12) > 0.5
        assert page.foreign_requests() == []
    finally:
        page.close()
        v.close()


def test_cli_view_serves_the_page_on_localhost(browser, shots):
    """`cranepredict view` as a user runs it: the address it prints opens the display."""
    proc = subprocess.Popen([sys.executable, "-m", "cranepredict.cli", "view", "--scenario",
                             "slew-folded", "--world", "building-edge", "--port", "0",
                             "--serve-for", "120"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        line = ""
        deadline = time.time() + 60
        while "display" not in line and time.time() < deadline:
            line = proc.stdout.readline()
            if not line and proc.poll() is not None:
                pytest.fail(f"cranepredict view exited: {proc.stderr.read()}")
        url = line.split()[1]
        assert url.startswith("http://127.0.0.1:")
        page = Page(browser, url)
        try:
            b = page.banner()
            assert b["signal"] == "GO"
            page.png(shots / "view-cli-slew-folded-building-edge.png")
            assert page.foreign_requests() == []
        finally:
            page.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_cli_view_replay_scrubs_a_recorded_log(browser, shots, tmp_path):
    """`cranepredict view --replay LOG` on a log of the simulated crane driving at the wall: the
    page opens on the first cycle; a person types a cycle into the recording's box and the
    banner and the crane follow."""
    from cranepredict.live.episode import demo_setup
    from cranepredict.live.runner import record
    from cranepredict.live.sim import LeverScript, Plant, SimCrane, perturbed_crane

    crane = cp.Crane.patu655()
    start, _, _ = demo_setup(crane)
    sim = SimCrane(Plant(perturbed_crane(crane), start),
                   LeverScript(((0.0, (0.0,) * 4), (0.1, (0.0, 0.0, 0.0, 1.0)))), obey=False)
    log = str(tmp_path / "towards-wall.asc")
    record(sim, 2.2, log)
    proc = subprocess.Popen([sys.executable, "-m", "cranepredict.cli", "view", "--replay", log,
                             "--world", "wall", "--port", "0", "--serve-for", "180"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = []
        deadline = time.time() + 120
        while not (lines and lines[-1].startswith("replay ")) and time.time() < deadline:
            line = proc.stdout.readline()
            if not line and proc.poll() is not None:
                pytest.fail(f"cranepredict view exited: {proc.stderr.read()}")
            lines.append(line)
        url = next(x for x in lines if x.startswith("display")).split()[1]
        counts = dict(re.findall(r"(GO|WARN|STOP|FAULT) (\d+)", lines[-1]))
        assert int(counts["STOP"]) > 0 and "220 cycles" in lines[-1]
        page = Page(browser, url, ready="#cp-banner[data-frame]:not([data-frame='0'])")
        try:
            assert page.banner()["signal"] == "FAULT"           # the estimator settling
            assert "at 0.00 s" in page.banner()["text"]
            first = page.png(shots / "view-replay-first-cycle.png")
            boxes = page.page.locator("input[type=number], input.mantine-NumberInput-input")
            box = boxes.nth(1)                                   # the recording's (after look ahead)
            shot = page.page.screenshot()
            box.fill("219")
            box.press("Enter")
            page.page.wait_for_selector("#cp-banner[data-signal=STOP]", timeout=30_000)
            page.changed(shot)
            img = page.png(shots / "view-replay-last-cycle-stop.png")
            b = page.banner()
            assert "at 2.19 s" in b["text"] and b["fields"]["obstacle"] == "wall"
            from cranepredict.view.scene import SIGNAL_COLOURS

            assert _rgb(b["background"]) == _hex(SIGNAL_COLOURS["STOP"])
            # the crane drawn moved: the telescope ran out some 0.4 m towards the wall
            assert _changed(_scene_region(first, b["box"]), _scene_region(img, b["box"])) > 1500
            assert page.foreign_requests() == []
        finally:
            page.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
