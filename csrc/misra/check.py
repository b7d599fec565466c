#!/usr/bin/env python3
"""MISRA C:2012 check of the cranepredict core with cppcheck's MISRA addon (Debian's cppcheck).

    python3 csrc/misra/check.py            (from anywhere; csrc/ci-embedded.sh runs it)

Runs cppcheck on csrc/*.c (and so on the headers they include: crane.h, crane_internal.h; not the
tests, fuzzer, example, benchmark or board harnesses) in every preprocessor configuration it finds
(double and -DCRANE_FLOAT), prints the violations per rule, and fails on:
  * a violation of a rule that deviations.txt does not list (a new violation), or lists for some
    files only ("only:FILE,..." before the reason) and that occurs in another file;
  * any mandatory rule (MISRA C:2012 with Amendments 1 and 2; never deviable) and any cppcheck
    error (e.g. an uninitialised read, rule 9.1);
  * a cppcheck finding that is not a rule (e.g. a file it could not parse).
A deviated rule with no violation is reported, not failed (the core changes in parallel; remove
it from deviations.txt when it is gone for good).
cppcheck 2.10's addon implements about 140 of the 175 guidelines, and only the decidable parts
of some: a clean run is evidence, not a compliance claim (docs/embedding.md).
"""
import argparse
import collections
import glob
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CSRC = os.path.dirname(HERE)
# MISRA C:2012 Appendix A (with Amendment 1's 21.13, 21.17-21.20): the mandatory rules.
MANDATORY = {"9.1", "12.5", "13.6", "17.3", "17.4", "17.6", "19.1", "21.13", "21.17", "21.18",
             "21.19", "21.20", "22.2", "22.4", "22.5", "22.6"}
LINE = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+):(?P<severity>\w+):(?P<id>[\w.-]+):(?P<msg>.*)$")


def deviations(path):
    """{rule: (category, reason, files)}: files is None (anywhere in the core) or the set of files
    (relative to csrc/) the deviation is scoped to, given as "only:FILE,FILE" before the reason."""
    dev = {}
    for line in open(path):
        if line.strip() and not line.startswith("#"):
            rule, category, reason = line.split(None, 2)
            files = None
            if reason.startswith("only:"):
                scope, reason = reason.split(None, 1)
                files = set(scope[len("only:"):].split(","))
            dev[rule] = (category, reason.strip(), files)
    return dev


def outside(where, files):
    """The violations (file:line) outside a deviation's files (all of them inside if None)."""
    return [w for w in where if files is not None and w.rsplit(":", 1)[0] not in files]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--deviations", default=os.path.join(HERE, "deviations.txt"))
    ap.add_argument("--table", action="store_true",
                    help="also print the deviations as docs/embedding.md's Markdown table")
    a = ap.parse_args(argv)
    sources = sorted(glob.glob(os.path.join(CSRC, "*.c")))
    # --inline-suppr: the core's few "cppcheck-suppress" comments, each with its reason beside it
    cmd = ["cppcheck", "--addon=misra", "--std=c99", "--error-exitcode=0", "-q", "--inline-suppr",
           "--template={file}:{line}:{severity}:{id}:{message}", "-I", CSRC] + sources
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=CSRC)
    dev = deviations(a.deviations)
    by_rule = collections.defaultdict(list)
    problems = []
    for line in (r.stdout + r.stderr).splitlines():
        m = LINE.match(line)
        if not m:
            if line.strip():
                problems.append(f"unexpected cppcheck output: {line}")
            continue
        where = f"{os.path.relpath(m['file'], CSRC)}:{m['line']}"
        rid = m["id"]
        if rid.startswith("misra-c2012-"):
            by_rule[rid[len("misra-c2012-"):]].append(where)
        else:
            problems.append(f"{where}: cppcheck {m['severity']} {rid}: {m['msg']}")
    if r.returncode != 0:
        problems.append(f"cppcheck exited {r.returncode}")

    key = lambda rule: tuple(int(x) for x in rule.split("."))
    print(f"MISRA C:2012, cppcheck MISRA addon, {len(sources)} files of csrc/ "
          f"({', '.join(os.path.basename(s) for s in sources)})")
    print(f"  {'rule':<7}{'category':<10}{'count':>6}  status")
    for rule in sorted(set(by_rule) | set(dev), key=key):
        n = len(by_rule.get(rule, []))
        category = "mandatory" if rule in MANDATORY else dev.get(rule, ("?",))[0]
        if rule in MANDATORY:
            status = "FAIL (mandatory)" if n else "deviation listed for a mandatory rule: FAIL"
            problems.append(f"rule {rule} is mandatory: " +
                            (", ".join(by_rule[rule]) if n else "it cannot be deviated"))
        elif rule in dev and outside(by_rule.get(rule, []), dev[rule][2]):
            status = "NEW VIOLATION outside " + ",".join(sorted(dev[rule][2]))
            problems.append(f"rule {rule} (deviated in {', '.join(sorted(dev[rule][2]))} only): "
                            f"{', '.join(outside(by_rule[rule], dev[rule][2]))}")
        elif rule in dev:
            scope = f" ({','.join(sorted(dev[rule][2]))} only)" if dev[rule][2] else ""
            status = ("deviation" if n else "deviation, no instance found now") + scope
        else:
            status = "NEW VIOLATION"
            problems.append(f"rule {rule} (not deviated): {', '.join(by_rule[rule])}")
        print(f"  {rule:<7}{category:<10}{n:>6}  {status}")
    if a.table:
        print("\n| rule | category | count | reason |\n|---|---|---|---|")
        for rule in sorted(dev, key=key):
            reason = re.sub(r"(\|\|)", r"`\\|\\|`", dev[rule][1])
            if dev[rule][2]:
                reason = f"({', '.join(sorted(dev[rule][2]))} only) {reason}"
            print(f"| {rule} | {dev[rule][0]} | {len(by_rule.get(rule, []))} | {reason} |")
    for p in problems:
        print("FAIL  " + p)
    print(f"misra: {sum(len(v) for v in by_rule.values())} violations of {len(by_rule)} rules, "
          f"{len(dev)} deviated; " + ("ok" if not problems else f"{len(problems)} problems"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
