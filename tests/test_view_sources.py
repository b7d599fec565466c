"""The display's live sources without a browser: a recorded CAN log replayed through the live twin
(``cranepredict view --replay``) and the live loop (``cranepredict live --view``). What the page
would show is read from the viewer's own state: the frame on display, the banner it sent and the
crane's instances it sent, checked against the log's truth and the scene of the frame."""

from __future__ import annotations

import numpy as np
import pytest

import cranepredict as cp

pytest.importorskip("viser", reason="the [view] extra")
can = pytest.importorskip("can", reason="the [live] extra")
pytest.importorskip("cantools", reason="the [live] extra")

from cranepredict.cli import main  # noqa: E402
from cranepredict.live.episode import demo_setup  # noqa: E402
from cranepredict.live.loop import LiveTwin  # noqa: E402
from cranepredict.live.runner import record  # noqa: E402
from cranepredict.live.sim import LeverScript, Plant, SimCrane, perturbed_crane  # noqa: E402
from cranepredict.view import Frame, Viewer  # noqa: E402
from cranepredict.view import scene as sc  # noqa: E402
from cranepredict.view import server  # noqa: E402
from cranepredict.view.sources import LiveDisplay, frames_of_verdicts, replay_frames  # noqa: E402

SECONDS = 2.2


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A CAN log of the simulated crane (a perturbed plant, noisy sensors) extending its telescope
    at full lever towards the example world's wall, the verdicts not obeyed; and the plant's true
    state at each cycle's time."""
    crane = cp.Crane.patu655()
    start, _, _ = demo_setup(crane)
    script = LeverScript(((0.0, (0.0,) * 4), (0.1, (0.0, 0.0, 0.0, 1.0))))
    sim = SimCrane(Plant(perturbed_crane(crane), start), script, obey=False)
    path = str(tmp_path_factory.mktemp("log") / "towards-wall.asc")
    assert record(sim, SECONDS, path) == 220
    truth = {round(t, 6): state for t, state, _, _ in sim.history}
    return crane, path, truth


@pytest.fixture(scope="module")
def replayed(recorded):
    crane, path, truth = recorded
    world = cp.worlds.get("wall")
    return replay_frames(path, LiveTwin(crane, world)), world


def test_a_replay_has_one_frame_per_cycle_following_the_crane_in_the_log(recorded, replayed):
    crane, _, truth = recorded
    frames, world = replayed
    assert len(frames) == len(truth)                       # one per Levers frame of the log
    assert [f.clock for f in frames] == pytest.approx(sorted(truth))
    signals = [f.signal for f in frames]
    # settling after the start, then clear, then the wall ahead, then too close to wait
    assert signals[0] == "FAULT"
    order = [s for k, s in enumerate(signals) if k == 0 or s != signals[k - 1]]
    assert order == ["FAULT", "GO", "WARN", "STOP"]
    for f in frames:
        true = truth[round(f.clock, 6)]
        # the estimate drawn is the crane of the log at that time (0.1 mm sensors, full-lever run)
        assert abs(f.state.extension - true.extension) < 5e-3
        assert abs(f.state.lift_stroke - true.lift_stroke) < 2e-3
        if f.verdict is not None:
            assert f.world is world and f.t[0] == 0.0 and f.horizon == pytest.approx(2.0)
    stop = next(f for f in frames if f.signal == "STOP")
    assert stop.verdict.contact.obstacle == "wall"
    assert stop.verdict.contact.t < 0.5


def test_scrubbing_the_replay_timeline_changes_the_crane_and_the_banner(replayed):
    frames, world = replayed
    v = Viewer(port=0)
    try:
        v.play(frames)
        assert v.position == 0 and v.frame is frames[0]
        assert 'data-signal="FAULT"' in v._banner.content
        picks = {s: next(k for k, f in enumerate(frames) if f.signal == s)
                 for s in ("GO", "WARN", "STOP")}
        sent = {}
        for signal, k in picks.items():
            v.seek(k)                                         # as dragging the slider does
            assert v.position == k and v.frame is frames[k]
            html = v._banner.content
            assert f'data-signal="{signal}"' in html and f"at {frames[k].clock:.2f} s" in html
            want = sc.frame_scene(frames[k], v.ghosts)
            got = v._handles["/now/cylinder"].batched_positions
            np.testing.assert_allclose(got, want.now["cylinder"].positions, atol=1e-5)
            ghosts = v._handles["/ghost/cylinder"].batched_positions
            np.testing.assert_allclose(ghosts, want.ghosts["cylinder"].positions, atol=1e-5)
            sent[signal] = np.array(got)
        # the telescope ran out between the picks: the crane drawn moved with it
        run = frames[picks["STOP"]].state.extension - frames[picks["GO"]].state.extension
        assert run > 0.3
        assert np.abs(sent["STOP"] - sent["GO"]).max() > 0.5 * run
        # the obstacle in contact is shown in its own colour at the STOP
        obstacles = v._handles["/obstacles/box"].batched_colors
        assert tuple(sc.CONTACT_OBSTACLE_COLOUR) in {tuple(c) for c in obstacles}
        with pytest.raises(ValueError, match="index must be in 0.."):
            v.seek(len(frames))
    finally:
        v.close()


def test_frames_of_verdicts_show_a_fault_at_the_last_estimate(recorded):
    crane, path, _ = recorded
    world = cp.worlds.get("wall")
    from cranepredict.live.runner import replay

    verdicts = replay(path, LiveTwin(crane, world))[:30]
    ok = verdicts[20]
    assert ok.signal == "GO"
    twin = LiveTwin(crane, world)
    stale = twin.fault(ok.t + 0.01, "stale", "no slew frame for 0.2 s")
    assert stale.state is None
    frames = frames_of_verdicts(list(verdicts[:21]) + [stale, stale], crane, world)
    assert len(frames) == 22                          # the repeated time is left out
    last = frames[-1]
    assert last.signal == "FAULT" and last.fault == "stale: no slew frame for 0.2 s"
    assert last.state is ok.state and last.clock == pytest.approx(ok.t + 0.01)
    assert sc.banner(last).detail == "stale: no slew frame for 0.2 s"


def test_view_replay_command_serves_the_log(recorded, capsys):
    _, path, truth = recorded
    assert main(["view", "--replay", path, "--world", "wall", "--port", "0",
                 "--serve-for", "0"]) == 0
    out = capsys.readouterr().out
    assert f"{len(truth)} cycles" in out and "STOP" in out and "display    http://127.0.0.1:" in out


def test_view_replay_refuses_bad_input_before_serving(recorded, tmp_path, capsys):
    _, path, _ = recorded
    assert main(["view", "--replay", str(tmp_path / "none.asc")]) == 2
    assert "--replay: no such file" in capsys.readouterr().err
    assert main(["view", "--replay", path, "--scenario", "paper-fig4"]) == 2
    assert "give one" in capsys.readouterr().err
    text = tmp_path / "notes.txt"
    text.write_text("hello")
    assert main(["view", "--replay", str(text)]) == 2
    assert ".blf, .asc or .log" in capsys.readouterr().err
    assert main(["view", "--scenario", "paper-fig4", "--crane", path]) == 2
    assert "--crane is the live twin's crane in a --replay" in capsys.readouterr().err


class _Recorded(Viewer):
    """The viewer, remembering what it was shown."""

    made: list = []

    def __init__(self, *a, **kw) -> None:
        super().__init__(*a, **kw)
        self.shown: list = []
        _Recorded.made.append(self)

    def show(self, frame: Frame) -> None:
        self.shown.append(frame)
        super().show(frame)


def test_live_demo_view_updates_the_display_as_the_loop_runs(monkeypatch, capsys):
    _Recorded.made = []
    monkeypatch.setattr(server, "Viewer", _Recorded)
    assert main(["live", "--demo", "--seconds", "1.5", "--view", "--port", "0",
                 "--serve-for", "0"]) == 0
    out = capsys.readouterr().out
    assert "updated every cycle" in out and "150 cycles to scrub back" in out
    (v,) = _Recorded.made
    live, last = v.shown[:-1], v.shown[-1]
    clocks = [f.clock for f in live]
    # shown while the loop ran, in time order, up to the last cycle
    assert len(live) >= 10 and all(b > a for a, b in zip(clocks, clocks[1:]))
    assert clocks[-1] == pytest.approx(1.49)
    assert "GO" in {f.signal for f in live}
    # the telescope moves from 0.5 s on: the crane shown follows it
    assert live[-1].state.extension - live[0].state.extension > 0.1
    # afterwards the run is a recording on its last cycle
    assert len(v.recording) == 150 and v.position == 149
    assert last is v.recording[-1] and v.frame is last
    assert f'data-signal="{v.frame.signal}"' in v._banner.content


def test_live_display_keeps_up_by_skipping_to_the_newest(replayed):
    """A display slower than the loop shows the newest cycle, never a backlog."""
    frames, world = replayed
    import threading

    class Slow:
        def __init__(self) -> None:
            self.shown, self.gate = [], threading.Event()

        def show(self, frame) -> None:
            self.gate.wait(10)
            self.shown.append(frame)

    crane = frames[0].crane
    from cranepredict.live.loop import LiveVerdict

    verdicts = [LiveVerdict(t=f.clock, signal=f.signal, reason="", fault=None if f.verdict else "x",
                            state=f.state, guard=f.verdict) for f in frames[:40]]
    slow = Slow()
    d = LiveDisplay(slow, crane, world)
    for v in verdicts:
        d(v)
    slow.gate.set()
    d.close()
    assert d.received == 40 and slow.shown[-1].clock == verdicts[-1].t
    assert len(slow.shown) == d.shown and d.shown + d.skipped == 40 and d.shown <= 3
