"""cocotb testbench for hdl/verilog/window_unit.v (run it with hdl/cocotb/run.py).

One clock-stepped loop drives the unit, one falling edge at a time (all logic is on the rising
edge): on each falling edge it reads the outputs of the last rising edge, then drives the
inputs of the next one.
- Camera: frames from a list of line lengths, with random fval lead, line blanking, frame tail,
  vertical blanking (with or without lval pulses), pixel_valid gaps, lines with no pixel, lines
  longer than WIDTH and frames taller than HEIGHT, lval outlasting fval. Every pixel's value is
  a hash of (frame, x, y), so a pixel from the wrong place is caught and can be named. The
  camera can hold fval low until a set completes a chosen number of edges before it rises.
- Writer: the processor's four-phase handshake with random delays, random `decimate` on all but
  the last byte, junk on coord_data while the strobe is low; it checks the handshake's timing.
- Monitor and scoreboard: each strobed pixel is matched, in order, with the reference model's
  (model.py) next expected pixel (value and latency of 1..4 clocks); coord_error is checked on
  every clock; each frame is closed with its expected and delivered counts, and the model's
  pixels are checked against a software crop of the frame the camera sent.
- Functional coverage (cocotb-coverage) of the window geometry, the camera, the sets, arming
  and resets; the last test reports it, writes coverage.xml and coverage.yml, and fails if a
  bin was not hit.
"""

from __future__ import annotations

import os
import random
import re
import time
from collections import deque
from dataclasses import dataclass

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, Timer
from cocotb_coverage.coverage import CoverCross, CoverPoint, coverage_db

from model import Window, WindowModel, crop

# The most clocks from a pixel on `pixel` (or a byte offered) to its strobe (or coord_ready).
LATENCY_MAX = 4
# Camera timing the unit needs, as the module's header and docs/window-logic.md document it
# (the CA-D1 raster of hdl/src/sim/camera.rs keeps both at 2 or more): lval low for at least 2
# clocks between lines, and fval high for at least 2 clocks before the first lval of a frame.
# The camera keeps to them; the two probes show what goes wrong with 1 (docs/cocotb.md).
MIN_HBLANK = 2
MIN_LEAD = 2
# Each test stops at the first few errors.
MAX_ERRORS = 5

FRAMES = int(os.environ.get("COOPWIN_FRAMES", "0"))   # 0: a default from the frame size
SEED = int(os.environ.get("COOPWIN_SEED", "1"))
VERBOSE = os.environ.get("COOPWIN_VERBOSE", "") not in ("", "0")
PROBES = os.environ.get("COOPWIN_PROBES", "") not in ("", "0")
COVERAGE_DIR = os.environ.get("COOPWIN_COVERAGE_DIR", ".")

STIMULUS_TESTS = ("test_random_windows", "test_invalid_sets", "test_arming",
                  "test_late_set_with_one_pending", "test_lval_outlasting_fval",
                  "test_resets", "test_full_frame")
_ran: set[str] = set()


def pixel_value(frame_id: int, x: int, y: int, bits: int) -> int:
    """The camera's pixel at (x, y) of frame frame_id: a hash, so that it names its place."""
    h = (x * 0x9E3779B1 + y * 0x85EBCA6B + frame_id * 0xC2B2AE35 + 0x165667B1) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x2C1B3C6D) & 0xFFFFFFFF
    h ^= h >> 12
    h = (h * 0x297A2D39) & 0xFFFFFFFF
    h ^= h >> 15
    return h & ((1 << bits) - 1)


# ------------------------------------------------------------------------------------------
# Functional coverage
# ------------------------------------------------------------------------------------------

SHAPES = ["not decimated", "1x1 after decimation", "1 row after decimation",
          "1 column after decimation", "rows and columns after decimation"]
STRESS = ["line longer than WIDTH", "line longer than 2^ceil(log2(max(WIDTH,HEIGHT)))",
          "frame taller than HEIGHT", "frame taller than 2^ceil(log2(max(WIDTH,HEIGHT)))",
          "pixel_valid gaps", f"{MIN_HBLANK}-clock line blanking", f"{MIN_LEAD}-clock fval lead",
          "lval pulse without pixels", "fval falls with lval", "lval pulses in vertical blanking",
          "window cut by the frame's end", "lval outlasts fval",
          "lval outlasts fval: a window pixel after fval fell"]
OUTCOMES = ["window delivered", "no set: nothing delivered", "frame after a window: nothing",
            "later set won", "aborted by reset"]
# Edges from a valid set's completion to the next edge with fval first seen high (the set
# arms that frame from 1 on), and whether another valid set was pending when it completed.
MARGINS = ["0: next frame", "1: this frame", "2-16", "more than 16"]
PENDING = ["another set pending", "no set pending"]


def margin_bin(d: int) -> str:
    return MARGINS[0] if d <= 0 else MARGINS[1] if d == 1 else MARGINS[2] if d <= 16 else MARGINS[3]

SET_CONTEXT = ["during blanking", "during a frame", "during a window", "with a set pending",
               "while coord_error high"]
# The status outputs (armed, window_done, set_accepted), seen as the model predicts them.
STATUS = ["set_accepted", "set_accepted while armed", "window_done",
          "window_done, corner not delivered (decimated)", "armed falls: window over",
          "armed falls: frame ended first", "armed held: a set pending at the window's end",
          "armed cleared by reset"]
RESETS = ["during a window", "in a frame, outside the window", "during blanking", "mid-write",
          "between last byte and check", "with a set pending", "with coord_error high",
          "held several clocks"]


def shape(w: Window) -> str:
    if not w.decimate:
        return SHAPES[0]
    rows, cols = (w.ymax - w.ymin) // 2 + 1, (w.xmax - w.xmin) // 2 + 1
    if rows == 1 and cols == 1:
        return SHAPES[1]
    if rows == 1:
        return SHAPES[2]
    if cols == 1:
        return SHAPES[3]
    return SHAPES[4]


def size_class(n: int) -> str:
    return "2" if n == 2 else ("odd" if n % 2 else "even, more than 2")


def invalid_kinds(width: int, height: int, wide: bool) -> list[str]:
    """The ways a set can be invalid, as far as the coordinate bytes can express them."""
    top = 0xFFFF if wide else 0xFF
    kinds = ["valid", "xmin == xmax", "xmin > xmax", "ymin == ymax", "ymin > ymax"]
    if top >= width:
        kinds.append("xmax >= WIDTH")
    if top >= height:
        kinds.append("ymax >= HEIGHT")
    return kinds


def set_kind_tags(w: Window, width: int, height: int) -> set[str]:
    tags = set()
    if w.xmin == w.xmax:
        tags.add("xmin == xmax")
    if w.xmin > w.xmax:
        tags.add("xmin > xmax")
    if w.ymin == w.ymax:
        tags.add("ymin == ymax")
    if w.ymin > w.ymax:
        tags.add("ymin > ymax")
    if w.xmax >= width:
        tags.add("xmax >= WIDTH")
    if w.ymax >= height:
        tags.add("ymax >= HEIGHT")
    return tags or {"valid"}


def member(tags, b):
    return b in tags


class Coverage:
    """The cover points. Built once per simulation (coverage_db is a singleton)."""

    def __init__(self, width: int, height: int, wide: bool):
        W, H = width, height
        TF = [True, False]

        @CoverPoint("top.window.touches_left", xf=lambda w: w.xmin == 0, bins=TF)
        @CoverPoint("top.window.touches_right", xf=lambda w: w.xmax == W - 1, bins=TF)
        @CoverPoint("top.window.touches_top", xf=lambda w: w.ymin == 0, bins=TF)
        @CoverPoint("top.window.touches_bottom", xf=lambda w: w.ymax == H - 1, bins=TF)
        @CoverPoint("top.window.full_frame",
                    xf=lambda w: (w.xmin, w.xmax, w.ymin, w.ymax) == (0, W - 1, 0, H - 1),
                    bins=TF)
        @CoverPoint("top.window.decimated", xf=lambda w: w.decimate, bins=TF)
        @CoverPoint("top.window.width", xf=lambda w: size_class(w.xmax - w.xmin + 1),
                    bins=["2", "odd", "even, more than 2"])
        @CoverPoint("top.window.height", xf=lambda w: size_class(w.ymax - w.ymin + 1),
                    bins=["2", "odd", "even, more than 2"])
        @CoverPoint("top.window.shape", xf=shape, bins=SHAPES)
        @CoverCross("top.window.left_x_decimated",
                    items=["top.window.touches_left", "top.window.decimated"])
        @CoverCross("top.window.right_x_decimated",
                    items=["top.window.touches_right", "top.window.decimated"])
        @CoverCross("top.window.top_x_decimated",
                    items=["top.window.touches_top", "top.window.decimated"])
        @CoverCross("top.window.bottom_x_decimated",
                    items=["top.window.touches_bottom", "top.window.decimated"])
        @CoverCross("top.window.full_frame_x_decimated",
                    items=["top.window.full_frame", "top.window.decimated"])
        @CoverCross("top.window.width_x_height",
                    items=["top.window.width", "top.window.height"])
        def window(w):
            pass

        @CoverPoint("top.frame.outcome", xf=lambda tags: tags, rel=member, bins=OUTCOMES,
                    inj=False)
        def outcome(tags):
            pass

        @CoverPoint("top.camera.stress", xf=lambda tags: tags, rel=member, bins=STRESS,
                    inj=False)
        def camera(tags):
            pass

        @CoverPoint("top.sets.kind", xf=lambda tags: tags, rel=member,
                    bins=invalid_kinds(W, H, wide), inj=False)
        @CoverPoint("top.sets.context", xf=lambda tags: tags, rel=member, bins=SET_CONTEXT,
                    inj=False)
        def coord_set(tags):
            pass

        @CoverPoint("top.sets.arming_margin", xf=lambda label, pending: label, bins=MARGINS)
        @CoverPoint("top.sets.arming_pending", xf=lambda label, pending: pending, bins=PENDING)
        @CoverCross("top.sets.arming_margin_x_pending",
                    items=["top.sets.arming_margin", "top.sets.arming_pending"])
        def margin(label, pending):
            pass

        @CoverPoint("top.reset.when", xf=lambda tags: tags, rel=member, bins=RESETS, inj=False)
        def reset(tags):
            pass

        @CoverPoint("top.status.seen", xf=lambda tag: tag, bins=STATUS)
        def status(tag):
            pass

        self.window, self.outcome, self.camera = window, outcome, camera
        self.coord_set, self.margin, self.reset = coord_set, margin, reset
        self.status = status


_coverage: Coverage | None = None


def coverage(width, height, wide) -> Coverage:
    global _coverage
    if _coverage is None:
        _coverage = Coverage(width, height, wide)
    return _coverage


# ------------------------------------------------------------------------------------------
# Camera
# ------------------------------------------------------------------------------------------

@dataclass
class Raster:
    """One frame as the camera sends it."""

    frame_id: int
    lengths: list[int]      # pixels in each line; one lval pulse each
    lead: int               # clocks of fval high and lval low before the first line
    hblank: list[int]       # clocks of lval low after each line (after the last: before fval falls)
    gap: float              # chance of a pixel_valid-low clock before each pixel
    start: int | None = None  # edge on which fval was first high
    pulsed_blanking: bool = False  # lval pulsed in the vertical blanking before it
    # Clocks that lval (with pixel_valid and the last line's next pixels) stays high after fval
    # falls; only when hblank[-1] is 0. The contract: no pixel once fval is low.
    overrun: int = 0

    def clocks(self) -> int:
        return (self.lead + int(sum(self.lengths) * (1 + 2 * self.gap)) + sum(self.hblank)
                + len(self.lengths) + self.overrun)


class Camera:
    """Queued segments (generators of (fval, lval, pixel_valid, pixel)), one tuple per edge."""

    def __init__(self, bench: "Bench"):
        self.b = bench
        self.segments: deque = deque()
        self.current = None
        self.rasters: dict[int, Raster] = {}   # by start edge
        self.frames_sent = 0
        self.in_frame = False
        self.pulsed = False       # lval has pulsed since the last frame

    def idle(self) -> bool:
        return self.current is None and not self.segments

    def queue_frame(self, raster: Raster):
        self.segments.append(self._frame(raster))

    def queue_blank(self, clocks: int, pulses: bool, until=None, align: int | None = None):
        """fval low for `clocks` edges, then until `until()` is true; then, with `align`, until
        the writer's sets are all in and the edge `align` after the last one's completion."""
        self.segments.append(self._blank(clocks, pulses, until, align))

    def step(self, n: int):
        while True:
            if self.current is None:
                if not self.segments:
                    self.in_frame = False
                    return (0, 0, self.b.noise_pv(), self.b.junk())
                self.current = self.segments.popleft()
            try:
                return next(self.current)
            except StopIteration:
                self.current = None

    def _frame(self, r: Raster):
        rng, bits, junk = self.b.rng, self.b.P, self.b.junk
        r.start = self.b.n
        r.pulsed_blanking, self.pulsed = self.pulsed, False
        self.rasters[r.start] = r
        self.in_frame = True
        self.frames_sent += 1
        for _ in range(r.lead):
            yield (1, 0, self.b.noise_pv(), junk())
        for y, length in enumerate(r.lengths):
            x = 0
            yield_any = False
            while x < length:
                if r.gap and rng.random() < r.gap:
                    yield (1, 1, 0, junk())
                else:
                    yield (1, 1, 1, pixel_value(r.frame_id, x, y, bits))
                    x += 1
                yield_any = True
            while not yield_any or (r.gap and rng.random() < r.gap):   # gaps at the line's end
                yield (1, 1, 0, junk())
                yield_any = True
            for _ in range(r.hblank[y]):
                yield (1, 0, self.b.noise_pv(), junk())
        if r.lengths and r.overrun:
            # fval falls, lval stays high and the last line's next pixels keep coming.
            y = len(r.lengths) - 1
            for k in range(r.overrun):
                yield (0, 1, 1, pixel_value(r.frame_id, r.lengths[y] + k, y, bits))
        self.in_frame = False

    def _blank(self, clocks, pulses, until, align):
        rng, junk = self.b.rng, self.b.junk
        k = 0
        lval_left = 0
        while True:
            done = k >= clocks and (until is None or until())
            if done and align is not None:
                done = self.b.writer.aligned(self.b.n, align, self.b.last_set)
            if done:
                return
            k += 1
            if pulses:
                if lval_left == 0 and rng.random() < 0.25:
                    lval_left = rng.randint(1, 12)
                if lval_left:
                    lval_left -= 1
                    self.pulsed = True
                    yield (0, 1, 1, junk())
                    continue
            yield (0, 0, self.b.noise_pv(), junk())


# ------------------------------------------------------------------------------------------
# Processor writer (four-phase handshake) with its protocol checks
# ------------------------------------------------------------------------------------------

@dataclass
class Job:
    window: Window          # coordinates as written (may be invalid)
    delay: int = 0          # clocks after it becomes the current job before the first byte
    retry: bool = True      # start again from the first byte if a reset interrupts it
    completed: int | None = None  # edge its last byte was taken (set by the bench)


class Writer:
    def __init__(self, bench: "Bench"):
        self.b = bench
        self.jobs: deque[Job] = deque()
        self.job: Job | None = None
        self.state = "idle"
        self.count = 0
        self.index = 0
        self.bytes: list[int] = []
        self.edge_mark = 0
        self.ready_prev = 0
        self.take_latency = 1     # clocks from a byte's first strobe edge to coord_ready, last seen
        self.out = (0, 0, 0)

    def idle(self) -> bool:
        return self.job is None and not self.jobs

    def queue(self, job: Job):
        self.jobs.append(job)

    def sets_done(self) -> bool:
        """Every queued set has had its last byte taken (the handshake may still be ending)."""
        return not self.jobs and (self.job is None or (self.index == len(self.bytes) - 1
                                                       and self.state in ("hold", "release")))

    def aligned(self, n: int, margin: int, last_set: int | None) -> bool:
        """Whether fval first high on edge n puts the last queued set's completion `margin`
        edges before it (n is the edge being driven). While the set's last byte is offered and
        not yet taken, its completion edge is predicted from the take latency of the byte
        before; the bench records the margin actually reached, and the model judges it."""
        if self.sets_done():
            return last_set is None or n >= last_set + margin
        if not self.jobs and self.index == len(self.bytes) - 1 and self.state == "offer":
            return n >= self.edge_mark + self.take_latency + margin
        return False

    def mid_set(self) -> bool:
        return self.job is not None and self.state != "idle" and (self.index > 0 or self.state != "wait")

    def encode(self, w: Window) -> list[int]:
        vals = [w.xmin, w.xmax, w.ymin, w.ymax]
        if self.b.wide:
            return [b for v in vals for b in ((v >> 8) & 0xFF, v & 0xFF)]
        return [v & 0xFF for v in vals]

    def on_reset(self):
        if self.job is not None and self.job.retry:
            self.jobs.appendleft(self.job)
        self.job, self.state, self.ready_prev = None, "idle", 0
        self.out = (0, self.b.rng.getrandbits(8), 0)

    def _delay(self) -> int:
        r = self.b.rng.random()
        return 0 if r < 0.5 else (self.b.rng.randint(1, 3) if r < 0.9 else self.b.rng.randint(4, 20))

    def step(self, m: int, ready: int):
        """coord_ready as registered on edge m; sets self.out for edge m + 1."""
        b, rng = self.b, self.b.rng
        rose, fell = ready and not self.ready_prev, self.ready_prev and not ready
        self.ready_prev = ready
        if rose and self.state != "offer":
            b.error(m, f"coord_ready rose with no byte offered (writer {self.state})")
        if fell and self.state in ("offer", "hold"):
            b.error(m, "coord_ready fell while coord_strobe was high")
        if self.state == "offer":
            if rose:
                if m - self.edge_mark > LATENCY_MAX:
                    b.error(m, f"byte taken {m - self.edge_mark} clocks after its strobe")
                self.take_latency = m - self.edge_mark
                if self.index == len(self.bytes) - 1:
                    b.set_completed(m, self.job)
                self.state, self.count = "hold", self._delay()
            elif m - self.edge_mark >= LATENCY_MAX:
                b.error(m, f"byte {self.index} not taken within {LATENCY_MAX} clocks")
        if self.state == "hold":
            if self.count == 0:
                self.state, self.edge_mark = "release", m + 1
            else:
                self.count -= 1
        elif self.state == "release":
            if not ready:
                self.index += 1
                if self.index == len(self.bytes):
                    self.job, self.state = None, "idle"
                else:
                    self.state, self.count = "wait", self._delay()
            elif m - self.edge_mark >= LATENCY_MAX:
                b.error(m, f"coord_ready still high {LATENCY_MAX} clocks after the strobe fell")
        if self.state == "idle" and self.jobs:
            self.job = self.jobs.popleft()
            self.bytes, self.index = self.encode(self.job.window), 0
            self.state, self.count = "wait", self.job.delay
        if self.state == "wait":
            if self.count == 0:
                self.state, self.edge_mark = "offer", m + 1
            else:
                self.count -= 1
        if self.state in ("offer", "hold"):
            last = self.index == len(self.bytes) - 1
            dec = int(self.job.window.decimate) if last else rng.getrandbits(1)
            self.out = (1, self.bytes[self.index], dec)
        else:
            # Junk on coord_data and decimate while the strobe is low (changed now and then).
            self.out = (0, rng.getrandbits(8) if rng.random() < 0.2 else self.out[1],
                        rng.getrandbits(1) if rng.random() < 0.2 else self.out[2])


# ------------------------------------------------------------------------------------------
# Scoreboard
# ------------------------------------------------------------------------------------------

class Scoreboard:
    def __init__(self, bench: "Bench"):
        self.b = bench
        self.due: deque = deque()   # (edge, frame, x, y, value), in order
        self.delivered: dict[int, int] = {}
        self.pixels = 0

    def expect(self, n, frame, x, y, value):
        self.due.append((n, frame, x, y, value))

    def strobe(self, m, value):
        if not self.due:
            self.b.error(m, f"pixel strobed ({value:#x}{self.b.whose(value, None)}) but none due")
            return
        n, f, x, y, e = self.due.popleft()
        if value != e:
            self.b.error(m, f"frame {f} pixel ({x}, {y}): got {value:#x}"
                            f"{self.b.whose(value, f, x, y)}, expected {e:#x}")
        elif not 1 <= m - n <= LATENCY_MAX:
            self.b.error(m, f"frame {f} pixel ({x}, {y}) strobed {m - n} clocks after it came")
        self.delivered[f] = self.delivered.get(f, 0) + 1
        self.pixels += 1

    def deadline(self, m):
        while self.due and self.due[0][0] + LATENCY_MAX <= m:
            n, f, x, y, e = self.due.popleft()
            self.b.error(m, f"frame {f} pixel ({x}, {y}) = {e:#x} from edge {n} never strobed")

    def reset(self, r):
        # Pixels still in the pipeline at a reset may be lost; nothing may come out after it.
        while self.due and self.due[0][0] < r:
            self.due.popleft()


# ------------------------------------------------------------------------------------------
# The bench: one clock-stepped loop
# ------------------------------------------------------------------------------------------

class Bench:
    def __init__(self, dut, name: str, seed: int):
        self.dut = dut
        self.name = name
        self.log = dut._log
        self.W, self.H, self.P = int(dut.WIDTH.value), int(dut.HEIGHT.value), int(dut.PIXEL_BITS.value)
        self.wide = max(self.W, self.H) > 256
        self.count_range = 1 << (max(self.W, self.H) - 1).bit_length()
        self.rng = random.Random(f"{seed}:{name}:{self.W}x{self.H}x{self.P}")
        self.model = WindowModel(self.W, self.H)
        self.sb = Scoreboard(self)
        self.camera = Camera(self)
        self.writer = Writer(self)
        self.cov = coverage(self.W, self.H, self.wide)
        self.errors: list[str] = []
        self.n = 0
        self.reset_left = 0
        self.reset_trigger = None   # (predicate, clocks): reset when predicate() on a drive
        self.resets = 0
        self.last_completion: int | None = None   # edge the last valid set completed
        self.last_set: int | None = None          # edge the last set (valid or not) completed
        self.error_settle = 0
        self.frames_seen = 0
        self.closing: deque = deque()   # (edge, frame) frames to close once their pixels are out
        self.unsampled_sets: list[tuple[int, bool]] = []   # valid sets: (edge, another pending)
        self.arming_seen: dict[tuple[str, str], int] = {}   # margin and pending bins sampled
        self.last_frame_had_window = False
        self.frames_closed = 0
        self.windows = 0
        self.checked_pixels = 0
        self.in_reset = False
        self.h_in = {k: getattr(dut, k) for k in ("fval", "lval", "pixel_valid", "pixel",
                                                   "coord_strobe", "coord_data", "decimate",
                                                   "reset")}
        self.cache = {k: None for k in self.h_in}
        self.h_strobe, self.h_pixel = dut.pixel_strobe, dut.pixel_out
        self.h_ready, self.h_error = dut.coord_ready, dut.coord_error
        self.h_armed, self.h_done, self.h_acc = dut.armed, dut.window_done, dut.set_accepted
        self.was_armed = 0
        self.fe = FallingEdge(dut.clock)
        self.t0 = time.time()
        self._junk = 0
        self._pv = 0

    def noise_pv(self) -> int:
        """pixel_valid while lval or fval is low: meaningless, changed now and then."""
        if self.rng.random() < 0.25:
            self._pv = 1 - self._pv
        return self._pv

    def junk(self) -> int:
        """A value for `pixel` when no pixel is on it (changed now and then: each change is a
        simulator write)."""
        if self.rng.random() < 0.25:
            self._junk = self.rng.getrandbits(self.P)
        return self._junk

    # --- errors and diagnostics ---

    def error(self, m: int, msg: str):
        text = f"edge {m}: {msg}"
        self.errors.append(text)
        self.log.error(text)
        if len(self.errors) >= MAX_ERRORS:
            raise AssertionError(f"{len(self.errors)} errors, the first: {self.errors[0]}")

    def whose(self, value, frame, x=None, y=None) -> str:
        """Which camera pixel(s) near (x, y) of that frame carry `value`. With no frame (a
        strobe with nothing due), anywhere in the latest frame, after fval's fall too."""
        if frame is None:
            if not self.model.frames:
                return ""
            frame = len(self.model.frames) - 1
        f = self.model.frames[frame]
        r = self.camera.rasters.get(f.start)
        if r is None or not r.lengths:
            return ""
        last = len(r.lengths) - 1
        sent = lambda yy: r.lengths[yy] + (r.overrun if yy == last else 0)
        if x is None:
            rows = range(len(r.lengths))
            cols = lambda yy: range(sent(yy))
        else:
            rows = range(max(0, y - 3), min(len(r.lengths), y + 4))
            cols = lambda yy: range(max(0, x - 8), min(sent(yy), x + 9))
        hits = sorted((xx < r.lengths[yy], yy, xx) for yy in rows for xx in cols(yy)
                      if pixel_value(r.frame_id, xx, yy, self.P) == value)   # after fval first
        hits = [f"({xx}, {yy})" + ("" if inside else " sent after fval fell")
                for inside, yy, xx in hits[:3]]
        where = "near it" if x is not None else f"in frame {frame}"
        return (f" = frame {frame}'s camera pixel {' or '.join(hits)}" if hits
                else f" (not a pixel {where})")

    # --- the clock loop ---

    async def start(self):
        for k, h in self.h_in.items():
            h.value = 1 if k == "reset" else 0
            self.cache[k] = 1 if k == "reset" else 0
        await Timer(1, unit="ns")
        Clock(self.dut.clock, 10, unit="ns", impl="gpi").start()
        await self.fe
        self.n = 0
        self.reset_left = 2
        self._drive(0)

    async def run(self, until=None, clocks: int | None = None, limit: int = 5_000_000):
        end = self.n + clocks if clocks is not None else None
        stop = self.n + limit
        while not ((until is not None and until()) or (end is not None and self.n >= end)):
            if self.n >= stop:
                raise AssertionError(f"{self.name}: no progress after {limit} clocks")
            await self.fe
            self._observe(self.n)
            self.n += 1
            self._drive(self.n)

    async def settle(self):
        """Let the camera and writer finish, then flush the pipeline."""
        await self.run(until=lambda: self.camera.idle() and self.writer.idle())
        await self.run(clocks=LATENCY_MAX + 2)

    def _observe(self, m: int):
        strobe = int(self.h_strobe.value)
        ready = int(self.h_ready.value)
        err = int(self.h_error.value)
        armed, done, acc = int(self.h_armed.value), int(self.h_done.value), int(self.h_acc.value)
        if self.in_reset:
            self.sb.reset(m)
            if strobe or ready or err or armed or done or acc:
                self.error(m, f"not in the power-on state after reset: pixel_strobe={strobe} "
                              f"coord_ready={ready} coord_error={err} armed={armed} "
                              f"window_done={done} set_accepted={acc}")
            if self.was_armed:
                self.cov.status(STATUS[7])
            self.was_armed = 0
            return
        self._status(m, armed, done, acc)
        if strobe:
            self.sb.strobe(m, int(self.h_pixel.value))
        self.sb.deadline(m)
        self.writer.step(m, ready)
        if m >= self.error_settle and err != int(self.model.error):
            self.error(m, f"coord_error is {err}, the model says {int(self.model.error)}")
        while self.closing and self.closing[0][0] <= m:
            self._close(self.closing.popleft()[1])

    def _status(self, m: int, armed: int, done: int, acc: int):
        """The status outputs after edge m against the model (before edge m's sets are told)."""
        md = self.model
        want = int(md.armed(m)), int(m in md.done_at), int(m in md.accepted_at)
        md.done_at.discard(m)
        md.accepted_at.discard(m)
        if (armed, done, acc) != want:
            self.error(m, f"armed, window_done, set_accepted = {armed}, {done}, {acc}; "
                          f"the model says {want[0]}, {want[1]}, {want[2]}")
        if acc:
            self.cov.status(STATUS[0])
            if self.was_armed:
                self.cov.status(STATUS[1])
        if done:
            self.cov.status(STATUS[2])
            f = md.frames[-1] if md.frames else None
            w = f.window if f is not None else None
            if w is not None and w.decimate and not w.contains(w.xmax, w.ymax):
                self.cov.status(STATUS[3])
        if md.live_until == m - 1:
            # The window closed on the last edge: armed falls now, or a pending set holds it.
            over = md.frame is not None and md.frame.end is None
            if armed:
                self.cov.status(STATUS[6])
            else:
                self.cov.status(STATUS[4] if over else STATUS[5])
        self.was_armed = armed

    def _drive(self, n: int):
        if self.reset_left == 0 and self.reset_trigger is not None:
            pred, clocks = self.reset_trigger
            if pred():
                self.reset_trigger = None
                self._sample_reset(clocks)
                self.reset_left = clocks
        reset = self.reset_left > 0
        if reset:
            self.reset_left -= 1
            self.writer.on_reset()
            self.error_settle = n
            self.unsampled_sets = []      # lost with the reset: they arm nothing
            if not self.in_reset:
                self.resets += 1
        self.in_reset = reset
        fval, lval, pv, px = self.camera.step(n)
        strobe, data, dec = self.writer.out
        out = self.model.edge(n, reset, fval, lval, pv, px)
        if len(self.model.frames) > self.frames_seen:
            self._frame_started(self.model.frames[-1])
        if reset and self.model.frames and self.model.frames[-1].end == n \
                and self.model.frames[-1].aborted:
            self.closing.append((n + LATENCY_MAX + 1, self.model.frames[-1]))
        elif self.model.frame is None and self.model.frames and self.model.frames[-1].end == n:
            self.closing.append((n + LATENCY_MAX + 1, self.model.frames[-1]))
        if out is not None:
            x, y, v = out
            self.sb.expect(n, self.model.frame.index, x, y, v)
        values = {"fval": fval, "lval": lval, "pixel_valid": int(pv), "pixel": px,
                  "coord_strobe": strobe, "coord_data": data, "decimate": dec,
                  "reset": int(reset)}
        cache, h_in = self.cache, self.h_in
        for k, v in values.items():
            if cache[k] != v:
                h_in[k].value = v
                cache[k] = v

    # --- events from the writer and the model ---

    def set_completed(self, m: int, job: Job):
        w = job.window
        tags = set()
        f = self.model.frame
        if f is None:
            tags.add("during blanking")
        else:
            tags.add("during a frame")
            if f.window is not None and f.window.ymin <= self.model.row <= f.window.ymax:
                tags.add("during a window")
        # Another valid set pending, as the unit sees it on edge m: one not yet armed, or the
        # one that arms the frame whose fval is first seen high on this very edge m (the model
        # has already given it to that frame; the unit copies it on the next clock).
        just_armed = f is not None and f.start == m and f.window is not None
        pending = bool(self.model.pending) or just_armed
        if pending:
            tags.add("with a set pending")
        if self.model.error:
            tags.add("while coord_error high")
        valid = self.model.set_completed(m, w)
        self.last_set = m
        job.completed = m
        self.cov.coord_set(set_kind_tags(w, self.W, self.H) | tags)
        self.error_settle = m + LATENCY_MAX
        if valid:
            self.last_completion = m
            if f is not None and f.start == m:
                self._sample_margin(0, pending)   # completed as that frame's fval was seen
            else:
                self.unsampled_sets.append((m, pending))
        if VERBOSE:
            self.log.info("edge %d: set %s completed (%s)", m, w, "valid" if valid else "refused")

    def _sample_margin(self, d: int, pending: bool):
        key = (margin_bin(d), PENDING[0] if pending else PENDING[1])
        self.cov.margin(*key)
        self.arming_seen[key] = self.arming_seen.get(key, 0) + 1

    def _frame_started(self, f):
        self.frames_seen = len(self.model.frames)
        for t, pending in self.unsampled_sets:
            self._sample_margin(f.start - t, pending)
        self.unsampled_sets = []
        if f.window is not None:
            self.windows += 1

    def _close(self, f):
        got = self.sb.delivered.get(f.index, 0)
        want = len(f.pixels)
        r = self.camera.rasters.get(f.start)
        tags = set()
        if f.aborted:
            tags.add("aborted by reset")
        elif f.window is None:
            tags.add("frame after a window: nothing" if self.last_frame_had_window
                     else "no set: nothing delivered")
        else:
            tags.add("window delivered")
            if f.superseded:
                tags.add("later set won")
        self.last_frame_had_window = f.window is not None and not f.aborted
        self.cov.outcome(tags)
        if f.window is not None and not f.aborted:
            self.cov.window(f.window)
        if r is not None and not f.aborted:
            if got != want:
                self.error(self.n, f"frame {f.index} ({f.window}): {got} pixels delivered, "
                                   f"{want} expected")
            # A second opinion on the model: the software crop of the frame the camera sent.
            if f.window is not None:
                ref = crop(f.window, r.lengths, lambda x, y: pixel_value(r.frame_id, x, y, self.P))
                if [p[1:] for p in f.pixels] != ref:
                    self.error(self.n, f"frame {f.index}: the model and the crop disagree")
            self.checked_pixels += want
            st = set()
            longest = max(r.lengths) if r.lengths else 0
            if longest > self.W:
                st.add(STRESS[0])
            if longest > self.count_range:
                st.add(STRESS[1])
            if len(r.lengths) > self.H:
                st.add(STRESS[2])
            if len(r.lengths) > self.count_range:
                st.add(STRESS[3])
            if r.gap:
                st.add(STRESS[4])
            if MIN_HBLANK in r.hblank[:-1]:
                st.add(STRESS[5])
            if r.lead == MIN_LEAD:
                st.add(STRESS[6])
            if 0 in r.lengths:
                st.add(STRESS[7])
            if r.hblank[-1] == 0 and not r.overrun:
                st.add(STRESS[8])
            if r.pulsed_blanking:
                st.add(STRESS[9])
            if f.window is not None and (f.window.ymax >= len(r.lengths)
                                         or any(n <= f.window.xmax for n in r.lengths)):
                st.add(STRESS[10])
            if r.overrun and r.lengths:
                st.add(STRESS[11])
                # The first pixel sent after fval fell lies in the window (decimation included):
                # a unit that took lval & pixel_valid without fval would deliver it.
                last = len(r.lengths) - 1
                if f.window is not None and f.window.contains(r.lengths[last], last):
                    st.add(STRESS[12])
            self.cov.camera(st)
        self.frames_closed += 1
        if VERBOSE or (got != want):
            self.log.info("frame %d%s [%s]: %d of %d pixels", f.index,
                          " (aborted by reset)" if f.aborted else "", f.window or "no window",
                          got, want)

    def _sample_reset(self, clocks: int):
        tags = set()
        f = self.model.frame
        if f is None:
            tags.add("during blanking")
        elif f.window is not None and f.window.ymin <= self.model.row <= f.window.ymax:
            tags.add("during a window")
        else:
            tags.add("in a frame, outside the window")
        if self.writer.mid_set():
            tags.add("mid-write")
        if self.last_completion is not None and self.n == self.last_completion + 1:
            tags.add("between last byte and check")
        if self.model.pending:
            tags.add("with a set pending")
        if self.model.error:
            tags.add("with coord_error high")
        if clocks > 1:
            tags.add("held several clocks")
        self.cov.reset(tags)
        if VERBOSE:
            self.log.info("edge %d: reset for %d clocks (%s)", self.n, clocks, ", ".join(sorted(tags)))

    def finish(self):
        if self.sb.due:
            n, f, x, y, e = self.sb.due[0]
            self.error(self.n, f"{len(self.sb.due)} pixels never strobed, the first frame {f} ({x}, {y})")
        dt = time.time() - self.t0
        self.log.info("%s: %d clocks, %d frames (%d with a window), %d pixels strobed and "
                      "matched, %d resets, %.1f s (%.0f clocks/s)", self.name, self.n,
                      self.frames_closed, self.windows, self.sb.pixels, self.resets - 1, dt,
                      self.n / max(dt, 1e-9))
        if self.errors:
            raise AssertionError(f"{len(self.errors)} errors, the first: {self.errors[0]}")


# ------------------------------------------------------------------------------------------
# Stimulus plans
# ------------------------------------------------------------------------------------------

# Window kinds the random test goes through first (so every seed reaches coverage), then draws.
FORCED_KINDS = ["left", "right", "top", "bottom", "tiny", "dec_one_row", "dec_one_col",
                "dec_1x1", "dec_odd", "full_width", "full_height", "long_lines", "tall",
                "cut", "corner_tl", "corner_tr", "corner_bl", "random"]
DRAWN_KINDS = (["random"] * 6 + ["tiny"] * 2 + ["left", "right", "top", "bottom", "dec_one_row",
               "dec_odd", "long_lines", "tall", "cut", "cut", "full_width", "full_height",
               "corner_tl", "corner_tr", "corner_bl"])
FRAME_BUDGET = 6000     # typical clocks per frame, for window placement


def plan_window(b: Bench, kind: str) -> Window:
    rng, W, H = b.rng, b.W, b.H
    dec = rng.random() < 0.5

    def wsize():
        return rng.choice([2, 3, rng.randint(2, 12), rng.randint(2, min(W, 48))])

    def hsize():
        return rng.choice([2, 3, rng.randint(2, 8), rng.randint(2, min(H, 20))])

    def rows_for(xmax):   # lines affordable with lines of xmax + 1 pixels
        return max(2, FRAME_BUDGET // (xmax + 8))

    if kind == "full":
        return Window(0, W - 1, 0, H - 1, dec)
    if kind == "full_width":
        h = rng.randint(2, 5)
        y0 = rng.randint(0, min(H - h, 3))
        return Window(0, W - 1, y0, y0 + h - 1, dec)
    if kind == "full_height":
        w = rng.randint(2, 5)
        x0 = rng.randint(0, 4)
        return Window(x0, x0 + w - 1, 0, H - 1, dec)
    if kind in ("tiny", "dec_one_row", "dec_one_col", "dec_1x1", "dec_odd", "random", "left",
                "right", "top", "bottom", "corner_tl", "corner_tr", "corner_bl", "cut"):
        w, h = wsize(), hsize()
        if kind == "tiny":
            w, h = rng.choice([(2, 2), (2, hsize()), (wsize(), 2)])
        if kind in ("dec_one_row", "dec_one_col", "dec_1x1", "dec_odd"):
            dec = True
            if kind == "dec_one_row":
                h = 2
            elif kind == "dec_one_col":
                w = 2
            elif kind == "dec_1x1":
                w, h = 2, 2
            else:
                w, h = w | 1, h | 1
                w, h = (w if w >= 3 else 3), (h if h >= 3 else 3)
        left = kind in ("left", "corner_tl", "corner_bl") or (kind == "tiny" and rng.random() < 0.3)
        right = kind in ("right", "corner_tr") or (kind == "tiny" and rng.random() < 0.3 and not left)
        top = kind in ("top", "corner_tl", "corner_tr") or (kind == "tiny" and rng.random() < 0.3)
        bottom = kind in ("bottom", "corner_bl") or (kind == "tiny" and not top and rng.random() < 0.2)
        if right and bottom:
            bottom = False      # the far corner costs a whole frame: test_full_frame has it
        if bottom:
            w = min(w, 6)
        if right:
            h = min(h, 6)
        x0 = (0 if left else W - w if right else rng.randint(0, min(W - w, 10)) if bottom
              else rng.randint(0, W - w))
        xmax = x0 + w - 1
        if top:
            y0 = 0
        elif bottom:
            y0 = H - h
        else:
            y0 = rng.randint(0, max(0, min(H - h, rows_for(xmax) - h)))
        return Window(x0, xmax, y0, y0 + h - 1, dec)
    if kind == "long_lines":
        # Lines past the counters' range: the window at the left (a wrapped X count would
        # deliver it again) or at the right edge.
        w, h = wsize(), rng.randint(2, 4)
        x0 = 0 if rng.random() < 0.5 else W - w
        return Window(x0, x0 + w - 1, 0, h - 1, dec)
    if kind == "tall":
        # Frames past the counters' range: the window at the top (a wrapped Y count would
        # deliver it again) or at the bottom.
        w, h = rng.randint(2, 4), hsize()
        y0 = 0 if rng.random() < 0.5 else H - h
        return Window(0, w - 1, y0, y0 + h - 1, dec)
    raise ValueError(kind)


def plan_raster(b: Bench, w: Window | None, kind: str) -> Raster:
    rng = b.rng
    xneed = w.xmax + 1 if w else rng.randint(4, 40)
    yneed = w.ymax + 1 if w else rng.randint(2, 12)
    extra = lambda: rng.choice([0, 0, 1, 2, rng.randint(0, 12)])
    cols, lines = xneed + extra(), yneed + extra()
    cut_both = False
    if kind == "long_lines":
        cols = b.count_range + rng.randint(1, 40)
        lines = yneed + rng.randint(0, 2)
    elif kind == "tall":
        lines = b.count_range + rng.randint(1, 20)
    elif kind == "cut":
        r = rng.random()
        if r < 0.25:
            cols = rng.randint(w.xmin, w.xmax)      # lines end inside the window
        elif r < 0.5:
            lines = rng.randint(w.ymin + 1, w.ymax + 1) if w.ymax > w.ymin else lines
            lines = min(lines, w.ymax)              # the frame ends inside the window
        else:
            # Both, on the window's grid: if lval outlasts fval, the first pixel sent after
            # fval falls is one the window would take.
            step = 2 if w.decimate else 1
            cols = w.xmin + step * rng.randint(0, (w.xmax - w.xmin) // step)
            lines = w.ymin + step * rng.randint(0, (w.ymax - w.ymin) // step) + 1
            cut_both = True
    elif kind != "full" and rng.random() < 0.05 and lines * (b.W + 30) < 3 * FRAME_BUDGET:
        cols = b.W + rng.randint(1, 30)
    elif kind != "full" and rng.random() < 0.05 and (b.H + 20) * (cols + 8) < 3 * FRAME_BUDGET:
        lines = b.H + rng.randint(1, 20)
    lengths = [cols] * lines
    if kind != "full" and rng.random() < 0.15:
        lengths = [max(0, cols + rng.randint(-3, 3)) if rng.random() < 0.5 else cols for _ in lengths]
        if rng.random() < 0.5:
            lengths[rng.randrange(len(lengths))] = 0
    gap = 0.0 if kind == "full" else rng.choice([0.0, 0.0, 0.05, 0.2, 0.5])

    def hb():
        r = rng.random()
        return MIN_HBLANK if r < 0.3 else rng.randint(MIN_HBLANK, 6) if r < 0.85 else rng.randint(7, 40)

    hblank = [hb() for _ in lengths]
    r = rng.random()
    hblank[-1] = 0 if r < 0.25 else rng.randint(1, 4) if r < 0.8 else rng.randint(5, 20)
    # lval outlasting fval: now and then, and mostly when the frame ends inside the window.
    overrun = 0
    if cut_both and rng.random() < 0.85:
        hblank[-1] = 0
    if hblank[-1] == 0 and rng.random() < (0.85 if cut_both else 0.3):
        overrun = rng.randint(1, 8)
    r = rng.random()
    lead = MIN_LEAD if r < 0.3 else rng.randint(MIN_LEAD, 8) if r < 0.85 else rng.randint(9, 40)
    raster = Raster(b.camera.frames_sent + 1000 * b.resets + 7919 * len(b.model.frames),
                    lengths, lead, hblank, gap, overrun=overrun)
    return raster


def invalid_window(b: Bench, kind: str | None = None) -> Window:
    """An invalid set of the given kind (or a random one the bytes can express)."""
    rng, W, H = b.rng, b.W, b.H
    top = 0xFFFF if b.wide else 0xFF
    kinds = invalid_kinds(W, H, b.wide)[1:]
    kind = kind or rng.choice(kinds)
    x0, y0 = rng.randint(0, W - 2), rng.randint(0, H - 2)
    x1, y1 = rng.randint(x0 + 1, W - 1), rng.randint(y0 + 1, H - 1)
    if kind == "xmin == xmax":
        x1 = x0
    elif kind == "xmin > xmax":
        x0, x1 = x1, x0
    elif kind == "ymin == ymax":
        y1 = y0
    elif kind == "ymin > ymax":
        y0, y1 = y1, y0
    elif kind == "xmax >= WIDTH":
        x1 = rng.choice([W, min(top, W + rng.randint(1, 300)), top])
    elif kind == "ymax >= HEIGHT":
        y1 = rng.choice([H, min(top, H + rng.randint(1, 300)), top])
    return Window(x0, x1, y0, y1, rng.random() < 0.5)


def vblank(b: Bench, until=None, align=None):
    r = b.rng.random()
    clocks = 1 if r < 0.15 else b.rng.randint(1, 8) if r < 0.6 else b.rng.randint(9, 60)
    b.camera.queue_blank(clocks, b.rng.random() < 0.5, until, align)


async def frame_with_writes(b: Bench, raster: Raster, jobs: list[Job], phase: str,
                            margin: int | None = None, reset: str | None = None):
    """Blanking, then one frame. `jobs` are written during this frame ('frame') to arm the
    next one, or during the blanking before it ('blank'), or so that the last completes
    `margin` edges before fval rises ('align'; 0: on the edge fval is first seen high).
    Returns, for 'align', the margin reached: the frame's first fval edge minus the edge the
    last set completed (None if it did not complete)."""
    if phase in ("blank", "align"):
        for j in jobs:
            b.writer.queue(j)
    if phase == "align":
        b.camera.queue_blank(1, b.rng.random() < 0.5, None, margin)
    else:
        vblank(b, until=b.writer.idle)
    b.camera.queue_frame(raster)
    await b.run(until=lambda: b.camera.in_frame)
    if phase == "frame":
        for j in jobs:
            b.writer.queue(j)
    if reset is not None:
        arm_reset(b, reset)
    await b.run(until=lambda: not b.camera.in_frame and b.camera.current is None)
    if phase == "align" and jobs and jobs[-1].completed is not None:
        return raster.start - jobs[-1].completed
    return None


def arm_reset(b: Bench, when: str):
    """Schedule one reset (1 to 5 clocks): 'window' once a window has delivered a few pixels,
    'frame' on a line outside the window, 'write' while a byte is offered, 'check' on the edge
    after a set's last byte, or else during vertical blanking."""
    rng = b.rng
    clocks = 1 if rng.random() < 0.6 else rng.randint(2, 5)
    if when == "window":
        target = rng.randint(1, 6)
        pred = lambda: (b.model.frame is not None and b.model.frame.window is not None
                        and len(b.model.frame.pixels) >= target)
    elif when == "write":
        byte = rng.randrange(4 * (2 if b.wide else 1))
        pred = lambda: b.writer.job is not None and b.writer.index >= byte and b.writer.state == "offer"
    elif when == "frame":
        pred = lambda: (b.model.frame is not None and b.model.row >= 0 and rng.random() < 0.02
                        and (b.model.frame.window is None
                             or not b.model.frame.window.ymin <= b.model.row <= b.model.frame.window.ymax))
    elif when == "check":
        pred = lambda: b.last_completion is not None and b.n == b.last_completion + 1
    else:
        pred = lambda: b.model.frame is None and rng.random() < 0.2
    b.reset_trigger = (pred, clocks)


# ------------------------------------------------------------------------------------------
# Tests
# ------------------------------------------------------------------------------------------

async def make_bench(dut, name) -> Bench:
    b = Bench(dut, name, SEED)
    await b.start()
    await b.run(clocks=3)
    _ran.add(name)
    return b


def default_frames(b: Bench) -> int:
    if FRAMES:
        return FRAMES
    return 200 if b.W * b.H <= 256 * 256 else 80


# Arming cases the random test goes through after the forced window kinds, so that every seed
# reaches them: the margin the last set is aligned to, and whether another valid set is
# pending when it completes (then the frame gets two sets, a random one then the planned one).
FORCED_ARMING = [(0, False), (0, True), (1, False), (1, True), (2, False), (2, True),
                 (9, True), (30, False), (30, True)]


def armed_by(b: Bench, jobs: list[Job], phase: str, margin: int | None) -> Window | None:
    """The window the contract gives the next frame, to plan its raster: the latest valid set
    completed in time for it, or else the one pending."""
    pending = [w for _, w in b.model.pending]
    if phase == "frame":
        return pending[-1] if pending else None
    valid = [j.window for j in jobs if j.window.valid(b.W, b.H)]
    if phase == "align" and margin == 0 and jobs and jobs[-1].window.valid(b.W, b.H):
        valid = valid[:-1]          # completed as fval rises: it waits for the frame after
    ready = pending + valid
    return ready[-1] if ready else None


@cocotb.test()
async def test_random_windows(dut):
    """Constrained-random windows over many frames, with random blanking, pixel_valid gaps,
    long lines and tall frames, lval outlasting fval, sets written during frames and blanking,
    invalid sets, later sets winning, arming margins 0 to 40 with and without a set pending,
    and the odd reset."""
    b = await make_bench(dut, "test_random_windows")
    rng = b.rng
    kinds = list(FORCED_KINDS)
    arming = list(FORCED_ARMING)
    kind_of: dict[Window, str] = {}
    for _ in range(default_frames(b)):
        forced_kind = bool(kinds)   # then w must arm this frame, so that its raster is sent
        kind = kinds.pop(0) if kinds else rng.choice(DRAWN_KINDS)
        w = plan_window(b, kind)
        kind_of[w] = kind
        forced = None
        if (arming and not kinds       # after the forced kinds, which must arm their frames
                and not (arming[0][1] is False and (b.model.pending or not b.writer.idle()))):
            forced = arming.pop(0)
        r = rng.random()
        if forced is not None:
            jobs = [Job(plan_window(b, "random")), Job(w)] if forced[1] else [Job(w)]
        elif forced_kind:
            jobs = rng.choice([[Job(w)], [Job(plan_window(b, "random")), Job(w)],
                               [Job(invalid_window(b)), Job(w)]])
        elif r < 0.08:
            jobs = []                                         # no set: nothing delivered
        elif r < 0.16:
            jobs = [Job(invalid_window(b))]                   # refused
        elif r < 0.26:
            jobs = [Job(plan_window(b, "random")), Job(w)]    # the later set wins
        elif r < 0.34:
            jobs = [Job(w), Job(invalid_window(b))]           # refused, w still pending
        elif r < 0.40:
            jobs = [Job(invalid_window(b)), Job(w)]           # w clears coord_error
        else:
            jobs = [Job(w)]
        for j in jobs:
            j.delay = b.writer._delay()
        # 'frame': written during the frame now sent (which carries what is pending), for the
        # next; 'blank': written in the blanking before this frame; 'align': the last set
        # completes `margin` edges before this frame's fval is first seen (0: on that edge, so
        # it waits for the next frame and a set already pending keeps this one).
        if forced is not None:
            phase, margin = "align", forced[0]
        elif forced_kind:
            phase = rng.choice(["blank", "align"])
            margin = rng.choice([1, 2, rng.randint(3, 40)]) if phase == "align" else None
        else:
            phase = rng.choice(["frame", "frame", "blank", "align"])
            margin = None
            if phase == "align":
                margin = rng.choice([0, 0, 1, 1, 2, 3, rng.randint(3, 16), rng.randint(17, 40)])
                if margin <= 1 and len(jobs) == 1 and rng.random() < 0.4:
                    jobs.insert(0, Job(plan_window(b, "random"), b.writer._delay()))
        target = armed_by(b, jobs, phase, margin)
        if target is None and rng.random() < 0.7:
            # Nothing to deliver: a frame large enough for the last window armed, so that a
            # unit delivering a stale or used-up set again shows it.
            used = [f.window for f in reversed(b.model.frames) if f.window is not None]
            raster = plan_raster(b, used[0] if used else None, "random")
        else:
            raster = plan_raster(b, target, kind_of.get(target, "random"))
        if phase == "frame" and jobs:
            jobs[0].delay = rng.randint(0, raster.clocks())   # anywhere in the frame
        reset = rng.choice(["window", "frame", "write", "blank"]) if rng.random() < 0.06 else None
        if forced is not None or forced_kind:
            reset = b.reset_trigger = None
        await frame_with_writes(b, raster, jobs, phase, margin, reset)
        if b.reset_trigger is not None and rng.random() < 0.5:
            b.reset_trigger = None
    await b.settle()
    b.log.info("arming margins reached (margin, another set pending): %s",
               ", ".join(f"{m} / {p}: {n}" for (m, p), n in sorted(b.arming_seen.items())))
    missing = [(m, p) for m in MARGINS for p in PENDING if (m, p) not in b.arming_seen]
    if missing and default_frames(b) >= 40:
        b.error(b.n, f"arming cases not reached by the random test: {missing}")
    b.finish()


@cocotb.test()
async def test_full_frame(dut):
    """The whole frame as the window, decimated and not, on a WIDTH x HEIGHT raster."""
    b = await make_bench(dut, "test_full_frame")
    for dec in (False, True):
        w = Window(0, b.W - 1, 0, b.H - 1, dec)
        await frame_with_writes(b, plan_raster(b, w, "full"), [Job(w)], "blank")
    await frame_with_writes(b, plan_raster(b, None, "random"), [], "blank")
    await b.settle()
    b.finish()


@cocotb.test()
async def test_invalid_sets(dut):
    """Each kind of invalid set: coord_error rises and holds, the pending set is untouched, a
    set refused during a window does not disturb it, a valid set clears the error."""
    b = await make_bench(dut, "test_invalid_sets")
    rng = b.rng
    for kind in invalid_kinds(b.W, b.H, b.wide)[1:]:
        good = plan_window(b, "random")
        # valid then invalid before the frame: the valid one is delivered, error stays high
        await frame_with_writes(b, plan_raster(b, good, "random"),
                                [Job(good, 3), Job(invalid_window(b, kind), rng.randint(0, 5))], "blank")
        # refused during a window, with nothing pending: the next frame delivers nothing
        nxt = plan_window(b, "random")
        await frame_with_writes(b, plan_raster(b, nxt, "random"),
                                [Job(invalid_window(b, kind), rng.randint(0, 40))], "frame")
        await frame_with_writes(b, plan_raster(b, nxt, "random"), [Job(nxt)], "frame")
        # invalid twice, then valid: error cleared, the valid set delivered
        await frame_with_writes(b, plan_raster(b, nxt, "random"),
                                [Job(invalid_window(b)), Job(invalid_window(b, kind)), Job(nxt)],
                                "blank")
    await b.settle()
    b.finish()


def expect_window(b: Bench, frame: int, window: Window | None, what: str):
    """The contract, stated by the test itself: frame `frame` of this bench's model arms
    `window`. (The scoreboard checks the unit against the model on every pixel.)"""
    got = b.model.frames[frame].window
    if got != window:
        b.error(b.n, f"{what}: frame {frame} arms {got or 'nothing'}, the contract says "
                     f"{window or 'nothing'}")


def expect_margin(b: Bench, reached: int | None, margin: int, what: str):
    if reached != margin:
        b.error(b.n, f"{what}: the set completed {reached} edges before fval, not {margin}")


@cocotb.test()
async def test_arming(dut):
    """The arming rule, at margins 0, 1, 2, 3 and 20 edges between a set's completion and the
    edge fval is first seen high, with and without another set pending: from 1 on the set arms
    that frame; at 0 it waits for the next, and a set already pending keeps this frame. Two
    sets before a frame: the later wins. A set written during a window arms the next frame
    only, and only once."""
    b = await make_bench(dut, "test_arming")
    rng = b.rng
    for pending in (False, True, False, True):
        for margin in (0, 1, 2, 3, 20):
            a, w = plan_window(b, "random"), plan_window(b, "random")
            jobs = [Job(a), Job(w, rng.randint(0, 5))] if pending else [Job(w, rng.randint(0, 5))]
            first = len(b.model.frames)
            reached = await frame_with_writes(b, plan_raster(b, a if pending else w, "random"),
                                              jobs, "align", margin)
            expect_margin(b, reached, margin, f"margin {margin}")
            # the frame after: with margin 0 the late set comes now, else nothing is left
            await frame_with_writes(b, plan_raster(b, w, "random"), [], "blank")
            this = w if margin >= 1 else (a if pending else None)
            expect_window(b, first, this, f"margin {margin}, pending {pending}, this frame")
            expect_window(b, first + 1, w if margin == 0 else None,
                          f"margin {margin}, pending {pending}, next frame")
    a, c = plan_window(b, "random"), plan_window(b, "tiny")
    await frame_with_writes(b, plan_raster(b, c, "random"), [Job(a), Job(c)], "blank")
    await frame_with_writes(b, plan_raster(b, c, "random"), [Job(a), Job(c)], "align", 1)
    w = plan_window(b, "random")
    await frame_with_writes(b, plan_raster(b, w, "random"), [Job(w, 200)], "frame")
    await frame_with_writes(b, plan_raster(b, w, "random"), [], "blank")   # w delivered here
    await frame_with_writes(b, plan_raster(b, w, "random"), [], "blank")   # and not again
    expect_window(b, len(b.model.frames) - 2, w, "set written during a frame")
    expect_window(b, len(b.model.frames) - 1, None, "one window per set")
    await b.settle()
    b.finish()


@cocotb.test()
async def test_late_set_with_one_pending(dut):
    """Set A is pending; set B completes 0 edges, then 1 edge, before fval is first seen high.
    At 0, A keeps this frame and B arms the next. At 1, B is the later set and wins this frame,
    and A is never delivered. (Under the earlier 2-edge rule, B at 1 edge should have waited
    and A kept the frame; the RTL of that time gave B the frame: docs/cocotb.md.)"""
    b = await make_bench(dut, "test_late_set_with_one_pending")
    big = Window(0, 40, 0, 12)
    for margin in (0, 1, 0, 1):
        a, c = Window(2, 9, 1, 4), Window(20, 27, 5, 8, True)
        b.writer.queue(Job(a))
        await b.run(until=b.writer.idle)
        first = len(b.model.frames)
        reached = await frame_with_writes(b, plan_raster(b, big, "random"), [Job(c)], "align",
                                          margin)
        expect_margin(b, reached, margin, "set B")
        await frame_with_writes(b, plan_raster(b, big, "random"), [], "blank")
        expect_window(b, first, a if margin == 0 else c, f"B at margin {margin}, this frame")
        expect_window(b, first + 1, c if margin == 0 else None, f"B at margin {margin}, next frame")
    await b.settle()
    b.finish()


@cocotb.test()
async def test_lval_outlasting_fval(dut):
    """fval falls while lval is still high and pixels keep coming, in the window's rows and
    columns, decimated and not: no pixel is present once fval is low, so none of them is
    delivered. (An earlier RTL tested lval & pixel_valid only and delivered the first.)"""
    b = await make_bench(dut, "test_lval_outlasting_fval")
    for i, w in enumerate([Window(0, 30, 0, 20), Window(4, 30, 0, 20, True), Window(0, 9, 0, 2),
                           Window(5, 15, 1, 2), Window(11, 12, 2, 3)]):
        b.writer.queue(Job(w))
        await b.run(until=b.writer.idle)
        # three lines of 10 pixels, the last one running on for 6 clocks after fval falls
        r = Raster(77 + i, [10, 10, 10], 4, [3, 3, 0], b.rng.choice([0.0, 0.2]), overrun=6)
        await frame_with_writes(b, r, [], "blank")
        await b.settle()
        expect_window(b, len(b.model.frames) - 1, w, "lval past fval")
        if any(x >= 10 for _, x, _, _ in b.model.frames[-1].pixels):
            b.error(b.n, "the model expects a pixel sent after fval fell")
    b.finish()


@cocotb.test()
async def test_resets(dut):
    """Resets mid-window, mid-write (each byte), between the last byte and its check, during
    blanking, with a set pending and with coord_error high; the unit recovers each time."""
    b = await make_bench(dut, "test_resets")
    rng = b.rng
    nbytes = 8 if b.wide else 4
    # mid-window or elsewhere in the frame, then a normal frame
    for when in ("window", "window", "frame", "window", "frame"):
        w = plan_window(b, "random")
        await frame_with_writes(b, plan_raster(b, w, "random"), [Job(w)], "blank", reset=when)
        w2 = plan_window(b, "random")
        await frame_with_writes(b, plan_raster(b, w2, "random"), [Job(w2)], "blank")
    # mid-write at each byte (the writer starts the set again after the reset)
    for byte in range(nbytes):
        w = plan_window(b, "random")
        state = rng.choice(["offer", "hold", "release"])
        b.reset_trigger = ((lambda byte=byte, state=state: b.writer.job is not None
                            and b.writer.index == byte and b.writer.state == state),
                           rng.choice([1, 1, 3]))
        await frame_with_writes(b, plan_raster(b, w, "random"), [Job(w)], "blank")
    # between the last byte and its check: the set is lost
    w = plan_window(b, "random")
    arm_reset(b, "check")
    await frame_with_writes(b, plan_raster(b, w, "random"), [Job(w, retry=False)], "blank")
    # with a set pending (dropped) and with coord_error high (cleared), in blanking
    for _ in range(3):
        w = plan_window(b, "random")
        b.writer.queue(Job(w))
        b.writer.queue(Job(invalid_window(b)))
        await b.run(until=b.writer.idle)
        b.reset_trigger = ((lambda: True), rng.randint(1, 4))
        await frame_with_writes(b, plan_raster(b, w, "random"), [], "blank")
        await frame_with_writes(b, plan_raster(b, w, "random"), [Job(w)], "blank")
    # a reset during a window while the next set is being written
    w, w2 = plan_window(b, "random"), plan_window(b, "random")
    await frame_with_writes(b, plan_raster(b, w, "random"), [Job(w)], "blank")
    b.writer.queue(Job(w2, 30))
    arm_reset(b, "window")
    b.camera.queue_frame(plan_raster(b, w, "random"))
    await b.settle()
    await frame_with_writes(b, plan_raster(b, w2, "random"), [Job(w2)], "blank")
    await b.settle()
    b.finish()


@cocotb.test()
async def test_coverage(dut):
    """Reports the functional coverage, writes coverage.xml and coverage.yml, and fails if a
    goal was not reached (only when all the stimulus tests ran)."""
    if _coverage is None:
        raise AssertionError("no stimulus test ran")
    lines = []
    strip = re.compile(r" : <cocotb_coverage[^>]*>")
    coverage_db.report_coverage(lambda text: lines.append(strip.sub("", text)), bins=True)
    dut._log.info("functional coverage:\n%s", "\n".join(lines))
    os.makedirs(COVERAGE_DIR, exist_ok=True)
    xml = os.path.join(COVERAGE_DIR, "coverage.xml")
    yml = os.path.join(COVERAGE_DIR, "coverage.yml")
    coverage_db.export_to_xml(filename=xml)
    coverage_db.export_to_yaml(filename=yml)
    dut._log.info("coverage written to %s and %s", xml, yml)
    missing = []
    for name in sorted(coverage_db):
        item = coverage_db[name]
        if hasattr(item, "detailed_coverage") and type(item).__name__ != "CoverItem":
            for bin_, hits in item.detailed_coverage.items():
                if hits < item.at_least:
                    missing.append(f"{name}: {bin_}")
    top = coverage_db["top"]
    dut._log.info("coverage: %d of %d bins (%.1f%%)", top.coverage, top.size, top.cover_percentage)
    if missing:
        if not set(STIMULUS_TESTS) <= _ran:
            dut._log.warning("not all stimulus tests ran; bins not hit: %s", "; ".join(missing))
            return
        raise AssertionError(f"coverage goal not reached, {len(missing)} bins not hit: "
                             + "; ".join(missing))


# ------------------------------------------------------------------------------------------
# Probes: camera timing below the documented minimums (1 clock of line blanking, 1 clock of
# fval before the first lval), showing why the minimums exist (docs/cocotb.md). Skipped unless
# COOPWIN_PROBES=1 (run.py --probes); each expects the pixels a unit with no minimum would
# deliver, so each fails with this RTL.
# ------------------------------------------------------------------------------------------

async def _probe_camera(dut, name, lead, hblank, window):
    b = await make_bench(dut, name)
    # A first frame of 7 lines without a window leaves the unit's line count at 7.
    await frame_with_writes(b, Raster(4241, [12] * 7, MIN_LEAD, [MIN_HBLANK] * 7, 0.0), [], "blank")
    w = window
    r = Raster(4242, [w.xmax + 3] * (w.ymax + 3), lead, [hblank] * (w.ymax + 2) + [3], 0.0)
    await frame_with_writes(b, r, [Job(w)], "blank")
    await b.settle()
    b.finish()


@cocotb.test(skip=not PROBES)
async def probe_one_clock_line_blanking(dut):
    """lval low for one clock between lines, window from column 0 and row 3."""
    await _probe_camera(dut, "probe_one_clock_line_blanking", MIN_LEAD, 1, Window(0, 5, 3, 6))


@cocotb.test(skip=not PROBES)
async def probe_one_clock_fval_lead(dut):
    """lval rises one clock after fval, window from (0, 0)."""
    await _probe_camera(dut, "probe_one_clock_fval_lead", 1, MIN_HBLANK, Window(0, 5, 0, 3))
