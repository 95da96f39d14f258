"""coopwin from Python: the cooperative-windowing tracker with OpenCV's tracker interface.

The same Rust code as the ``coopwin`` command line runs underneath, so every number here is
the one ``coopwin track`` writes to its CSV:

- :class:`Tracker` (or :func:`TrackerCOOP_create` for code written for OpenCV's trackers):
  ``ok, box = tracker.update(frame)`` on NumPy frames (``uint8``, gray or BGR);
- :func:`track_video`: the rows of ``coopwin track --frames PATH`` as :class:`Row` tuples,
  streamed while the run goes on;
- :func:`verilog`: the window logic's Verilog for a sensor, as ``coopwin verilog`` writes it;
- :mod:`coopwin.trax`: the tracker served over TraX for the VOT toolkit
  (``python -m coopwin.trax``; needs ``vot-trax``).

Errors are Python exceptions with the command line's messages: ``TypeError`` for a frame or
option of the wrong type, ``ValueError`` for a bad value (a box outside the frame, a wrong
shape), ``FileNotFoundError`` for a missing video.
"""
from __future__ import annotations

import csv as _csv
import math
import numbers
import os
from typing import Any, Dict, Iterator, List, NamedTuple, Optional, Sequence, Tuple, Union

from . import _coopwin

__all__ = ["COLUMNS", "Row", "Tracker", "TrackerCOOP", "TrackerCOOP_create", "track_video", "verilog"]

#: The CSV's columns (``coopwin track --out``), the fields of :class:`Row`.
COLUMNS: Tuple[str, ...] = tuple(_coopwin.TRACK_HEADER.split(","))


class Row(NamedTuple):
    """One frame of a run: a row of ``coopwin track``'s CSV, typed (empty fields are None).

    See ``coopwin track --help`` for the columns' meaning.
    """

    frame: int
    x: Optional[float]
    y: Optional[float]
    mode: str
    source: str
    measured_frame: Optional[int]
    file: str
    box_x: Optional[float]
    box_y: Optional[float]
    box_w: Optional[float]
    box_h: Optional[float]
    confidence: Optional[float]
    ok: bool
    time_s: Optional[float]
    damaged: bool
    state: str
    scale: Optional[float]
    angle_deg: Optional[float]

    @classmethod
    def parse(cls, line: str) -> "Row":
        """The row of one CSV line (without its line break)."""
        fields = next(_csv.reader([line]))
        if len(fields) != len(cls._fields):
            raise ValueError(f"a coopwin row has {len(cls._fields)} fields, this line {len(fields)}: {line!r}")
        return cls(*(_PARSE[name](v) for name, v in zip(cls._fields, fields)))


def _number(kind: type) -> Any:
    return lambda v: kind(v) if v != "" else None


_PARSE = {name: _number(float) for name in Row._fields}
_PARSE.update(
    frame=int,
    measured_frame=_number(int),
    mode=str,
    source=str,
    file=str,
    state=str,
    ok=lambda v: v == "1",
    damaged=lambda v: v == "1",
)

Box = Tuple[int, int, int, int]


def _options(**options: Any) -> List[str]:
    """``coopwin track``'s command-line options for keyword arguments (None: the CLI's
    default; True: a flag), their values checked by the CLI's own parser in Rust."""
    argv: List[str] = []
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if value is None or value is False:
            continue
        if value is True:
            argv.append(flag)
        elif name == "target_box":
            argv.append(f"{flag}={','.join(str(v) for v in _box(value))}")
        elif name == "blank_jitter" and isinstance(value, (tuple, list)):
            # (LINE, FRAME) or (LINE, FRAME, SEED), the option's LINE,FRAME[,SEED].
            argv.append(f"{flag}={','.join(str(v) for v in value)}")
        elif isinstance(value, (str, numbers.Real)) and not isinstance(value, bool):
            # One word, so a negative value reaches the option's own check.
            argv.append(f"{flag}={value}")
        else:
            raise TypeError(f"{name} must be a number or a string, got {type(value).__name__}")
    return argv


def _keywords(arguments: Dict[str, Any], *positional: str) -> Dict[str, Any]:
    """A function's ``locals()`` without its positional arguments: its keyword options."""
    return {name: v for name, v in arguments.items() if name not in positional}


def _box(box: Any) -> Box:
    """An (x, y, w, h) box of whole pixels (OpenCV's convention: columns x..x+w-1)."""
    try:
        if isinstance(box, (str, bytes)):
            raise TypeError
        values = tuple(box)
    except TypeError:
        raise TypeError(f"box must be (x, y, w, h), got {type(box).__name__}") from None
    if len(values) != 4:
        raise ValueError(f"box must be (x, y, w, h): 4 values, got {len(values)}")
    whole = []
    for v in values:
        if isinstance(v, numbers.Integral) and not isinstance(v, bool):
            whole.append(int(v))
        elif isinstance(v, numbers.Real) and float(v).is_integer():
            whole.append(int(v))
        else:
            raise TypeError(f"box must hold whole pixels (x, y, w, h), got {box!r}")
    return (whole[0], whole[1], whole[2], whole[3])


class Tracker:
    """The cooperative tracker (COOP by default) on frames handed in one at a time.

    ``Tracker(frame, box)`` starts tracking the box (x, y, w, h) of ``frame`` (a NumPy
    ``uint8`` array: H x W gray, or H x W x 3 BGR as OpenCV reads it, converted to gray as
    the CLI converts colour PNG frames); ``ok, box = tracker.update(next_frame)`` follows
    it. The keyword options are ``coopwin track``'s (``template``, ``bin``, ``search``,
    ``strategy``, ``policy``, ``profile``, ``fixed_template``, ``coop_n``, ``watch``; see
    ``coopwin track --help``): a box much larger than the template is tracked on the
    frames binned as the CLI bins them, and ``bin=1`` turns that off. ``fps`` is the frames' rate; without it, the rate of the thesis camera's 8 MHz
    pixel clock over the frames' raster, ``8e6 / ((H + 2) * (W + 16) + 16)``: 114 frames/s
    at 256x256, but 17.65 at 768x576. For a video, give its own rate
    (``fps=cap.get(cv2.CAP_PROP_FPS)``), as ``coopwin track`` takes a video's.

    The CLI's options of a run over a whole source (``--start-frame``, ``--end-frame``,
    ``--blank-jitter``, a clocked ``--hdl``, ``--allow-damaged``) are :func:`track_video`'s,
    and those that write files (``--out``, ``--overlay``, ``--vcd``) the CLI's: the run
    behind a Tracker (``_coopwin.FrameRun``) refuses them with a ``ValueError`` that says so.

    After each frame (the first included), the attributes say what the run knew at the end
    of that frame's period: :attr:`row` (the CSV's row: the same line ``coopwin track``
    writes for this frame), :attr:`ok`, :attr:`box`, :attr:`point` (sub-pixel), :attr:`state`,
    :attr:`confidence`, :attr:`scale` and :attr:`angle`.
    """

    def __init__(
        self,
        frame: Any,
        box: Sequence[int],
        *,
        fps: Optional[float] = None,
        template: Optional[int] = None,
        bin: Optional[int] = None,
        search: Optional[int] = None,
        strategy: Optional[str] = None,
        policy: Optional[str] = None,
        profile: Optional[str] = None,
        fixed_template: bool = False,
        coop_n: Optional[int] = None,
        watch: Optional[str] = None,
    ) -> None:
        # Every keyword argument is the CLI option of the same name.
        options = _options(target_box=box, **_keywords(locals(), "self", "frame", "box"))
        self._run = _coopwin.FrameRun(frame, options)
        self._take(self._run.first_row)

    def update(self, frame: Any) -> Tuple[bool, Box]:
        """Tracks the next frame: ``(ok, (x, y, w, h))`` as OpenCV's trackers return it (the
        box rounded to whole pixels; ``(0, 0, 0, 0)`` when there is no position at all)."""
        self._take(self._run.push(frame))
        return self.ok, self.box

    def _take(self, line: str) -> None:
        self.csv_row: str = line
        self.row: Row = Row.parse(line)

    @property
    def ok(self) -> bool:
        """True when the frame has a fresh position confirmed to be the target's."""
        return self.row.ok

    @property
    def box(self) -> Box:
        """The box around the position, rounded to whole pixels (x, y, w, h)."""
        r = self.row
        if r.box_x is None or r.box_y is None or r.box_w is None or r.box_h is None:
            return (0, 0, 0, 0)
        return (_round(r.box_x), _round(r.box_y), _round(r.box_w), _round(r.box_h))

    @property
    def point(self) -> Optional[Tuple[float, float]]:
        """The position (pixel centres at integers), sub-pixel; the estimate when nothing was
        measured; None with neither."""
        return None if self.row.x is None or self.row.y is None else (self.row.x, self.row.y)

    @property
    def state(self) -> str:
        """``tracking``, ``unconfirmed``, ``predicted``, ``searching`` or ``lost``."""
        return self.row.state

    @property
    def confidence(self) -> Optional[float]:
        """The chance the position is the target's: 0.9-1.0 where ``ok``, 0.6 where not; None without a measured position."""
        return self.row.confidence

    @property
    def scale(self) -> Optional[float]:
        """The object's scale against lock-on, when this frame measured it."""
        return self.row.scale

    @property
    def angle(self) -> Optional[float]:
        """The object's turn in degrees (clockwise on the screen), when this frame measured it."""
        return self.row.angle_deg


def _round(v: float) -> int:
    return int(math.floor(v + 0.5))


class TrackerCOOP:
    """A drop-in for OpenCV's trackers: ``init(frame, box)``, then ``update(frame)``."""

    def __init__(self, **options: Any) -> None:
        self._options = options
        self._tracker: Optional[Tracker] = None

    def init(self, image: Any, boundingBox: Sequence[int]) -> None:
        """Starts tracking ``boundingBox`` (x, y, w, h) in ``image``."""
        self._tracker = Tracker(image, boundingBox, **self._options)

    def update(self, image: Any) -> Tuple[bool, Box]:
        """``(ok, (x, y, w, h))`` for the next frame."""
        if self._tracker is None:
            raise RuntimeError("call init(frame, box) before update(frame)")
        return self._tracker.update(image)

    @property
    def tracker(self) -> Optional[Tracker]:
        """The :class:`Tracker` behind it (its state, confidence, ...), once ``init`` ran."""
        return self._tracker


def TrackerCOOP_create(**options: Any) -> TrackerCOOP:
    """OpenCV's naming (``cv2.TrackerCSRT_create()``): a :class:`TrackerCOOP` with
    :class:`Tracker`'s keyword options."""
    return TrackerCOOP(**options)


def track_video(
    path: Union[str, "os.PathLike[str]"],
    box: Optional[Sequence[int]] = None,
    *,
    fps: Optional[float] = None,
    start_frame: Optional[int] = None,
    end_frame: Optional[int] = None,
    allow_damaged: bool = False,
    template: Optional[int] = None,
    bin: Optional[int] = None,
    search: Optional[int] = None,
    strategy: Optional[str] = None,
    policy: Optional[str] = None,
    profile: Optional[str] = None,
    fixed_template: bool = False,
    coop_n: Optional[int] = None,
    watch: Optional[str] = None,
    blank_jitter: Optional[Union[str, Sequence[int]]] = None,
    hdl: Optional[str] = None,
    pixel_bits: Optional[int] = None,
) -> Iterator[Row]:
    """``coopwin track --frames PATH [--target-box X,Y,W,H] ...``'s rows, one :class:`Row` a
    frame, as the run makes them (a video through FFmpeg, or a folder of PNG frames).

    Without ``box`` the tracker locks on to the first motion. ``fps`` defaults to a video's
    own rate (for PNG frames, the pixel clock's rate, as :class:`Tracker`'s);
    ``blank_jitter`` is ``(LINE, FRAME)`` or ``(LINE, FRAME, SEED)``; ``hdl`` is ``"model"``,
    ``"rust-hdl"`` or ``"verilator"`` (with ``pixel_bits``). The input is opened and checked
    now (``FileNotFoundError``, ``ValueError``); the run goes on in the background, a little
    ahead of the reader, and stops when the iterator is dropped. Nothing is written: the
    CLI's ``--out``, ``--overlay``, ``--vcd`` and ``--list`` raise ``ValueError``.
    """
    # Every keyword argument is the CLI option of the same name.
    options = _options(target_box=box, **_keywords(locals(), "path", "box"))
    rows = _coopwin.VideoRows(os.fspath(path), options)
    return (Row.parse(line) for line in rows)


def verilog(
    width: int = 256,
    height: int = 256,
    pixel_bits: int = 8,
    axis: bool = False,
    *,
    units: Optional[int] = None,
    netlist: Optional[str] = None,
) -> Dict[str, str]:
    """The window logic's Verilog for a ``width`` x ``height`` sensor with ``pixel_bits``-bit
    pixels, as ``coopwin verilog`` writes it: ``{file name: Verilog text}`` for
    ``window_unit.v`` and ``window_network.v`` (``units`` units, default 4), and with ``axis``
    ``window_unit_axis.v`` and ``axil_cdc.v``. ``netlist="rust-hdl"`` gives rust-hdl's
    netlist of the blocks instead of the readable module."""
    options = _options(width=width, height=height, pixel_bits=pixel_bits, axis=axis, units=units, netlist=netlist)
    return dict(_coopwin.verilog(options))
