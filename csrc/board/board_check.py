#!/usr/bin/env python3
"""Checks the board run (csrc/board, QEMU mps2-an386) against the host and the static analysis.

    python3 board_check.py --board board.txt --host host.txt [--footprint footprint.log]
                           [--profile profile.txt]

  * samples: every sample of every scenario the board printed must be the host float build's
    (host.c, the same scenarios.c) to TIP_TOL in the tip position; it says how many are bit for
    bit equal and where the largest difference is;
  * estimates (make HYD=1): the estimator's estimate after each update, board vs host, to
    ESTIMATE_TOL of each field's scale;
  * instructions: the board's timer ticks under QEMU's -icount shift=0, turned into instructions
    with the board's own calibration loop (which must show 40 instructions per tick, i.e. icount
    on and the 25 MHz timer clock), per entry point, checked against the count of --profile
    (board_profile.py, QEMU's execution log); for every scenario, the time on a 168 MHz
    Cortex-M4F and the faster-than-real-time ratio with the cycles per instruction of that
    profile (low, flash accelerator model, high; without --profile only instructions);
  * stack: the depth measured by painting for every entry point the board called, next to the
    static worst case of tools/footprint.py (--footprint: its output; else it is run on
    csrc/build-m4 or --footprint-build); measured > static fails, and so does an entry point
    without a static figure.

Exit status 0 if all checks pass, 1 otherwise; the last line is "board-check: N passed, N failed".
"""
import argparse
import math
import os
import re
import struct
import subprocess
import sys

TIP_TOL = 1e-6                 # m: the bound for the board vs the host float build
CLOCK_HZ = 168e6               # the Cortex-M4F of the issue (e.g. STM32F407 at its top clock)
INSNS_PER_TICK = 40            # 1 ns per instruction (-icount shift=0) at the 25 MHz timer clock
DEFAULT_SCENARIO = "paper-dt2ms"   # the scenario the board's figures are quoted for (dt = 2 ms)
RATIO_GOAL = 100.0
# The estimator's estimates, board vs host, in each field's scale (mm, mm/s, bar: the estimator's
# own, crane_estimator_config.scale): its finite-difference Jacobian in float turns the last bit
# of a libm result (newlib's on the board, glibc's on the host) into differences that grow over
# the updates (measured 0.002 after 10), far below the sensors' noise (0.2 mm, 2 bar).
ESTIMATE_SCALE = [1e-3] * 8 + [1e5] * 8
ESTIMATE_TOL = 1e-2

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC = os.path.dirname(HERE)


def parse_run(path):
    """Samples per scenario ({name: [fields...]}), ticks/stack per entry point, calibration."""
    out = {"samples": {}, "ticks": {}, "stack": {}, "count": {}, "failures": None, "cal": None,
           "estimates": [], "calls": {}}
    context = None
    for line in open(path):
        f = line.split()
        if not f:
            continue
        if f[0] == "sample":
            out["samples"].setdefault(f[1], []).append(f[3:])
        elif f[0] == "scenario":
            context = f[1]
            out["count"][context] = int(f[2])
        elif f[0] == "estimate":
            out["estimates"].append(f[2:])
        elif f[0] in ("entry_points", "estimator"):
            context = None
        elif f[0] in ("ticks", "stack"):
            # an entry point called more than once (the estimator's updates): the largest, and
            # every call's ticks in "calls"
            key = f[1] if context is None else f"{f[1]}[{context}]"
            out[f[0]][key] = max(out[f[0]].get(key, 0), int(f[2]))
            if f[0] == "ticks":
                out["calls"].setdefault(key, []).append(int(f[2]))
        elif f[0] == "calibration":
            loops = int(f[1])
        elif f[0] == "calibration_ticks":
            out["cal"] = (loops, int(f[1]))
        elif f[0] == "failures":
            out["failures"] = int(f[1])
    return out


def real(hexbits):
    """A crane_real from the hex digits of its bits (8: float, 16: double)."""
    if len(hexbits) == 8:
        return struct.unpack(">f", bytes.fromhex(hexbits))[0]
    return struct.unpack(">d", bytes.fromhex(hexbits))[0]


def static_stack(footprint_log, build="build-m4"):
    """Entry point -> worst-case stack from tools/footprint.py's output (its exit status, which
    says whether the budget is kept, does not matter here)."""
    if footprint_log:
        text = open(footprint_log).read()
    else:
        r = subprocess.run([sys.executable, os.path.join(os.path.dirname(CSRC), "tools",
                                                         "footprint.py"),
                            "--build", os.path.join(CSRC, build)],
                           capture_output=True, text=True)
        text = r.stdout
    section = text.split("worst-case stack depth", 1)[-1].split("\n\n", 1)[0]
    return {m.group(1): int(m.group(2))
            for m in re.finditer(r"^\s+(crane_\w+)\s+(\d+)\s*$", section, re.M)}


def read_profile(profile):
    """((low, high, flash accelerator estimate) cycles per instruction, instructions) from
    board_profile.py's output."""
    cpi = insns = None
    art = None
    for line in open(profile):
        m = re.match(r"cpi_art\s+([\d.]+)", line)
        if m:
            art = float(m.group(1))
        m = re.match(r"cpi_range\s+([\d.]+)\s+([\d.]+)", line)
        if m:
            cpi = float(m.group(1)), float(m.group(2))
        m = re.match(r"profile_instructions\s+(\d+)", line)
        if m:
            insns = int(m.group(1))
    return (cpi + (art,) if cpi else None), insns


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--board", required=True)
    ap.add_argument("--host", required=True)
    ap.add_argument("--footprint", help="output of tools/footprint.py (default: run it)")
    ap.add_argument("--profile", help="output of board_profile.py (the CPI range)")
    ap.add_argument("--profiled", default=DEFAULT_SCENARIO,
                    help="the scenario whose prediction --profile is of")
    ap.add_argument("--footprint-build", default="build-m4",
                    help="the core's build in csrc/ that the board links (for tools/footprint.py)")
    a = ap.parse_args(argv)
    board, host = parse_run(a.board), parse_run(a.host)
    results = []

    def check(name, ok, detail):
        results.append(ok)
        print(f"{'ok  ' if ok else 'FAIL'}  {name}: {detail}")

    check("board run", board["failures"] == 0,
          f"{board['failures']} failed calls reported by the board")

    # ---- samples ----
    check("scenarios", set(board["samples"]) == set(host["samples"]) and board["samples"],
          f"board {sorted(board['samples'])}, host {sorted(host['samples'])}")
    for name in sorted(host["samples"]):
        b, h = board["samples"].get(name, []), host["samples"][name]
        worst, at, same = 0.0, None, 0
        for sb, sh in zip(b, h):
            if sb == sh:
                same += 1
                continue
            tip_b = [real(x) for x in sb[1:4]]
            tip_h = [real(x) for x in sh[1:4]]
            e = math.dist(tip_b, tip_h)
            if e > worst or at is None:
                worst, at = e, real(sh[0])
        ok = len(b) == len(h) == board["count"].get(name) and worst <= TIP_TOL
        where = "" if at is None else f" at t = {at:.4g} s"
        check(f"samples {name}", ok,
              f"{len(b)} board, {len(h)} host samples; {same} bit for bit equal; largest tip "
              f"difference {worst:.3g} m{where} (tolerance {TIP_TOL:g} m)")

    # ---- the estimator (make HYD=1): the board's estimates are the host float build's ----
    if board["estimates"] or host["estimates"]:
        b, h = board["estimates"], host["estimates"]
        same, worst, at = 0, 0.0, None
        for k, (eb, eh) in enumerate(zip(b, h), 1):
            same += eb == eh
            for i, (xb, xh) in enumerate(zip(eb, eh)):
                e = abs(real(xb) - real(xh)) / ESTIMATE_SCALE[i]
                if e > worst:
                    worst, at = e, (k, i)
        where = "" if at is None else f" (update {at[0]}, field {at[1]})"
        check("estimates", len(b) == len(h) > 0 and worst <= ESTIMATE_TOL,
              f"{len(b)} board, {len(h)} host updates; {same} bit for bit equal; largest "
              f"difference {worst:.3g} of the field's scale{where} (tolerance {ESTIMATE_TOL:g})")

    # ---- instructions ----
    loops, ticks = board["cal"]
    per_tick = 2 * loops / ticks
    check("instruction clock", abs(per_tick - INSNS_PER_TICK) <= 0.001 * INSNS_PER_TICK,
          f"calibration loop: {2 * loops} instructions in {ticks} ticks = {per_tick:.3f} per tick "
          f"(expected {INSNS_PER_TICK}: -icount shift=0, 25 MHz timer)")
    print("\ninstructions per call (timer, +-1 tick = +-40 instructions):")
    for k, t in board["ticks"].items():
        print(f"  {k:<40}{t * INSNS_PER_TICK:>12,}")
    cpi, profiled = read_profile(a.profile) if a.profile else (None, None)
    key = f"crane_predict[{a.profiled}]"
    insns = board["ticks"][key] * INSNS_PER_TICK
    if profiled is not None:
        # Two independent counts of one call: the timer (+-1 tick, plus the few instructions of
        # the call itself) and QEMU's execution log of the profile build.
        check("instructions vs profile", abs(profiled - insns) <= 2 * INSNS_PER_TICK + 20,
              f"timer {insns:,}, execution log {profiled:,}")
    if cpi:
        # The CPI comes from the profile of --profiled; the other scenarios use it too (their
        # mix differs: an approximation, said so in the output).
        print(f"\ntime at {CLOCK_HZ / 1e6:g} MHz with the CPI of {a.profiled}'s profile "
              f"(low {cpi[0]:.2f}, flash accelerator model {cpi[2]:.2f}, high {cpi[1]:.2f}); "
              f"goal {RATIO_GOAL:g}x for {DEFAULT_SCENARIO}:")
        for name in board["count"]:
            n = board["ticks"][f"crane_predict[{name}]"] * INSNS_PER_TICK
            h = real(board["samples"][name][-1][0])
            t_lo, t_art, t_hi = (n * c / CLOCK_HZ for c in (cpi[0], cpi[2], cpi[1]))
            print(f"  {name}: {n:,} instructions for {h:g} s: {t_lo * 1e3:.1f} / {t_art * 1e3:.1f} / "
                  f"{t_hi * 1e3:.1f} ms = {h / t_lo:.0f}x / {h / t_art:.0f}x / {h / t_hi:.0f}x "
                  f"faster than real time")
    else:
        print(f"\n{a.profiled}: {insns:,} instructions (no --profile: no CPI range)")
    updates = board["calls"].get("crane_estimator_update")
    if updates and len(updates) > 1:
        # the first update after init renews the whole Jacobian, the others their share of it
        n = [t * INSNS_PER_TICK for t in updates]
        first, later = n[0], n[1:]

        def ms(x):
            return " / ".join(f"{x * c / CLOCK_HZ * 1e3:.2f}" for c in (cpi[0], cpi[2], cpi[1])) \
                if cpi else "-"
        print(f"\nestimator update ({len(n)} cycles of lever-open, 10 ms each), instructions and "
              f"ms at {CLOCK_HZ / 1e6:g} MHz with the CPI above (low / flash model / high):")
        print(f"  first after init (every column): {first:,} ({ms(first)} ms)")
        print(f"  the others: {min(later):,} to {max(later):,}, mean {sum(later) / len(later):,.0f} "
              f"(the largest {ms(max(later))} ms)")

    # ---- stack ----
    static = static_stack(a.footprint, a.footprint_build)
    print("\nstack (bytes): measured by painting on the board vs tools/footprint.py's worst case")
    for k, used in board["stack"].items():
        entry = k.split("[")[0]
        if entry == "probe_256":   # the painting's self-test: a 256-byte frame plus a few words
            check("stack painting self-test", 256 <= used <= 256 + 32,
                  f"a function with a 256-byte local array measured {used}")
        elif entry in static:
            check(f"stack {k}", used <= static[entry],
                  f"measured {used}, static worst case {static[entry]}")
        else:
            check(f"stack {k}", False, f"measured {used}, no static figure from tools/footprint.py")

    measured = {k.split("[")[0] for k in board["stack"]}
    for entry in sorted(set(static) - measured):
        print(f"note  stack {entry}: not called on the board (static worst case {static[entry]})")

    passed = sum(1 for r in results if r)
    failed = len(results) - passed
    print(f"board-check: {passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
