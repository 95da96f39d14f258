#!/usr/bin/env python3
"""OpenCV tracking baselines on real clips, scored without ground truth.

    python3 scripts/opencv_footage.py [--data /usr/share/doc/opencv-doc/examples/data]
        [--objects fixtures/footage/objects.csv] [--out fixtures/opencv/footage]

The clips are Debian opencv-doc's examples (Megamind.avi, Megamind_bugy.avi,
tree.avi); --objects lists the objects to track, one a line:
clip,object,first,last,x,y,w,h (clip = file stem, frames 0-based in decoding
order, box in full-frame pixels). Pixel centres are at integer coordinates,
(0,0) the top-left pixel; a box's centre is (x + (w-1)/2, y + (h-1)/2).

Frames are decoded by cv2.VideoCapture and converted to gray
(cv2.COLOR_BGR2GRAY); the OpenCV trackers get the gray frame replicated to
3-channel BGR, as scripts/opencv_real.py does. Every tracker runs forward from
`first` to `last` starting from the object's box, then backward from `last` to
`first`, started afresh on frame `last` from the integer box nearest its own
forward box there (top-left rounded half up); its reported centres are shifted
by the rounding remainder, so the backward run starts exactly on the forward
centre. No forward position at `last`: no backward run.

  match  cv2.matchTemplate(TM_CCOEFF_NORMED) of the start frame's w x h
         template over a window of +-SEARCH[clip] px around the last box
         (clipped to the image), peak refined by a 1-D parabola in x and in y
         (opencv_real.track_template); best score < 0.5: no position that frame and
         the next search stays around the last known box.
  csrt   cv2.TrackerCSRT_create(), default parameters.
  kcf    cv2.TrackerKCF_create(), default parameters.
  mosse  cv2.legacy.TrackerMOSSE_create(), default parameters.
         update() == False means no position that frame.

Output (in --out): <clip>-<object>.<tracker>.csv (frame,x,y,back_x,back_y:
forward and backward centres, 3 decimals, empty when none), summary.csv and
README.md; damage.csv compares Megamind_bugy's frames with Megamind's.
Scores per object and tracker (no ground truth): positions = frames with a
forward position; fb_first_px = distance between the start centre and
the backward run's centre at `first`; fb_mean_px = mean distance between the
forward and backward centres over frames where both exist; agreement with CSRT
= mean distance to CSRT's forward centre and % of frames within 5 px of it,
over frames where both report. OpenCV runs single-threaded so reruns give
identical files.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import math
import sys
import time
from pathlib import Path

import cv2
import numpy as np

# Shared with the rendered real-image baselines (same folder as this script).
from opencv_real import LOSS_PX, MIN_SCORE, factory, round_half_up, track_cv, track_template

REPO = Path(__file__).resolve().parent.parent
DATA = Path("/usr/share/doc/opencv-doc/examples/data")
TRACKERS = ("match", "csrt", "kcf", "mosse")
# match's search margin per clip (px around the last box): about twice the
# largest frame-to-frame motion of the clip's objects, as motion() measures it,
# and at least 8 px (tree.avi's camera stands still).
SEARCH = {"Megamind": 24, "Megamind_bugy": 24, "tree": 8}
# motion() looks this far for a patch and trusts steps with at least this NCC.
MOTION_REACH = 48
MOTION_SCORE = 0.8

Point = tuple[float, float]


def read_clip(path: Path) -> list[np.ndarray]:
    """Every decodable frame of the clip, converted to 8-bit gray."""
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise RuntimeError(f"{path}: cv2.VideoCapture cannot open it (install opencv-doc?)")
    frames = []
    while True:
        ok, bgr = cap.read()
        if not ok:
            break
        frames.append(cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY))
    cap.release()
    return frames


def track(name: str, frames: list[np.ndarray], start: Point, w: int, h: int, search: int) -> list[Point | None]:
    """Centres from a run over frames that starts on frames[0] at the centre `start`.

    The tracker gets the integer box nearest `start`; the rounding remainder is
    added back to every reported centre, so the run starts exactly at `start`."""
    bx, by = round_half_up(start[0] - (w - 1) / 2), round_half_up(start[1] - (h - 1) / 2)
    off = (start[0] - bx, start[1] - by)
    box = (bx, by, w, h)
    if name == "match":
        tpl = frames[0][by:by + h, bx:bx + w].astype(np.float32)
        tops = track_template((f.astype(np.float32) for f in frames[1:]), tpl, (bx, by), search)
    else:
        tops = track_cv(factory(name)[0](), frames, box)
    return [None if t is None else (t[0] + off[0], t[1] + off[1]) for t in tops]


def motion(frames: list[np.ndarray], centres: list[Point | None], w: int, h: int) -> float:
    """Largest step of the object between consecutive frames, independent of any tracker's own
    step: the w x h patch at `centres[t-1]` (CSRT's) is found in frame t by NCC within
    +-MOTION_REACH px; steps whose best score is below MOTION_SCORE are not counted."""
    best = 0.0
    for t in range(1, len(frames)):
        c = centres[t - 1]
        if c is None:
            continue
        x, y = round_half_up(c[0] - (w - 1) / 2), round_half_up(c[1] - (h - 1) / 2)
        H, W = frames[t].shape
        if x < 0 or y < 0 or x + w > W or y + h > H:
            continue
        x0, y0 = max(0, x - MOTION_REACH), max(0, y - MOTION_REACH)
        x1, y1 = min(W, x + w + MOTION_REACH), min(H, y + h + MOTION_REACH)
        res = cv2.matchTemplate(frames[t][y0:y1, x0:x1], frames[t - 1][y:y + h, x:x + w], cv2.TM_CCOEFF_NORMED)
        _, score, _, (px, py) = cv2.minMaxLoc(res)
        if np.isfinite(score) and score >= MOTION_SCORE:
            best = max(best, math.hypot(x0 + px - x, y0 + py - y))
    return best


def damage(clean: list[np.ndarray], bugy: list[np.ndarray]) -> list[tuple]:
    """Per frame of Megamind_bugy: mean |difference| from Megamind's same frame (gray levels),
    % of pixels differing by more than 30, and which of Megamind's frames i-1, i, i+1 is
    nearest (so a repeated or shifted frame shows)."""
    rows = []
    for i, b in enumerate(bugy):
        near = [(float(np.abs(b.astype(np.int16) - clean[j].astype(np.int16)).mean()), j)
                for j in (i - 1, i, i + 1) if 0 <= j < len(clean)]
        d = np.abs(b.astype(np.int16) - clean[i].astype(np.int16))
        rows.append((i, float(d.mean()), 100.0 * float((d > 30).mean()), min(near)[1]))
    return rows


def dist(p: Point, q: Point) -> float:
    """Euclidean distance between two centres."""
    return math.hypot(p[0] - q[0], p[1] - q[1])


def fmt(v: float | None, digits: int = 3) -> str:
    """A CSV cell: the value with `digits` decimals, empty for None."""
    return "" if v is None else f"{v:.{digits}f}"


def read_objects(path: Path) -> list[dict]:
    """The objects file's rows, with the frame and box columns as integers."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    want = ["clip", "object", "first", "last", "x", "y", "w", "h"]
    if not rows or list(rows[0].keys()) != want:
        raise RuntimeError(f"{path}: expected the header {','.join(want)} and at least one object")
    for r in rows:
        for k in want[2:]:
            r[k] = int(r[k])
    return rows


README = """# OpenCV baselines on real clips (no ground truth)

Made by `scripts/opencv_footage.py` from Debian `opencv-doc`'s example clips
(`{data}`) and the objects of `fixtures/footage/objects.csv` (what they are and why:
`fixtures/footage/README.md`). Command, from the repository root:

```sh
{command}
```

Clips (SHA-256 of the files read): {hashes}.

OpenCV **{cv_version}** (Python module `cv2`; {factories}), numpy {np_version},
Python {py_version}; `cv2.setNumThreads(1)`.

## Files

* `<clip>-<object>.<tracker>.csv`: `frame,x,y,back_x,back_y` for frames `first`..`last`:
  the forward run's box centre (`x,y`) and the backward run's (`back_x,back_y`), 3
  decimals, empty where the run reports none. A box's centre is
  `(x + (w-1)/2, y + (h-1)/2)`; pixel centres are at integer coordinates, (0,0) is the
  centre of the top-left pixel.
* `damage.csv` (when both Megamind clips are tracked): `frame,mean_abs_diff,changed_pct,nearest_clean_frame`,
  every frame of `Megamind_bugy.avi` against `Megamind.avi`'s same frame (gray): mean
  absolute difference, % of pixels differing by more than 30 levels, and which of
  `Megamind.avi`'s frames i-1, i, i+1 is nearest. Undamaged frames differ by about 1.2
  levels (re-encoding); damaged ones stand out (`fixtures/footage/README.md`).
* `summary.csv`: `clip,object,tracker,frames,positions,back_positions,fb_first_px,fb_mean_px,csrt_frames,csrt_mean_px,csrt_within5_pct`.

## Method

Frames are decoded by `cv2.VideoCapture` (FFmpeg backend, 0-based in decoding order)
and converted to gray (`cv2.COLOR_BGR2GRAY`). Every tracker runs **forward** from
`first` to `last` starting from the object's box, then **backward** from `last` to
`first`, started afresh on frame `last` from the integer box nearest its own forward
box there (top-left rounded half up); the rounding remainder is added back to the
backward centres, so the backward run starts exactly on the forward centre. With no
forward position at `last` the backward run is empty.

| tracker | what runs |
|---|---|
| `match` | `cv2.matchTemplate(..., TM_CCOEFF_NORMED)` of the start frame's w x h template (fixed for the run) in a window of +-`SEARCH` px around the last box (clipped to the image), peak refined by a 1-D parabola in x and in y separately; best score < {min_score} gives no position and the search stays around the last known box. `SEARCH`: {search} |
| `csrt` | `{csrt}()`, default parameters |
| `kcf` | `{kcf}()`, default parameters |
| `mosse` | `{mosse}()`, default parameters |

`csrt`, `kcf` and `mosse` get the gray frame replicated to 3-channel BGR and the
integer box; `update()` returning False means no position that frame (the tracker
keeps running). The search margins are about twice the largest frame-to-frame motion
of the clip's objects, and at least 8 px ({steps}): the w x h patch at CSRT's forward centre in frame
t-1 found in frame t by NCC within +-{reach} px, steps with a best score below
{mscore} not counted (CSRT's own steps are no measure of motion: where it jumps, the
patch barely moves). The clips, their damaged frames and shot cuts:
`fixtures/footage/README.md`.

Scores (no ground truth), per object and tracker, over frames `first`..`last`
(`frames` is their number):

* `positions` / `back_positions`: frames with a forward / backward position.
* `fb_first_px`: forward-backward error, the distance between the start centre and
  the backward run's centre at `first` (empty if the backward run has none there).
* `fb_mean_px`: mean distance between the forward and backward centres over the frames
  where both exist.
* `csrt_frames`, `csrt_mean_px`, `csrt_within5_pct`: agreement with CSRT's forward run,
  over the frames where both report: their number, the mean distance between the two
  centres and the % of them within {loss_px:g} px (empty for CSRT itself).

## Summary

{table}
"""

HEADER = ("clip", "object", "tracker", "frames", "positions", "back_positions", "fb_first_px",
          "fb_mean_px", "csrt_frames", "csrt_mean_px", "csrt_within5_pct")


def main() -> int:
    ap = argparse.ArgumentParser(description="OpenCV tracking baselines on opencv-doc's real clips")
    ap.add_argument("--data", default=str(DATA), help="folder with the clips (<clip>.avi)")
    ap.add_argument("--objects", default=str(REPO / "fixtures" / "footage" / "objects.csv"))
    ap.add_argument("--out", default=str(REPO / "fixtures" / "opencv" / "footage"))
    args = ap.parse_args()
    t0 = time.monotonic()
    cv2.setNumThreads(1)
    data, out = Path(args.data), Path(args.out)
    try:
        objects = read_objects(Path(args.objects))
    except (OSError, ValueError, RuntimeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    out.mkdir(parents=True, exist_ok=True)
    clips: dict[str, list[np.ndarray]] = {}
    summary, steps = [], {}
    for obj in objects:
        clip, name, a, b = obj["clip"], obj["object"], obj["first"], obj["last"]
        if clip not in SEARCH:
            print(f"error: {clip}: no search margin for this clip in SEARCH", file=sys.stderr)
            return 1
        if clip not in clips:
            try:
                clips[clip] = read_clip(data / f"{clip}.avi")
            except RuntimeError as e:
                print(f"error: {e}", file=sys.stderr)
                return 1
        w, h = obj["w"], obj["h"]
        if not 0 <= a < b < len(clips[clip]):
            print(f"error: {clip}-{name}: frames {a}..{b} outside the clip's 0..{len(clips[clip]) - 1}",
                  file=sys.stderr)
            return 1
        H, W = clips[clip][a].shape
        if not (0 < w <= 32 and 0 < h <= 32 and obj["x"] >= 0 and obj["y"] >= 0
                and obj["x"] + w <= W and obj["y"] + h <= H):
            print(f"error: {clip}-{name}: box must be at most 32x32 and inside the {W}x{H} frame",
                  file=sys.stderr)
            return 1
        frames = clips[clip][a:b + 1]
        start = (obj["x"] + (w - 1) / 2, obj["y"] + (h - 1) / 2)
        runs = {}
        for tr in TRACKERS:
            fwd = track(tr, frames, start, w, h, SEARCH[clip])
            back = [None] * len(frames)
            if fwd[-1] is not None:
                back = track(tr, frames[::-1], fwd[-1], w, h, SEARCH[clip])[::-1]
            runs[tr] = (fwd, back)
        csrt = runs["csrt"][0]
        steps[clip] = max(steps.get(clip, 0.0), motion(frames, csrt, w, h))
        line = []
        for tr in TRACKERS:
            fwd, back = runs[tr]
            with open(out / f"{clip}-{name}.{tr}.csv", "w", newline="") as f:
                f.write("frame,x,y,back_x,back_y\n")
                for t, (p, q) in enumerate(zip(fwd, back)):
                    f.write(f"{a + t},{fmt(p and p[0])},{fmt(p and p[1])},{fmt(q and q[0])},{fmt(q and q[1])}\n")
            fb = [dist(p, q) for p, q in zip(fwd, back) if p is not None and q is not None]
            agree = [dist(p, q) for p, q in zip(fwd, csrt) if p is not None and q is not None]
            row = (clip, name, tr, len(frames), sum(p is not None for p in fwd), sum(q is not None for q in back),
                   None if back[0] is None else dist(start, back[0]),
                   sum(fb) / len(fb) if fb else None,
                   None if tr == "csrt" else len(agree),
                   None if tr == "csrt" or not agree else sum(agree) / len(agree),
                   None if tr == "csrt" or not agree else 100.0 * sum(d <= LOSS_PX for d in agree) / len(agree))
            summary.append(row)
            line.append(f"{tr} {row[4]}/{row[3]} fb {fmt(row[6])}")
        print(f"{clip}-{name} ({a}..{b}): " + "; ".join(line), flush=True)

    if "Megamind" in clips and "Megamind_bugy" in clips and len(clips["Megamind"]) == len(clips["Megamind_bugy"]):
        with open(out / "damage.csv", "w", newline="") as f:
            f.write("frame,mean_abs_diff,changed_pct,nearest_clean_frame\n")
            for i, m, c, j in damage(clips["Megamind"], clips["Megamind_bugy"]):
                f.write(f"{i},{m:.2f},{c:.2f},{j}\n")

    def cells(r):
        return [str(r[0]), r[1], r[2], str(r[3]), str(r[4]), str(r[5]), fmt(r[6]), fmt(r[7]),
                "" if r[8] is None else str(r[8]), fmt(r[9]), fmt(r[10], 1)]

    with open(out / "summary.csv", "w", newline="") as f:
        f.write(",".join(HEADER) + "\n")
        for r in summary:
            f.write(",".join(cells(r)) + "\n")
    rows = ["| " + " | ".join(HEADER) + " |", "|---|---|---|" + "---:|" * (len(HEADER) - 3)]
    rows += ["| " + " | ".join(cells(r)) + " |" for r in summary]
    opts = []
    for flag, val, default in (("--data", args.data, str(DATA)),
                               ("--objects", args.objects, str(REPO / "fixtures" / "footage" / "objects.csv")),
                               ("--out", args.out, str(REPO / "fixtures" / "opencv" / "footage"))):
        if Path(val).resolve() != Path(default).resolve():
            opts.append(f" {flag} {val}")
    (out / "README.md").write_text(README.format(
        hashes=", ".join(f"`{c}.avi` {hashlib.sha256((data / f'{c}.avi').read_bytes()).hexdigest()}" for c in clips),
        data=data, command="python3 scripts/opencv_footage.py" + "".join(opts),
        cv_version=cv2.__version__, np_version=np.__version__, py_version=sys.version.split()[0],
        factories=", ".join(factory(t)[1] for t in TRACKERS[1:]),
        min_score=MIN_SCORE,
        search=", ".join(f"{c} {m} px" for c, m in SEARCH.items()),
        steps=", ".join(f"{c} {s:.1f} px" for c, s in steps.items()),
        reach=MOTION_REACH, mscore=MOTION_SCORE,
        csrt=factory("csrt")[1], kcf=factory("kcf")[1], mosse=factory("mosse")[1], loss_px=LOSS_PX,
        table="\n".join(rows)))
    print(f"wrote {len(summary)} tracker CSVs, summary.csv and README.md to {out} in {time.monotonic() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
