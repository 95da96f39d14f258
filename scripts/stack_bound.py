#!/usr/bin/env python3
"""A static worst-case stack bound for the Cortex-M4F firmware (`firmware/board`), from its
ELF and its disassembly (`arm-none-eabi-objdump -d --no-show-raw-insn -C`). Standard library
only. `scripts/board_figures.py` imports it for docs/firmware-target.md; run alone it prints
the bound and its path, and exits 1 if the bound is below the measured high-water mark
(`# stack used=` in the board's run.txt) or if any instruction defeats the analysis.

usage: stack_bound.py [ELF] [--disasm DISASM.txt] [--run RUN.txt] [--times N]
       stack_bound.py --selftest

Method.
* Frames. Each function's stack depth (bytes below the sp at its entry) is followed through
  its control-flow graph: branches, `cbz`/`cbnz`, `tbb`/`tbh` jump tables (read from the
  ELF), conditional returns (`popcs {.., pc}`, `bxne lr`). `push`, `stmdb sp!`,
  `str rX, [sp, #-n]!` and `vpush`/`vstmdb sp!` grow it (4 bytes a core or s register, 8 a d
  register); `sub sp, #n`, `sub.w sp, sp, #n`, `subw sp, sp, #n` grow it by n, and so does
  `sub sp, rN` once rN holds a constant from `movw`/`movt` (or `mov`) in the same straight
  run of code; the matching pops and `add`s shrink it. Two paths joining at different
  depths, any other write to sp, a depth below the entry's or control running off a
  function's end other than after a `bl` (to a function that does not return) is an error.
* Calls. `bl` to a symbol is a call at the depth of the call site; a branch out of the
  function (`b.w`, also conditional) is a tail call at the depth at the branch; `blx rN` is
  an indirect call, `bx rN` (not `lr`) an indirect tail call.
* Indirect calls go to functions whose address is taken: a word of .rodata, .data or a
  literal pool in .text, or a `movw`/`movt` pair, equal to a function's address with the
  Thumb bit set (the vector table's entries are called by the hardware, not by `blx`). A
  data word counts where function pointers sit (a vtable, a table: `pointer_slot`), not
  where an isolated one happens to equal an address inside other data.
  Every indirect call site may call every such function: sound as long as no code address
  is computed otherwise, coarse otherwise.
* Bound(f) = max(deepest point of f, max over its call sites (depth there + Bound(callee))).
  Recursion is a cycle of the call graph (a strongly connected component); without a limit
  it makes every function that reaches it unbounded. With `times` = N, each function of a
  cycle may be on the stack at most N times, so the component adds at most N x (the sum of
  its members' deepest points) before a call leaves it.
* Roots. `Reset` (cortex-m-rt: `Reset` -> `main` -> `__cortex_m_rt_main`) starts at the
  top of the stack. Exceptions use the same stack (MSP) and stack on top of any point: each
  adds its hardware frame (108 bytes on a Cortex-M4F with the FPU enabled: the 26-word
  extended frame and 4 of alignment) and its handler's bound. The firmware sets no
  priorities, so the configurable exceptions (all at priority 0) cannot preempt one another:
  at most one of them, then HardFault (-1), then NMI (-2).
  Total = Bound(Reset) + max(configurable) + HardFault + NMI.
* Check. The bound from Reset (with the cycles' limit) must not be below the measured
  high-water mark; the call chains exactly as deep as the measurement are listed.
"""
import os
import re
import struct
import subprocess
import sys
import time
from collections import defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ELF = os.path.join(ROOT, "target/board/thumbv7em-none-eabihf/release/coopwin-board")
EXC_FRAME = 26 * 4 + 4   # extended (FP) exception frame, plus the STKALIGN word
TIMES = 2                # default: each function of a cycle at most twice on the stack
REG = r"(?:r\d+|ip|lr|fp|sl|sb)"
ALIAS = {"sb": "r9", "sl": "r10", "fp": "r11", "ip": "r12"}
COND = r"(?:eq|ne|cs|cc|hs|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)"


class Error(Exception):
    pass


# ------------------------------------------------------------------------------------- ELF
def read_elf(path):
    """{section name: (address, bytes)} of the allocated sections of a little-endian ELF32."""
    data = open(path, "rb").read()
    if data[:4] != b"\x7fELF" or data[4] != 1 or data[5] != 1:
        raise Error(f"{path}: not a little-endian ELF32")
    shoff, = struct.unpack_from("<I", data, 0x20)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
    hdrs = [struct.unpack_from("<IIIIII", data, shoff + i * shentsize) for i in range(shnum)]
    stroff = hdrs[shstrndx][4]
    secs = {}
    for name, typ, flags, addr, off, size in hdrs:
        sname = data[stroff + name:data.index(b"\0", stroff + name)].decode()
        if flags & 2 and size:  # SHF_ALLOC; NOBITS (.bss) reads as zeros
            secs[sname] = (addr, data[off:off + size] if typ != 8 else bytes(size))
    return secs


# ----------------------------------------------------------------------------- disassembly
class Insn:
    __slots__ = ("addr", "op", "args")

    def __init__(self, addr, op, args):
        self.addr, self.op, self.args = addr, op, args


def parse_disasm(text):
    """{start: name}, {start: [Insn]}; data (`.word`, `.short`) kept as Insns too."""
    names, body, cur = {}, {}, None
    for line in text.splitlines():
        m = re.match(r"^([0-9a-f]+) <(.*)>:$", line)
        if m:
            cur = int(m[1], 16)
            names[cur], body[cur] = m[2], []
            continue
        m = re.match(r"^\s+([0-9a-f]+):\t(\S+)(?:\t([^\t]*))?", line)
        if m and cur is not None:
            body[cur].append(Insn(int(m[1], 16), m[2], (m[3] or "").split("\t@")[0].strip()))
    return names, body


def is_code(i):
    return not i.op.startswith(".")


def reglist(args):
    m = re.search(r"\{([^}]*)\}", args)
    if not m:
        raise Error(f"no register list in `{args}`")
    regs = []
    for part in (p.strip() for p in m[1].split(",")):
        r = re.match(r"([a-z]+)(\d+)-[a-z]+(\d+)$", part)
        regs += [f"{r[1]}{n}" for n in range(int(r[2]), int(r[3]) + 1)] if r else [part]
    return regs


def list_bytes(regs):
    return sum(8 if r.startswith("d") else 4 for r in regs)


def target_of(args):
    m = re.search(r"(?:^|, )([0-9a-f]+) <", args)
    return int(m[1], 16) if m else None


def split_cond(op):
    """('pop', 'cs') for `popcs`, ('b', 'ne') for `bne.n`; ('bl', None) for `bl`."""
    base = re.sub(r"\.[wn]$", "", op)
    if base in ("bl", "bls", "blt", "ble", "blx"):
        return (base, None) if base in ("bl", "blx") else ("b", base[1:])
    m = re.match(rf"^(blx|bl|bx|b|v?push|v?pop|v?ldmia|v?stmdb|ldr|str|add|sub|addw|subw|mov|movw|movt|movs)({COND})$", base)
    return (m[1], m[2]) if m else (base, None)


# ----------------------------------------------------------------------------- one function
class Func:
    def __init__(self, addr, name, insns):
        self.addr, self.name, self.insns = addr, name, insns
        self.frame = 0       # deepest point: bytes below the sp at entry
        self.calls = []      # (depth at the site, callee or None if indirect, kind, site address)
        self.depth = {}      # instruction address -> depth before it


def jump_table(ins, code, secs):
    """Targets of a `tbb`/`tbh` at ins. The table runs from ins+4 (`[pc, rM]`), or from the
    address an `addw rN, pc, #imm` just before puts in the base register (`[rN, rM]`, the
    table then past a padding `nop`), to the next instruction; targets are ins+4 + 2 entry."""
    base, blob = secs[".text"]
    start = ins.addr + 4
    reg = ins.args.lstrip("[").split(",")[0].strip()
    if reg != "pc":
        prev = [i for i in code if i.addr < ins.addr]
        m = re.match(r"^(\w+), pc, #(\d+)$", prev[-1].args) if prev and prev[-1].op == "addw" else None
        if not m or m.group(1) != reg:
            raise Error(f"{ins.addr:#x} `{ins.op} {ins.args}`: table base not from `addw {reg}, pc, #imm`")
        start = ((prev[-1].addr + 4) & ~3) + int(m.group(2))
    end = min((i.addr for i in code if i.addr >= start), default=start)
    raw = blob[start - base:end - base]
    if ins.op == "tbb":
        entries = list(raw)
    else:
        entries = [struct.unpack_from("<H", raw, o)[0] for o in range(0, len(raw) - 1, 2)]
    return [ins.addr + 4 + 2 * e for e in entries]


def analyse_function(f, funcs, secs):
    code = [i for i in f.insns if is_code(i)]
    at = {i.addr: k for k, i in enumerate(code)}
    where = lambda i: f"{f.name}+{i.addr - f.addr:#x} `{i.op} {i.args}`"
    # Branch targets start a new straight run: constants in registers are forgotten there.
    joins = set()
    for i in code:
        t = target_of(i.args) if i.op.startswith(("b", "cb")) else None
        if t in at:
            joins.add(at[t])
        if i.op in ("tbb", "tbh"):
            joins.update(at[t] for t in jump_table(i, code, secs) if t in at)
    depth, calls, work, frame = {}, {}, [(0, 0, {})], 0
    while work:
        k, d, regs = work.pop()
        if k >= len(code):
            # Padding after a call that does not return: `nop`, or the zero halfword (`movs r0, r0`).
            prev = [i for i in code[:k] if i.op != "nop" and (i.op, i.args) != ("movs", "r0, r0")]
            if not prev or split_cond(prev[-1].op)[0] != "bl":
                raise Error(f"{f.name}: control runs off its end")
            continue
        if k in depth:
            if depth[k] != d:
                raise Error(f"{where(code[k])}: paths join at depths {depth[k]} and {d}")
            continue
        depth[k] = d
        ins = code[k]
        op, a = ins.op, ins.args
        base, cond = split_cond(op)
        regs = {} if k in joins else dict(regs)
        before = dict(regs)
        nd, succ, site = d, [k + 1], ins.addr

        # ---- the stack pointer
        if base in ("push", "vpush") or base in ("stmdb", "vstmdb") and a.startswith("sp!"):
            if cond:
                raise Error(f"{where(ins)}: a conditional push")
            nd = d + list_bytes(reglist(a))
        elif base in ("pop", "vpop") or base in ("ldmia", "vldmia") and a.startswith("sp!"):
            rl = reglist(a)
            if cond and "pc" not in rl:
                raise Error(f"{where(ins)}: a conditional pop that does not return")
            if not cond:  # a taken conditional `pop {.., pc}` returns; not taken, pops nothing
                nd = d - list_bytes(rl)
                if "pc" in rl:
                    succ = []
        elif re.match(r"^str(\.w)?$", op) and re.search(r"\[sp, #-(\d+)\]!$", a):
            nd = d + int(re.search(r"\[sp, #-(\d+)\]!$", a)[1])
        elif re.match(r"^ldr(\.w)?$", op) and re.search(r"\[sp\], #(\d+)$", a):
            nd = d - int(re.search(r"\[sp\], #(\d+)$", a)[1])
            if a.startswith("pc,"):
                succ = []
        elif base in ("sub", "subw", "add", "addw") and re.match(rf"sp, (sp, )?(#\d+|{REG})$", a):
            src = a.split(", ")[-1]
            n = int(src[1:]) if src.startswith("#") else regs.get(ALIAS.get(src, src))
            if n is None:
                raise Error(f"{where(ins)}: sp moved by a register not known to hold a constant")
            if cond:
                raise Error(f"{where(ins)}: a conditional sp adjustment")
            nd = d + n if base.startswith("sub") else d - n
        elif (re.match(r"^[a-z.]+\tsp\b", f"{op}\t{a}") and not re.match(r"^(stm|str|cmp|cmn|tst|vst)", op)
              # A load-multiple from sp without writeback, sp not in its list, only reads.
              and not (re.match(r"^v?ldm", op) and "!" not in a and not re.search(r"\{[^}]*\bsp\b", a))) \
                or "sp!" in a or re.search(r"\[sp(, #-?\d+)?\]!|\[sp\], #", a) \
                or (op.startswith("msr") and "SP" in a.upper()):
            raise Error(f"{where(ins)}: writes sp in a way not understood")
        if nd < 0:
            raise Error(f"{where(ins)}: depth {nd}, above the sp at entry")

        # ---- constants in registers, for `sub sp, rN`
        for r in written(base, op, a):
            regs.pop(ALIAS.get(r, r), None)
        m = re.match(rf"^({REG}), #(\d+)$", a)
        if m and not cond:
            rd = ALIAS.get(m[1], m[1])
            if base == "movw" or op in ("mov", "movs", "mov.w", "movs.w"):
                regs[rd] = int(m[2])
            elif base == "movt" and rd in before:
                regs[rd] = (before[rd] & 0xFFFF) | int(m[2]) << 16
        frame = max(frame, nd)

        # ---- control flow
        if base == "bl" or base == "blx" and not re.match(rf"^{REG}$", a):
            t = target_of(a)
            if t not in funcs:
                raise Error(f"{where(ins)}: a call to no known function")
            calls[site] = (nd, t, "call", site)
        elif base == "blx":
            calls[site] = (nd, None, "indirect", site)
        elif base == "bx":
            if a != "lr":
                calls[site] = (nd, None, "indirect tail call", site)
            if not cond:
                succ = []
        elif base == "b" or op.startswith(("cbz", "cbnz")):
            t = target_of(a)
            uncond = base == "b" and not cond
            if t in at:
                succ = [at[t]] if uncond else [k + 1, at[t]]
            elif t in funcs:
                calls[site] = (nd, t, "tail call", site)
                succ = [] if uncond else [k + 1]
            else:
                raise Error(f"{where(ins)}: a branch neither within it nor to a function")
        elif base in ("tbb", "tbh"):
            succ = [at[t] for t in jump_table(ins, code, secs) if t in at]
            if not succ:
                raise Error(f"{where(ins)}: jump table not read")
        elif base == "udf":
            succ = []
        elif re.match(r"^pc\b", a) and not op.startswith(("str", "cmp")) or re.search(r"\{[^}]*\bpc\b", a) and not op.startswith(("pop", "ldm")):
            raise Error(f"{where(ins)}: writes pc in a way not understood")
        for s in succ:
            work.append((s, nd, regs if s == k + 1 else {}))
    f.depth = {code[k].addr: v for k, v in depth.items()}
    f.frame = frame
    f.calls = sorted(calls.values(), key=lambda c: c[3])
    dead = [i for k, i in enumerate(code) if k not in depth and i.op != "nop" and (i.op, i.args) != ("movs", "r0, r0")]
    if dead:
        raise Error(f"{where(dead[0])}: not reached from the function's entry ({len(dead)} such)")


def written(base, op, args):
    """Core registers an instruction may write: its first operand (two for `ldrd`, the long
    multiplies and `vmov rA, rB, dC`), a register list it loads, a base register written
    back; the caller-saved registers across a call."""
    if base in ("bl", "blx"):
        return ["r0", "r1", "r2", "r3", "r12", "lr"]
    wb = re.findall(rf"\b({REG})!|\[({REG})\], #|\[({REG}), #-?\d+\]!", args)
    out = [x for t in wb for x in t if x]
    if re.match(r"^(b|bx|cbz|cbnz|tbb|tbh|it[te]*|cmp|cmn|tst|teq|vcmp|vcmpe|nop|udf|bkpt|dsb|isb|dmb|cpsid|cpsie|msr)$", base) \
            or base.startswith(("str", "stm", "vst", "push", "vpush")) and not base.startswith("strex"):
        return out
    if base.startswith(("pop", "ldm")) and "{" in args:
        return out + reglist(args)
    ops = [o.strip() for o in args.split("[")[0].split(",")]
    n = 2 if base.startswith(("ldrd", "umull", "smull", "umlal", "smlal", "vmov", "ldrexd")) else 1
    return out + [o for o in ops[:n] if re.match(rf"^{REG}$", o)]


# ----------------------------------------------------------------------------- the call graph
def pointer_slot(blob, o, starts):
    """Whether the data word at `o` (a function's address with the Thumb bit) sits where code
    keeps function pointers: in a Rust vtable (`[drop_in_place or 0, size, align, methods..]`:
    a method after the header and the methods before it, or the drop entry before size and
    align), or beside another function's address (a table). Only an isolated word that
    happens to equal an address, inside other data (core's Unicode tables hold such bytes),
    is not."""
    def word(k):
        return struct.unpack_from("<I", blob, k)[0] if 0 <= k <= len(blob) - 4 else None

    def fn(v):
        return v is not None and v & 1 and v - 1 in starts

    def size_align(size, align):
        return align in (1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096) and \
            size is not None and size % align == 0 and size < 1 << 24

    if fn(word(o - 4)) or fn(word(o + 4)):
        return True
    drop = word(o - 12)
    return (size_align(word(o - 8), word(o - 4)) and (drop == 0 or fn(drop))) or \
        size_align(word(o + 4), word(o + 8))


def address_taken(secs, names, body):
    """{function: set of places its address (Thumb bit set) is found}."""
    starts, taken = set(names), defaultdict(set)
    for sec in (".rodata", ".data", ".vector_table"):
        addr, blob = secs.get(sec, (0, b""))
        for o in range(0, len(blob) - 3, 4):
            v, = struct.unpack_from("<I", blob, o)
            if v & 1 and v - 1 in starts and (sec == ".vector_table" or pointer_slot(blob, o, starts)):
                taken[v - 1].add(sec)
    for insns in body.values():
        half = {}
        for i in insns:
            if i.op == ".word":
                for w in i.args.split(","):
                    v = int(w, 16)
                    if v & 1 and v - 1 in starts:
                        taken[v - 1].add("literal pool")
            m = re.match(rf"^({REG}), #(\d+)$", i.args)
            if i.op == "movw" and m:
                half[m[1]] = int(m[2])
            elif i.op == "movt" and m and m[1] in half:
                v = half.pop(m[1]) | int(m[2]) << 16
                if v & 1 and v - 1 in starts:
                    taken[v - 1].add("movw/movt")
    return taken


def tarjan(nodes, adj):
    """Strongly connected components, each after every component it reaches."""
    index, low, on, stack, out, n = {}, {}, set(), [], [], 0
    for root in nodes:
        if root in index:
            continue
        index[root] = low[root] = n; n += 1
        stack.append(root); on.add(root)
        work = [(root, iter(adj[root]))]
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = n; n += 1
                    stack.append(w); on.add(w)
                    work.append((w, iter(adj[w])))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop(); on.discard(w); comp.append(w)
                    if w == v:
                        break
                out.append(comp)
    return out


def bounds(funcs, resolve, times=None):
    """(bound, step, cycles, cycle_of): bound[f] in bytes, or None where recursion is reachable
    and `times` is None; step[f] = (depth at the site, callee, call) of f's deepest call (of
    its cycle's deepest exit for a function in a cycle)."""
    edges = {a: [(c[0], t, c) for c in f.calls for t in resolve(c)] for a, f in funcs.items()}
    adj = {a: [t for _, t, _ in es] for a, es in edges.items()}
    comps = tarjan(sorted(funcs), adj)
    cycles = [c for c in comps if len(c) > 1 or c[0] in adj[c[0]]]
    cycle_of = {a: tuple(sorted(c)) for c in cycles for a in c}
    bound, step = {}, {}
    for comp in comps:
        members = set(comp)
        inside = 0 if comp[0] not in cycle_of else None if times is None else \
            times * sum(funcs[a].frame for a in comp)
        if inside is None:
            for a in comp:
                bound[a], step[a] = None, None
            continue
        b, s = (inside, None) if comp[0] in cycle_of else (funcs[comp[0]].frame, None)
        for a in comp:
            for d, t, c in edges[a]:
                if t in members:
                    continue
                if bound[t] is None:
                    b, s = None, (d, t, c)
                    break
                # in a cycle the frame making the call is already counted in `inside`
                v = (inside if comp[0] in cycle_of else d) + bound[t]
                if v > b:
                    b, s = v, (d, t, c)
            if b is None:
                break
        for a in comp:
            bound[a], step[a] = b, s
    return bound, step, cycles, cycle_of


def deepest_path(funcs, step, cycle_of, a, times):
    """[(function address, or a tuple of them for a cycle; bytes it adds; the kind of call
    that reached it, None for a)] from a."""
    out, kind = [], None
    while a is not None:
        s = step.get(a)
        if a in cycle_of:
            comp = cycle_of[a]
            out.append((comp, (times or 1) * sum(funcs[x].frame for x in comp), kind))
        else:
            out.append((a, s[0] if s else funcs[a].frame, kind))
        a, kind = (s[1], s[2][2]) if s else (None, None)
    return out


# ----------------------------------------------------------------------------------- analysis
def analyse(elf=ELF, disasm=None, run=None, times=TIMES):
    t0 = time.time()
    if disasm is None:
        disasm = subprocess.run(["arm-none-eabi-objdump", "-d", "--no-show-raw-insn", "-C", elf],
                                check=True, capture_output=True, text=True).stdout
    secs = read_elf(elf)
    names, body = parse_disasm(disasm)
    if not names:
        raise Error("no functions in the disassembly")
    # The disassembly must be of this ELF: its literal words must be the ELF's.
    tbase, tblob = secs[".text"]
    for insns in body.values():
        for i in insns:
            if i.op == ".word" and tbase <= i.addr < tbase + len(tblob) - 3:
                if struct.unpack_from("<I", tblob, i.addr - tbase)[0] != int(i.args.split(",")[0], 16):
                    raise Error(f"the disassembly is not of {elf} (stale? rerun scripts/board.sh --figures)")
    funcs = {a: Func(a, names[a], body[a]) for a in names}
    for f in funcs.values():
        analyse_function(f, funcs, secs)
    taken = address_taken(secs, names, body)
    # The vector table's entries are called by the hardware, not through `blx`.
    targets = sorted(a for a, w in taken.items() if w - {".vector_table"})

    vec = secs[".vector_table"][1]
    vectors = [struct.unpack_from("<I", vec, o)[0] for o in range(0, len(vec), 4)]
    reset = vectors[1] & ~1
    handlers = defaultdict(list)  # handler -> exception numbers
    for n, v in enumerate(vectors[2:], start=2):
        if v:
            handlers[v & ~1].append(n)
    for h in [reset] + list(handlers):
        if h not in funcs:
            raise Error(f"vector {h:#x} is no function of the disassembly")

    res = {"funcs": funcs, "taken": taken, "targets": targets, "reset": reset,
           "handlers": dict(handlers), "times": times, "models": {}}
    direct = lambda c: [c[1]] if c[1] is not None else []
    coarse = lambda c: [c[1]] if c[1] is not None else targets
    for model, resolve in (("direct", direct), ("address-taken", coarse)):
        for n in (None, times):
            b, step, cycles, cycle_of = bounds(funcs, resolve, n)
            exc = {h: None if b[h] is None else EXC_FRAME + b[h] for h in handlers}
            groups = {"configurable (one at a time)": [h for h, e in handlers.items() if any(x >= 4 for x in e)],
                      "HardFault": [h for h, e in handlers.items() if 3 in e],
                      "NMI": [h for h, e in handlers.items() if 2 in e]}
            parts = [("Reset", reset, b[reset])]
            for g, hs in groups.items():
                worst = max(hs, key=lambda h: -1 if exc[h] is None else exc[h], default=None)
                parts.append((g, worst, None if worst is None else exc[worst]))
            values = [v for _, h, v in parts if h is not None]
            res["models"][model, n] = {
                "bound": b, "cycles": cycles, "cycle_of": cycle_of, "parts": parts,
                "thread": b[reset], "total": None if None in values else sum(values),
                "path": deepest_path(funcs, step, cycle_of, reset, n) if b[reset] is not None else None}
    res["indirect"] = [(f.addr, c) for f in funcs.values() for c in f.calls if c[1] is None]
    res["measured"] = None
    if run:
        m = re.search(r"^# stack used=(\d+)", run, re.M)
        res["measured"] = int(m[1]) if m else None
    res["seconds"] = time.time() - t0
    return res


def chains_at(res, target, model=("direct", None), limit=100000):
    """The call chains from Reset (distinct lists of functions) whose static depth, the sum of
    the call sites' depths and the last function's frame, is exactly `target` bytes: to
    compare the frames with the measured high-water mark."""
    funcs, bound = res["funcs"], res["models"][model]["bound"]
    found, visits = [], [0]

    def walk(a, d, chain):
        visits[0] += 1
        if visits[0] > limit:
            return
        if d + funcs[a].frame == target:
            found.append(chain)
        for dep, t in sorted({(c[0], c[1]) for c in funcs[a].calls if c[1] is not None}):
            if bound[t] is not None and d + dep + bound[t] >= target and t not in chain:
                walk(t, d + dep, chain + [t])

    walk(res["reset"], 0, [res["reset"]])
    return found


def check(res):
    """Raises Error if the bound is below the measured high-water mark."""
    m = res["models"]["address-taken", res["times"]]
    if res["measured"] is not None and (m["thread"] is None or m["thread"] < res["measured"]):
        raise Error(f"the static bound from Reset ({m['thread']}) is below the measured "
                    f"high-water mark ({res['measured']}): the analysis is wrong")


def brief(name):
    """A name without its module paths: `<Foveal>::new`, `<SseCoop as ConfidencePolicy>::push`,
    `suite::run::<..>` (a free function keeps its last module)."""
    name = short(name, 1000)
    name = re.sub(r"\b(?:[a-z_][a-z0-9_]*::)+(?=[A-Z_])", "", name)
    name = re.sub(r"^(?:[a-z_][a-z0-9_]*::)+(?=[a-z_][a-z0-9_]*::[a-z_])", "", name)
    return name


def short(name, n=90):
    """Generic arguments elided (`::<..>`); a leading `<Type>` is kept, it names the method."""
    return re.sub(r"::<[^<>]*(?:<[^<>]*(?:<[^<>]*>[^<>]*)*>[^<>]*)*>", "::<..>", name)[:n]


# ----------------------------------------------------------------------------------- self-test
SELFTEST = """
00000100 <leaf>:
     100:\tpush\t{r4, r5, r7, lr}
     102:\tvpush\t{d8-d9}
     106:\tsub\tsp, #8
     108:\tcbz\tr0, 110 <leaf+0x10>
     10a:\tadd\tsp, #8
     10c:\tvpop\t{d8-d9}
     10e:\tpop\t{r4, r5, r7, pc}
     110:\tb.n\t10a <leaf+0xa>

00000200 <big>:
     200:\tpush\t{r7, lr}
     202:\tmovw\tr4, #45104\t@ 0xb030
     206:\tmovt\tr4, #2
     20a:\tsub.w\tsp, sp, r4
     20e:\tbl\t100 <leaf>
     212:\tblx\tr3
     214:\tadd.w\tsp, sp, r4
     218:\tldmia.w\tsp!, {r7, lr}
     21c:\tb.w\t100 <leaf>

00000300 <table>:
     300:\ttbb\t[pc, r0]
     304:\t.word\t0x00000302
     308:\tbx\tlr
     30a:\tsub\tsp, #16
     30c:\tadd\tsp, #16
     30e:\tbx\tlr
"""

UNEVEN = """
00000100 <uneven>:
     100:\tcbz\tr0, 106 <uneven+0x6>
     102:\tpush\t{r7, lr}
     104:\tnop
     106:\tbx\tlr
"""


def selftest():
    names, body = parse_disasm(SELFTEST)
    text = bytearray(0x400)
    text[0x304:0x308] = bytes([2, 3, 0, 0])   # tbb entries: 0x308, 0x30a (0 is the table)
    secs = {".text": (0, bytes(text))}
    funcs = {a: Func(a, names[a], body[a]) for a in names}
    for f in funcs.values():
        analyse_function(f, funcs, secs)
    leaf, big = funcs[0x100], funcs[0x200]
    assert funcs[0x300].frame == 16 and len(funcs[0x300].depth) == 5, funcs[0x300].depth
    assert leaf.frame == 16 + 16 + 8, leaf.frame            # 4 core regs, 2 d regs, 8
    assert big.frame == 8 + 0x2B030, big.frame              # movw/movt: 176,176 bytes
    assert [(c[0], c[1], c[2]) for c in big.calls] == [
        (8 + 0x2B030, 0x100, "call"), (8 + 0x2B030, None, "indirect"), (0, 0x100, "tail call")], big.calls
    b, step, cycles, _ = bounds(funcs, lambda c: [c[1]] if c[1] else [0x100, 0x200])
    assert b[0x200] is None and cycles, "a blx that may call its own function is recursion"
    b, *_ = bounds(funcs, lambda c: [c[1]] if c[1] else [])
    assert b[0x200] == 8 + 0x2B030 + 40, b[0x200]
    b, *_ = bounds(funcs, lambda c: [c[1]] if c[1] else [0x100, 0x200], 3)
    assert b[0x200] == 3 * (8 + 0x2B030) + 40, b[0x200]
    names, body = parse_disasm(UNEVEN)
    try:
        analyse_function(Func(0x100, names[0x100], body[0x100]), {0x100: None}, secs)
        raise AssertionError("paths joining at different depths must be an error")
    except Error:
        pass
    print("stack_bound.py: self-test passed")


# ----------------------------------------------------------------------------------- report
def main(argv):
    elf, disasm, run, times = ELF, None, None, TIMES
    args = list(argv)
    while args:
        a = args.pop(0)
        if a == "--selftest":
            return selftest()
        if a == "--disasm":
            disasm = open(args.pop(0)).read()
        elif a == "--run":
            run = open(args.pop(0)).read()
        elif a == "--times":
            times = int(args.pop(0))
        elif a.startswith("-"):
            raise Error(__doc__.split("\n\n")[1])
        else:
            elf = a
    if run is None and os.path.exists(os.path.join(os.path.dirname(elf), "../../run.txt")):
        run = open(os.path.join(os.path.dirname(elf), "../../run.txt")).read()
    r = analyse(elf, disasm, run, times)
    funcs = r["funcs"]
    for (model, n), m in r["models"].items():
        cyc = f", each function of a cycle at most {n} times on the stack" if n else ""
        print(f"{model} calls{cyc}: from Reset {m['thread']}, with exceptions {m['total']}")
        for c in m["cycles"]:
            print(f"  cycle of {len(c)}: " + ", ".join(short(funcs[a].name, 50) for a in sorted(c)[:6])
                  + (", ..." if len(c) > 6 else ""))
        for a, add, kind in m["path"] or []:
            name = short(funcs[a].name) if isinstance(a, int) else f"(cycle of {len(a)} functions)"
            print(f"  {add:>9,}  {name}" + (f"  [{kind}]" if kind and kind != "call" else ""))
    print(f"{len(r['indirect'])} indirect call sites in "
          f"{len({a for a, _ in r['indirect']})} functions, {len(r['targets'])} address-taken targets")
    if r["measured"] is not None:
        m = r["models"]["address-taken", times]
        print(f"measured high-water {r['measured']:,}; bound from Reset {m['thread']:,} "
              f"({m['thread'] / r['measured']:.4f}x); with exceptions {m['total']:,}")
        for c in chains_at(r, r["measured"]):
            print("  a chain exactly as deep as measured: " + " -> ".join(brief(funcs[a].name) for a in c))
    check(r)
    print(f"{r['seconds']:.2f} s")


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except Error as e:
        print(f"stack_bound.py: {e}", file=sys.stderr)
        sys.exit(1)
