#!/usr/bin/env python3
"""The figures behind the support NCC (firmware/src/kernels/support.rs), measured with OpenCV
on the real-image corner sequences, independently of the firmware.

    mkdir -p /tmp/seqs && cargo run --release -- experiment real-images --out /tmp/r --sequences /tmp/seqs/real
    python3 scripts/support_check.py /tmp/seqs/real

For each corner-* condition the 20x20 template is cut around the true corner of frame 0; its
support is the cone between the part's edges (15 and 105 degrees, the renderer's outline,
`testbench/src/frames/scene/texture.rs`), 1 px inside them. It prints:

  * tracking with cv2.matchTemplate(TM_CCORR_NORMED), the thesis's NCC, over a +-8 px
    search from the last position with a parabola per axis, with the whole template and with
    the support as the mask: the lowest best score over the run, the RMS error and the share
    of frames more than 5 px off;
  * zero-mean NCC over the support at whole-pixel placements, every third frame: the best
    within 1 px of the true placement (the object) and the best 3 to 10 px away (anything
    else), minimum and maximum over the frames.
"""
import argparse
import csv
import math
import sys
from pathlib import Path

import cv2
import numpy as np

N, SEARCH, MARGIN = 20, 8, 1.0


def load(folder: Path):
    truth = [(float(r["corner_x"]), float(r["corner_y"])) for r in csv.DictReader(open(folder / "groundtruth.csv"))]
    frames = [cv2.imread(str(folder / f"frame_{k:05d}.png"), cv2.IMREAD_GRAYSCALE).astype(np.float32) for k in range(len(truth))]
    return truth, frames


def support(corner, top_left):
    ys, xs = np.mgrid[0:N, 0:N]
    px, py = xs + top_left[0] - corner[0], ys + top_left[1] - corner[1]
    a1, a2 = math.radians(15), math.radians(105)
    inside1 = math.cos(a1) * py - math.sin(a1) * px >= MARGIN
    inside2 = px * math.sin(a2) - py * math.cos(a2) >= MARGIN
    return (inside1 & inside2).astype(np.float32)


def parabola(a, b, c):
    d = a - 2 * b + c
    return 0.0 if d >= 0 else max(-0.5, min(0.5, 0.5 * (a - c) / d))


def track(truth, frames, tpl, top_left, mask):
    """Lowest best score, RMS error and loss share of a matchTemplate track."""
    x, y = top_left
    # The tracked point sits where the corner sat in the template.
    ox, oy = truth[0][0] - top_left[0], truth[0][1] - top_left[1]
    errs, scores = [], []
    for k in range(1, len(frames)):
        x0, y0 = x - SEARCH, y - SEARCH
        area = frames[k][y0:y0 + N + 2 * SEARCH, x0:x0 + N + 2 * SEARCH]
        res = cv2.matchTemplate(area, tpl, cv2.TM_CCORR_NORMED, mask=mask)
        _, s, _, (bx, by) = cv2.minMaxLoc(res)
        sx = parabola(res[by, bx - 1], s, res[by, bx + 1]) if 0 < bx < 2 * SEARCH else 0.0
        sy = parabola(res[by - 1, bx], s, res[by + 1, bx]) if 0 < by < 2 * SEARCH else 0.0
        x, y = x0 + bx, y0 + by
        errs.append(math.hypot(x + sx + ox - truth[k][0], y + sy + oy - truth[k][1]))
        scores.append(s)
    e = np.array(errs)
    return min(scores), float(np.sqrt((e ** 2).mean())), float((e > 5).mean())


def zncc_spread(truth, frames, tpl, top_left, mask):
    m = mask > 0
    ox, oy = truth[0][0] - top_left[0], truth[0][1] - top_left[1]
    b = tpl[m] - tpl[m].mean()
    near, far = [], []
    for k in range(0, len(frames), 3):
        # The whole-pixel placement nearest the true one.
        X, Y = int(round(truth[k][0] - ox)), int(round(truth[k][1] - oy))
        best_near, best_far = -1.0, -1.0
        for dy in range(-10, 11):
            for dx in range(-10, 11):
                w = frames[k][Y + dy:Y + dy + N, X + dx:X + dx + N]
                if w.shape != (N, N):
                    continue
                a = w[m] - w[m].mean()
                z = float((a * b).sum() / math.sqrt((a * a).sum() * (b * b).sum() + 1e-9))
                if max(abs(dx), abs(dy)) <= 1:
                    best_near = max(best_near, z)
                elif max(abs(dx), abs(dy)) >= 3:
                    best_far = max(best_far, z)
        near.append(best_near)
        far.append(best_far)
    return min(near), max(near), min(far), max(far)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("root", type=Path, help="the folder `experiment real-images --sequences` wrote")
    args = ap.parse_args()
    folders = sorted(p for p in args.root.glob("corner-*") if (p / "groundtruth.csv").exists())
    if not folders:
        print(f"{args.root}: no corner-* sequences (write them with experiment real-images --sequences)", file=sys.stderr)
        return 2
    print("condition | whole: min score, RMS px, loss | support: min score, RMS px, loss | ZNCC object min-max | ZNCC elsewhere min-max")
    for folder in folders:
        truth, frames = load(folder)
        top_left = (int(round(truth[0][0] - 9.5)), int(round(truth[0][1] - 9.5)))
        tpl = frames[0][top_left[1]:top_left[1] + N, top_left[0]:top_left[0] + N].copy()
        mask = support(truth[0], top_left)
        whole = track(truth, frames, tpl, top_left, None)
        masked = track(truth, frames, tpl, top_left, mask)
        z = zncc_spread(truth, frames, tpl, top_left, mask)
        print(f"{folder.name} | {whole[0]:.4f}, {whole[1]:.2f}, {whole[2]:.0%} | {masked[0]:.4f}, {masked[1]:.2f}, {masked[2]:.0%} | "
              f"{z[0]:.2f}-{z[1]:.2f} | {z[2]:.2f}-{z[3]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
