"""Reference model of the window_unit contract (hdl/verilog/window_unit.v, docs/window-logic.md).

It knows nothing of the RTL: it is the contract written as code. Feed it, edge by edge, what
the camera and `reset` present on each rising clock edge, and tell it when a coordinate set
completes (the edge on which the unit takes the set's last byte, i.e. raises coord_ready for
it). It answers which pixels must be delivered, in order, and what coord_error must be.

The rules:
- A pixel is present on an edge only when fval, lval and pixel_valid are all high. One lval
  pulse is one line, however many clocks it lasts; columns count the pixels of a line from 0,
  rows count the frame's lines from 0.
- A set is valid iff xmin < xmax < width and ymin < ymax < height. An invalid set raises
  coord_error and is refused (the pending set is untouched); a valid set clears coord_error.
- A valid set completed at least ARM_MARGIN (1) edge before the edge on which fval is first
  seen high arms that frame; a set completed on that edge or later waits, pending, for the
  next frame, and does not displace a set already pending for this one. Of several sets
  completed in time for a frame, the latest wins. A set arms one frame only: one window per
  set. (The RTL takes a set whose last byte is taken on edge s for the first frame whose fval
  is first sampled high on edge s+1 or later: hdl/verilog/window_unit.v's header.)
- An armed frame delivers its window's pixels, in raster order; with decimation only those
  with (x - xmin) and (y - ymin) both even.
- reset (synchronous, active high) returns to the power-on state: nothing pending or armed,
  coord_error low, and the unit has not seen fval high.
- Status outputs, as read after edge n: set_accepted is high after edge s+1 for a valid set
  completed on edge s; window_done after edge c+2, where c is the edge on which the window's
  corner pixel (xmax, ymax) came (delivered or, decimated, not); armed while a valid set is
  pending (after edge s+1 on) or the armed frame's window is open: up to and including the
  edge on which its last line (row ymax) is first seen ended, or fval first seen low. A reset
  clears all three.
"""

from __future__ import annotations

from dataclasses import dataclass, field

# Edges between a set's completion and the first edge with fval high, for it to arm that frame.
ARM_MARGIN = 1


@dataclass(frozen=True)
class Window:
    xmin: int
    xmax: int
    ymin: int
    ymax: int
    decimate: bool = False

    def valid(self, width: int, height: int) -> bool:
        return self.xmin < self.xmax < width and self.ymin < self.ymax < height

    def contains(self, x: int, y: int) -> bool:
        if not (self.xmin <= x <= self.xmax and self.ymin <= y <= self.ymax):
            return False
        return not self.decimate or ((x - self.xmin) % 2 == 0 and (y - self.ymin) % 2 == 0)

    def __str__(self) -> str:
        d = " decimated" if self.decimate else ""
        return f"x {self.xmin}..{self.xmax}, y {self.ymin}..{self.ymax}{d}"


@dataclass
class Frame:
    """One frame as the unit sees it: from the edge fval is first seen high."""

    index: int                 # frames counted by this model since it was made
    start: int                 # edge on which fval was first seen high
    window: Window | None      # the window this frame delivers, or None
    set_edge: int | None       # completion edge of that window's set
    superseded: int = 0        # older valid sets that this frame's set replaced
    end: int | None = None     # edge on which fval was first seen low, or the reset edge
    aborted: bool = False      # ended by reset
    lines: int = 0             # lval pulses seen in the frame
    longest_line: int = 0      # most pixels in one line
    pixels: list = field(default_factory=list)  # expected deliveries: (edge, x, y, value)


class WindowModel:
    def __init__(self, width: int, height: int):
        self.width, self.height = width, height
        self.frames: list[Frame] = []
        self._power_on()

    def _power_on(self) -> None:
        self.pending: list[tuple[int, Window]] = []  # valid sets not yet armed: (edge, window)
        self.error = False
        self.frame: Frame | None = None
        self._fval = False   # fval on the previous edge, as the unit saw it
        self._lval = False
        self.row = -1
        self._col = 0
        self.accepted_at: set[int] = set()   # edges after which set_accepted is high
        self.done_at: set[int] = set()       # edges after which window_done is high
        self.live = False                    # the armed frame's window is open...
        self.live_until: int | None = None   # ...up to this edge, once its end is seen

    def armed(self, n: int) -> bool:
        """What armed must be after edge n (before the sets completed on edge n are told)."""
        return bool(self.pending) or (self.live and (self.live_until is None or n <= self.live_until))

    def set_completed(self, edge: int, window: Window) -> bool:
        """A set's last byte was taken on `edge`. Returns whether the set is valid."""
        if not window.valid(self.width, self.height):
            self.error = True
            return False
        self.error = False
        self.pending.append((edge, window))
        self.accepted_at.add(edge + 1)
        return True

    def edge(self, n: int, reset: bool, fval: bool, lval: bool, pixel_valid: bool, pixel: int):
        """Rising edge n with these inputs. Returns the delivered pixel (x, y, value) or None."""
        if reset:
            if self.frame is not None:
                self.frame.end, self.frame.aborted = n, True
            self._power_on()
            return None
        out = None
        if fval and not self._fval:
            # A frame starts: the latest set completed early enough arms it; later ones wait.
            early = [(t, w) for t, w in self.pending if t <= n - ARM_MARGIN]
            self.pending = [(t, w) for t, w in self.pending if t > n - ARM_MARGIN]
            t, w = early[-1] if early else (None, None)
            self.frame = Frame(len(self.frames), n, w, t, superseded=max(0, len(early) - 1))
            self.frames.append(self.frame)
            self.row, self._col = -1, 0
            self.live, self.live_until = w is not None, None
        elif not fval and self._fval and self.frame is not None:
            self.frame.end = n
            self.frame = None
            if self.live_until is None:
                self.live_until = n
        f = self.frame
        if f is not None:
            if lval and not self._lval:  # a line starts
                self.row += 1
                self._col = 0
                f.lines += 1
            elif not lval and self._lval and f.window is not None and self.row == f.window.ymax \
                    and self.live_until is None:
                self.live_until = n      # the window's last line ended
            # fval is high here (f is None from the edge fval is first seen low), so a pixel
            # is fval & lval & pixel_valid: lval outlasting fval carries none.
            if fval and lval and pixel_valid and self.row >= 0:
                x, y = self._col, self.row
                self._col += 1
                f.longest_line = max(f.longest_line, self._col)
                if f.window is not None and f.window.contains(x, y):
                    out = (x, y, pixel)
                    f.pixels.append((n, x, y, pixel))
                if f.window is not None and (x, y) == (f.window.xmax, f.window.ymax):
                    self.done_at.add(n + 2)
        self._fval, self._lval = fval, lval
        return out


def crop(window: Window, line_lengths: list, pixel) -> list:
    """The software crop, a second opinion on `edge`: the (x, y, value) a window delivers from
    a frame whose line y holds line_lengths[y] pixels, pixel(x, y) each, in order."""
    return [(x, y, pixel(x, y))
            for y in range(window.ymin, min(window.ymax + 1, len(line_lengths)))
            for x in range(window.xmin, min(window.xmax + 1, line_lengths[y]))
            if window.contains(x, y)]


# ------------------------------------------------------------------------------------------
# window_unit_axis (hdl/verilog/window_unit_axis.v): the AXI4-Stream wrapper's contract, as
# its header states it. Windows are inclusive rectangles at least two pixels wide and high
# (the bare unit's rule, thesis 2.2.1), a commit applies to the first frame whose tuser beat is
# taken on the commit's edge or later, a set without `continuous` delivers one window, and each
# window's beats carry tuser on its first pixel and tlast on the last pixel of each of its rows.
# ------------------------------------------------------------------------------------------

# Register offsets (bytes): global, then window k at AXIS_WINDOW * (k + 1) + offset.
AXIS_INFO, AXIS_GEOMETRY, AXIS_IRQ_STATUS, AXIS_IRQ_ENABLE = 0x00, 0x04, 0x08, 0x0C
AXIS_WINDOW = 0x20
AXIS_X, AXIS_Y, AXIS_CTRL, AXIS_COMMIT, AXIS_STATUS, AXIS_FRAMES, AXIS_OVERFLOWS = \
    0x00, 0x04, 0x08, 0x0C, 0x10, 0x14, 0x18


@dataclass(frozen=True)
class Rect:
    """A window of window_unit_axis: columns xmin..xmax and rows ymin..ymax, inclusive."""

    xmin: int
    xmax: int
    ymin: int
    ymax: int
    decimate: bool = False
    continuous: bool = False

    def valid(self, width: int, height: int) -> bool:
        return self.xmin < self.xmax < width and self.ymin < self.ymax < height

    def contains(self, x: int, y: int) -> bool:
        if not (self.xmin <= x <= self.xmax and self.ymin <= y <= self.ymax):
            return False
        return not self.decimate or ((x - self.xmin) % 2 == 0 and (y - self.ymin) % 2 == 0)

    def last_column(self) -> int:
        return self.xmax - ((self.xmax - self.xmin) % 2 if self.decimate else 0)

    def last_row(self) -> int:
        return self.ymax - ((self.ymax - self.ymin) % 2 if self.decimate else 0)

    def beats(self) -> int:
        step = 2 if self.decimate else 1
        return len(range(self.xmin, self.xmax + 1, step)) * len(range(self.ymin, self.ymax + 1, step))

    def __str__(self) -> str:
        mode = (" decimated" if self.decimate else "") + (" continuous" if self.continuous else "")
        return f"x {self.xmin}..{self.xmax}, y {self.ymin}..{self.ymax}{mode}"


@dataclass
class AxisBeat:
    """A beat a window must deliver: its window frame (counted per window), place and flags."""

    wframe: int
    x: int
    y: int
    data: int
    user: bool
    last: bool


class AxisModel:
    """The register file and the windows of window_unit_axis, told each register write (on the
    edge of its write handshake) and each input beat, in edge order, writes before beats."""

    def __init__(self, width: int, height: int, windows: int):
        self.width, self.height, self.n = width, height, windows
        self.reset()

    def reset(self) -> None:
        n = self.n
        self.written = [Rect(0, 0, 0, 0) for _ in range(n)]   # X, Y and CTRL as written
        self.pending: list[Rect | None] = [None] * n
        self.active: list[Rect | None] = [None] * n
        self.live = [False] * n
        self.invalid = [False] * n
        self.frames = [0] * n          # windows completed (FRAMES)
        self.wframes = [0] * n         # window frames opened
        self.irq_status = 0
        self.irq_enable = 0
        self.expected: list[list[AxisBeat]] = [[] for _ in range(n)]
        self.in_frame = False
        self.x = self.y = 0
        self.frame = -1                # input frames since reset

    def write(self, addr: int, data: int) -> str | None:
        """A register write. Returns what a COMMIT did: 'valid', 'invalid' or None."""
        if addr == AXIS_IRQ_STATUS:
            self.irq_status &= ~data
        elif addr == AXIS_IRQ_ENABLE:
            self.irq_enable = data & ((1 << self.n) - 1)
        k, off = addr // AXIS_WINDOW - 1, addr % AXIS_WINDOW
        if not 0 <= k < self.n:
            return None
        w = self.written[k]
        lo, hi = data & 0xFFFF, data >> 16
        if off == AXIS_X:
            self.written[k] = Rect(lo, hi, w.ymin, w.ymax, w.decimate, w.continuous)
        elif off == AXIS_Y:
            self.written[k] = Rect(w.xmin, w.xmax, lo, hi, w.decimate, w.continuous)
        elif off == AXIS_CTRL:
            self.written[k] = Rect(w.xmin, w.xmax, w.ymin, w.ymax, bool(data & 1), bool(data & 2))
        elif off == AXIS_COMMIT:
            if w.valid(self.width, self.height):
                self.pending[k], self.invalid[k] = w, False
                return "valid"
            self.invalid[k] = True
            return "invalid"
        return None

    def beat(self, data: int, user: bool, last: bool) -> None:
        """An input beat taken."""
        if user:
            self.in_frame, self.x, self.y = True, 0, 0
            self.frame += 1
            for k in range(self.n):
                if self.pending[k] is not None:
                    self.active[k], self.pending[k] = self.pending[k], None
                    self.live[k] = True
                else:
                    self.live[k] = self.active[k] is not None and self.active[k].continuous
                self.wframes[k] += self.live[k]
        if not self.in_frame:
            return
        x, y = self.x, self.y
        for k in range(self.n):
            r = self.active[k]
            if self.live[k] and r.contains(x, y):
                self.expected[k].append(AxisBeat(self.wframes[k], x, y, data,
                                                 (x, y) == (r.xmin, r.ymin), x == r.last_column()))
                if (x, y) == (r.last_column(), r.last_row()):
                    self.live[k] = False
                    self.frames[k] += 1
                    self.irq_status |= 1 << k
        self.x, self.y = (0, y + 1) if last else (x + 1, y)

    def status(self, k: int, fifo_busy: bool) -> int:
        """STATUS of window k, given whether its FIFO holds beats (not the model's to know)."""
        armed = self.pending[k] is not None or self.live[k] or \
            (self.active[k] is not None and self.active[k].continuous)
        return (int(armed) | (int(self.live[k] or fifo_busy) << 1)
                | (int(self.pending[k] is not None) << 2) | (int(self.invalid[k]) << 3))


def match_with_drops(expected: list, delivered: list) -> tuple[int, str | None]:
    """Scoreboard of one window's output when beats may have been dropped on overflow.

    `expected` holds AxisBeat, `delivered` (data, user, last) in order. The delivered beats must
    be the expected ones in order with some left out, a dropped beat's tlast is not carried, and
    tuser is on exactly the first delivered beat of each window frame (a dropped first beat's
    tuser moves to the next one delivered). So a beat with tuser is matched in a later window
    frame than the last match, one without in the same frame, each with the earliest expected
    beat of equal data and tlast (pixel values may repeat; the earliest match finds a way
    whenever one exists). Returns (beats dropped, None) or (beats matched, what went wrong)."""
    j, wframe = 0, None
    for i, (data, user, last) in enumerate(delivered):
        if user:
            while j < len(expected) and expected[j].wframe == wframe:
                j += 1
            if j < len(expected):
                wframe = expected[j].wframe
        while j < len(expected) and expected[j].wframe == wframe \
                and (expected[j].data, expected[j].last) != (data, last):
            j += 1
        if j == len(expected) or expected[j].wframe != wframe:
            where = "its window frame" if not user else "a later window frame"
            return i, (f"delivered beat {i} ({data:#x}, tuser {user}, tlast {last}) is not in "
                       f"{where} after the last match (tuser on the first beat delivered of each "
                       "window frame, the others in order)")
        j += 1
    return len(expected) - len(delivered), None
