#!/usr/bin/env python3
"""Instructions per function of one crane_predict call on the board, and its cycles per instruction.

    qemu-system-arm ... -d exec,nochain,in_asm -D exec.log -kernel board-profile.elf
    python3 board_profile.py --elf board-profile.elf --log exec.log

(`make -C csrc/board profile` does both.) QEMU logs every translated block's instructions
(in_asm) and, with chaining off, every execution of a block (exec): together they give the
exact sequence of instructions the board executed. Between the first entry into crane_predict
and the return to main, this prints:
  * the instructions per function (self), from the ELF's symbols (arm-none-eabi-nm);
  * the instruction mix and the cycles it takes on a Cortex-M4F with the instruction timings of
    the Arm Cortex-M4 Technical Reference Manual (r0p1, section 3.3, table 3-1; FPU: table 7-1),
    as a range: LOW = zero-wait memory, neighbouring loads/stores pipelined (1 cycle each), a
    branch's pipeline refill 1 cycle, IT folded, divisions 2 cycles; HIGH = every load/store
    2 cycles, refill 3 cycles, IT 1 cycle, divisions 12 cycles, plus FLASH_WAIT cycles for every
    taken branch (an STM32F4 at 168 MHz runs its flash with 5 wait states; its ART accelerator
    hides them for sequential code, this assumes that every branch target misses its cache);
  * an estimate between the two: LOW plus the stalls of a model of the STM32F4's flash
    accelerator (RM0090, "Adaptive real-time memory accelerator": 128-bit flash lines, an
    instruction cache of 64 lines replaced least recently used, the next sequential line
    prefetched while the current one executes). A line that misses the cache costs FLASH_WAIT
    cycles after a jump, and after sequential execution only what the prefetch could not hide
    (1 + FLASH_WAIT cycles minus the cycles spent in the previous line). Constants read from
    flash (literal pools, the accelerator's 8-line data cache) are not modelled;
  * "cpi_range LOW HIGH" and "cpi_art ESTIMATE" for board_check.py.
Exit status 1 if the window is not found.
"""
import argparse
import bisect
import collections
import re
import subprocess
import sys

FLASH_WAIT = 5
ENTRY, CALLER = "crane_predict", "main"

INSN = re.compile(r"^0x([0-9a-f]+):\s+((?:[0-9a-f]{4}\s)+)\s*(\S+)\s*(.*)$")
TRACE = re.compile(r"^Trace \d+: 0x[0-9a-f]+ \[[0-9a-f]+/([0-9a-f]+)/[0-9a-f]+/([0-9a-f]+)\]")
COND = r"(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?"


class FlashAccelerator:
    """The instruction side of the STM32F4's ART accelerator, as the module docstring says."""
    LINES = 64

    def __init__(self):
        self.cache = collections.OrderedDict()
        self.line = None
        self.spent = 0       # cycles spent in the current line so far
        self.stall = 0
        self.misses = 0
        self.seen = set()    # every line executed: the code's working set

    def execute(self, addr, cycles):
        line = addr >> 4
        if line != self.line:
            self.seen.add(line)
            if line in self.cache:
                self.cache.move_to_end(line)
            else:
                self.misses += 1
                if self.line is not None and line == self.line + 1:
                    self.stall += max(0, 1 + FLASH_WAIT - self.spent)
                else:
                    self.stall += FLASH_WAIT
                self.cache[line] = True
                if len(self.cache) > self.LINES:
                    self.cache.popitem(last=False)
            self.line = line
            self.spent = 0
        self.spent += cycles


def symbols(elf, nm):
    out = subprocess.run([nm, "-n", "--defined-only", elf], capture_output=True, text=True,
                         check=True).stdout
    addrs, names = [], []
    for line in out.splitlines():
        f = line.split()
        if len(f) == 3 and f[1] in "tTwW":
            addrs.append(int(f[0], 16) & ~1)
            names.append(f[2])
    return addrs, names


def nregs(ops):
    m = re.search(r"\{([^}]*)\}", ops)
    if not m:
        return 1
    n = 0
    for item in m.group(1).split(","):
        item = item.strip()
        r = re.fullmatch(r"([a-z]+)(\d+)\s*-\s*[a-z]+(\d+)", item)
        width = 2 if item.startswith("d") else 1
        n += (int(r.group(3)) - int(r.group(2)) + 1) * width if r else width
    return n


# Mnemonics whose last two letters are not a condition although they look like one (shorter
# ones, such as movs or lsls, are told apart by their length in base_mnemonic).
NOT_CONDITIONAL = {"vmls", "vnmls", "teq"}
CONDITIONS = set(COND.strip("()?").split("|"))


def base_mnemonic(mnem):
    """The mnemonic without its width qualifier and, inside an IT block, its condition (QEMU's
    disassembler prints e.g. vldrgt, bleq, popgt)."""
    m = mnem.split(".")[0]
    if m in NOT_CONDITIONAL or re.fullmatch(r"b" + COND, m):
        return m
    base = m[:-2]
    if m[-2:] in CONDITIONS and (len(base) >= 3 or base in ("bl", "bx")):
        return base
    return m


def classify(mnem, ops):
    """(class, low cycles, high cycles, is_branch) of one instruction, without refill/wait."""
    m = base_mnemonic(mnem)
    if re.fullmatch(r"b" + COND, m) or m in ("bl", "blx", "bx", "cbz", "cbnz", "tbb", "tbh"):
        return "branch", 1, 1, True
    if m in ("pop", "ldm", "ldmia", "ldmfd") and "pc" in ops:
        n = nregs(ops)
        return "pop_pc", 1 + n, 1 + n, True
    if m in ("push", "pop", "ldm", "ldmia", "ldmdb", "stm", "stmia", "stmdb"):
        n = nregs(ops)
        return "ldm_stm", 1 + n, 1 + n, False
    if m in ("vpush", "vpop", "vldm", "vldmia", "vstm", "vstmia", "vstmdb"):
        n = nregs(ops)
        return "fp_ldm_stm", 1 + n, 1 + n, False
    if m.startswith(("ldrd", "strd")):
        return "load_store_double", 2, 3, False
    if m.startswith(("ldr", "str", "ldrex", "strex")):
        if m.startswith("ldr") and re.match(r"pc\b", ops):
            return "branch", 2, 2, True
        return "load_store", 1, 2, False
    if m in ("vldr", "vstr"):
        return "fp_load_store", 1, 2, False
    if m in ("vdiv", "vsqrt"):
        return "fp_div_sqrt", 14, 14, False
    if m in ("vmla", "vmls", "vnmla", "vnmls", "vfma", "vfms", "vfnma", "vfnms"):
        return "fp_mac", 3, 3, False
    if m == "vmov" and ops.count(",") >= 2:
        return "fp_move", 2, 2, False
    if m.startswith("v"):
        return "fp_arith", 1, 1, False
    if m in ("sdiv", "udiv"):
        return "divide", 2, 12, False
    if m.startswith("it"):
        return "it", 0, 1, False
    if m in ("mul", "muls", "mla", "mls", "smull", "umull", "smlal", "umlal"):
        return "multiply", 1, 1, False
    return "alu", 1, 1, False


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--elf", required=True)
    ap.add_argument("--log", required=True)
    ap.add_argument("--nm", default="arm-none-eabi-nm")
    ap.add_argument("--top", type=int, default=20)
    ap.add_argument("--entry", default=ENTRY, help="the profiled function (its first call)")
    ap.add_argument("--caller", default=CALLER, help="the function it returns to")
    a = ap.parse_args(argv)
    addrs, names = symbols(a.elf, a.nm)
    start_pc = addrs[names.index(a.entry)]
    caller = names.index(a.caller)
    caller_range = (addrs[caller], addrs[caller + 1])

    def func(pc):
        return names[bisect.bisect_right(addrs, pc) - 1]

    blocks = {}          # pc -> [(addr, size, class, lo, hi, branch, function)], longest seen
    cur = None
    per_func = collections.Counter()
    per_class = collections.Counter()
    lo = hi = 0
    taken = not_taken = 0
    state = "before"
    pending = None       # the last block executed: (fallthrough address, ends in a branch)
    art = FlashAccelerator()
    with open(a.log, errors="replace") as log:
        for line in log:
            if line.startswith("IN:"):
                cur = []
                continue
            if cur is not None:
                m = INSN.match(line)
                if m:
                    addr = int(m.group(1), 16)
                    size = 2 * len(m.group(2).split())
                    cls, l, h, br = classify(m.group(3), m.group(4))
                    cur.append((addr, size, cls, l, h, br, func(addr)))
                    continue
                if cur:
                    pc0 = cur[0][0]
                    if len(cur) > len(blocks.get(pc0, ())):
                        blocks[pc0] = cur
                cur = None
            m = TRACE.match(line)
            if not m:
                continue
            pc = int(m.group(1), 16)
            if state == "before":
                if pc != start_pc:
                    continue
                state = "in"
            elif caller_range[0] <= pc < caller_range[1]:
                state = "after"
                break
            if pending is not None and pending[1]:
                if pc == pending[0]:
                    not_taken += 1
                else:
                    taken += 1
                    lo += 1          # pipeline refill, best case
                    hi += 3 + FLASH_WAIT
                    art.spent += 1
            count = int(m.group(2), 16) & 0x1FF
            tb = blocks[pc][:count] if count else blocks[pc]
            for addr, size, cls, l, h, br, fn in tb:
                per_func[fn] += 1
                per_class[cls] += 1
                lo += l
                hi += h
                art.execute(addr, l)
            last = tb[-1]
            pending = (last[0] + last[1], last[5])
    if state != "after":
        print(f"profile: no complete call of {a.entry} from {a.caller} in {a.log}")
        return 1

    total = sum(per_func.values())
    print(f"profile of one {a.entry} call on the board: {total:,} instructions")
    print(f"  {'function':<28}{'instructions':>14}{'share':>8}")
    for fn, n in per_func.most_common(a.top):
        print(f"  {fn:<28}{n:>14,}{100 * n / total:>7.1f}%")
    rest = total - sum(n for _, n in per_func.most_common(a.top))
    if rest:
        print(f"  {'(the other functions)':<28}{rest:>14,}{100 * rest / total:>7.1f}%")
    soft = sum(n for fn, n in per_func.items() if fn.startswith("__aeabi_") or
               re.match(r"__\w+[sd]f\d$", fn))
    print(f"  soft-float/double helpers (__aeabi_*, __*df3): {soft:,} ({100 * soft / total:.1f}%)")
    print("\ninstruction mix:")
    for cls, n in per_class.most_common():
        print(f"  {cls:<20}{n:>12,}{100 * n / total:>7.1f}%")
    print(f"  branches taken {taken:,}, not taken {not_taken:,}")
    print(f"\ncycles on a Cortex-M4F (TRM timings): low {lo:,} (CPI {lo / total:.3f}), high {hi:,} "
          f"(CPI {hi / total:.3f}; {FLASH_WAIT} flash wait states on every taken branch)")
    est = lo + art.stall
    print(f"with a model of the STM32F4 flash accelerator: {est:,} cycles (CPI {est / total:.3f}; "
          f"{art.misses:,} instruction cache misses, {art.stall:,} stall cycles; the code executed "
          f"spans {len(art.seen):,} lines = {16 * len(art.seen):,} bytes)")
    print(f"cpi_range {lo / total:.4f} {hi / total:.4f}")
    print(f"cpi_art {est / total:.4f}")
    print(f"profile_instructions {total}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
