#!/usr/bin/env python3
"""Writes the board's measured figures into docs/embedding.md (`make -C csrc/board docs`).

    python3 board_docs.py --board board.txt --profile profile.txt --board-hyd board.txt \
                          --profile-hyd profile.txt [--docs docs/embedding.md]

Replaces the text between the markers <!-- board:NAME --> and <!-- /board:NAME --> (NAME = speed,
profile, stack, hydraulics) with tables made from the board's output (main.c), board_profile.py's output and
tools/footprint.py's static worst case, so that the docs carry the numbers of one run and nothing
is copied by hand. Run it after `make -C csrc/board check` has passed.
"""
import argparse
import os
import re
import sys
import textwrap

import board_check as bc

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))), "tools"))
import footprint  # noqa: E402  (the budgets: one source)

HERE = os.path.dirname(os.path.abspath(__file__))
DOCS = os.path.join(os.path.dirname(os.path.dirname(HERE)), "docs", "embedding.md")
TOP = 10          # functions listed by name; libm and the soft-float helpers are grouped
# What each leading function does, for the reader of the table.
ROLE = {
    "rk4": "integrator.c: the stages, with the forces inlined",
    "crane__id_planar": "the planar kernel's inverse dynamics",
    "crane__sincosf": "the float build's own sin/cos",
    "put_sample": "the tip position of each sample",
}
SOFT = re.compile(r"^(__aeabi_\w+|__\w+[sd]f\d|__\w+df2)$")


def wrap(text):
    return textwrap.fill(text, width=100, break_long_words=False, break_on_hyphens=False)


def parse_profile(path):
    funcs, mix, art = [], {}, {}
    section = None
    for line in open(path):
        if line.startswith("profile of"):
            section = "funcs"
            continue
        if line.startswith("instruction mix"):
            section = "mix"
            continue
        m = re.match(r"\s+(\S+)\s+([\d,]+)\s+[\d.]+%$", line)
        if m and section == "funcs" and not line.strip().startswith("("):
            funcs.append((m.group(1), int(m.group(2).replace(",", ""))))
        elif m and section == "mix":
            mix[m.group(1)] = int(m.group(2).replace(",", ""))
        m = re.search(r"([\d,]+) instruction cache misses.* spans ([\d,]+) lines", line)
        if m:
            art["misses"] = int(m.group(1).replace(",", ""))
            art["lines"] = int(m.group(2).replace(",", ""))
        m = re.match(r"profile_instructions (\d+)", line)
        if m:
            art["total"] = int(m.group(1))
        m = re.search(r"soft-float/double helpers.*: ([\d,]+) \(", line)
        if m:
            art["soft"] = int(m.group(1).replace(",", ""))
    return funcs, mix, art


def speed_rows(board, cpi, profiled_name):
    rows = []
    for name in board["count"]:
        n = board["ticks"][f"crane_predict[{name}]"] * bc.INSNS_PER_TICK
        h = bc.real(board["samples"][name][-1][0])
        dt = bc.real(board["samples"][name][1][0])
        t = [n * c / bc.CLOCK_HZ for c in (cpi[0], cpi[2], cpi[1])]
        label = f"dt = {dt * 1e3:g} ms" + (", profiled" if name == profiled_name else "")
        rows.append(f"| {name} ({label}) | {n:,} | {cpi[0]:.2f} / {cpi[2]:.2f} / {cpi[1]:.2f} | "
                    f"{t[0] * 1e3:.1f} / {t[1] * 1e3:.1f} / {t[2] * 1e3:.1f} ms | "
                    f"**{h / t[0]:.0f}x** / **{h / t[1]:.0f}x** / **{h / t[2]:.0f}x** |")
    return ["| 2-s prediction | instructions | CPI | time | faster than real time |",
            "|---|---|---|---|---|"] + rows


def speed(board, cpi, profiled):
    rows = speed_rows(board, cpi, bc.DEFAULT_SCENARIO)
    if "crane_guard" in board["ticks"]:
        g = board["ticks"]["crane_guard"] * bc.INSNS_PER_TICK
        t = [g * c / bc.CLOCK_HZ for c in (cpi[0], cpi[2], cpi[1])]
        rows += ["", wrap(f"The collision guard on that prediction (`crane_guard`; main.c's own three "
                          f"parts and two obstacles, 1,001 samples) takes {g:,} instructions more: "
                          f"{t[0] * 1e3:.1f} / {t[1] * 1e3:.1f} / {t[2] * 1e3:.1f} ms.")]
    n = board["ticks"][f"crane_predict[{bc.DEFAULT_SCENARIO}]"] * bc.INSNS_PER_TICK
    dt = bc.real(board["samples"][bc.DEFAULT_SCENARIO][1][0])
    return "\n".join([
        wrap(f"A 2-s prediction of the paper scenario at dt = {dt * 1e3:g} ms executes **{n:,} "
             f"instructions** on the board (the timer; QEMU's execution log counts {profiled:,}). "
             f"Times on a {bc.CLOCK_HZ / 1e6:g} MHz Cortex-M4F, as low bound / flash estimate / "
             f"high bound, with the CPI of the default scenario's profile for both rows:"),
        "",
    ] + rows)


def hydraulics(board, cpi, profiled, art, static):
    name = "lever-open"
    n = board["ticks"][f"crane_predict[{name}]"] * bc.INSNS_PER_TICK
    return "\n".join([
        wrap(f"With the valve-driven scenario (`make -C csrc/board HYD=1`: the same core, "
             f"`lever-open` added), a 2-s prediction of `{name}` executes **{n:,} "
             f"instructions** (QEMU's execution log: {profiled:,}). Its own profile gives the CPI "
             f"below, which serves for all rows; the code it executes spans {art['lines']:,} "
             f"flash lines ({16 * art['lines'] / 1024:.0f} kB):"),
        "",
    ] + speed_rows(board, cpi, name) + ["", "Stack with that scenario:", "", stack(board, static)])


def profile(funcs, mix, art):
    total = art["total"]
    named = [(f, n) for f, n in funcs if not SOFT.match(f)][:TOP]
    soft = art["soft"]
    lines = ["| function | instructions | share |", "|---|---|---|"]
    for f, n in named:
        role = f" ({ROLE[f]})" if f in ROLE else ""
        lines.append(f"| `{f}`{role} | {n:,} | {100 * n / total:.1f}% |")
    rest = total - sum(n for _, n in named) - soft
    lines.append(f"| everything else (other core functions, libm) | {rest:,} | "
                 f"{100 * rest / total:.1f}% |")
    lines.append(f"| soft-float helpers (`__aeabi_*`: the step count, once per call) | {soft:,} | "
                 f"{100 * soft / total:.2f}% |")

    def pct(*classes):
        return 100 * sum(mix.get(c, 0) for c in classes) / total

    lines += ["", wrap(f"The instruction mix: {pct('fp_arith'):.0f}% FP arithmetic, "
              f"{pct('fp_load_store', 'fp_ldm_stm'):.0f}% FP loads and stores, "
              f"{pct('fp_mac'):.1f}% FP multiply-accumulate (3 cycles each), "
              f"{pct('fp_div_sqrt'):.1f}% FP divisions and square roots (14 cycles each), "
              f"{pct('branch', 'pop_pc'):.0f}% branches. The code executed spans "
              f"{art['lines']:,} flash lines of 16 bytes ({16 * art['lines'] / 1024:.0f} kB): in "
              f"the flash accelerator model {art['misses']:,} of the {total:,} instructions start "
              f"a line that misses its 1 kB cache.")]
    return "\n".join(lines)


def stack(board, static):
    seen, rows = {}, []
    for k, used in board["stack"].items():
        entry = k.split("[")[0]
        if entry == "probe_256":
            continue
        seen.setdefault(entry, []).append(used)
    for entry, used in sorted(seen.items(), key=lambda e: -max(e[1])):
        s = static.get(entry)
        budget = footprint.BUDGET["estimator stack" if entry.startswith(footprint.ESTIMATOR_ENTRY)
                                  else "stack"]
        over = f" (over the {budget:,}-byte budget)" if max(used + [s or 0]) > budget else ""
        rows.append(f"| `{entry}`{over} | {max(used):,} | "
                    f"{'not analysed by tools/footprint.py yet' if s is None else f'{s:,}'} |")
    return "\n".join(["| entry point | measured on the board (bytes) | static worst case (bytes) |",
                      "|---|---|---|"] + rows)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--board", required=True)
    ap.add_argument("--profile", required=True)
    ap.add_argument("--footprint", help="output of tools/footprint.py (default: run it)")
    ap.add_argument("--footprint-build", default="build-m4")
    ap.add_argument("--board-hyd", required=True, help="the board's output with HYD=1")
    ap.add_argument("--profile-hyd", required=True)
    ap.add_argument("--footprint-build-hyd", default="build-m4")
    ap.add_argument("--docs", default=DOCS)
    a = ap.parse_args(argv)
    board, board_hyd = bc.parse_run(a.board), bc.parse_run(a.board_hyd)
    cpi, profiled = bc.read_profile(a.profile)
    cpi_hyd, profiled_hyd = bc.read_profile(a.profile_hyd)
    funcs, mix, art = parse_profile(a.profile)
    art_hyd = parse_profile(a.profile_hyd)[2]
    blocks = {"speed": speed(board, cpi, profiled), "profile": profile(funcs, mix, art),
              "stack": stack(board, bc.static_stack(a.footprint, a.footprint_build)),
              "hydraulics": hydraulics(board_hyd, cpi_hyd, profiled_hyd, art_hyd,
                                       bc.static_stack(None, a.footprint_build_hyd))}
    text = open(a.docs).read()
    for name, body in blocks.items():
        pattern = re.compile(rf"(<!-- board:{name} -->\n)(?:.*?\n)?(<!-- /board:{name} -->)", re.S)
        if not pattern.search(text):
            sys.exit(f"board_docs: no <!-- board:{name} --> block in {a.docs}")
        text = pattern.sub(lambda m: m.group(1) + body + "\n" + m.group(2), text)
    with open(a.docs, "w") as f:
        f.write(text)
    print(f"board_docs: updated {', '.join(blocks)} in {a.docs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
