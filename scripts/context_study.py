#!/usr/bin/env python3
"""Could a model of the object's surroundings hold the eye through its blinks? (issue 21)

    cargo build --release -p coopwin-testbench
    python3 scripts/context_study.py [--data /usr/share/doc/opencv-doc/examples/data]
        [--coopwin target/release/coopwin] [--verbose]

On the real clips of fixtures/footage/objects.csv, the eye is shut on 24 of its
97 frames: no template of the eye confirms it there, CSRT reports a position on
all of them. A tracker of the surroundings would. This measures the cheapest
such model coopwin's Peripheral processor could run: the 64x64 pixels around the
point at 25 % (32x32 samples, each the mean of 2x2 pixels, where the Peripheral's
windows take every other pixel: the means only help the model), matched by
zero-mean NCC (cv2.TM_CCOEFF_NORMED) over +-R samples (R = 8: +-16 px) around the
constant-velocity prediction, the model a running mean (1 - A) * model + A *
samples at the found point (A = 0.1).

Two uses, each scored against CSRT's forward point (fixtures/opencv/footage; for
Megamind_bugy's eye, CSRT's in Megamind.avi, the same pictures undamaged, as CSRT
loses the eye in the damaged clip at frame 40):
  free      the model alone from the object's box to its last frame;
  anchored  the model re-centred on `coopwin track`'s trusted point (ok = 1) on
            every frame that has one, searching only on the others: the frames
            it would fill in. `coopwin track` runs into a temporary folder.
  --verbose lists the anchored model's searched frames (frame, score, px from CSRT).
and the per-frame time of OpenCV's CSRT and KCF on the eye (one thread, gray
frames as BGR, best of 3), against the Cortex-M4 budget of issue 21 item 6
(8.8 ms at 168 MHz with 5x margin: 1.76 ms, 295,680 cycles).
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile
import time

import cv2
import numpy as np

# Shared with the OpenCV baselines on the same clips (same folder as this script).
from opencv_footage import read_clip

SIDE, DECIMATION, RADIUS, RATE = 64, 2, 8, 0.1
ROOT = pathlib.Path(__file__).resolve().parent.parent


def frames(clip, first, last):
    """Frames first..=last (0-based, decoding order) of a clip's gray frames, float32."""
    if len(clip) <= last:
        sys.exit(f"the clip decodes {len(clip)} frames, the object needs {first}..{last}")
    return [f.astype(np.float32) for f in clip[first:last + 1]]


def samples(img, x0, y0, side):
    """The side x side window at (x0, y0), edges replicated, as 2x2 means."""
    pad = cv2.copyMakeBorder(img, side, side, side, side, cv2.BORDER_REPLICATE)
    w = pad[y0 + side:y0 + 2 * side, x0 + side:x0 + 2 * side]
    n = side // DECIMATION
    return w.reshape(n, DECIMATION, n, DECIMATION).mean(axis=(1, 3)).astype(np.float32)


def corner(v):
    return int(round(v - (SIDE - 1) / 2))


def context_track(fr, x, y, given=None):
    """The model's point on frames 1.. (with the score of its search, None where
    `given` has the frame's point: the model is re-centred there)."""
    model = samples(fr[0], corner(x), corner(y), SIDE)
    vx = vy = 0.0
    out = []
    for k in range(1, len(fr)):
        if given and k in given:
            (nx, ny), score = given[k], None
        else:
            side = SIDE + 2 * RADIUS * DECIMATION
            wx, wy = int(round(x + vx - (side - 1) / 2)), int(round(y + vy - (side - 1) / 2))
            res = cv2.matchTemplate(samples(fr[k], wx, wy, side), model, cv2.TM_CCOEFF_NORMED)
            _, score, _, (mx, my) = cv2.minMaxLoc(res)
            nx, ny = wx + mx * DECIMATION + (SIDE - 1) / 2, wy + my * DECIMATION + (SIDE - 1) / 2
        vx, vy, x, y = nx - x, ny - y, nx, ny
        model = (1 - RATE) * model + RATE * samples(fr[k], corner(x), corner(y), SIDE)
        out.append((k, x, y, score))
    return out


def trusted(coopwin, data, o, folder):
    """`coopwin track`'s trusted points of object `o`, by frame index from `first`."""
    out = folder / f"{o['clip']}-{o['object']}.csv"
    box = ",".join(o[k] for k in "xywh")
    subprocess.run([str(coopwin), "track", "--frames", str(data / f"{o['clip']}.avi"), "--start-frame", o["first"],
                    "--target-box", box, "--out", str(out)], check=True, capture_output=True)
    first, last = int(o["first"]), int(o["last"])
    return {int(r["frame"]) - first: (float(r["x"]), float(r["y"])) for r in csv.DictReader(open(out))
            if r["ok"] == "1" and first <= int(r["frame"]) <= last}


def distances(rows, csrt, first):
    """(frame, score, px from CSRT) of the searched frames of `rows` where CSRT reports."""
    return [(first + k, s, np.hypot(x - csrt[first + k][0], y - csrt[first + k][1])) for k, x, y, s in rows
            if s is not None and first + k in csrt]


def score_line(name, rows, csrt, first):
    """Distance to CSRT (where it reports) and the search scores of `rows`."""
    d = np.array([e for *_, e in distances(rows, csrt, first)])
    s = np.array([s for *_, s in rows if s is not None])
    if len(s) == 0:
        return f"{name:10s} no frame searched"
    within = f"{np.mean(d < 5) * 100:3.0f} %" if len(d) else "  - "
    dist = f"mean {d.mean():5.1f} max {d.max():5.1f}" if len(d) else "no CSRT point      "
    return f"{name:10s} {len(s):3d} frames searched: {dist} px from CSRT, within 5 px {within}, score {s.min():.2f}-{s.max():.2f}"


def timing(fr, box):
    """OpenCV's CSRT and KCF a frame on `fr` (gray, float32) from `box`."""
    fr = [cv2.cvtColor(f.astype(np.uint8), cv2.COLOR_GRAY2BGR) for f in fr]
    cv2.setNumThreads(1)
    for name, make in [("CSRT", cv2.TrackerCSRT.create), ("KCF", cv2.TrackerKCF.create)]:
        best = float("inf")
        for _ in range(3):
            t = make()
            t.init(fr[0], box)
            t0 = time.perf_counter()
            for f in fr[1:]:
                t.update(f)
            best = min(best, (time.perf_counter() - t0) / (len(fr) - 1))
        print(f"OpenCV {name} on the eye: {best * 1e3:.2f} ms a frame on one core of this machine "
              f"({best / 1.76e-3:.1f}x the M4's 1.76 ms)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=pathlib.Path, default=pathlib.Path("/usr/share/doc/opencv-doc/examples/data"))
    ap.add_argument("--coopwin", type=pathlib.Path, default=ROOT / "target/release/coopwin")
    ap.add_argument("--verbose", action="store_true", help="list the anchored model's searched frames")
    a = ap.parse_args()
    if not a.coopwin.is_file():
        sys.exit(f"{a.coopwin}: not found; build it first: cargo build --release -p coopwin-testbench")
    clips, eye = {}, None
    with tempfile.TemporaryDirectory() as tmp:
        for o in csv.DictReader(open(ROOT / "fixtures/footage/objects.csv")):
            first, last = int(o["first"]), int(o["last"])
            x = int(o["x"]) + (int(o["w"]) - 1) / 2
            y = int(o["y"]) + (int(o["h"]) - 1) / 2
            if o["clip"] not in clips:
                clips[o["clip"]] = read_clip(a.data / f"{o['clip']}.avi")
            fr = frames(clips[o["clip"]], first, last)
            if (o["clip"], o["object"]) == ("Megamind", "eye"):
                eye = (fr, tuple(int(o[k]) for k in "xywh"))
            name = f"{o['clip']}-{o['object']}"
            # Megamind_bugy shows Megamind's pictures, damaged: where CSRT is lost in the damaged
            # clip, its point in the clean one is the reference.
            clean = ROOT / f"fixtures/opencv/footage/Megamind-{o['object']}.csrt.csv"
            ref = clean if o["clip"] == "Megamind_bugy" and clean.is_file() else ROOT / f"fixtures/opencv/footage/{name}.csrt.csv"
            csrt = {int(r["frame"]): (float(r["x"]), float(r["y"])) for r in csv.DictReader(open(ref)) if r["x"]}
            print(name)
            print("  " + score_line("free", context_track(fr, x, y), csrt, first))
            given = trusted(a.coopwin, a.data, o, pathlib.Path(tmp))
            anchored = context_track(fr, x, y, given)
            print("  " + score_line("anchored", anchored, csrt, first))
            if a.verbose:
                print("    " + " ".join(f"{k}:{s:.2f}/{d:.0f}" for k, s, d in distances(anchored, csrt, first)))
    if eye:
        timing(*eye)


if __name__ == "__main__":
    main()
