"""What the operator's display shows at one moment: a :class:`Frame`.

A frame is the crane's predicted samples from "now" on (joint angles, slew, extension and the tip
at each sample time) together with the collision guard's :class:`~cranepredict.Verdict` on them,
or, when no verdict could be made, the reason (the FAULT signal). Every source of the display
makes frames: a named scenario makes one, a recorded log or the live loop makes one per cycle and
pushes it to :meth:`cranepredict.view.Viewer.show`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..crane import Crane
from ..guard import Verdict, guard
from ..types import Inputs, State
from ..world import World

__all__ = ["Frame", "SIGNALS"]

#: The display's signals: the guard's three, and FAULT when there is no verdict to trust.
SIGNALS = ("GO", "WARN", "STOP", "FAULT")


@dataclass(frozen=True, eq=False)
class Frame:
    """One picture of the display (read-only; arrays are copies the frame owns).

    crane, state: the crane and its state now (the first sample); world: the obstacles shown;
    t (N,) s: sample times from now (t[0] = 0); theta (N, 2) rad; slew (N,) rad; extension (N,) m;
    tip (N, 3) m: the samples judged; verdict: the guard's (None with a fault); fault: why there
    is no verdict ("" otherwise); clock: the source's time of "now", s (a log's time; 0 for a
    scenario).
    """

    crane: Crane
    state: State
    world: World
    t: np.ndarray
    theta: np.ndarray
    slew: np.ndarray
    extension: np.ndarray
    tip: np.ndarray
    verdict: Optional[Verdict] = None
    fault: str = ""
    clock: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.crane, Crane):
            raise TypeError(f"crane must be a cranepredict.Crane, got {type(self.crane).__name__}")
        if not isinstance(self.state, State):
            raise TypeError(f"state must be a cranepredict.State, got {type(self.state).__name__}")
        if not isinstance(self.world, World):
            raise TypeError(f"world must be a cranepredict.World, got {type(self.world).__name__}")
        if self.verdict is not None and not isinstance(self.verdict, Verdict):
            raise TypeError(f"verdict must be a cranepredict.Verdict or None, got "
                            f"{type(self.verdict).__name__}")
        if (self.verdict is None) == (not self.fault):
            raise ValueError("a frame has either a verdict or a fault (the reason there is none)")
        t = np.array(self.t, dtype=float).reshape(-1)
        n = len(t)
        if n < 1 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0) or t[0] != 0.0:
            raise ValueError("t must be finite sample times from now, increasing, t[0] = 0 s")
        shapes = {"theta": (n, 2), "slew": (n,), "extension": (n,), "tip": (n, 3)}
        for name, shape in shapes.items():
            a = np.array(np.broadcast_to(np.asarray(getattr(self, name), dtype=float), shape)) \
                if name in ("slew", "extension") else np.array(getattr(self, name), dtype=float)
            if a.shape != shape:
                raise ValueError(f"{name} must have shape {shape} (one row per sample), "
                                 f"got {a.shape}")
            if not np.all(np.isfinite(a)):
                raise ValueError(f"{name} must be finite")
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        t.setflags(write=False)
        object.__setattr__(self, "t", t)
        if not math.isfinite(float(self.clock)):
            raise ValueError(f"clock must be finite, got {self.clock}")
        object.__setattr__(self, "clock", float(self.clock))

    @property
    def signal(self) -> str:
        """GO, WARN, STOP (the guard's) or FAULT (no verdict)."""
        return "FAULT" if self.verdict is None else self.verdict.signal

    @property
    def horizon(self) -> float:
        """s: the last sample's time."""
        return float(self.t[-1])

    @classmethod
    def from_verdict(cls, crane: Crane, state: State, verdict: Verdict,
                     clock: float = 0.0) -> "Frame":
        """The frame of a verdict of :func:`cranepredict.guard` (its judged samples)."""
        if not isinstance(verdict, Verdict):
            raise TypeError(f"verdict must be a cranepredict.Verdict, got {type(verdict).__name__}")
        tr = verdict.trajectory
        return cls(crane=crane, state=state, world=verdict.world, t=tr.t - tr.t[0], theta=tr.theta,
                   slew=tr.slew, extension=tr.extension, tip=tr.tip, verdict=verdict, clock=clock)

    @classmethod
    def predict(cls, crane: Crane, world: World, state: State, inputs: Inputs, horizon: float,
                clock: float = 0.0, **guard_options) -> "Frame":
        """Runs the guard on the future of ``state`` under ``inputs`` and makes its frame
        (``guard_options``: reaction, cycle, dt ... as :func:`cranepredict.guard` takes them)."""
        return cls.from_verdict(crane, state, guard(crane, world, state, inputs, horizon,
                                                    **guard_options), clock=clock)

    @classmethod
    def faulted(cls, crane: Crane, state: State, world: World, fault: str,
                clock: float = 0.0) -> "Frame":
        """A frame without a verdict (signal FAULT): the crane as last known, the reason why."""
        if not isinstance(fault, str) or not fault:
            raise ValueError("fault must say why there is no verdict (a non-empty string)")
        from .. import _core
        from ..types import POINT_NAMES

        theta = np.array([[_core.joint_angle(crane, 0, state.lift_stroke, state.extension)[0],
                           _core.joint_angle(crane, 1, state.tilt_stroke, state.extension)[0]]])
        tip = _core.points(crane, state.extension, state.slew, theta)[:, POINT_NAMES.index("tip")]
        return cls(crane=crane, state=state, world=world, t=[0.0], theta=theta,
                   slew=[state.slew], extension=[state.extension], tip=tip, fault=fault,
                   clock=clock)

