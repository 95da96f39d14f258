#!/usr/bin/env python3
"""OpenCV tracking baselines on the rendered real-image sequences.

    python3 scripts/opencv_real.py SEQ_ROOT [--out fixtures/opencv/real]

SEQ_ROOT holds one folder per condition (centre-pendulum-40, corner-plain,
...), each with frame_00000.png, frame_00001.png, ... (8-bit gray, sorted by
number) and groundtruth.csv (frame,centre_x,centre_y,corner_x,corner_y,visible).
Folders named centre-* are scored on the centre columns, corner-* on the corner
columns. Pixel centres are at integer coordinates, (0,0) the top-left pixel.

Three trackers start on frame 0 from a 20x20 box centred on the true point p0:
box top-left b0 = round(p0 - 9.5) (round half up). The tracked point of every
frame is box position + (p0 - b0), so a perfect tracker reports the true point.
Frame 0 reports the initial point.

  match  cv2.matchTemplate(TM_CCOEFF_NORMED) of the frame-0 20x20 template
         over a search window of +-16 px around the last box (clipped to the
         image); the best peak is refined with a 1-D parabola through the
         peak and its neighbours in x and in y separately (no refinement on
         the result border). Score < 0.5: no position that frame, and the
         next search stays around the last known box.
  csrt   cv2.TrackerCSRT_create() (cv2.legacy.TrackerCSRT_create() when the
         main-namespace factory is missing), default parameters.
  kcf    cv2.TrackerKCF_create() (or cv2.legacy), default parameters.
         Both get the frames as 3-channel BGR (gray replicated), init with the
         integer box (b0, 20, 20); update() == False means no position.

Output (in --out):
  <condition>.<tracker>.csv   frame,x,y  (x,y empty when no position, 3 decimals)
  summary.csv                 condition,tracker,frames,rms_px,loss_pct
  README.md                   what the files are, the OpenCV version, the command

Scoring, over the frames where the target is visible (frames = their count):
error = distance of the reported point to the true point; rms_px = RMS error
over the visible frames that have a position (empty if none); loss_pct =
percentage of visible frames with error > 5 px or no position.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path
from typing import Iterable

import cv2
import numpy as np

# The sequence readers are shared with the ground-truth check (same folder as this script).
from real_images import frame_files, read_gray

REPO = Path(__file__).resolve().parent.parent
BOX = 20
SEARCH = 16
MIN_SCORE = 0.5
LOSS_PX = 5.0
TRACKERS = ("match", "csrt", "kcf")


def read_truth(folder: Path, kind: str) -> dict[int, tuple[float, float, bool]]:
    out = {}
    with open(folder / "groundtruth.csv", newline="") as f:
        for r in csv.DictReader(f):
            out[int(r["frame"])] = (float(r[f"{kind}_x"]), float(r[f"{kind}_y"]), int(r["visible"]) != 0)
    return out


def round_half_up(v: float) -> int:
    return int(math.floor(v + 0.5))


def parabola(a: float, b: float, c: float) -> float:
    """Vertex offset of the parabola through (-1,a), (0,b), (1,c)."""
    den = a - 2.0 * b + c
    return 0.0 if den == 0.0 else 0.5 * (a - c) / den


def factory(name: str):
    attr = {"csrt": "TrackerCSRT_create", "kcf": "TrackerKCF_create", "mosse": "TrackerMOSSE_create"}[name]
    if hasattr(cv2, attr):
        return getattr(cv2, attr), f"cv2.{attr}"
    if hasattr(cv2, "legacy") and hasattr(cv2.legacy, attr):
        return getattr(cv2.legacy, attr), f"cv2.legacy.{attr}"
    raise RuntimeError(f"this OpenCV ({cv2.__version__}) has no {attr}")


def track_template(images: Iterable[np.ndarray], tpl: np.ndarray, b0: tuple[int, int],
                   search: int) -> list[tuple[float, float] | None]:
    """Top-left of the fixed template's best placement: b0 for the start frame, then one entry
    per image of `images` (float32 gray, the frames after the start)."""
    th, tw = tpl.shape
    out: list[tuple[float, float] | None] = [(float(b0[0]), float(b0[1]))]
    last = (float(b0[0]), float(b0[1]))
    for img in images:
        h, w = img.shape
        lx, ly = round_half_up(last[0]), round_half_up(last[1])
        x0, y0 = max(0, lx - search), max(0, ly - search)
        x1, y1 = min(w, lx + tw + search), min(h, ly + th + search)
        if x1 - x0 < tw or y1 - y0 < th:
            out.append(None)
            continue
        res = cv2.matchTemplate(img[y0:y1, x0:x1], tpl, cv2.TM_CCOEFF_NORMED)
        _, score, _, (px, py) = cv2.minMaxLoc(res)
        if not np.isfinite(score) or score < MIN_SCORE:
            out.append(None)
            continue
        dx = parabola(res[py, px - 1], res[py, px], res[py, px + 1]) if 0 < px < res.shape[1] - 1 else 0.0
        dy = parabola(res[py - 1, px], res[py, px], res[py + 1, px]) if 0 < py < res.shape[0] - 1 else 0.0
        last = (x0 + px + dx, y0 + py + dy)
        out.append(last)
    return out


def run_match(frames: list[Path], b0: tuple[int, int]) -> list[tuple[float, float] | None]:
    f0 = read_gray(frames[0]).astype(np.float32)
    tpl = f0[b0[1]:b0[1] + BOX, b0[0]:b0[0] + BOX].copy()
    return track_template((read_gray(p).astype(np.float32) for p in frames[1:]), tpl, b0, SEARCH)


def track_cv(tracker, images: Iterable[np.ndarray], box: tuple[int, int, int, int]) -> list[tuple[float, float] | None]:
    """Top-left of an OpenCV tracker's box in every image (8-bit gray, the first is the start,
    given as 3-channel BGR); update() == False gives None."""
    bgr = lambda g: cv2.cvtColor(g, cv2.COLOR_GRAY2BGR)
    it = iter(images)
    tracker.init(bgr(next(it)), tuple(int(v) for v in box))
    out: list[tuple[float, float] | None] = [(float(box[0]), float(box[1]))]
    for img in it:
        ok, b = tracker.update(bgr(img))
        out.append((float(b[0]), float(b[1])) if ok else None)
    return out


def run_cv_tracker(name: str, frames: list[Path], b0: tuple[int, int]) -> list[tuple[float, float] | None]:
    return track_cv(factory(name)[0](), (read_gray(p) for p in frames), (b0[0], b0[1], BOX, BOX))


def score(points, truth) -> tuple[int, float | None, float]:
    visible, errs, lost = 0, [], 0
    for t, p in enumerate(points):
        if t not in truth or not truth[t][2]:
            continue
        visible += 1
        if p is None:
            lost += 1
            continue
        e = math.hypot(p[0] - truth[t][0], p[1] - truth[t][1])
        errs.append(e)
        if e > LOSS_PX:
            lost += 1
    rms = math.sqrt(sum(e * e for e in errs) / len(errs)) if errs else None
    return visible, rms, (100.0 * lost / visible if visible else 0.0)


README = """# OpenCV baselines on the real-image sequences

Made by `scripts/opencv_real.py` from the sequences that coopwin renders from
`fixtures/real/` (one folder per condition under SEQ_ROOT). Command, from the
repository root:

```sh
{command}
```

OpenCV **{cv_version}** (Python module `cv2`, {factories}), numpy {np_version},
Python {py_version}.

## Files

* `<condition>.<tracker>.csv`: `frame,x,y`, the point the tracker reports in every
  frame (x and y empty when it reports none), 3 decimals. Pixel centres are at
  integer coordinates, (0,0) is the centre of the top-left pixel.
* `summary.csv`: `condition,tracker,frames,rms_px,loss_pct`.
* `<condition>.fingerprint`: the fingerprint of the sequence the trackers ran on, as
  `coopwin` wrote it; `testbench/tests/real_images.rs` fails when the current renderer
  makes a different sequence (the fixtures are then stale: rerun the command above).

## Method

`centre-*` conditions track the `centre_x,centre_y` columns of `groundtruth.csv`,
`corner-*` conditions the `corner_x,corner_y` columns. Every tracker starts on frame 0
from the 20x20 box centred on the true point p0: top-left b0 = round(p0 - 9.5),
rounding half up. The reported point is box position + (p0 - b0), so a perfect
tracker reports the true point. Frame 0 reports the initial point.

| tracker | what runs |
|---|---|
| `match` | `cv2.matchTemplate(..., TM_CCOEFF_NORMED)` of the frame-0 20x20 template in a window of +-16 px around the last box (clipped to the image), peak refined by a 1-D parabola in x and in y separately; best score < 0.5 gives no position and the search stays around the last known box |
| `csrt` | `{csrt}()` with default parameters |
| `kcf` | `{kcf}()` with default parameters |

`csrt` and `kcf` get the gray frames replicated to 3-channel BGR and the integer
box `(b0x, b0y, 20, 20)`; `update()` returning False means no position that frame.
Their boxes are integer rectangles in this OpenCV version, so they report
whole-pixel positions (plus the constant sub-pixel offset p0 - b0).

Scoring, over the frames where `visible` = 1 (`frames` is their number, frame 0
included): error = distance from the reported point to the true point; `rms_px` =
RMS error over those frames that have a position (empty if none); `loss_pct` = % of
those frames with error > 5 px or no position.

## Summary

{table}
"""


def main() -> int:
    ap = argparse.ArgumentParser(description="OpenCV tracking baselines on rendered real-image sequences")
    ap.add_argument("seq_root")
    ap.add_argument("--out", default=str(REPO / "fixtures" / "opencv" / "real"))
    args = ap.parse_args()
    root, out = Path(args.seq_root), Path(args.out)
    if not root.is_dir():
        print(f"error: {root} is not a directory", file=sys.stderr)
        return 1
    conds = sorted(p for p in root.iterdir()
                   if p.is_dir() and p.name.split("-")[0] in ("centre", "corner")
                   and (p / "groundtruth.csv").is_file())
    if not conds:
        print(f"error: no centre-*/corner-* folders with groundtruth.csv under {root}", file=sys.stderr)
        return 1
    out.mkdir(parents=True, exist_ok=True)
    print(f"OpenCV {cv2.__version__}: csrt = {factory('csrt')[1]}, kcf = {factory('kcf')[1]}")
    summary = []
    for cond in conds:
        kind = cond.name.split("-")[0]
        truth = read_truth(cond, kind)
        frames = frame_files(cond)
        if not frames or 0 not in truth:
            print(f"error: {cond}: no frames or no ground truth for frame 0", file=sys.stderr)
            return 1
        p0 = truth[0][:2]
        b0 = (round_half_up(p0[0] - 9.5), round_half_up(p0[1] - 9.5))
        off = (p0[0] - b0[0], p0[1] - b0[1])
        line = []
        for name in TRACKERS:
            boxes = run_match(frames, b0) if name == "match" else run_cv_tracker(name, frames, b0)
            pts = [None if b is None else (b[0] + off[0], b[1] + off[1]) for b in boxes]
            with open(out / f"{cond.name}.{name}.csv", "w", newline="") as f:
                f.write("frame,x,y\n")
                for t, p in enumerate(pts):
                    f.write(f"{t},,\n" if p is None else f"{t},{p[0]:.3f},{p[1]:.3f}\n")
            n, rms, loss = score(pts, truth)
            summary.append((cond.name, name, n, rms, loss))
            line.append(f"{name} rms {'-' if rms is None else f'{rms:.3f}'} loss {loss:.1f}%")
        print(f"{cond.name}: {len(frames)} frames ({kind} point); " + "; ".join(line), flush=True)
        # The sequence's fingerprint, written by `coopwin experiment real-images --sequences`:
        # the Rust test compares it with a fresh rendering, so stale fixtures fail.
        fp = cond / "fingerprint.txt"
        if fp.exists():
            (out / f"{cond.name}.fingerprint").write_text(fp.read_text())
    with open(out / "summary.csv", "w", newline="") as f:
        f.write("condition,tracker,frames,rms_px,loss_pct\n")
        for c, t, n, rms, loss in summary:
            f.write(f"{c},{t},{n},{'' if rms is None else f'{rms:.3f}'},{loss:.1f}\n")
    rows = ["| condition | tracker | frames | rms_px | loss_pct |", "|---|---|---:|---:|---:|"]
    rows += [f"| {c} | {t} | {n} | {'' if rms is None else f'{rms:.3f}'} | {loss:.1f} |"
             for c, t, n, rms, loss in summary]
    try:
        rel = out.resolve().relative_to(REPO)
        out_arg = "" if rel == Path("fixtures/opencv/real") else f" --out {rel}"
    except ValueError:
        out_arg = f" --out {out}"
    command = f"python3 scripts/opencv_real.py {args.seq_root}{out_arg}"
    (out / "README.md").write_text(README.format(
        command=command, cv_version=cv2.__version__, np_version=np.__version__,
        py_version=sys.version.split()[0], factories=f"{factory('csrt')[1]}, {factory('kcf')[1]}",
        csrt=factory("csrt")[1], kcf=factory("kcf")[1], table="\n".join(rows)))
    print()
    print(f"{'condition':<24}{'tracker':<8}{'frames':>7}{'rms_px':>9}{'loss_pct':>9}")
    for c, t, n, rms, loss in summary:
        print(f"{c:<24}{t:<8}{n:>7}{'' if rms is None else f'{rms:.3f}':>9}{loss:>9.1f}")
    print(f"wrote {len(summary)} tracker CSVs, summary.csv and README.md to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
