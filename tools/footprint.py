#!/usr/bin/env python3
"""Footprint of the cranepredict C core on a bare-metal ARM target, checked against a budget.

    make -C csrc footprint          (builds csrc/build-m4 first; the usual way)
    python3 tools/footprint.py --build csrc/build-m4 --cflags '-mcpu=cortex-m4 ...'

Prints and checks:
  * text / data / bss of the core: the library objects only (arm-none-eabi-size, Berkeley
    format: text includes read-only data);
  * the worst-case stack depth of every entry point of crane.h's CDEF section (the budget applies
    to each; crane_predict_many included): the frames of
    every function along the deepest path of the call graph, the core's from -fstack-usage (.su
    files) and everything else (libm, libc) from the prologues of the linked code, summed from
    the entry point to the deepest leaf. Needs no recursion and no indirect calls on the way, and
    no two functions of one name (static functions in two files: the call graph is by name, so
    one would be analysed with the other's frame and calls); all are reported as errors;
  * for information, the flash of everything crane_predict pulls in from the C library (libm).

Nothing is excluded from the call graph: every function the linked code can call counts, whether
or not a given input reaches it. (The float core has its own sin/cos for this reason: newlib's
sinf/cosf can call a 416-byte large-argument reduction.)

The objects must be compiled with -fstack-usage (csrc/Makefile's m4 target does). The probe
program linked here (with --specs=nosys.specs) only gives the call graph; it is not run.
Exit status 1 if a budget is exceeded or the analysis is incomplete.
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

BUDGET = {"data+bss": 1024, "stack": 1024, "text": 32 * 1024, "guard text": 10 * 1024,
          "estimator text": 6 * 1024, "estimator stack": 1024 + 128}
# The collision guard is an optional module: a controller that only predicts does not
# link it (--gc-sections). Its code has its own budget. The prediction's is 32 kB (four joints:
# the slew and the telescope, valves on all four).
GUARD_OBJECTS = {"geometry.o", "guard.o"}
# The state estimator is optional in the same way (a controller that is handed its state does not
# link it); its state and scratch live in the caller's crane_estimator, not on the stack.
ESTIMATOR_OBJECTS = {"estimator.o"}
# Its update runs a batch of predictions (crane_predict_many) under its own frame: its stack
# budget is the predictor's plus 128 bytes.
ESTIMATOR_ENTRY = "crane_estimator_"


def entry_points(header):
    """Every function of the public API: the declarations of crane.h's CDEF section (so that a new
    entry point cannot be left out of the budget)."""
    with open(header, encoding="utf-8") as f:
        text = f.read()
    cdef = re.search(r"CRANE_CDEF_BEGIN(.*)CRANE_CDEF_END", text, re.S).group(1)
    return re.findall(r"^(?:crane_status|const char \*)\s*\*?(crane_[a-z_]+)\(", cdef, re.M)


PROBE = r"""
#include "crane.h"
/* Keeps every entry point in the image; values come from volatile memory so nothing folds. */
volatile crane_real v;
static crane_params params;
static crane_state state;
static crane_inputs inputs;
static crane_model model;
static crane_work work;
static crane_sample out[4];
static crane_real buf[4 * CRANE_N_POINTS * 3], th[4], w[4], a[4], t[4];
static crane_solid solids[2];
static crane_part parts[2];
static crane_guard_config config;
static crane_guard_result result;
static crane_estimator est;
static crane_estimator_config est_config;
static crane_real est_z[CRANE_EST_N];
int main(void)
{
    size_t n, failed;
    crane_field field;
    int s = 0;
    s += (int)crane_predict(&params, &state, &inputs, v, v, out, 4, &n, &work);
    s += (int)crane_predict_many(&params, 1, 1, &state, &inputs, v, v, (size_t)v, out, 4, &failed, &work);
    s += (int)crane_sample_count_every(v, v, (size_t)v, &n);
    s += (int)crane_predict_model(&model, &state, &inputs, v, v, out, 4, &n, &work);
    s += (int)crane_model_init(&model, &params, v);
    s += (int)crane_step(&model, &state, &inputs, v, v, &state, out, &work);
    s += (int)crane_params_check(&params, &field);
    s += (int)crane_field_rule(field)[0];
    s += (int)crane_points(&model, v, 1, th, buf);
    s += (int)crane_sample_count(v, v, &n);
    s += (int)crane_solver_default(&inputs.solver);
    s += (int)crane_joint_angle(&model, s, v, th, w);
    s += (int)crane_joint_stroke(&model, s, v, th);
    s += (int)crane_inverse_dynamics(&model, th, w, a, t);
    s += (int)crane_cylinder_force(&model, s, v, v, v, th);
    s += (int)crane_solid_check(&solids[0], &s);
    s += (int)crane_solid_distance(&solids[0], &solids[1], th, buf, buf + 3);
    s += (int)crane_guard_check(parts, 2, solids, 2, &n, &s);
    s += (int)crane_part_solids(&model, parts, 2, v, v, th, solids);
    s += (int)crane_guard(&model, parts, 2, solids, 2, out, 4, &config, th, buf, 12, &result);
    s += (int)crane_estimator_init(&est, &est_config, est_z, est.covariance, est_z);
    s += (int)crane_estimator_update(&est, &model, &inputs, v, est_z, est_z);
    return s + (int)crane_status_message((crane_status)s)[0];
}
"""


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"footprint: {' '.join(cmd)} failed:\n{r.stdout}{r.stderr}")
    return r.stdout


def sizes(size_tool, objs):
    out = run([size_tool] + objs)
    tot = {"text": 0, "data": 0, "bss": 0}
    rows = []
    for line in out.splitlines()[1:]:
        f = line.split()
        if len(f) >= 6:
            rows.append((os.path.basename(f[5]), int(f[0]), int(f[1]), int(f[2])))
            tot["text"] += int(f[0])
            tot["data"] += int(f[1])
            tot["bss"] += int(f[2])
    return rows, tot


def su_frames(build):
    """-fstack-usage: function -> (bytes, qualifier), and the names that two different functions
    have (static functions of the same name in two files: the call graph, keyed by name, cannot
    tell them apart; a header's static inline kept out of line in two objects is one function)."""
    frames, where, ambiguous = {}, {}, set()
    for path in sorted(glob.glob(os.path.join(build, "*.su"))):
        for line in open(path):
            parts = line.rstrip("\n").split("\t")
            if len(parts) != 3:
                continue
            loc, name = parts[0].rsplit(":", 1)
            if name in where and where[name] != loc:
                ambiguous.add(name)
            where[name] = loc
            frames[name] = max((int(parts[1]), parts[2]), frames.get(name, (0, "")))
    return frames, ambiguous


REGLIST = re.compile(r"\{([^}]*)\}")
BRANCH = re.compile(r"b(eq|ne|cs|cc|hs|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?")


def count_regs(lst):
    n = 0
    for item in lst.split(","):
        item = item.strip()
        m = re.fullmatch(r"([a-z]+)(\d+)-[a-z]+(\d+)", item)
        if m:
            width = 8 if m.group(1) == "d" else 4
            n += (int(m.group(3)) - int(m.group(2)) + 1) * width
        elif item:
            n += 8 if item.startswith("d") and item[1:].isdigit() else 4
    return n


def parse_objdump(text):
    """function -> {'frame': bytes pushed/allocated (sum: an upper bound), 'calls': set,
    'indirect': bool, 'size': bytes}"""
    funcs = {}
    cur = None
    start = None
    last_addr = None
    head = re.compile(r"^([0-9a-f]+) <([^>]+)>:$")
    ins = re.compile(r"^\s*([0-9a-f]+):\s+(?:[0-9a-f]{4}\s?){1,2}\s+(\S+)\s*(.*)$")
    for line in text.splitlines():
        m = head.match(line)
        if m:
            if cur is not None and last_addr is not None:
                funcs[cur]["size"] = last_addr - start + 2
            cur = m.group(2)
            start = int(m.group(1), 16)
            last_addr = None
            # a second function of this name (static, in another file) gets a name of its own,
            # which no call resolves to: the caller reports the name as ambiguous
            if cur in funcs:
                cur = f"{cur}@{m.group(1)}"
            funcs[cur] = {"frame": 0, "calls": set(), "indirect": False, "size": 0}
            continue
        if cur is None:
            continue
        m = ins.match(line)
        if not m:
            continue
        last_addr = int(m.group(1), 16)
        op, args = m.group(2), m.group(3)
        args = args.split(";")[0].split("@")[0].strip()
        f = funcs[cur]
        opb = op.split(".")[0]
        if opb in ("push", "vpush") or (opb in ("stmdb", "vstmdb", "stmfd") and
                                          args.startswith("sp!")):
            r = REGLIST.search(args)
            if r:
                f["frame"] += count_regs(r.group(1))
        elif opb in ("sub", "subw") and re.match(r"sp,\s*(sp,\s*)?#", args):
            f["frame"] += int(re.search(r"#(-?\d+)", args).group(1))
        elif opb in ("str", "strd") and re.search(r"\[sp,\s*#-(\d+)\]!", args):
            f["frame"] += int(re.search(r"\[sp,\s*#-(\d+)\]!", args).group(1))
        elif opb in ("bl", "blx") or (BRANCH.fullmatch(opb) and "<" in m.group(0)):
            t = re.search(r"<([^>+]+)(\+0x[0-9a-f]+)?>", m.group(0))
            if t is None:
                if opb in ("bl", "blx"):
                    f["indirect"] = True
            elif t.group(2) is None and t.group(1) != cur:
                f["calls"].add(t.group(1))
        elif opb == "bx" and not args.startswith("lr"):
            f["indirect"] = True
    if cur is not None and last_addr is not None:
        funcs[cur]["size"] = last_addr - start + 2
    return funcs


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="directory with the objects and .su files")
    ap.add_argument("--cross", default="arm-none-eabi-")
    ap.add_argument("--cflags", default="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 "
                                        "-mfloat-abi=hard -Os")
    ap.add_argument("--float", dest="flt", action="store_true", default=True)
    ap.add_argument("--callees", metavar="FUNC", action="append", default=[],
                    help="also print FUNC's frame and the depth under each function it calls "
                         "(what takes the stack, when a path is over budget)")
    ap.add_argument("--unchecked", metavar="FIGURE", action="append", default=[],
                    choices=sorted(BUDGET),
                    help="print FIGURE against its budget but do not fail on it (the build with "
                         "the error-controlled methods, whose text is over the budget: "
                         "docs/embedding.md); the other figures are checked")
    a = ap.parse_args(argv)
    csrc = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "csrc")
    objs = sorted(p for p in glob.glob(os.path.join(a.build, "*.o")))
    if not objs:
        sys.exit(f"footprint: no objects in {a.build}")
    lib = os.path.join(a.build, "libcranepredict.a")
    ok = True

    rows, tot = sizes(a.cross + "size", objs)
    print(f"cranepredict core on {a.cflags}  (objects in {a.build})")
    print(f"  {'object':<16}{'text':>8}{'data':>8}{'bss':>8}")
    for r in rows:
        print(f"  {r[0]:<16}{r[1]:>8}{r[2]:>8}{r[3]:>8}")
    print(f"  {'total':<16}{tot['text']:>8}{tot['data']:>8}{tot['bss']:>8}")
    guard_text = sum(r[1] for r in rows if r[0] in GUARD_OBJECTS)
    estimator_text = sum(r[1] for r in rows if r[0] in ESTIMATOR_OBJECTS)
    print(f"  of which the prediction {tot['text'] - guard_text - estimator_text}, the collision "
          f"guard {guard_text} (geometry.o, guard.o) and the estimator {estimator_text} "
          "(estimator.o)")

    # link the probe for the call graph
    with tempfile.TemporaryDirectory() as tmp:
        probe = os.path.join(tmp, "probe.c")
        elf = os.path.join(tmp, "probe.elf")
        with open(probe, "w") as f:
            f.write(PROBE)
        cflags = a.cflags.split() + (["-DCRANE_FLOAT"] if a.flt else [])
        run([a.cross + "gcc", "-std=c99"] + cflags + ["-I", csrc, probe, lib,
             "--specs=nosys.specs", "-Wl,--gc-sections", "-lm", "-o", elf])
        dis = run([a.cross + "objdump", "-d", elf])
        owned = {l.split()[3]: int(l.split()[1], 16)
                 for l in run([a.cross + "nm", "-S", elf]).splitlines()
                 if len(l.split()) == 4 and l.split()[3] in ("work", "est")}
    # the caller's memory that the entry points take (RAM, not stack: not in the budget)
    print(f"\ncaller-owned storage: crane_work {owned['work']} bytes (crane_predict, "
          f"crane_predict_model, crane_step, crane_predict_many), crane_estimator {owned['est']} "
          "bytes (its crane_work included)")
    funcs = parse_objdump(dis)
    su, ambiguous = su_frames(a.build)
    # -fstack-usage names a clone "f.isra" where the symbol is "f.isra.0"
    for n in list(funcs):
        base = re.sub(r"\.\d+$", "", n)
        if n not in su and base != n and base in su:
            su[n] = su[base]
    twice = sorted({n.split("@")[0] for n in funcs if "@" in n})
    for name in twice:
        if name in ambiguous or name not in su:
            print(f"  ERROR two functions are named {name}: rename one (the call graph is by name)")
            ok = False

    def frame(name):
        f = funcs[name]["frame"]
        if name in su:
            return max(su[name][0], f), "su"
        return f, "asm"

    core_funcs = set(su)
    memo, stackpath = {}, []

    def depth(name):
        if name in memo:
            return memo[name]
        if name in stackpath:
            raise RuntimeError("recursion: " + " -> ".join(stackpath + [name]))
        if name not in funcs:
            raise RuntimeError(f"no code for {name}")
        if funcs[name]["indirect"]:
            raise RuntimeError(f"indirect call in {name}: stack depth unknown")
        if name in su and su[name][1] not in ("static",):
            raise RuntimeError(f"{name}: -fstack-usage says '{su[name][1]}'")
        stackpath.append(name)
        best, path = 0, []
        for c in sorted(funcs[name]["calls"]):
            d, p = depth(c)
            if d > best:
                best, path = d, p
        stackpath.pop()
        fr = frame(name)[0]
        memo[name] = (fr + best, [(name, fr)] + path)
        return memo[name]

    def reach(name, seen):
        if name in seen or name not in funcs:
            return
        seen.add(name)
        for c in funcs[name]["calls"]:
            reach(c, seen)

    print("\nworst-case stack depth (bytes) by entry point (the budget applies to each):")
    stack, worst, est_stack = None, None, 0
    for e in entry_points(os.path.join(csrc, "crane.h")):
        if e not in funcs:
            print(f"  {e}: ERROR not in the probe (add a call to PROBE)")
            ok = False
            continue
        try:
            d, path = depth(e)
        except RuntimeError as err:
            print(f"  {e}: ERROR {err}")
            ok = False
            continue
        print(f"  {e:<26}{d:>6}")
        if e.startswith(ESTIMATOR_ENTRY):
            est_stack = max(est_stack, d)
            continue
        if stack is None or d > stack:
            stack, worst = d, (e, path)
    if worst is not None:
        print(f"    deepest: {worst[0]}: " + " -> ".join(f"{n} ({fr})" for n, fr in worst[1]))
    for name in a.callees:
        if name not in funcs:
            print(f"  --callees {name}: no such function in the probe")
            continue
        print(f"  {name} (frame {frame(name)[0]}) calls: " +
              ", ".join(f"{c} {depth(c)[0]}" for c in
                        sorted(funcs[name]["calls"], key=lambda c: -depth(c)[0])))
    mism = [(n, su[n][0], funcs[n]["frame"]) for n in su if n in funcs and
            su[n][0] != funcs[n]["frame"]]
    if mism:
        print("  (frames where the prologue sum differs from -fstack-usage; the larger is used: " +
              ", ".join(f"{n} su {s} asm {f}" for n, s, f in mism) + ")")

    seen = set()
    reach("crane_predict", seen)
    libc = sorted(n for n in seen if n not in core_funcs)
    libc_text = sum(funcs[n]["size"] for n in libc)
    print(f"\nC library code reached from crane_predict: {libc_text} bytes of text in "
          f"{len(libc)} functions ({', '.join(libc)})")

    print("\nbudget (Cortex-M4F float build):")
    checks = [("text", tot["text"] - guard_text - estimator_text), ("guard text", guard_text),
              ("estimator text", estimator_text),
              ("data+bss", tot["data"] + tot["bss"]),
              ("stack", stack if stack is not None else 10**9),   # deepest entry point
              ("estimator stack", est_stack)]
    for k, v in checks:
        good = v <= BUDGET[k]
        if k not in a.unchecked:
            ok &= good
        note = " (reported, not checked)" if k in a.unchecked else ""
        print(f"  {k:<12}{v:>8} <= {BUDGET[k]:<6} {'ok' if good else 'OVER BUDGET'}{note}")
    over = [k for k, v in checks if k in a.unchecked and v > BUDGET[k]]
    print("footprint: " + ("within budget" if ok else "FAILED")
          + (f" ({', '.join(over)} over, reported, not checked)" if over else ""))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
