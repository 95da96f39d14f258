"""coopwin as a TraX tracker, for the VOT toolkit: ``python -m coopwin.trax [OPTIONS]``.

The VOT toolkit (``vot-toolkit``) runs a tracker as a process that speaks the TraX protocol
(PyPI ``vot-trax``) on its standard input and output (or the socket in ``TRAX_SOCKET``). This
module serves :class:`coopwin.Tracker` that way; a ``trackers.ini`` entry is::

    [coopwin]
    label = coopwin
    protocol = trax
    command = python -m coopwin.trax --fps 30

The options are :class:`coopwin.Tracker`'s keyword options as ``coopwin track`` spells them
(``--fps 30``, ``--profile ...``, ``--fixed-template``); ``python -m coopwin.trax --help``
lists them. Each frame's reply is one rectangle and the ``confidence`` property VOT-LT scores:
the tracker's box and confidence while it vouches for the position (``ok``), else an empty
rectangle (0, 0, 0, 0) with confidence 0, the bottom of the tracker's scale, so VOT-LT counts
the frame as "target absent" at every threshold above 0 (and as no overlap at 0).

Images come as file paths (read with OpenCV, ``cv2.imread``: the VOT toolkit sends paths) or
in memory (RGB or 8-bit gray); the initial region is a rectangle, rounded to whole pixels.
Input the tracker cannot take (a 16-bit image, a box whose centre is outside the frame, a
missing file) ends the session with the reason, which the client raises as a TraxException.
"""
from __future__ import annotations

import argparse
import inspect
import math
import sys
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import Box, Tracker

#: The reply's region for a frame the tracker does not vouch for.
EMPTY: Tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)


def region(tracker: Tracker) -> Tuple[Tuple[float, float, float, float], float]:
    """The region and confidence a frame's reply carries: the CSV row's box (sub-pixel, as
    ``coopwin track`` writes it) and confidence while ``tracker.ok``, else :data:`EMPTY`
    and 0 (the frame is not a prediction)."""
    r = tracker.row
    if not r.ok or r.box_x is None or r.box_y is None or r.box_w is None or r.box_h is None:
        return EMPTY, 0.0
    return (r.box_x, r.box_y, r.box_w, r.box_h), r.confidence if r.confidence is not None else 0.0


def whole_box(bounds: Sequence[float]) -> Box:
    """A TraX rectangle (x, y, w, h in pixels, edges between pixels) as whole pixels, each
    edge rounded to the nearest pixel boundary (the Tracker takes whole pixels)."""
    x, y, w, h = (float(v) for v in bounds)
    x0, y0 = _round(x), _round(y)
    return (x0, y0, _round(x + w) - x0, _round(y + h) - y0)


def _round(v: float) -> int:
    return int(math.floor(v + 0.5))


def frame_of(image: Any) -> np.ndarray:
    """A TraX image as a frame :class:`coopwin.Tracker` takes (H x W gray or H x W x 3 BGR)."""
    import trax

    if isinstance(image, trax.FileImage):
        path = image.path()
        try:
            import cv2
        except ImportError:
            raise ImportError(f"reading the image file {path} needs OpenCV: pip install opencv-python-headless") from None
        frame = cv2.imread(path, cv2.IMREAD_COLOR)
        if frame is None:
            raise FileNotFoundError(f"no such image file, or not one OpenCV reads: {path}")
        return frame
    if isinstance(image, trax.MemoryImage):
        pixels = image.array()
        # TraX's memory images are RGB; the Tracker takes OpenCV's BGR.
        return pixels[:, :, ::-1] if pixels.shape[2] == 3 else pixels
    raise ValueError(f"the {image.type()} image format is not served (only path and memory): {image}")


def serve(options: Dict[str, Any], server: Any) -> None:
    """Answers ``server``'s requests until the client quits: a new :class:`coopwin.Tracker`
    with ``options`` on each initialisation, its update on each frame."""
    import trax

    tracker: Optional[Tracker] = None
    while True:
        request = server.wait()
        if request.type == trax.TraxStatus.QUIT:
            return
        frame = frame_of(request.image[trax.ImageChannel.COLOR])
        if request.type == trax.TraxStatus.INITIALIZE:
            if len(request.objects) != 1:
                raise ValueError(f"coopwin tracks one object, the client sent {len(request.objects)}")
            bounds = request.objects[0][0].bounds()
            tracker = Tracker(frame, whole_box(bounds), **options)
        elif tracker is None:
            raise ValueError("a frame came before the tracker was initialised")
        else:
            tracker.update(frame)
        box, confidence = region(tracker)
        server.status([(trax.Rectangle.create(*box), {"confidence": confidence})])


def _parser() -> argparse.ArgumentParser:
    """The command line: :class:`coopwin.Tracker`'s keyword options, read off its signature
    (so the two cannot drift apart); values are checked by the Tracker, as the CLI checks them."""
    parser = argparse.ArgumentParser(
        prog="python -m coopwin.trax",
        description="Serve coopwin's tracker over TraX (for the VOT toolkit). Options are coopwin track's; see coopwin track --help.",
    )
    for name, p in inspect.signature(Tracker.__init__).parameters.items():
        if p.kind is not inspect.Parameter.KEYWORD_ONLY:
            continue
        flag = "--" + name.replace("_", "-")
        if p.default is False:
            parser.add_argument(flag, dest=name, action="store_true")
        else:
            parser.add_argument(flag, dest=name, metavar=name.upper())
    return parser


def main(argv: Optional[List[str]] = None) -> int:
    """Serves on standard input and output (or ``TRAX_SOCKET``); 0 when the client quit, 1
    when a request could not be tracked (the session ends with the reason)."""
    options = {k: v for k, v in vars(_parser().parse_args(argv)).items() if v is not None}
    try:
        import trax
    except ImportError:
        print("coopwin.trax needs the TraX protocol's Python package: pip install vot-trax", file=sys.stderr)
        return 1
    server = trax.Server(
        [trax.Region.RECTANGLE],
        [trax.Image.PATH, trax.Image.MEMORY],
        tracker_name="coopwin",
        tracker_description="cooperative-windowing tracker",
        tracker_family="coopwin",
    )
    try:
        serve(options, server)
    except (ValueError, TypeError, OSError, ImportError) as e:
        # The reason reaches the client (the VOT toolkit shows it); a traceback would not.
        server.quit(reason=f"{type(e).__name__}: {e}")
        return 1
    server.quit()
    return 0


if __name__ == "__main__":
    sys.exit(main())
