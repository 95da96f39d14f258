#!/usr/bin/env python3
"""Where a COOP frame's instructions go on the Cortex-M4F: a profile of the board run from
QEMU's execution trace. Called by `scripts/board.sh --profile`; standard library and
binutils-arm-none-eabi only.

usage: board_profile.py ELF TRACE [--lines N] [--frames K:A-B]

TRACE is QEMU's `-d exec,nochain,in_asm` log (a file or a FIFO): each translated block's
instructions once (`IN:`), then a `Trace` line each time the block runs. A frame opens when
`coopwin_parity::suite::CoopPair::frame` is entered and closes when the run is back in
`suite::tracker`: the metered frame (the master's window, the partner's, the decision) and the
partner's answer to the decision's messages. Each replay (the thesis's pair, then the adapting
one) is profiled apart: one begins where `CoopPair::new` is entered. Library helpers
(soft-float, `memcpy`, `libm`) are charged to the function that called them. Prints, for each
replay, a line `replay K: F frames, I instructions a frame on average, C cycles (CPI R)`, a
markdown table of instructions per frame by function and, with `--lines N`, the N busiest
source lines. With `--frames K:A-B` only frames A to B (from 0) of replay K are counted there
(the covered replay's frames in doubt: `--frames 2:30-44`); the other replays are whole.

Cycles are estimated from the executed instructions with the Cortex-M4's instruction timings
(ARM Cortex-M4 Technical Reference Manual r0p1, 3.3.1, Table 3-1; the FPU's, 7.2.3): loads and
stores 2 cycles (a neighbouring pair's pipelining is not counted), `ldrd`/`strd` 3,
`ldm`/`stm`/`push`/`pop` 1 + N, `mla`/`mls` 2, `sdiv`/`udiv` 7 (2 to 12), `vldr`/`vstr` 2,
`vldm`/`vstm`/`vpush`/`vpop` 1 + N, `vmla`-family 3, `vdiv`/`vsqrt` 14, a branch 1 not taken
and 1 + P taken with the pipeline refill P = 2 (1 to 3; the trace tells which were taken),
`tbb`/`tbh` 2 + P, a `pop` or load into pc 1 + N + P; everything else 1. Flash wait states are
not counted: the STM32F4's ART accelerator (prefetch, 1 KB instruction cache) hides them for
code like this (see docs/firmware-target.md).
"""
import bisect
import collections
import re
import subprocess
import sys

HELPERS = ("compiler_builtins", "__aeabi", "libm::", "memcmp", "memcpy", "memset", "__float", "__udivmod")
TRACE = re.compile(r"Trace \d+: 0x([0-9a-f]+) \[[0-9a-f]+/([0-9a-f]+)/")


def symbols(elf):
    """Sorted (start, size, demangled name) of the ELF's functions."""
    out = subprocess.run(["arm-none-eabi-nm", "-C", "-S", "--defined-only", elf],
                         capture_output=True, text=True, check=True).stdout
    syms = []
    for line in out.splitlines():
        parts = line.split(" ", 3)
        if len(parts) == 4 and parts[2] in "tTwW":
            syms.append((int(parts[0], 16), int(parts[1], 16), parts[3]))
    return sorted(syms)


CONDS = ("eq", "ne", "cs", "cc", "hs", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt", "le", "al")
BRANCHES = {"b", "bl", "bx", "blx", "cbz", "cbnz"}
REFILL = 2


def instructions(elf):
    """Address -> (mnemonic stem, operands, size in bytes) of the ELF's instructions."""
    out = subprocess.run(["arm-none-eabi-objdump", "-d", elf], capture_output=True, text=True, check=True).stdout
    insns = {}
    for line in out.splitlines():
        m = re.match(r"\s*([0-9a-f]+):\t([0-9a-f ]+?)\s*\t(\S+)\s*(.*)", line)
        if not m:
            continue
        size = sum(len(w) // 2 for w in m[2].split())
        mn = m[3].lower().split(".")[0]
        insns[int(m[1], 16)] = (mn, m[4], size)
    return insns


def stem(mn):
    """The mnemonic without its condition code (`ldrne` -> `ldr`, `bne` -> `b`)."""
    if mn in ("vmls", "vnmls", "vfms", "vfnms"):
        return mn
    for c in CONDS:
        if mn.endswith(c) and len(mn) > 2:
            base = mn[: -len(c)]
            if base in BRANCHES or base.startswith(("ld", "st", "mov", "add", "sub", "v", "b")) and base not in ("", "v"):
                return base
    return mn


def registers(ops):
    """Words a register list `{r4, r5, d8}` moves (a d register two)."""
    m = re.search(r"\{([^}]*)\}", ops)
    if not m:
        return 1
    words = 0
    for r in (r.strip() for r in m[1].split(",") if r.strip()):
        lo, _, hi = r.partition("-")
        n = int(hi[1:]) - int(lo[1:]) + 1 if hi else 1
        words += n * (2 if lo.startswith("d") else 1)
    return words


def cycles(mn, ops, taken):
    """Cycles of one execution of an instruction (Table 3-1 of the Cortex-M4 TRM, above)."""
    s = stem(mn)
    to_pc = "pc" in ops.split(",")[0] or ("pc" in ops and s in ("pop", "ldm", "ldmia"))
    if s in BRANCHES or (s.startswith("b") and mn in BRANCHES):
        return 1 + REFILL if taken else 1
    if s in ("tbb", "tbh"):
        return 2 + REFILL
    if s in ("ldrd", "strd"):
        return 3
    if s in ("pop", "ldm", "ldmia", "ldmdb", "push", "stm", "stmia", "stmdb"):
        return 1 + registers(ops) + (REFILL if to_pc and s in ("pop", "ldm", "ldmia", "ldmdb") else 0)
    if s in ("vpush", "vpop", "vldm", "vldmia", "vldmdb", "vstm", "vstmia", "vstmdb"):
        return 1 + registers(ops)
    if s in ("vldr", "vstr"):
        return 2
    if s.startswith(("ldr", "str")):
        return 2 + (REFILL if s.startswith("ldr") and ops.startswith("pc") else 0)
    if s in ("vdiv", "vsqrt"):
        return 14
    if s in ("vmla", "vmls", "vnmla", "vnmls", "vfma", "vfms", "vfnma", "vfnms"):
        return 3
    if s in ("mla", "mls"):
        return 2
    if s in ("sdiv", "udiv"):
        return 7
    return 1


def short(name):
    """A function's name without the crate's path and generic arguments."""
    name = re.sub(r"coopwin_\w+::(kernels::|processors::)?", "", name)
    return re.sub(r"::<.*>$", "", name)


def profile(elf, trace, only=None):
    syms = symbols(elf)
    starts = [s[0] for s in syms]

    def function(pc):
        i = bisect.bisect_right(starts, pc) - 1
        return syms[i][2] if i >= 0 and pc < syms[i][0] + syms[i][1] else "?"

    blocks = {}                      # host block -> its guest instruction addresses
    names = {}                       # guest pc -> function name (cached)
    replays = []                     # (frames, by_fn, by_pc, taken) of each replay
    insns = instructions(elf)
    taken = collections.Counter()    # branch address -> times taken
    last = None                      # the previous block's last instruction
    by_fn = collections.Counter()    # caller (helpers folded in) -> instructions
    by_pc = collections.Counter()    # guest instruction address -> executions
    frames, open_, owner = 0, False, "?"
    frames_skipped = set()           # the frames of the replay `only` names left out
    block = None
    with open(trace, errors="replace") as f:
        for line in f:
            if line.startswith("IN:"):
                block = []
            elif block is not None and line.startswith("0x"):
                block.append(int(line[2:10], 16))
            else:
                m = TRACE.match(line)
                if not m:
                    continue
                host, pc = m[1], int(m[2], 16)
                if block is not None:
                    blocks[host], block = block, None
                name = names.get(pc) or names.setdefault(pc, function(pc))
                if open_ and last is not None and pc != last + insns.get(last, ("", "", 0))[2]:
                    taken[last] += 1
                if not open_ and "CoopPair>::new" in name and frames:
                    replays.append((frames - len(frames_skipped), by_fn, by_pc, taken))
                    frames_skipped = set()
                    frames, by_fn, by_pc, taken = 0, collections.Counter(), collections.Counter(), collections.Counter()
                if not open_ and "CoopPair>::frame" in name:
                    open_, frames = True, frames + 1
                elif open_ and "suite::tracker" in name:
                    open_ = False
                if not open_:
                    last = None
                    continue
                if only and only[0] == len(replays) and not only[1] <= frames - 1 <= only[2]:
                    frames_skipped.add(frames)
                    last = None
                    continue
                if not any(h in name for h in HELPERS):
                    owner = name
                insns_of = blocks.get(host, ())
                by_fn[owner] += len(insns_of)
                for a in insns_of:
                    by_pc[a] += 1
                last = insns_of[-1] if insns_of else None
    if frames:
        replays.append((frames - len(frames_skipped), by_fn, by_pc, taken))
    return replays, insns


def source_lines(elf, by_pc):
    """Executions per source line, each address charged to its innermost firmware line."""
    addrs = sorted(by_pc)
    out = subprocess.run(["arm-none-eabi-addr2line", "-e", elf, "-a", "-i"],
                         input="\n".join(f"{a:x}" for a in addrs), capture_output=True, text=True).stdout
    lines, where = collections.Counter(), None
    locs = collections.defaultdict(list)
    for line in out.splitlines():
        if line.startswith("0x"):
            where = int(line, 16)
        elif where is not None:
            locs[where].append(line.split(" ")[0])
    for a in addrs:
        mine = [l for l in locs[a] if "/firmware/" in l and not l.endswith(":?")]
        loc = re.sub(r".*/firmware/", "firmware/", mine[0]) if mine else "(library)"
        lines[loc] += by_pc[a]
    return lines


def main():
    usage = __doc__.split("\n\n")[1]
    args = sys.argv[1:]
    if len(args) < 2 or len(args) % 2:
        sys.exit(usage)
    elf, trace = args[:2]
    opts = dict(zip(args[2::2], args[3::2]))
    if set(opts) - {"--lines", "--frames"}:
        sys.exit(usage)
    lines, only = opts.get("--lines"), None
    if "--frames" in opts:
        m = re.fullmatch(r"(\d+):(\d+)-(\d+)", opts["--frames"])
        if not m or int(m[2]) > int(m[3]):
            sys.exit(f"board_profile.py: --frames wants K:A-B (replay K, its frames A to B), not {opts['--frames']!r}")
        only = tuple(int(v) for v in m.groups())
    replays, insns = profile(elf, trace, only)
    if not replays:
        sys.exit("board_profile.py: no COOP frame in the trace")
    for k, (frames, by_fn, by_pc, taken) in enumerate(replays):
        if not frames:
            print(f"replay {k}: no frame counted (--frames)")
            print()
            continue
        total = sum(by_fn.values())
        cyc = 0
        for a, n in by_pc.items():
            mn, ops, _ = insns.get(a, ("", "", 0))
            t = taken[a]
            cyc += (n - t) * cycles(mn, ops, False) + t * cycles(mn, ops, True)
        print(f"replay {k}: {frames} frames, {total / frames:,.0f} instructions a frame on average, "
              f"{cyc / frames:,.0f} cycles (CPI {cyc / sum(by_pc.values()):.2f})")
        print()
        print("| function (library helpers folded in) | instructions a frame | share |")
        print("|---|---:|---:|")
        for name, n in by_fn.most_common(12):
            print(f"| `{short(name)}` | {n / frames:,.0f} | {100 * n / total:.1f} % |")
        print()
        if lines:
            print("| source line | instructions a frame |")
            print("|---|---:|")
            for loc, n in source_lines(elf, by_pc).most_common(int(lines)):
                print(f"| `{loc}` | {n / frames:,.0f} |")
            print()


if __name__ == "__main__":
    main()
