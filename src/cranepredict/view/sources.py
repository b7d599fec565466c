"""The live twin as the display's source: its verdicts made into frames, one per control cycle.

:func:`frames_of_verdicts` turns a run of :class:`~cranepredict.live.LiveVerdict` (a recorded
log's replay, a demo) into the frames of a recording for :meth:`Viewer.play`;
:func:`replay_frames` does it for a CAN log. :class:`LiveDisplay` feeds a :class:`Viewer` from the
live loop: the loop hands it each verdict (cheap, on the loop's thread) and a display thread
shows the newest, so the loop never waits for the page.

A cycle with a verdict shows its predicted future; a FAULT shows the crane as last estimated with
the fault's reason (cycles before the estimator's first estimate have no crane to show and are
left out).
"""

from __future__ import annotations

import threading
from typing import Any, Iterable, List, Optional

from ..crane import Crane
from ..types import State
from ..world import World
from .frame import Frame

__all__ = ["frame_of_verdict", "frames_of_verdicts", "replay_frames", "LiveDisplay"]


def frame_of_verdict(verdict: Any, crane: Crane, world: World,
                     last_state: Optional[State] = None) -> Optional[Frame]:
    """The frame of one live verdict at its time ``verdict.t``: its prediction, or (FAULT) the
    crane at the verdict's estimate, else at ``last_state``; None when there is no state at all."""
    from ..live.loop import LiveVerdict

    if not isinstance(verdict, LiveVerdict):
        raise TypeError(f"verdict must be a cranepredict.live.LiveVerdict, "
                        f"got {type(verdict).__name__}")
    if verdict.guard is not None and verdict.state is not None:
        return Frame.from_verdict(crane, verdict.state, verdict.guard, clock=verdict.t)
    state = verdict.state if verdict.state is not None else last_state
    if state is None:
        return None
    reason = f"{verdict.fault}: {verdict.reason}" if verdict.fault else verdict.reason
    return Frame.faulted(crane, state, world, reason or verdict.signal, clock=verdict.t)


def frames_of_verdicts(verdicts: Iterable[Any], crane: Crane, world: World) -> List[Frame]:
    """The recording of a run of live verdicts: one frame per verdict, in time order (a verdict
    at the same time as the previous one, and those before the first estimate, are left out)."""
    frames: List[Frame] = []
    last: Optional[State] = None
    for v in verdicts:
        f = frame_of_verdict(v, crane, world, last)
        if v.state is not None:
            last = v.state
        if f is None or (frames and not f.clock > frames[-1].clock):
            continue
        frames.append(f)
    return frames


def replay_frames(path: str, twin: Any) -> List[Frame]:
    """The live twin (a :class:`~cranepredict.live.LiveTwin`) over a recorded CAN log (.blf,
    .asc, .log), as the frames of a recording. Needs the ``[live]`` extra."""
    from ..live.runner import replay

    return frames_of_verdicts(replay(path, twin), twin.crane, twin.world)


class LiveDisplay:
    """Shows the live loop on a :class:`Viewer`: call it with each :class:`LiveVerdict` (it keeps
    only the newest; a display thread makes its frame and shows it). When the display is slower
    than the loop, the cycles in between are not drawn (:attr:`skipped` counts them) and the
    page never falls behind. ``keep``: also keep every cycle's frame (:attr:`frames`) to play the
    run back as a recording afterwards (a demo; not for a loop that runs for hours)."""

    def __init__(self, viewer: Any, crane: Crane, world: World, keep: bool = False) -> None:
        if not isinstance(crane, Crane):
            raise TypeError(f"crane must be a cranepredict.Crane, got {type(crane).__name__}")
        if not isinstance(world, World):
            raise TypeError(f"world must be a cranepredict.World, got {type(world).__name__}")
        self.viewer, self.crane, self.world, self.keep = viewer, crane, world, keep
        self.frames: List[Frame] = []
        self.received = 0
        self.shown = 0
        self.skipped = 0
        self._cond = threading.Condition()
        self._latest: Any = None
        self._latest_state: Optional[State] = None   # the estimate before the newest verdict
        self._last_state: Optional[State] = None
        self._closed = False
        self._thread = threading.Thread(target=self._run, name="cranepredict-display", daemon=True)
        self._thread.start()

    def __call__(self, verdict: Any) -> None:
        frame = None
        if self.keep:
            frame = frame_of_verdict(verdict, self.crane, self.world, self._last_state)
            if frame is not None and (not self.frames or frame.clock > self.frames[-1].clock):
                self.frames.append(frame)
        with self._cond:
            if self._latest is not None:
                self.skipped += 1
            self._latest, self._latest_state = (frame if frame is not None else verdict,
                                                self._last_state)
            if verdict.state is not None:
                self._last_state = verdict.state
            self.received += 1
            self._cond.notify()

    def _run(self) -> None:
        while True:
            with self._cond:
                while self._latest is None and not self._closed:
                    self._cond.wait()
                if self._latest is None:
                    return
                item, last = self._latest, self._latest_state
                self._latest = None
            frame = item if isinstance(item, Frame) else frame_of_verdict(item, self.crane,
                                                                          self.world, last)
            if frame is not None:
                self.viewer.show(frame)
                self.shown += 1

    def close(self, timeout: float = 10.0) -> None:
        """Shows the newest verdict still waiting, then stops the display thread."""
        with self._cond:
            self._closed = True
            self._cond.notify()
        self._thread.join(timeout=timeout)
