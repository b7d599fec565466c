"""The operator's display as a local web page, on viser (the ``[view]`` extra).

:class:`Viewer` serves the page and draws whatever :class:`~cranepredict.view.Frame` it is shown;
a source (a scenario, a recorded log, the live loop) makes frames and calls :meth:`Viewer.show`
for each (thread-safe), or hands a whole recording to :meth:`Viewer.play`. See docs/display.md.
"""

from __future__ import annotations

import html
import math
import threading
from typing import Any, Dict, Iterable, Optional, Sequence

import numpy as np

from . import scene as sc
from .frame import Frame

__all__ = ["Viewer", "DEFAULT_HOST", "DEFAULT_PORT", "require_viser"]

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8080
_TIP_PATH_COLOUR = (20, 90, 220)
_CONTACT_COLOUR = (0, 0, 0)
_SCRUB_OPACITY = 0.75
_TIP_SEGMENTS = 50


def require_viser() -> Any:
    """The viser module, or ValueError saying how to install it."""
    try:
        import viser
    except ImportError:
        raise ValueError("the display needs viser: pip install 'cranepredict[view]'") from None
    return viser


def _banner_html(b: sc.Banner, clock: Optional[float], number: int = 0) -> str:
    def field(name: str, value: str) -> str:
        return (f'<div><span style="opacity:0.8">{name}</span> '
                f'<b data-field="{name}">{html.escape(value)}</b></div>')

    ttc = "-" if b.time_to_contact is None else f"{b.time_to_contact:.2f} s"
    if b.stop_by is None:
        stop = "-"
    elif not math.isfinite(b.stop_by):
        stop = "too late"
    else:
        stop = f"{b.stop_by:.2f} s" if b.stop_by > 0 else "now"
    rows = "".join([field("time to contact", ttc), field("part", b.part or "-"),
                    field("obstacle", b.obstacle or "-"), field("begin stopping by", stop)])
    when = "" if clock is None else f'<div style="opacity:0.8">at {clock:.2f} s</div>'
    return (f'<div id="cp-banner" data-signal="{b.signal}" data-frame="{number}" style="background:{b.colour};color:#fff;'
            f'padding:10px 12px;border-radius:6px;font-family:sans-serif;line-height:1.35">'
            f'<div id="cp-signal" style="font-size:34px;font-weight:800;letter-spacing:2px">'
            f'{b.signal}</div>'
            f'<div id="cp-headline" style="font-size:15px;font-weight:600;margin:2px 0 6px">'
            f'{html.escape(b.headline)}</div>'
            f'<div style="font-size:13px">{rows}</div>{when}'
            f'<div id="cp-detail" style="font-size:11px;opacity:0.85;margin-top:6px">'
            f'{html.escape(b.detail)}</div></div>')


_LEGEND = ("<div style=\"font-family:sans-serif;font-size:12px;line-height:1.5\">"
           + "".join(f'<span style="display:inline-block;width:11px;height:11px;margin-right:4px;'
                     f'background:rgb{c}"></span>{name}&nbsp;&nbsp;'
                     for name, c in (("within margin", sc.CLEARANCE_COLOURS["within margin"]),
                                     (f"within {sc.NEAR_BAND:g} m more", sc.CLEARANCE_COLOURS["near"]),
                                     ("clear", sc.CLEARANCE_COLOURS["clear"]),
                                     ("obstacle", sc.OBSTACLE_COLOUR),
                                     ("obstacle in contact", sc.CONTACT_OBSTACLE_COLOUR)))
           + "<br>solid: the crane now; translucent: the crane ahead; blue line: the tip's path "
             "(parts coloured by their smallest predicted clearance)</div>")


class Viewer:
    """The display's web server (viser). ``host`` defaults to this machine only (127.0.0.1);
    ``port`` 0 picks a free one (see :attr:`url`). ``ghosts``: how many future poses to draw."""

    def __init__(self, host: str = DEFAULT_HOST, port: int = DEFAULT_PORT, ghosts: int = sc.GHOSTS,
                 title: str = "cranepredict") -> None:
        if not isinstance(host, str) or not host:
            raise ValueError(f"host must be an address to listen on, got {host!r}")
        if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
            raise ValueError(f"port must be in 0..65535 (0: any free port), got {port!r}")
        if isinstance(ghosts, bool) or not isinstance(ghosts, int) or not 0 <= ghosts <= 12:
            raise ValueError(f"ghosts must be in 0..12, got {ghosts!r}")
        viser = require_viser()
        if port == 0:
            port = _free_port(host)
        self._lock = threading.RLock()
        self.ghosts = ghosts
        self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.host, self.port = host, self.server.get_port()
        s = self.server
        s.gui.configure_theme(control_layout="floating", control_width="large", show_logo=False,
                              show_share_button=False, dark_mode=False)
        if hasattr(s.gui, "set_panel_label"):
            s.gui.set_panel_label(title)
        s.scene.set_up_direction("+z")
        # plain lights, no image-based lighting nor shadows: a PC without a GPU (WebGL in
        # software) then draws the scene some 40 times as often
        s.scene.configure_environment_map(None)
        s.scene.configure_default_lights(True, cast_shadow=False)
        s.scene.add_light_hemisphere("/lights/sky", sky_color=(255, 255, 255),
                                     ground_color=(150, 150, 150), intensity=1.6)
        s.scene.add_light_ambient("/lights/ambient", intensity=0.8)
        s.initial_camera.position = (-2.0, -11.0, 5.0)   # beside the crane, looking at its reach
        s.initial_camera.look_at = (2.5, 0.0, 1.2)
        s.scene.add_grid("/grid", width=20.0, height=20.0, plane="xy", position=(0.0, 0.0, 0.0),
                         visible=False)
        self._banner = s.gui.add_html(_banner_html(sc.Banner("FAULT", sc.SIGNAL_COLOURS["FAULT"],
                                                             "waiting for the first prediction",
                                                             "", None, None, None, None), None),
                                      order=0)
        self._timeline = s.gui.add_slider("look ahead, s", min=0.0, max=1.0, step=0.01,
                                          initial_value=0.0, order=1)
        self._scrub_text = s.gui.add_markdown("the crane now", order=2)
        self._show_ghosts = s.gui.add_checkbox("ghosts (the crane ahead)", True, order=3)
        self._show_obstacles = s.gui.add_checkbox("obstacles", True, order=4)
        s.gui.add_html(_LEGEND, order=6)
        self._log_slider = None
        self._recording: Sequence[Frame] = ()
        self._meshes = sc.unit_meshes()
        self._handles: Dict[str, Any] = {}
        self._sent: Dict[str, Dict[str, np.ndarray]] = {}
        self._frame: Optional[Frame] = None
        self._world = None
        self._highlight: tuple = ()
        self.frames_shown = 0
        self._timeline.on_update(lambda _: self._draw_scrub())
        self._show_ghosts.on_update(lambda _: self._set_visible("ghost", self._show_ghosts.value))
        self._show_obstacles.on_update(lambda _: self._set_visible("obstacles",
                                                                   self._show_obstacles.value))

    # -- sources ----------------------------------------------------------------------------------

    @property
    def url(self) -> str:
        host = "127.0.0.1" if self.host in ("0.0.0.0", "") else self.host
        return f"http://{host}:{self.port}/"

    @property
    def frame(self) -> Optional[Frame]:
        """The frame on display."""
        return self._frame

    def show(self, frame: Frame) -> None:
        """Draws a frame: the crane now, the ghosts, the tip's path, the banner; the obstacles
        when the world (or the obstacle in contact) changed. Thread-safe."""
        if not isinstance(frame, Frame):
            raise TypeError(f"frame must be a cranepredict.view.Frame, got {type(frame).__name__}")
        scene = sc.frame_scene(frame, self.ghosts)
        v = frame.verdict
        highlight = (v.contact.obstacle,) if v is not None and v.contact is not None else ()
        with self._lock, self.server.atomic():
            if frame.world is not self._world or highlight != self._highlight:
                self._layer("obstacles", sc.obstacle_instances(frame.world, highlight),
                            visible=self._show_obstacles.value)
                self._world, self._highlight = frame.world, highlight
            self._layer("now", scene.now)
            self._layer("ghost", scene.ghosts, visible=self._show_ghosts.value)
            self._tip_path(scene.tip_path)
            self._contact(scene.contact)
            self._banner.content = _banner_html(scene.banner, frame.clock if self._recording
                                                or frame.clock else None, self.frames_shown + 1)
            self._frame = frame
            step = float(np.min(np.diff(frame.t))) if len(frame.t) > 1 else 0.01
            if len(frame.t) > 1:
                self._timeline.max = round(frame.horizon, 6)
                self._timeline.step = round(max(step, 1e-3), 6)
            self._timeline.disabled = len(frame.t) < 2
            self._draw_scrub()
            self.frames_shown += 1

    def play(self, frames: Sequence[Frame], start: int = 0) -> None:
        """A recording: a slider over the frames (their clocks increase) picks the frame shown;
        ``start``: the index shown first (-1: the last)."""
        frames = list(frames)
        if not frames or not all(isinstance(f, Frame) for f in frames):
            raise ValueError("play needs a non-empty sequence of cranepredict.view.Frame")
        clocks = [f.clock for f in frames]
        if any(b <= a for a, b in zip(clocks, clocks[1:])):
            raise ValueError("the frames' clocks must increase (a recording in time order)")
        if isinstance(start, bool) or not isinstance(start, int) \
                or not -len(frames) <= start < len(frames):
            raise ValueError(f"start must index the frames (-{len(frames)}..{len(frames) - 1}), "
                             f"got {start!r}")
        start %= len(frames)
        with self._lock:
            self._recording = frames
            if self._log_slider is None:
                self._log_slider = self.server.gui.add_slider(
                    "recording, frame", min=0, max=max(1, len(frames) - 1), step=1,
                    initial_value=start, order=5)
                self._log_slider.on_update(lambda _: self._show_recorded())
            else:
                self._log_slider.max = max(1, len(frames) - 1)
                self._log_slider.value = start
            self.show(frames[start])

    @property
    def recording(self) -> Sequence[Frame]:
        """The frames of the recording being played (empty without one)."""
        return self._recording

    @property
    def position(self) -> Optional[int]:
        """The recording slider's frame index (None without a recording)."""
        return None if self._log_slider is None else int(self._log_slider.value)

    def seek(self, index: int) -> None:
        """Moves the recording slider to frame ``index`` (as dragging it in the page does)."""
        if self._log_slider is None:
            raise ValueError("seek needs a recording (Viewer.play)")
        n = len(self._recording)
        if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < n:
            raise ValueError(f"index must be in 0..{n - 1}, got {index!r}")
        self._log_slider.value = index

    def _show_recorded(self) -> None:
        frames = self._recording
        if frames:
            self.show(frames[min(max(int(self._log_slider.value), 0), len(frames) - 1)])

    def follow(self, source: Iterable[Frame]) -> int:
        """Shows each frame of a source as it comes (a live loop's generator); returns how many."""
        n = 0
        for frame in source:
            self.show(frame)
            n += 1
        return n

    def close(self) -> None:
        self.server.stop()

    def __enter__(self) -> "Viewer":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    # -- drawing ----------------------------------------------------------------------------------

    def _layer(self, name: str, inst: Dict[str, sc.Instances], visible: bool = True) -> None:
        for shape, x in inst.items():
            key = f"/{name}/{shape}"
            h = self._handles.get(key)
            translucent = bool(len(x)) and bool(np.any(x.opacities < 1.0))
            if h is not None and (len(h.batched_positions) != len(x) or
                                  (h.batched_opacities is not None) != translucent):
                self._handles.pop(key).remove()
                self._sent.pop(key, None)
                h = None
            if not len(x):
                continue
            if h is None:
                v, f = self._meshes[shape]
                self._handles[key] = self.server.scene.add_batched_meshes_simple(
                    key, vertices=v, faces=f, batched_wxyzs=x.wxyzs, batched_positions=x.positions,
                    batched_scales=x.scales, batched_colors=x.colours,
                    batched_opacities=x.opacities if translucent else None, lod="off",
                    side="double", cast_shadow=False, receive_shadow=False, visible=visible)
            else:
                # send only what changed (a browser re-uploads each array it receives)
                sent = self._sent.setdefault(key, {})
                for attr, value in (("batched_positions", x.positions.astype(np.float32)),
                                    ("batched_wxyzs", x.wxyzs.astype(np.float32)),
                                    ("batched_scales", x.scales.astype(np.float32)),
                                    ("batched_colors", x.colours),
                                    ("batched_opacities", x.opacities.astype(np.float32)
                                     if translucent else None)):
                    if value is None or (attr in sent and np.array_equal(sent[attr], value)):
                        continue
                    setattr(h, attr, value)
                    sent[attr] = value
                if h.visible != visible:
                    h.visible = visible
                continue
            self._sent.pop(key, None)
        for key in [k for k in self._handles if k.startswith(f"/{name}/")]:
            if key.rsplit("/", 1)[1] not in inst or not len(inst[key.rsplit("/", 1)[1]]):
                self._handles.pop(key).remove()
                self._sent.pop(key, None)

    def _set_visible(self, name: str, visible: bool) -> None:
        with self._lock:
            for key, h in self._handles.items():
                if key.startswith(f"/{name}/"):
                    h.visible = visible

    def _tip_path(self, tip: np.ndarray) -> None:
        h = self._handles.get("/tip_path")
        if len(tip) < 2:
            if h is not None:
                self._handles.pop("/tip_path").remove()
            return
        # at most _TIP_SEGMENTS segments (through the first and the last sample): thick lines
        # are rebuilt by the browser at every update
        keep = np.unique(np.linspace(0, len(tip) - 1, min(len(tip), _TIP_SEGMENTS + 1)).round()
                         .astype(int))
        tip = tip[keep]
        seg = np.stack([tip[:-1], tip[1:]], axis=1).astype(np.float32)
        if h is not None and len(h.points) == len(seg):
            h.points = seg
        else:
            if h is not None:
                h.remove()
            self._handles["/tip_path"] = self.server.scene.add_line_segments(
                "/tip_path", points=seg, colors=_TIP_PATH_COLOUR, thickness=3.0,
                thickness_units="screen")

    def _contact(self, contact: Optional[tuple]) -> None:
        """The closest points of the first contact: a line and a ball on the part (made once,
        then moved, hidden when there is no contact)."""
        line, ball = self._handles.get("/contact/line"), self._handles.get("/contact/point")
        if contact is None:
            for h in (line, ball):
                if h is not None and h.visible:
                    h.visible = False
            return
        a, b = (np.asarray(p, dtype=np.float32) for p in contact)
        if line is None:
            self._handles["/contact/line"] = self.server.scene.add_line_segments(
                "/contact/line", points=np.array([[a, b]]), colors=_CONTACT_COLOUR,
                thickness=3.0, thickness_units="screen")
            self._handles["/contact/point"] = self.server.scene.add_icosphere(
                "/contact/point", radius=0.08, color=sc.CLEARANCE_COLOURS["within margin"],
                position=tuple(float(x) for x in a))
            return
        line.points = np.array([[a, b]])
        ball.position = tuple(float(x) for x in a)
        for h in (line, ball):
            if not h.visible:
                h.visible = True

    def _draw_scrub(self) -> None:
        with self._lock:
            frame = self._frame
            if frame is None:
                return
            k = sc.sample_at(frame, self._timeline.value)
            if k == 0:
                self._layer("scrub", {shape: sc.Instances(np.zeros((0, 3)), np.zeros((0, 4)),
                                                          np.zeros((0, 3)), np.zeros((0, 3), np.uint8),
                                                          np.zeros(0)) for shape in sc.SHAPES})
                self._scrub_text.content = "look ahead: the crane now (drag the slider to see it ahead)"
                return
            self._layer("scrub", sc.pose_instances(frame, [k], [_SCRUB_OPACITY]))
            x, y, z = frame.tip[k]
            self._scrub_text.content = (f"look ahead: the crane at **t = {frame.t[k]:.2f} s** "
                                        f"(tip at {x:.2f}, {y:.2f}, {z:.2f} m)")


def _free_port(host: str) -> int:
    import socket

    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host if host not in ("", "0.0.0.0") else "127.0.0.1", 0))
        return int(s.getsockname()[1])
