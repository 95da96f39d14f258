#!/usr/bin/env python3
"""Hand ground truth for the long-term evaluation (issue 38, item 6): proposals and contact sheets.

The labels are keyframes, one file per object, `fixtures/longterm/<clip>/<object>.csv`:

    frame,x,y,w,h,state

every 5th frame (and at shot cuts and damaged frames of the footage clips), `state` one of
`visible`, `hidden` (more than half of the object covered; the box is where it is behind the
cover, or empty when that cannot be seen, e.g. an earring turned away), `gone` (out of the
view; x,y,w,h empty). Boxes follow OpenCV's convention: the box covers
pixel columns x..x+w-1 and rows y..y+h-1 of the full frame, pixel centres at integer
coordinates, frames numbered from 0 in decoding order (cv2.VideoCapture). The labels are
written by a person looking at the sheets this script renders; the script only proposes.

Commands (clip = file stem in --data, e.g. vtest; frames are decoded once per run):

  propose CLIP OBJECT FRAME X,Y,W,H --to LAST
      Run CSRT (cv2.TrackerCSRT_create, colour frames) from FRAME with the box, forward to
      LAST (or backward when LAST < FRAME), and write its box on every 5th frame into the
      object's label file as `visible` rows, replacing the rows strictly after FRAME up to
      LAST (before FRAME when going backward), and FRAME itself when it has no row yet. Each proposal is also appended to
      --work/<clip>-<object>.proposals.csv, which `count` compares the labels with.
  sheet CLIP OBJECT [--from F] [--to T] [--per 20] [--disagree | --consensus]
      Contact sheets of the keyframes: a zoomed crop around each box (the label's box in
      green, CSRT's forward box from the object's start in red, dashed when CSRT reports
      failure), frame number and state printed, coordinate ticks every 10 px on the crop's
      edges (labelled every 50). PNGs in --work. --disagree: only the keyframes `check` lists.
  check CLIP OBJECT
      Keyframes where the label and CSRT's forward run from the start box disagree by more
      than half a box (centre distance > half the label's smaller side), or where one of
      them has a box and the other not: the frames to look at a second time. Then the
      keyframes where two or more of OpenCV's trackers in fixtures/longterm/opencv agree
      with each other (centres within 8 px) off the label (`sheet --consensus` shows them).
  count CLIP
      Per object: keyframes and what became of CSRT's last proposal for each (kept, box
      redrawn by hand, only marked hidden, marked gone; see cmd_count), the second look's
      count, and interpolated frames per state.
  interpolate CLIP OBJECT
      Print the per-frame labels (see `interpolate()`).

The objects of a clip are listed in fixtures/longterm/<clip>/objects.csv
(object,first,last,x,y,w,h: the first and last labelled frames and the start box).
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

import cv2
import numpy as np

REPO = Path(__file__).resolve().parent.parent
DATA = Path("/usr/share/doc/opencv-doc/examples/data")
STEP = 5  # keyframe spacing
STATES = ("visible", "hidden", "gone")

Box = tuple[float, float, float, float]


def read_clip(path: Path) -> list[np.ndarray]:
    """Every decodable frame, colour (BGR)."""
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        sys.exit(f"{path}: cv2.VideoCapture cannot open it (apt-get install opencv-doc?)")
    frames = []
    while True:
        ok, f = cap.read()
        if not ok:
            break
        frames.append(f)
    return frames


def read_labels(path: Path) -> dict[int, tuple[Box | None, str]]:
    """Keyframes of one object: frame -> (box or None, state)."""
    out = {}
    if not path.exists():
        return out
    with path.open() as fh:
        for r in csv.DictReader(fh):
            if r["state"] not in STATES:
                sys.exit(f"{path}: frame {r['frame']}: state {r['state']!r} is not one of {STATES}")
            box = None if r["x"] == "" else tuple(float(r[k]) for k in "xywh")
            if box is None and r["state"] == "visible":
                sys.exit(f"{path}: frame {r['frame']}: a visible row needs a box")
            out[int(r["frame"])] = (box, r["state"])
    return out


def write_labels(path: Path, labels: dict[int, tuple[Box | None, str]]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["frame", "x", "y", "w", "h", "state"])
        for f in sorted(labels):
            box, state = labels[f]
            w.writerow([f, *(["", "", "", ""] if box is None else [int(round(v)) for v in box]), state])


def interpolate(labels: dict[int, tuple[Box | None, str]]) -> dict[int, tuple[Box | None, str]]:
    """Per-frame labels from the first keyframe to the last. Between keyframes k0 < f < k1 the
    state is k0's (a hidden or gone label holds until the next keyframe, and so does visible);
    the box is the linear interpolation of k0's and k1's boxes when both have one
    (x0 + (x1 - x0) * (f - k0) / (k1 - k0), per coordinate, unrounded), k0's box when k1 has
    none, and none when k0 has none."""
    keys = sorted(labels)
    out = {}
    for k0, k1 in zip(keys, keys[1:]):
        b0, s0 = labels[k0]
        b1, _ = labels[k1]
        for f in range(k0, k1):
            t = (f - k0) / (k1 - k0)
            box = None if b0 is None else b0 if b1 is None else tuple(a + (b - a) * t for a, b in zip(b0, b1))
            out[f] = (box, s0)
    if keys:
        out[keys[-1]] = labels[keys[-1]]
    return out


def csrt_run(frames: list[np.ndarray], start: int, box: Box, last: int) -> dict[int, Box | None]:
    """CSRT's box on every frame from `start` to `last` (either direction), None on failure."""
    tr = cv2.TrackerCSRT_create()
    tr.init(frames[start], tuple(int(round(v)) for v in box))
    step = 1 if last >= start else -1
    out: dict[int, Box | None] = {start: box}
    for f in range(start + step, last + step, step):
        ok, b = tr.update(frames[f])
        out[f] = tuple(float(v) for v in b) if ok else None
    return out


def label_path(clip: str, obj: str) -> Path:
    return REPO / "fixtures" / "longterm" / clip / f"{obj}.csv"


def objects(clip: str) -> dict[str, tuple[int, int, Box]]:
    path = REPO / "fixtures" / "longterm" / clip / "objects.csv"
    with path.open() as fh:
        return {r["object"]: (int(r["first"]), int(r["last"]), tuple(float(r[k]) for k in "xywh"))
                for r in csv.DictReader(fh)}


def parse_box(s: str) -> Box:
    v = [float(p) for p in s.split(",")]
    if len(v) != 4:
        raise argparse.ArgumentTypeError(f"{s!r}: expected X,Y,W,H")
    return tuple(v)


def cmd_propose(a, frames) -> None:
    path = label_path(a.clip, a.object)
    labels = read_labels(path)
    run = csrt_run(frames, a.frame, a.box, a.to)
    lo, hi = sorted((a.frame, a.to))
    log = a.work / f"{a.clip}-{a.object}.proposals.csv"
    new = not log.exists()
    with log.open("a", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        if new:
            w.writerow(["frame", "x", "y", "w", "h", "state"])
        for f in range(lo, hi + 1):
            if f % STEP and f != a.frame or f == a.frame and a.frame in labels:
                continue
            b = run[f]
            if b is None:
                print(f"frame {f}: CSRT reports failure; keyframe left as it was")
                continue
            labels[f] = (b, "visible")
            w.writerow([f, *[int(round(v)) for v in b], "visible"])
    write_labels(path, labels)
    print(f"{path}: {len(labels)} keyframes")


def csrt_reference(frames, clip: str, obj: str) -> dict[int, Box | None]:
    """CSRT's forward run from the object's start box, cached in --work."""
    first, last, box = objects(clip)[obj]
    cache = ARGS.work / f"{clip}-{obj}.csrt.csv"
    if cache.exists():
        with cache.open() as fh:
            rows = {int(r["frame"]): None if r["x"] == "" else tuple(float(r[k]) for k in "xywh")
                    for r in csv.DictReader(fh)}
        if min(rows) == first and max(rows) == last and rows[first] == box:
            return rows
    rows = csrt_run(frames, first, box, last)
    with cache.open("w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["frame", "x", "y", "w", "h"])
        for f, b in sorted(rows.items()):
            w.writerow([f, *(["", "", "", ""] if b is None else b)])
    return rows


def centre(b: Box) -> tuple[float, float]:
    return b[0] + (b[2] - 1) / 2, b[1] + (b[3] - 1) / 2


def draw_box(img, box: Box, ox: int, oy: int, z: float, colour, dashed=False) -> None:
    x0, y0 = (box[0] - ox) * z, (box[1] - oy) * z
    x1, y1 = (box[0] + box[2] - ox) * z, (box[1] + box[3] - oy) * z
    p = [(int(x0), int(y0)), (int(x1), int(y0)), (int(x1), int(y1)), (int(x0), int(y1))]
    for i in range(4):
        a, b = p[i], p[(i + 1) % 4]
        if not dashed:
            cv2.line(img, a, b, colour, 1)
            continue
        n = max(1, int(math.hypot(b[0] - a[0], b[1] - a[1]) // 6))
        for k in range(0, n, 2):
            s = (a[0] + (b[0] - a[0]) * k // n, a[1] + (b[1] - a[1]) * k // n)
            e = (a[0] + (b[0] - a[0]) * (k + 1) // n, a[1] + (b[1] - a[1]) * (k + 1) // n)
            cv2.line(img, s, e, colour, 1)


def cmd_sheet(a, frames) -> None:
    labels = read_labels(label_path(a.clip, a.object))
    ref = csrt_reference(frames, a.clip, a.object)
    keys = [f for f in sorted(labels) if a.first <= f <= a.last]
    cv_rows = opencv_rows(a.clip, a.object) if a.consensus else {}
    if a.disagree:
        odd = {f for f, _ in disagreements(labels, ref)}
        keys = [f for f in keys if f in odd]
    if a.consensus:
        odd = {f for f, _ in consensus(labels, cv_rows)}
        keys = [f for f in keys if f in odd]
    if not keys:
        print("no keyframes to show")
        return
    H, W = frames[0].shape[:2]
    CW, CH, Z = 150, 190, 1.5  # crop size (source px) and zoom
    last_box = None
    tiles = []
    for f in keys:
        box, state = labels[f]
        seen = [rows[f] for rows in cv_rows.values() if f in rows and off_label(rows[f], labels[f])]
        last_box = box or (seen[0] if seen else None) or last_box or ref.get(f)
        cx, cy = centre(last_box) if last_box else (W / 2, H / 2)
        ox = int(min(max(cx - CW / 2, 0), W - CW))
        oy = int(min(max(cy - CH / 2, 0), H - CH))
        crop = cv2.resize(frames[f][oy:oy + CH, ox:ox + CW], None, fx=Z, fy=Z, interpolation=cv2.INTER_NEAREST)
        tile = cv2.copyMakeBorder(crop, 14, 14, 22, 4, cv2.BORDER_CONSTANT, value=(255, 255, 255))
        view = tile[14:14 + crop.shape[0], 22:22 + crop.shape[1]]
        r = ref.get(f)
        if r is not None:
            draw_box(view, r, ox, oy, Z, (0, 0, 255))
        for name, rows in cv_rows.items():
            if f in rows:
                draw_box(view, rows[f], ox, oy, Z, OPENCV_COLOURS[name])
        if box is not None:
            draw_box(view, box, ox, oy, Z, (0, 255, 0), dashed=state != "visible")
        for x in range((ox + 9) // 10 * 10, ox + CW, 10):
            px = 22 + int((x - ox) * Z)
            cv2.line(tile, (px, 14 + crop.shape[0]), (px, 14 + crop.shape[0] + (6 if x % 50 == 0 else 3)), (0, 0, 0), 1)
            if x % 50 == 0:
                cv2.putText(tile, str(x), (px - 10, tile.shape[0] - 1), cv2.FONT_HERSHEY_PLAIN, 0.7, (0, 0, 0), 1)
        for y in range((oy + 9) // 10 * 10, oy + CH, 10):
            py = 14 + int((y - oy) * Z)
            cv2.line(tile, (22 - (6 if y % 50 == 0 else 3), py), (21, py), (0, 0, 0), 1)
            if y % 50 == 0:
                cv2.putText(tile, str(y), (0, py - 2), cv2.FONT_HERSHEY_PLAIN, 0.7, (0, 0, 0), 1)
        text = f"{f} {state[0].upper()}" + ("" if box is None else " %d,%d,%d,%d" % tuple(round(v) for v in box))
        cv2.putText(tile, text, (22, 11), cv2.FONT_HERSHEY_PLAIN, 0.9, (0, 0, 0), 1)
        tiles.append(tile)
    cols = 5
    for s in range(0, len(tiles), a.per):
        chunk = tiles[s:s + a.per]
        chunk += [np.full_like(tiles[0], 255)] * (-len(chunk) % cols)
        rows = [np.hstack(chunk[i:i + cols]) for i in range(0, len(chunk), cols)]
        out = a.work / f"sheet-{a.clip}-{a.object}{'-second' if a.disagree else '-consensus' if a.consensus else ''}-{keys[s]:03d}.png"
        cv2.imwrite(str(out), np.vstack(rows))
        print(out)


def disagreements(labels, ref) -> list[tuple[int, str]]:
    out = []
    for f in sorted(labels):
        box, state = labels[f]
        r = ref.get(f)
        if (box is None) != (r is None):
            out.append((f, f"label {state}, CSRT {'none' if r is None else 'a box'}"))
        elif box is not None:
            d = math.dist(centre(box), centre(r))
            if d > min(box[2], box[3]) / 2:
                out.append((f, f"label {state}, centres {d:.0f} px apart"))
    return out


OPENCV = ("csrt", "kcf", "mosse", "tld")
# BGR colours of OpenCV's fixture boxes on the sheets (`--consensus`).
OPENCV_COLOURS = {"csrt": (255, 255, 0), "kcf": (0, 255, 255), "mosse": (255, 0, 255), "tld": (255, 0, 0)}


def opencv_rows(clip: str, obj: str) -> dict[str, dict[int, Box]]:
    """The boxes (ok=1 rows) of scripts/opencv_longterm.py's fixtures for one object."""
    base = REPO / "fixtures" / "longterm" / "opencv"
    folder = base if clip == "vtest" else base / clip
    out = {}
    for name in OPENCV:
        path = folder / f"{name}_{obj}.csv"
        if path.exists():
            with path.open() as fh:
                out[name] = {int(r["frame"]): tuple(float(r[k]) for k in "xywh")
                             for r in csv.DictReader(fh) if r["ok"] == "1"}
    return out


def off_label(b: Box, label) -> bool:
    """Is a tracker's box off the label (its centre outside the box and more than 5 px away)?"""
    box, _ = label
    if box is None:
        return True
    cx, cy = centre(b)
    inside = box[0] <= cx <= box[0] + box[2] - 1 and box[1] <= cy <= box[1] + box[3] - 1
    return not inside and math.dist((cx, cy), centre(box)) > 5


def consensus(labels, rows) -> list[tuple[int, str]]:
    """Keyframes where two or more of OpenCV's trackers report boxes within 8 px of each other
    (centres) and off the label: where the label, not the trackers, might be wrong."""
    out = []
    for f in sorted(labels):
        off = [(n, centre(r[f])) for n, r in rows.items() if f in r and off_label(r[f], labels[f])]
        agree = sorted({n for n, c in off for m, d in off if m != n and math.dist(c, d) <= 8})
        if len(agree) >= 2:
            out.append((f, f"label {labels[f][1]}, {' and '.join(agree)} agree elsewhere"))
    return out


def cmd_check(a, frames) -> None:
    labels = read_labels(label_path(a.clip, a.object))
    for f, why in disagreements(labels, csrt_reference(frames, a.clip, a.object)):
        print(f"{a.object} {f}: {why}")
    for f, why in consensus(labels, opencv_rows(a.clip, a.object)):
        print(f"{a.object} {f}: {why}")


def cmd_count(a, frames) -> None:
    """Keyframes per object and what the person did to CSRT's proposals: kept as proposed,
    box redrawn (a side moved by more than 2 px; any state but gone), only the state changed
    (the box kept, marked hidden), marked gone; `disagree_csrt` is the second look's count."""
    print("object,keyframes,kept,box_redrawn,state_only,gone_marked,disagree_csrt,frames,visible,hidden,gone")
    for obj in objects(a.clip):
        labels = read_labels(label_path(a.clip, obj))
        proposed = {}
        log = a.work / f"{a.clip}-{obj}.proposals.csv"
        if log.exists():
            with log.open() as fh:
                for r in csv.DictReader(fh):
                    proposed[int(r["frame"])] = tuple(float(r[k]) for k in "xywh")
        n = dict.fromkeys(("kept", "box", "state", "gone"), 0)
        for f, (box, state) in labels.items():
            p = proposed.get(f)
            if state == "gone":
                n["gone"] += 1
            elif p is None or max(abs(u - v) for u, v in zip(
                    (box[0], box[1], box[0] + box[2], box[1] + box[3]), (p[0], p[1], p[0] + p[2], p[1] + p[3]))) > 2:
                n["box"] += 1
            elif state != "visible":
                n["state"] += 1
            else:
                n["kept"] += 1
        per = interpolate(labels)
        m = {s: sum(1 for _, st in per.values() if st == s) for s in STATES}
        dis = len(disagreements(labels, csrt_reference(frames, a.clip, obj)))
        print(f"{obj},{len(labels)},{n['kept']},{n['box']},{n['state']},{n['gone']},{dis},"
              f"{len(per)},{m['visible']},{m['hidden']},{m['gone']}")


def cmd_interpolate(a, frames) -> None:
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["frame", "x", "y", "w", "h", "state"])
    for f, (box, state) in sorted(interpolate(read_labels(label_path(a.clip, a.object))).items()):
        w.writerow([f, *(["", "", "", ""] if box is None else [f"{v:.2f}" for v in box]), state])


def main() -> None:
    global ARGS
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--data", type=Path, default=DATA, help="folder of the clips (default: %(default)s)")
    p.add_argument("--work", type=Path, default=Path("/tmp/longterm_annotate"),
                   help="sheets, proposal log and CSRT cache (default: %(default)s)")
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("propose")
    s.add_argument("clip"), s.add_argument("object"), s.add_argument("frame", type=int)
    s.add_argument("box", type=parse_box)
    s.add_argument("--to", type=int, required=True)
    s = sub.add_parser("sheet")
    s.add_argument("clip"), s.add_argument("object")
    s.add_argument("--from", dest="first", type=int, default=0)
    s.add_argument("--to", dest="last", type=int, default=10**9)
    s.add_argument("--per", type=int, default=20)
    s.add_argument("--disagree", action="store_true",
                   help="only the keyframes where the label and CSRT disagree (the second look)")
    s.add_argument("--consensus", action="store_true",
                   help="only the keyframes where two of OpenCV's fixture trackers agree off the label, "
                        "their boxes drawn (cyan CSRT, yellow KCF, magenta MOSSE, blue TLD)")
    for name in ("check", "interpolate"):
        s = sub.add_parser(name)
        s.add_argument("clip"), s.add_argument("object")
    s = sub.add_parser("count")
    s.add_argument("clip")
    ARGS = p.parse_args()
    ARGS.work.mkdir(parents=True, exist_ok=True)
    frames = [] if ARGS.cmd == "interpolate" else read_clip(ARGS.data / f"{ARGS.clip}.avi")
    {"propose": cmd_propose, "sheet": cmd_sheet, "check": cmd_check, "count": cmd_count,
     "interpolate": cmd_interpolate}[ARGS.cmd](ARGS, frames)


if __name__ == "__main__":
    main()
