#!/usr/bin/env python3
"""Per-frame speed of OpenCV's trackers, to set against coopwin's host pipeline (issue 21
item 6: "the host pipeline at least 10x faster than KCF per frame").

    python3 scripts/tracker_speed.py FRAMES [--box X,Y,W,H] [--point corner|centre]
        [--repeats 5] [--search 14] [--trackers kcf,csrt,mosse,match]

FRAMES: a folder from `coopwin scene --out DIR` (frame_NNNNN.png/.pgm + groundtruth.csv) or
a video (cv2.VideoCapture); all frames are decoded to 8-bit gray into memory first. Default
box: 20x20 centred on groundtruth.csv's first-row corner_x,corner_y (what coopwin's pipeline
bench tracks; --point centre: centre_x,centre_y), top-left round(p - 9.5) half up.
Each repeat starts each tracker afresh on frame 0 (init not timed), then times one call per
later frame (perf_counter_ns, cv2.setNumThreads(1)): kcf, csrt, mosse = update() of
cv2.TrackerKCF_create(), cv2.TrackerCSRT_create(), cv2.legacy.TrackerMOSSE_create()
(defaults; gray replicated to BGR beforehand, as scripts/opencv_real.py feeds them); match =
opencv_real.py's track_template, timed frame by frame: TM_CCOEFF_NORMED of frame 0's template
(float32) over the template plus --search px a side around the last box, minMaxLoc,
parabola refinement, score < 0.5 keeps the last box. Prints a markdown table: median and
mean us per frame over all repeats, frames/s = 1e6 / mean, lost = updates without a
position; with the CPU model and the OpenCV version.
"""

import argparse
import csv
import re
import statistics
import sys
import time
from pathlib import Path

import cv2
import numpy as np

from opencv_real import factory, round_half_up, track_template

TRACKERS = ("kcf", "csrt", "mosse")


def gray(img: np.ndarray | None, what: str) -> np.ndarray:
    if img is None or img.dtype != np.uint8:
        raise RuntimeError(f"{what}: cannot read it as 8-bit")
    return cv2.cvtColor(img, cv2.COLOR_BGR2GRAY if img.shape[2] == 3 else cv2.COLOR_BGRA2GRAY) if img.ndim == 3 else img


def load(src: Path) -> list[np.ndarray]:
    """Every frame of the folder (sorted by number) or of the video, as 8-bit gray."""
    if src.is_dir():
        files = sorted((int(m.group(1)), p) for p in src.iterdir()
                       if (m := re.fullmatch(r"frame_(\d+)\.(?:png|pgm)", p.name)))
        return [gray(cv2.imread(str(p), cv2.IMREAD_UNCHANGED), str(p)) for _, p in files]
    cap = cv2.VideoCapture(str(src))
    if not cap.isOpened():
        raise RuntimeError(f"{src}: cv2.VideoCapture cannot open it")
    frames = []
    while (r := cap.read())[0]:
        frames.append(gray(r[1], str(src)))
    return frames


def time_match(frames: list[np.ndarray], box, search: int) -> tuple[list[int], int]:
    """Nanoseconds for each frame after the first, and the frames without a position:
    opencv_real.py's track_template itself, fed one frame at a time (the time between two
    frames it takes is the previous frame's step)."""
    x, y, tw, th = box
    stamps: list[int] = []

    def feed():
        for img in frames[1:]:
            stamps.append(time.perf_counter_ns())
            yield img
        stamps.append(time.perf_counter_ns())

    points = track_template(feed(), frames[0][y:y + th, x:x + tw].copy(), (x, y), search)
    return [b - a for a, b in zip(stamps, stamps[1:])], sum(p is None for p in points[1:])


def time_cv(name: str, frames: list[np.ndarray], box) -> tuple[list[int], int]:
    """Nanoseconds of update() for each frame after the first, and the updates returning False."""
    tracker, times, lost = factory(name)[0](), [], 0
    tracker.init(frames[0], tuple(int(v) for v in box))
    for img in frames[1:]:
        t0 = time.perf_counter_ns()
        ok, _ = tracker.update(img)
        times.append(time.perf_counter_ns() - t0)
        lost += not ok
    return times, lost


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("frames", help="folder of frame_NNNNN.png/.pgm (+ groundtruth.csv), or a video file")
    ap.add_argument("--box", help="X,Y,W,H [default: 20x20 around groundtruth.csv's first row]")
    ap.add_argument("--point", choices=("corner", "centre"), default="corner", help="default box's point [corner]")
    ap.add_argument("--repeats", type=int, default=5, help="runs over the sequence [default: 5]")
    ap.add_argument("--search", type=int, default=14, help="match's margin, px a side [default: 14]")
    ap.add_argument("--trackers", default="kcf,csrt,mosse,match", help="comma-separated [default: all four]")
    args = ap.parse_args()
    cv2.setNumThreads(1)
    src = Path(args.frames)
    names = [t.strip() for t in args.trackers.split(",") if t.strip()]
    try:
        if set(names) - {*TRACKERS, "match"} or args.repeats < 1:
            raise RuntimeError(f"--trackers: only {','.join(TRACKERS)},match; --repeats: at least 1")
        frames = load(src)
        if len(frames) < 2:
            raise RuntimeError(f"{src}: need at least 2 frames, found {len(frames)}")
        if args.box:
            box = tuple(int(v) for v in args.box.split(","))
        elif src.is_dir():
            with open(src / "groundtruth.csv", newline="") as f:
                row = next(csv.DictReader(f))
            p = float(row[f"{args.point}_x"]), float(row[f"{args.point}_y"])
            box = round_half_up(p[0] - 9.5), round_half_up(p[1] - 9.5), 20, 20
        else:
            raise RuntimeError("a video needs --box X,Y,W,H")
    except (OSError, ValueError, RuntimeError, StopIteration, KeyError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    bgr = [cv2.cvtColor(f, cv2.COLOR_GRAY2BGR) for f in frames]
    f32 = [f.astype(np.float32) for f in frames]
    rows = []
    for name in names:
        times, lost = [], 0
        try:  # a tracker that fails (init or update raises) gets a row saying so
            label = "cv2.matchTemplate" if name == "match" else factory(name)[1]
            for _ in range(args.repeats):
                t, n = time_match(f32, box, args.search) if name == "match" else time_cv(name, bgr, box)
                times, lost = times + t, lost + n
        except (cv2.error, RuntimeError) as e:
            rows.append(f"| {name} | failed: {str(e).strip().splitlines()[-1]} | | | | |")
            continue
        med, mean = statistics.median(times) / 1e3, statistics.fmean(times) / 1e3
        rows.append(f"| {name} (`{label}`) | {len(times)} | {lost} | {med:.1f} | {mean:.1f} | {1e6 / mean:,.0f} |")
    H, W = frames[0].shape
    cpu = re.search(r"^model name\s*:\s*(.*)$", Path("/proc/cpuinfo").read_text(), re.M)
    print(f"CPU: {cpu.group(1) if cpu else 'unknown'}; OpenCV {cv2.__version__}, cv2.setNumThreads(1); numpy {np.__version__}, "
          f"Python {sys.version.split()[0]}")
    print(f"Input: {src} ({len(frames)} frames, {W}x{H}); box {box}; {args.repeats} repeats; frames "
          f"1..{len(frames) - 1} timed, init excluded; match margin {args.search} px\n")
    print("| tracker | frames timed | lost | median us/frame | mean us/frame | frames/s (1e6/mean) |\n"
          "|---|---:|---:|---:|---:|---:|\n" + "\n".join(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
