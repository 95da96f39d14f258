#!/usr/bin/env python3
"""Where a COOP frame's instructions go on the Cortex-M4F: a profile of the board run from
QEMU's execution trace. Called by `scripts/board.sh --profile`; standard library and
binutils-arm-none-eabi only.

usage: board_profile.py ELF TRACE [--lines N]

TRACE is QEMU's `-d exec,nochain,in_asm` log (a file or a FIFO): each translated block's
instructions once (`IN:`), then a `Trace` line each time the block runs. A frame opens when
`coopwin_parity::suite::CoopPair::frame` is entered and closes when the run is back in
`suite::tracker`: the metered frame (the master's window, the partner's, the decision) and the
partner's answer to the decision's messages. Library helpers (soft-float, `memcpy`,
`libm`) are charged to the function that called them. Prints a markdown table of
instructions per frame by function and, with `--lines N`, the N busiest source lines.
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


def short(name):
    """A function's name without the crate's path and generic arguments."""
    name = re.sub(r"coopwin_\w+::(kernels::|processors::)?", "", name)
    return re.sub(r"::<.*>$", "", name)


def profile(elf, trace):
    syms = symbols(elf)
    starts = [s[0] for s in syms]

    def function(pc):
        i = bisect.bisect_right(starts, pc) - 1
        return syms[i][2] if i >= 0 and pc < syms[i][0] + syms[i][1] else "?"

    blocks = {}                      # host block -> its guest instruction addresses
    names = {}                       # guest pc -> function name (cached)
    by_fn = collections.Counter()    # caller (helpers folded in) -> instructions
    by_pc = collections.Counter()    # guest instruction address -> executions
    frames, open_, owner = 0, False, "?"
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
                if not open_ and "CoopPair>::frame" in name:
                    open_, frames = True, frames + 1
                elif open_ and "suite::tracker" in name:
                    open_ = False
                if not open_:
                    continue
                if not any(h in name for h in HELPERS):
                    owner = name
                insns = blocks.get(host, ())
                by_fn[owner] += len(insns)
                for a in insns:
                    by_pc[a] += 1
    return frames, by_fn, by_pc


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
    args = sys.argv[1:]
    if len(args) not in (2, 4) or (len(args) == 4 and args[2] != "--lines"):
        sys.exit(__doc__.split("\n\n")[1])
    elf, trace = args[:2]
    frames, by_fn, by_pc = profile(elf, trace)
    if frames == 0:
        sys.exit("board_profile.py: no COOP frame in the trace")
    total = sum(by_fn.values())
    print(f"{frames} frames, {total / frames:,.0f} instructions a frame on average")
    print()
    print("| function (library helpers folded in) | instructions a frame | share |")
    print("|---|---:|---:|")
    for name, n in by_fn.most_common(12):
        print(f"| `{short(name)}` | {n / frames:,.0f} | {100 * n / total:.1f} % |")
    if len(args) == 4:
        print()
        print("| source line | instructions a frame |")
        print("|---|---:|")
        for loc, n in source_lines(elf, by_pc).most_common(int(args[3])):
            print(f"| `{loc}` | {n / frames:,.0f} |")


if __name__ == "__main__":
    main()
