"""Update rate of the operator's display (docs/display.md): the crane, 4 ghosts, the tip's path
and 20 obstacles, redrawn per frame on a running display with a client connected.

    pytest benchmarks/test_bench_view.py --benchmark-only      the figures of docs/display.md
    pytest benchmarks --benchmark-disable                      each once, as a test (CI)

Target: >= 20 frames per second. Printed (frames/s in extra_info), not asserted: timings on a
shared machine are noisy. Each frame alternates between two verdicts (WARN and STOP, different
poses and obstacles in contact), so every update changes what is drawn.
"""

from __future__ import annotations

import threading
import time

import pytest

import cranepredict as cp

from test_bench_guard import site_world

viser = pytest.importorskip("viser")
from cranepredict.view import Frame, Viewer  # noqa: E402
from cranepredict.view import scene as sc  # noqa: E402

TARGET_HZ = 20.0
#: The browser benchmark's pushing rate (above the target) and duration.
PUSH_HZ = 25.0
SECONDS = 4.0


def _frames(world):
    out = []
    for name in ("paper-fig4", "end-stop-lift-lower"):
        s = cp.scenarios.get(name)
        out.append(Frame.predict(s.crane, world, s.initial, s.inputs, s.horizon))
    return out


class _Client:
    """A websocket client that receives and drops everything the display sends (as a browser
    would receive it), so that the server really encodes and sends each frame."""

    def __init__(self, url: str) -> None:
        from websockets.sync.client import connect

        self.ws = connect(url.replace("http://", "ws://"),
                          subprotocols=[f"viser-v{viser.__version__}"], max_size=None)
        self.received = 0
        self.thread = threading.Thread(target=self._drain, daemon=True)
        self.thread.start()

    def _drain(self) -> None:
        try:
            for message in self.ws:
                self.received += len(message)
        except Exception:   # closed at the end of the benchmark
            pass

    def close(self) -> None:
        self.ws.close()
        self.thread.join(timeout=5)


@pytest.fixture(scope="module")
def display():
    world = site_world()
    assert len(world.obstacles) == 20
    frames = _frames(world)
    v = Viewer(port=0, ghosts=4)
    v.show(frames[0])
    client = _Client(v.url)
    yield v, frames, world, client
    client.close()
    v.close()


def _report(benchmark, label: str) -> None:
    stats = getattr(benchmark, "stats", None)
    if stats is None or not getattr(stats, "stats", None):
        return
    mean = stats.stats.mean
    benchmark.extra_info["frames_per_s"] = round(1.0 / mean, 1)
    print(f"\n{label}: {mean * 1e3:.2f} ms per frame = {1.0 / mean:.0f} frames/s "
          f"(target >= {TARGET_HZ:g}: {'met' if 1.0 / mean >= TARGET_HZ else 'NOT met'})")


def test_view_scene_of_a_frame(benchmark, display):
    """The arrays of one frame: the parts at 5 poses (now + 4 ghosts) as instances."""
    _, frames, _, _ = display
    scene = benchmark(sc.frame_scene, frames[0])
    assert len(scene.ghost_times) == 4
    _report(benchmark, "scene of a frame (crane + 4 ghosts)")


def test_view_update_rate(benchmark, display):
    """Viewer.show on a running display with a client: crane, 4 ghosts, tip path, contact, banner
    and (the obstacle in contact changes) the 20 obstacles."""
    v, frames, _, client = display
    i = iter(range(10 ** 9))

    def one():
        v.show(frames[next(i) % 2])

    before = client.received
    benchmark(one)
    assert v.frames_shown > 1
    v.server.flush()
    deadline = time.time() + 5
    while client.received == before and time.time() < deadline:
        time.sleep(0.05)
    assert client.received > before        # the client really got the updates
    _report(benchmark, "display update (crane + 4 ghosts + 20 obstacles)")


def test_view_guard_and_update_rate(benchmark, display):
    """A whole cycle of a live display: the guard's verdict on a 2-s future (20 obstacles), its
    frame and the update."""
    v, _, world, _ = display
    s = cp.scenarios.get("paper-fig4")

    def cycle():
        v.show(Frame.predict(s.crane, world, s.initial, s.inputs, s.horizon))

    benchmark(cycle)
    _report(benchmark, "guard + display update")


def test_view_update_rate_seen_by_the_browser(benchmark, display):
    """The frames a browser page actually receives and draws per second: headless Chromium (no
    GPU: WebGL in software) on the display while frames are pushed at PUSH_HZ for SECONDS s (a
    live loop's pace); the page counts, at each of its animation frames, the distinct frame
    numbers in the banner.
    Skips where Debian's chromium or Playwright's client is missing (in CI both are installed)."""
    import shutil

    playwright = pytest.importorskip("playwright.sync_api")
    exe = shutil.which("chromium")
    if exe is None:
        pytest.skip("Debian's chromium is not installed")
    _, frames, _, _ = display
    v = Viewer(port=0, ghosts=4)        # the browser its only client
    v.show(frames[0])
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
             "--disable-component-update", "--no-first-run", "--enable-unsafe-swiftshader"]
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=exe, args=flags)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(v.url)
            page.wait_for_selector("#cp-banner[data-frame]", timeout=60_000)
            time.sleep(2.0)
            page.evaluate("""() => {
                window.cpSeen = []; window.cpPaints = 0;
                const tick = () => {
                    window.cpPaints += 1;
                    const b = document.querySelector('#cp-banner');
                    const n = b ? b.dataset.frame : null;
                    if (n !== null && (cpSeen.length === 0 || cpSeen[cpSeen.length - 1] !== n))
                        cpSeen.push(n);
                    requestAnimationFrame(tick);
                };
                requestAnimationFrame(tick);
            }""")
            def push() -> tuple:
                pushed, t0 = 0, time.perf_counter()
                while time.perf_counter() - t0 < SECONDS:     # at the pace of a live loop
                    v.show(frames[pushed % 2])
                    pushed += 1
                    time.sleep(max(0.0, t0 + pushed / PUSH_HZ - time.perf_counter()))
                return pushed, time.perf_counter() - t0

            # one round, through the benchmark fixture so that --benchmark-only runs it too
            pushed, wall = benchmark.pedantic(push, rounds=1, iterations=1)
            time.sleep(0.5)
            seen, paints = page.evaluate("() => [window.cpSeen.length, window.cpPaints]")
        finally:
            browser.close()
            v.close()
    print(f"\nbrowser (headless Chromium, software WebGL): {seen / wall:.0f} frames/s received "
          f"and drawn, {paints / (wall + 0.5):.0f} page paints/s; {pushed / wall:.0f} frames/s "
          f"pushed (target >= {TARGET_HZ:g}: {'met' if seen / wall >= TARGET_HZ else 'NOT met'} "
          f"in this browser)")
    assert pushed >= 0.8 * PUSH_HZ * SECONDS - 1     # the pushing side kept the pace
    assert seen > 1
    benchmark.extra_info.update(frames_per_s_drawn=round(seen / wall, 1),
                                paints_per_s=round(paints / (wall + 0.5), 1))
