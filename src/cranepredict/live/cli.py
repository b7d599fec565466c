"""The live twin's commands: ``cranepredict live`` (on a bus, or ``--demo``), ``replay`` and
``sim-crane``; cranepredict.cli adds them with :func:`add_parsers`."""

from __future__ import annotations

import argparse
import json
import os
from typing import Any, List

from .loop import LiveVerdict

_INTERFACE_HELP = "python-can interface (socketcan on a crane, udp_multicast, virtual, pcan, ...)"


def _world(name: str) -> Any:
    from .. import world as world_mod

    if os.path.exists(name):
        return world_mod.World.from_toml(name)
    if name in world_mod.names():
        return world_mod.get(name)
    raise ValueError(f"--world: no such file, and not an example world "
                     f"({', '.join(world_mod.names())}): {name!r}")


def _crane(path: Any) -> Any:
    from ..crane import Crane

    return Crane.patu655() if path is None else Crane.from_toml(path)


def _line(v: LiveVerdict) -> str:
    text = f"t {v.t:7.2f} s  {v.signal:5s}"
    if v.signal == "FAULT":
        return f"{text}  [{v.fault}] {v.reason}"
    if v.time_to_contact is not None:
        text += f"  contact in {v.time_to_contact:.2f} s ({v.part} / {v.obstacle})"
        latest = v.latest_stop
        if latest is not None:
            text += f", stop by {latest:.2f} s" if latest > -1e300 else ", too late to stop"
        text += f", speed limit {v.speed_limit:.0%}"
    else:
        text += f"  {v.reason}"
    return text


class _Printer:
    """Prints each verdict whose signal differs from the previous one (and every ``every``-th)."""

    def __init__(self, every: int = 50) -> None:
        self.last, self.count, self.every = None, 0, every

    def __call__(self, v: LiveVerdict) -> None:
        self.count += 1
        if v.signal != self.last or self.count % self.every == 0:
            print(_line(v), flush=True)
        self.last = v.signal


def _twin(args: argparse.Namespace, crane: Any, world: Any) -> Any:
    from .loop import LiveTwin

    return LiveTwin(crane, world, horizon=args.horizon, reaction=args.reaction)


def _live(args: argparse.Namespace) -> int:
    crane, world = _crane(args.crane), _world(args.world)
    if args.demo:
        return _demo(args, crane, world)
    if args.interface is None or args.channel is None:
        raise ValueError("live needs --interface and --channel (or --demo)")
    import can

    from .runner import run_twin

    twin = _twin(args, crane, world)
    with _Display(args, crane, world) as display:
        print(f"live twin on {args.interface}:{args.channel}, world {world.name}; Ctrl-C stops",
              flush=True)
        with can.Bus(interface=args.interface, channel=args.channel, bitrate=args.bitrate) as bus:
            printer = _Printer()
            out = (lambda v: print(json.dumps(v.to_dict()), flush=True)) if args.json else printer
            run_twin(bus, twin, on_verdict=display.chain(out), max_cycles=args.cycles)
        display.end()
    return 0


class _Display:
    """``--view``: the operator's display fed every cycle (a no-op without --view). After the
    loop, :meth:`end` keeps the page up (--serve-for, or until Ctrl-C); a demo's run is then a
    recording with its timeline."""

    def __init__(self, args: argparse.Namespace, crane: Any, world: Any, keep: bool = False) -> None:
        self.args, self.viewer, self.live = args, None, None
        if not args.view:
            return
        from ..view.server import Viewer, require_viser
        from ..view.sources import LiveDisplay

        require_viser()
        self.viewer = Viewer(host=args.host, port=args.port, ghosts=args.ghosts)
        self.live = LiveDisplay(self.viewer, crane, world, keep=keep)
        print(f"display    {self.viewer.url}  (updated every cycle)", flush=True)

    def __enter__(self) -> "_Display":
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.live is not None:
            self.live.close()
        if self.viewer is not None:
            self.viewer.close()

    def chain(self, out: Any) -> Any:
        if self.live is None:
            return out
        live = self.live

        def both(v: LiveVerdict) -> None:
            out(v)
            live(v)
        return both

    def end(self) -> None:
        if self.live is None:
            return
        from ..view.app import serve

        self.live.close()
        print(f"display    drew {self.live.shown} of {self.live.received} cycles as they came "
              f"({self.live.skipped} skipped for a newer one)", flush=True)
        if self.live.frames:
            self.viewer.play(self.live.frames, start=-1)
            print(f"display    {self.viewer.url}: {len(self.live.frames)} cycles to scrub back "
                  f"(the slider 'recording, frame'); "
                  + ("Ctrl-C stops" if self.args.serve_for is None
                     else f"serving for {self.args.serve_for:g} s"), flush=True)
        else:
            print(f"display    {self.viewer.url}: the last cycle; "
                  + ("Ctrl-C stops" if self.args.serve_for is None
                     else f"serving for {self.args.serve_for:g} s"), flush=True)
        serve(self.args.serve_for)


def _demo(args: argparse.Namespace, crane: Any, world: Any) -> int:
    from .episode import demo_setup
    from .runner import demo
    from .sim import Plant, SimCrane, SensorModel, perturbed_crane

    start, script, default_world = demo_setup(crane)
    if args.world != default_world:
        print(f"note: the demo's lever script is made for the world {default_world!r}")
    plant_crane = perturbed_crane(crane)
    print(f"demo: a simulated {crane.name} (its load x1.3, friction x1.2, supply x0.97 off the "
          f"twin's crane file) and the live twin on one virtual CAN bus, world {world.name!r}")
    print("operator: telescope lever at 0.8 from t = 0.5 s, held; the crane obeys the verdict "
          "(valves to neutral on STOP and FAULT)")
    sim = SimCrane(Plant(plant_crane, start, world=world), script)
    twin = _twin(args, crane, world)
    with _Display(args, crane, world, keep=True) as display:
        demo(crane, world, sim, twin, args.seconds, on_verdict=display.chain(_Printer()),
             log=args.log)
        _demo_end(args, crane, world, twin, sim, start, script)
        display.end()
    return 0


def _demo_end(args: argparse.Namespace, crane: Any, world: Any, twin: Any, sim: Any, start: Any,
              script: Any) -> None:
    from .episode import run_episode

    obeyed = sim.plant
    counterfactual = run_episode(crane, world, start, script, args.seconds, obey=False,
                                 horizon=args.horizon)
    print(f"with the interlock:    {'COLLISION: ' + obeyed.contact if obeyed.collided else 'no contact'}"
          f" (signals: {', '.join(f'{k} {n}' for k, n in twin.counts.items() if n)})")
    print(f"without the interlock: "
          f"{'the ' + counterfactual.contact if counterfactual.collided else 'no contact either'}")
    if counterfactual.collided and not obeyed.collided:
        print("the interlock prevented that contact")
    if args.log:
        print(f"bus log: {args.log} (cranepredict replay {args.log} --world {world.name}; "
              f"cranepredict view --replay {args.log} --world {world.name})")


def _replay(args: argparse.Namespace) -> int:
    from .runner import replay

    crane, world = _crane(args.crane), _world(args.world)
    if not os.path.exists(args.log):
        raise ValueError(f"LOG: no such file: {args.log!r}")
    if args.plot:
        from ..cli import _check_plot_dir

        _check_plot_dir(args.plot)
    verdicts = replay(args.log, _twin(args, crane, world))
    if args.json:
        print(json.dumps([v.to_dict() for v in verdicts], indent=1))
    else:
        printer = _Printer(every=10**9)
        for v in verdicts:
            printer(v)
        counts = {s: sum(v.signal == s for v in verdicts) for s in ("GO", "WARN", "STOP", "FAULT")}
        print(f"{len(verdicts)} cycles: " + ", ".join(f"{k} {n}" for k, n in counts.items()))
    if args.plot:
        import sys

        print(f"plot: {_plot(verdicts, args.plot, os.path.basename(args.log))}",
              file=sys.stderr if args.json else sys.stdout)
    return 0


def _plot(verdicts: List[LiveVerdict], out_dir: str, name: str) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = [v.t for v in verdicts]
    code = {"GO": 0, "WARN": 1, "STOP": 2, "FAULT": 3}
    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(8, 5))
    a.step(t, [code[v.signal] for v in verdicts], where="post")
    a.set_yticks(range(4), list(code))
    a.set_title(f"verdicts of {name}")
    b.plot(t, [float("nan") if v.time_to_contact is None else v.time_to_contact for v in verdicts],
           label="time to contact")
    b.plot(t, [float("nan") if v.latest_stop is None or v.latest_stop < -1 else v.latest_stop
               for v in verdicts], label="latest stop")
    b.set_xlabel("t, s")
    b.set_ylabel("s")
    b.legend()
    fig.tight_layout()
    path = os.path.join(out_dir, f"replay-{os.path.splitext(name)[0]}.png")
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def _sim_crane(args: argparse.Namespace) -> int:
    import can

    from .episode import demo_setup
    from .runner import run_sim
    from .sim import Plant, SimCrane, perturbed_crane

    crane = _crane(args.crane)
    start, script, _ = demo_setup(crane)
    world = _world(args.world) if args.world else None
    sim = SimCrane(Plant(perturbed_crane(crane), start, world=world), script, obey=not args.ignore_verdict)
    print(f"simulated {crane.name} on {args.interface}:{args.channel} for {args.seconds:g} s "
          f"({'lockstep' if args.lockstep else 'real time'})", flush=True)
    with can.Bus(interface=args.interface, channel=args.channel, bitrate=args.bitrate) as bus:
        mon = run_sim(bus, sim, args.seconds, lockstep=args.lockstep)
    print(f"done at t = {sim.plant.t:.2f} s; last verdict {mon.signal(mon.last_time)}"
          + (f"; {sim.plant.contact}" if sim.plant.collided else ""))
    return 0


def add_parsers(sub: Any) -> None:
    def common(p: argparse.ArgumentParser) -> None:
        p.add_argument("--crane", default=None, help="crane file (TOML; default: the PATU 655)")
        p.add_argument("--horizon", type=float, default=2.0, help="prediction horizon, s (default 2)")
        p.add_argument("--reaction", type=float, default=0.2,
                       help="delay from the stop decision to the stop, s (default 0.2)")

    live = sub.add_parser("live", help="the live twin on a CAN bus: sensors in, a verdict out every "
                                       "cycle (needs the [live] extra); --demo runs it against a "
                                       "simulated crane")
    live.add_argument("--interface", default=None, help=_INTERFACE_HELP)
    live.add_argument("--channel", default=None, help="bus channel (can0, a multicast group, ...)")
    live.add_argument("--bitrate", type=int, default=250_000, help="bit/s (default 250000, J1939)")
    live.add_argument("--world", default="wall", help="world file or example world (default: wall)")
    live.add_argument("--demo", action="store_true",
                      help="simulated crane + twin on a virtual bus, driving towards the wall")
    live.add_argument("--seconds", type=float, default=6.0, help="demo length, s (default 6)")
    live.add_argument("--log", default=None, help="demo: record the bus (.blf, .asc or .log)")
    live.add_argument("--cycles", type=int, default=None, help="stop after this many verdicts")
    live.add_argument("--json", action="store_true", help="one JSON line per verdict")
    live.add_argument("--view", action="store_true",
                      help="show the loop on the operator's display, updated every cycle (a local "
                           "web page; needs the [view] extra)")
    live.add_argument("--host", default="127.0.0.1",
                      help="--view: address to listen on (default: 127.0.0.1, this machine only)")
    live.add_argument("--port", type=int, default=8080,
                      help="--view: port (default: 8080; 0: any free one)")
    live.add_argument("--ghosts", type=int, default=4, help="--view: future poses drawn (default: 4)")
    live.add_argument("--serve-for", type=float, default=None, metavar="S",
                      help="--view: after the loop ends, keep the page up S seconds (default: "
                           "until Ctrl-C)")
    common(live)
    live.set_defaults(func=_live)
    rep = sub.add_parser("replay", help="run the live twin over a recorded CAN log (.blf, .asc, .log)")
    rep.add_argument("log", metavar="LOG")
    rep.add_argument("--world", required=True, help="world file or example world")
    rep.add_argument("--json", action="store_true", help="the verdict timeline as JSON")
    rep.add_argument("--plot", metavar="DIR", default=None, help="write the timeline plot (needs [plot])")
    common(rep)
    rep.set_defaults(func=_replay)
    sim = sub.add_parser("sim-crane", help="a simulated crane's ECU on a CAN bus (perturbed plant, "
                                           "noisy sensors, the demo's lever script; obeys the verdict)")
    sim.add_argument("--interface", required=True, help=_INTERFACE_HELP)
    sim.add_argument("--channel", required=True, help="bus channel")
    sim.add_argument("--bitrate", type=int, default=250_000, help="bit/s (default 250000)")
    sim.add_argument("--seconds", type=float, default=6.0, help="simulated time, s (default 6)")
    sim.add_argument("--world", default=None, help="report contacts against this world")
    sim.add_argument("--lockstep", action="store_true",
                     help="wait for each verdict instead of running by the wall clock")
    sim.add_argument("--ignore-verdict", action="store_true", help="do not obey the verdict")
    sim.add_argument("--crane", default=None, help="crane file (TOML; default: the PATU 655)")
    sim.set_defaults(func=_sim_crane)
