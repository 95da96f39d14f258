"""cocotb testbench for hdl/verilog/window_unit_axis.v (run it with hdl/cocotb/run.py --axis).

The bench top hdl/cocotb/tb_window_unit_axis.v holds three windows, each on its own m<k>_axis_
prefix. cocotbext-axi drives the buses: an AxiStreamSource is the camera (tuser on each frame's
first pixel, one AxiStreamFrame a line so tlast ends each line, random tvalid gaps), an
AxiStreamSink per window takes its output (random tready gaps), an AxiLiteMaster writes and
reads the registers.

A monitor samples every rising edge: the register writes (on their handshake edge) and the
input beats go, in that order, into the reference model (model.py's AxisModel: the contract in
the RTL's header, written as code); the output handshakes are recorded per window and the
AXI4-Stream rule is checked on every clock (a beat offered and not taken stays, unchanged).
After each frame the outputs drain and are scoreboarded against the model: exactly its beats
when OVERFLOWS is 0, otherwise its beats in order with exactly OVERFLOWS left out and tuser on
each window frame's first delivered beat (model.match_with_drops); FRAMES, OVERFLOWS, STATUS,
IRQ_STATUS and the irq pin are read and compared, and the sinks' own record of the beats must
equal the monitor's.

Functional coverage (cocotb-coverage) of the listed situations; test_coverage reports it,
writes coverage.xml and coverage.yml, and fails if one was not reached.
"""

from __future__ import annotations

import hashlib
import os
import random
import re

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge
from cocotb_coverage.coverage import CoverPoint, coverage_db
from cocotbext.axi import (AxiLiteBus, AxiLiteMaster, AxiStreamBus, AxiStreamFrame,
                           AxiStreamSink, AxiStreamSource)

from model import (AXIS_COMMIT, AXIS_CTRL, AXIS_FRAMES, AXIS_INFO, AXIS_GEOMETRY,
                   AXIS_IRQ_ENABLE, AXIS_IRQ_STATUS, AXIS_OVERFLOWS, AXIS_STATUS, AXIS_WINDOW,
                   AXIS_X, AXIS_Y, AxisModel, Rect, match_with_drops)

W = int(os.environ.get("COOPWIN_WIDTH", "80"))
H = int(os.environ.get("COOPWIN_HEIGHT", "40"))
P = int(os.environ.get("COOPWIN_PIXEL_BITS", "16"))
DEPTH = int(os.environ.get("COOPWIN_FIFO_DEPTH", "8"))
FRAMES = int(os.environ.get("COOPWIN_FRAMES", "0")) or 10
SEED = int(os.environ.get("COOPWIN_SEED", "1"))
COVERAGE_DIR = os.environ.get("COOPWIN_COVERAGE_DIR", ".")
N = 3                                   # windows of the bench top
TW = (P + 7) // 8 * 8                   # tdata bits
MAX_ERRORS = 5

STIMULUS_TESTS = ("test_shapes", "test_commit_races", "test_random_windows", "test_invalid_sets",
                  "test_overflow", "test_reset_in_frame")
_ran: set[str] = set()

SITUATIONS = [
    "commit 2+ edges before the tuser beat (applies)", "commit 1 edge before the tuser beat (applies)",
    "commit on the tuser beat's edge (applies)", "commit 1 edge after the tuser beat (waits)",
    "commit 1 edge after a tuser beat that takes a pending set (waits)",
    "commit during a frame, for the next", "a later commit replaces a pending one",
    "three windows open in one frame, overlapping", "window on the frame's first pixel",
    "window on the last column", "window on the last row", "full-frame window", "2x2 window",
    "two-row window", "two-column window", "decimated, odd width and height",
    "decimated, even width and height", "decimated 2x2 (one pixel)", "continuous over 3+ frames",
    "continuous replaced by a one-shot set", "input tvalid gaps",
    "back-pressure: tvalid and not tready", "back-pressure absorbed without loss",
    "overflow counted and flagged", "dropped tuser carried to the next beat",
    "overflow flag cleared by writing 1", "invalid: xmax beyond the sensor",
    "invalid: ymax beyond the sensor", "invalid: xmin > xmax", "invalid: ymin > ymax",
    "invalid: xmin = xmax (one column)", "invalid: ymin = ymax (one row)",
    "invalid keeps the pending set", "invalid keeps the repeating set",
    "interrupt raised and cleared", "reset in a frame",
]


@CoverPoint("top.situation", xf=lambda s: s, bins=SITUATIONS)
def cover(situation: str) -> None:
    if situation not in SITUATIONS:
        raise ValueError(f"no such cover bin: {situation}")


def pixel(frame: int, x: int, y: int) -> int:
    """The camera's pixel at (x, y) of frame `frame`: a hash, so a misplaced one is caught."""
    d = hashlib.blake2s(f"{frame},{x},{y}".encode(), digest_size=4).digest()
    return int.from_bytes(d, "little") & ((1 << P) - 1)


def window_base(k: int) -> int:
    return AXIS_WINDOW * (k + 1)


def cover_shape(r: Rect) -> None:
    if (r.xmin, r.ymin) == (0, 0):
        cover("window on the frame's first pixel")
    if r.xmax == W - 1:
        cover("window on the last column")
    if r.ymax == H - 1:
        cover("window on the last row")
    if (r.xmin, r.xmax, r.ymin, r.ymax) == (0, W - 1, 0, H - 1):
        cover("full-frame window")
    w, h = r.xmax - r.xmin + 1, r.ymax - r.ymin + 1
    if not r.decimate:
        if (w, h) == (2, 2):
            cover("2x2 window")
        elif h == 2:
            cover("two-row window")
        elif w == 2:
            cover("two-column window")
    elif (w, h) == (2, 2):
        cover("decimated 2x2 (one pixel)")
    elif w % 2 and h % 2:
        cover("decimated, odd width and height")
    elif w % 2 == 0 and h % 2 == 0:
        cover("decimated, even width and height")


class Bench:
    def __init__(self, dut, seed: str):
        self.dut = dut
        self.rng = random.Random(seed)
        cocotb.start_soon(Clock(dut.aclk, 10, unit="ns").start())
        self.source = AxiStreamSource(AxiStreamBus.from_prefix(dut, "s_axis"), dut.aclk, dut.aresetn,
                                      reset_active_level=False, byte_size=TW)
        self.sinks = [AxiStreamSink(AxiStreamBus.from_prefix(dut, f"m{k}_axis"), dut.aclk, dut.aresetn,
                                    reset_active_level=False, byte_size=TW) for k in range(N)]
        self.axil = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.aclk, dut.aresetn,
                                  reset_active_level=False)
        for bus in self.sinks + [self.source, self.axil.write_if, self.axil.read_if]:
            bus.log.setLevel("WARNING")
        self.model = AxisModel(W, H, N)
        self.delivered: list[list[tuple]] = [[] for _ in range(N)]
        self.checked = [0] * N          # expected beats already scoreboarded, per window
        self.drops_seen = [0] * N       # OVERFLOWS as last read
        self.frames_sent = 0
        self.edge = 0
        self.sofs: list[int] = []       # edges of the tuser beats
        self.commits: list[tuple] = []  # (edge, window, 'valid' or 'invalid')
        self.errors: list[str] = []
        self.stalled = [False] * N
        self.sink_pending: list[list[tuple]] = [[] for _ in range(N)]
        self.last_frames, self.last_active, self.repeats = [0] * N, [None] * N, [0] * N
        self.gaps = False
        dut.aresetn.value = 0
        cocotb.start_soon(self.monitor())

    def error(self, text: str) -> None:
        self.errors.append(text)
        self.dut._log.error(text)
        if len(self.errors) >= MAX_ERRORS:
            raise AssertionError("; ".join(self.errors))

    async def reset(self, clocks: int = 3) -> None:
        self.dut.aresetn.value = 0
        await ClockCycles(self.dut.aclk, clocks)
        self.dut.aresetn.value = 1
        await RisingEdge(self.dut.aclk)

    async def monitor(self) -> None:
        d = self.dut
        held = [None] * N
        outs = [(getattr(d, f"m{k}_axis_tvalid"), getattr(d, f"m{k}_axis_tready"),
                 getattr(d, f"m{k}_axis_tdata"), getattr(d, f"m{k}_axis_tuser"),
                 getattr(d, f"m{k}_axis_tlast")) for k in range(N)]
        while True:
            await RisingEdge(d.aclk)
            self.edge += 1
            if not int(d.aresetn.value):
                self.model.reset()
                held = [None] * N
                continue
            if int(d.s_axil_awvalid.value) and int(d.s_axil_awready.value) \
                    and int(d.s_axil_wvalid.value) and int(d.s_axil_wready.value):
                addr, data = int(d.s_axil_awaddr.value), int(d.s_axil_wdata.value)
                result = self.model.write(addr, data)
                if result is not None:
                    self.commits.append((self.edge, addr // AXIS_WINDOW - 1, result))
            if int(d.s_axis_tvalid.value):
                if not int(d.s_axis_tready.value):
                    self.error(f"edge {self.edge}: s_axis_tready low (it is held high)")
                user = bool(int(d.s_axis_tuser.value))
                if user:
                    self.sofs.append(self.edge)
                self.model.beat(int(d.s_axis_tdata.value), user, bool(int(d.s_axis_tlast.value)))
            elif self.sofs:
                self.gaps = True
            for k, (valid, ready, data, user, last) in enumerate(outs):
                v, r = int(valid.value), int(ready.value)
                beat = (int(data.value), bool(int(user.value)), bool(int(last.value))) if v else None
                if held[k] is not None and beat != held[k]:
                    self.error(f"edge {self.edge}: window {k} changed an offered beat before it was "
                               f"taken: {held[k]} -> {beat}")
                if v and r:
                    self.delivered[k].append(beat)
                held[k] = beat if v and not r else None
                self.stalled[k] |= bool(v and not r)

    async def write(self, addr: int, data: int) -> None:
        await self.axil.write_dword(addr, data)

    async def read(self, addr: int) -> int:
        return await self.axil.read_dword(addr)

    async def set_window(self, k: int, r: Rect, commit: bool = True) -> None:
        b = window_base(k)
        old = self.model.active[k]
        if commit and r.valid(W, H) and old is not None and old.continuous and not r.continuous:
            cover("continuous replaced by a one-shot set")
        await self.write(b + AXIS_X, r.xmin | r.xmax << 16)
        await self.write(b + AXIS_Y, r.ymin | r.ymax << 16)
        await self.write(b + AXIS_CTRL, int(r.decimate) | int(r.continuous) << 1)
        if commit:
            await self.write(b + AXIS_COMMIT, 1)

    async def send_frame(self, lines: range | None = None, user: bool = True) -> None:
        """One frame (or its `lines`), a line an AxiStreamFrame; tuser on its first pixel."""
        f = self.frames_sent
        self.frames_sent += 1
        for y in lines if lines is not None else range(H):
            data = [pixel(f, x, y) for x in range(W)]
            tuser = [int(user and x == 0 and y == 0) for x in range(W)]
            await self.source.send(AxiStreamFrame(data, tuser=tuser))
        await self.source.wait()

    def pauses(self, source: float, sink: float) -> None:
        """Random tvalid gaps on the input and tready gaps on the outputs, with these odds."""
        def gen(p, rng):
            while True:
                yield rng.random() < p
        self.source.set_pause_generator(gen(source, random.Random(self.rng.random())) if source else None)
        for s in self.sinks:
            s.set_pause_generator(gen(sink, random.Random(self.rng.random())) if sink else None)

    async def drain(self) -> None:
        """Waits until every window's FIFO and output register are empty (STATUS busy low)."""
        for _ in range(4 * W * H):
            busy = [(await self.read(window_base(k) + AXIS_STATUS)) & 2 for k in range(N)]
            if not any(busy):
                return
            await ClockCycles(self.dut.aclk, 8)
        self.error("the outputs did not drain")

    async def check(self) -> None:
        """Drains, then scoreboards every window and checks the status registers."""
        await self.drain()
        m = self.model
        for k in range(N):
            # Windows completed since the last check by a set that repeats without a commit.
            same = m.active[k] is not None and m.active[k] == self.last_active[k]
            self.repeats[k] = self.repeats[k] + 1 if same and m.active[k].continuous else 0
            if self.repeats[k] >= 2:
                cover("continuous over 3+ frames")
        if all(f == f0 + 1 for f, f0 in zip(m.frames, self.last_frames)):
            a = m.active
            if max(r.xmin for r in a) <= min(r.xmax for r in a) and \
                    max(r.ymin for r in a) <= min(r.ymax for r in a):
                cover("three windows open in one frame, overlapping")
        self.last_frames, self.last_active = list(m.frames), list(m.active)
        for k in range(N):
            b = window_base(k)
            drops = await self.read(b + AXIS_OVERFLOWS)
            frames = await self.read(b + AXIS_FRAMES)
            status = await self.read(b + AXIS_STATUS)
            expected, delivered = m.expected[k], self.delivered[k]
            new_drops = drops - self.drops_seen[k]
            self.drops_seen[k] = drops
            if new_drops == 0:
                want = [(e.data, e.user, e.last) for e in expected]
                if delivered != want:
                    i = next((i for i, (a, b_) in enumerate(zip(delivered, want)) if a != b_),
                             min(len(delivered), len(want)))
                    self.error(f"window {k}: beat {i} of {len(want)} expected: delivered "
                               f"{delivered[i] if i < len(delivered) else 'nothing'}, expected "
                               f"{want[i] if i < len(want) else 'nothing'} "
                               f"({expected[i].x}, {expected[i].y})" if i < len(want) else "")
                elif self.stalled[k]:
                    cover("back-pressure absorbed without loss")
            else:
                lost, why = match_with_drops(expected, delivered)
                if why is not None:
                    self.error(f"window {k} (OVERFLOWS +{new_drops}): {why}")
                elif lost != new_drops:
                    self.error(f"window {k}: {lost} beats missing but OVERFLOWS rose by {new_drops}")
                if not status & 16:
                    self.error(f"window {k}: beats dropped but STATUS overflow is low ({status:#x})")
                cover("overflow counted and flagged")
                await self.write(b + AXIS_STATUS, 16)
                if (await self.read(b + AXIS_STATUS)) & 16:
                    self.error(f"window {k}: writing 1 to STATUS bit 4 did not clear the overflow flag")
                else:
                    cover("overflow flag cleared by writing 1")
                status &= ~16
            if frames != m.frames[k]:
                self.error(f"window {k}: FRAMES {frames}, expected {m.frames[k]}")
            if status != m.status(k, False):
                self.error(f"window {k}: STATUS {status:#x}, expected {m.status(k, False):#x}")
            # The sinks' own record: the same beats, rows ended by tlast (a row whose tlast is
            # still to come stays in the sink).
            rows = []
            while not self.sinks[k].empty():
                rows.append(self.sinks[k].recv_nowait())
            got = [v for fr in rows for v in fr.tdata]
            stream = self.sink_pending[k] + delivered
            cut = max((i + 1 for i, (_, _, last) in enumerate(stream) if last), default=0)
            if got != [d for d, _, _ in stream[:cut]]:
                self.error(f"window {k}: the sink's record differs from the monitor's")
            self.sink_pending[k] = stream[cut:]
            if new_drops and any(u and d not in {e.data for e in expected if e.user}
                                 for d, u, _ in delivered):
                cover("dropped tuser carried to the next beat")
            expected.clear()
            delivered.clear()
        irq_status = await self.read(AXIS_IRQ_STATUS)
        if irq_status != m.irq_status:
            self.error(f"IRQ_STATUS {irq_status:#x}, expected {m.irq_status:#x}")
        if int(self.dut.irq.value) != bool(m.irq_status & m.irq_enable):
            self.error(f"irq {int(self.dut.irq.value)} with IRQ_STATUS {irq_status:#x}, IRQ_ENABLE {m.irq_enable:#x}")
        if irq_status:
            await self.write(AXIS_IRQ_STATUS, irq_status)
            await ClockCycles(self.dut.aclk, 1)
            if int(self.dut.irq.value) or await self.read(AXIS_IRQ_STATUS):
                self.error("IRQ_STATUS written back did not clear the interrupt")
            elif m.irq_enable & irq_status:
                cover("interrupt raised and cleared")
        if any(self.stalled):
            cover("back-pressure: tvalid and not tready")
        if self.gaps:
            cover("input tvalid gaps")
        self.stalled = [False] * N

    def cover_races(self) -> None:
        """Classifies each commit by its edge against the nearest tuser beat after it."""
        for edge, k, result in self.commits:
            if result != "valid":
                continue
            later = [s for s in self.sofs if s >= edge - 1]
            if not later:
                continue
            d = later[0] - edge
            if d >= 2:
                cover("commit 2+ edges before the tuser beat (applies)")
            elif d == 1:
                cover("commit 1 edge before the tuser beat (applies)")
            elif d == 0:
                cover("commit on the tuser beat's edge (applies)")
            elif d == -1:
                cover("commit 1 edge after the tuser beat (waits)")
                if any(r == "valid" and e < edge and w == k for e, w, r in self.commits):
                    cover("commit 1 edge after a tuser beat that takes a pending set (waits)")
        self.commits.clear()

    def done(self, name: str) -> None:
        if self.errors:
            raise AssertionError("; ".join(self.errors))
        _ran.add(name)


async def start(dut, name: str) -> Bench:
    # A string seed (hashed by random with SHA-512), not hash(), which changes from process to process.
    bench = Bench(dut, f"{SEED}:{name}")
    await bench.reset()
    info, geometry = await bench.read(AXIS_INFO), await bench.read(AXIS_GEOMETRY)
    if (info, geometry) != (N | DEPTH << 16, W | H << 16):
        raise AssertionError(f"INFO {info:#x}, GEOMETRY {geometry:#x}: not the bench's {N} windows, "
                             f"FIFO {DEPTH}, {W}x{H}")
    await bench.write(AXIS_IRQ_ENABLE, (1 << N) - 1)
    return bench


def random_rect(rng: random.Random) -> Rect:
    x0, y0 = rng.randrange(W - 1), rng.randrange(H - 1)
    x1 = rng.choice([x0 + 1, min(W - 1, x0 + rng.randrange(1, 12)), rng.randrange(x0 + 1, W), W - 1])
    y1 = rng.choice([y0 + 1, min(H - 1, y0 + rng.randrange(1, 8)), rng.randrange(y0 + 1, H), H - 1])
    return Rect(x0, x1, y0, y1, rng.random() < 0.4, rng.random() < 0.3)


@cocotb.test()
async def test_shapes(dut):
    """Every window shape the coverage lists, three at a time, without back-pressure: the
    outputs must be the model's exactly."""
    b = await start(dut, "test_shapes")
    shapes = [Rect(0, W - 1, 0, H - 1), Rect(0, 1, 0, 1), Rect(3, 20, 5, 6), Rect(W - 2, W - 1, 2, H - 1),
              Rect(1, 9, 2, 8, True), Rect(2, 9, 4, 11, True), Rect(W - 5, W - 4, H - 3, H - 2, True),
              Rect(W - 7, W - 1, H - 6, H - 1), Rect(0, 5, 0, 3, True), Rect(10, 30, 10, 20),
              Rect(15, 40, 5, 25, True), Rect(20, 25, 12, 14, False, True)]
    for i in range(0, len(shapes), N):
        for k, r in enumerate(shapes[i:i + N]):
            await b.set_window(k, r)
            cover_shape(r)
        await b.send_frame()
        await b.check()
    for _ in range(2):              # the last set repeats without a commit
        await b.send_frame()
        await b.check()
    b.done("test_shapes")


@cocotb.test()
async def test_commit_races(dut):
    """Commits issued from 4 clocks before to 4 clocks after the frame is handed to the source:
    their handshakes land before, on and after the tuser beat's edge, and the model decides from
    the edges which frame each one applies to (a commit that waits delivers in the next frame)."""
    b = await start(dut, "test_commit_races")

    async def commit_all(wait: int) -> None:
        await ClockCycles(dut.aclk, wait)
        for k in range(N):
            await b.write(window_base(k) + AXIS_COMMIT, 1)

    for delay in range(-4, 5):
        for k in range(N):
            # Set A pending, then set B written and committed in the race: B applies to the
            # frame, or waits and A does.
            await b.set_window(k, Rect(k * (delay + 5), k * 5 + 17, k * 4, k + 7, k == 2))
            await b.set_window(k, Rect(k * 3 + delay + 4, k * 3 + 20, k, k + 10, k == 1), commit=False)
        commits = cocotb.start_soon(commit_all(max(delay, 0)))
        await ClockCycles(dut.aclk, max(-delay, 0))
        await b.send_frame()
        await commits
        await b.check()
        b.cover_races()
    await b.send_frame()
    await b.check()
    b.done("test_commit_races")


@cocotb.test()
async def test_random_windows(dut):
    """Random overlapping windows (decimated, continuous, one-shot), random tvalid and tready
    gaps, commits at random times in and between frames."""
    b = await start(dut, "test_random_windows")
    rng = b.rng
    b.pauses(0.2, 0.15)
    for _ in range(FRAMES):
        frame = cocotb.start_soon(b.send_frame())
        await ClockCycles(dut.aclk, rng.randrange(0, W * H // 2))
        for k in range(N):
            if rng.random() < 0.6:
                r = random_rect(rng)
                await b.set_window(k, r)
                cover_shape(r)
                cover("commit during a frame, for the next")
                if rng.random() < 0.3:
                    r2 = random_rect(rng)
                    await b.set_window(k, r2)
                    cover_shape(r2)
                    cover("a later commit replaces a pending one")
        await frame
        await b.check()
        b.cover_races()
    await b.send_frame()
    await b.check()
    b.done("test_random_windows")


@cocotb.test()
async def test_invalid_sets(dut):
    """Sets outside the sensor or empty are refused (STATUS invalid) and the previous set, pending
    or repeating, is kept."""
    b = await start(dut, "test_invalid_sets")
    bad = [(Rect(0, W, 0, 5), "invalid: xmax beyond the sensor"),
           (Rect(0, 5, 0, H), "invalid: ymax beyond the sensor"),
           (Rect(6, 5, 0, 5), "invalid: xmin > xmax"),
           (Rect(0, 5, 9, 8), "invalid: ymin > ymax"),
           (Rect(5, 5, 0, 5), "invalid: xmin = xmax (one column)"),
           (Rect(0, 5, 7, 7), "invalid: ymin = ymax (one row)"),
           (Rect(0, 0xFFFF, 0, 0xFFFF), "invalid: xmax beyond the sensor")]
    for i, (r, label) in enumerate(bad):
        good = Rect(i, i + 7, 1, 6, False, i % 2 == 1)
        await b.set_window(0, good)
        if good.continuous:
            await b.send_frame()        # the good set now repeats
            await b.check()
        await b.set_window(0, r)
        if await b.read(window_base(0) + AXIS_STATUS) & 8 == 0:
            b.error(f"{r} was not refused")
        cover(label)
        await b.send_frame()            # the good set still delivers
        if len(b.model.expected[0]) != good.beats():
            b.error(f"after refusing {r}, {len(b.model.expected[0])} beats are due, not {good}'s {good.beats()}")
        await b.check()
        cover("invalid keeps the repeating set" if good.continuous else "invalid keeps the pending set")
        await b.set_window(0, Rect(0, 1, 0, 1))     # a valid set clears INVALID
        if await b.read(window_base(0) + AXIS_STATUS) & 8:
            b.error("a valid set did not clear INVALID")
        await b.send_frame()
        await b.check()
    b.done("test_invalid_sets")


@cocotb.test()
async def test_overflow(dut):
    """A sink that stops: the FIFO fills, the rest is dropped and counted, and the next frame's
    window, whose first beat finds the FIFO still full, gets tuser on its first delivered beat."""
    b = await start(dut, "test_overflow")
    await b.set_window(0, Rect(0, W - 1, 0, H - 1, False, True))
    await b.set_window(1, Rect(5, 20, 3, 9))
    b.sinks[0].pause = True
    await b.send_frame()
    # Frame 2 starts with window 0's FIFO full; its sink resumes mid-frame.
    frame = cocotb.start_soon(b.send_frame())
    await ClockCycles(dut.aclk, W * 3)
    b.sinks[0].pause = False
    await frame
    await b.check()
    if b.drops_seen[0] == 0:
        b.error("no beat was dropped with the sink stopped")
    b.done("test_overflow")


@cocotb.test()
async def test_reset_in_frame(dut):
    """A reset after a frame's tuser: the rest of that frame (no tuser since reset) is ignored,
    the registers are back to power-on, and a new set delivers the next frame."""
    b = await start(dut, "test_reset_in_frame")
    await b.set_window(0, Rect(0, W - 1, 0, H - 1, False, True))
    await b.send_frame(range(0, H // 2))
    await b.reset()
    cover("reset in a frame")
    for k in range(N):
        b.delivered[k].clear()
        b.model.expected[k].clear()
        b.sinks[k].clear()
    b.drops_seen = [0] * N
    b.sink_pending = [[] for _ in range(N)]
    await b.write(AXIS_IRQ_ENABLE, (1 << N) - 1)
    b.frames_sent -= 1
    await b.send_frame(range(H // 2, H), user=False)
    await b.check()                 # nothing: no set since reset
    await b.set_window(2, Rect(2, 12, 3, 13, True))
    await b.send_frame()
    await b.check()
    if b.model.frames != [0, 0, 1]:
        b.error(f"windows completed after the reset: {b.model.frames}, expected [0, 0, 1]")
    b.done("test_reset_in_frame")


@cocotb.test()
async def test_coverage(dut):
    """Reports the functional coverage, writes coverage.xml and coverage.yml, and fails if a
    situation was not reached (only when all the stimulus tests ran)."""
    lines = []
    strip = re.compile(r" : <cocotb_coverage[^>]*>")
    coverage_db.report_coverage(lambda text: lines.append(strip.sub("", text)), bins=True)
    dut._log.info("functional coverage:\n%s", "\n".join(lines))
    os.makedirs(COVERAGE_DIR, exist_ok=True)
    coverage_db.export_to_xml(filename=os.path.join(COVERAGE_DIR, "coverage.xml"))
    coverage_db.export_to_yaml(filename=os.path.join(COVERAGE_DIR, "coverage.yml"))
    item = coverage_db["top.situation"]
    missing = [b for b, hits in item.detailed_coverage.items() if hits < item.at_least]
    dut._log.info("coverage: %d of %d situations", item.coverage, item.size)
    if missing:
        if not set(STIMULUS_TESTS) <= _ran:
            dut._log.warning("not all stimulus tests ran; not reached: %s", "; ".join(missing))
            return
        raise AssertionError(f"{len(missing)} situations not reached: " + "; ".join(missing))
