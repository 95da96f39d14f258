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
