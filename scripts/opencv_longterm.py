#!/usr/bin/env python3
"""OpenCV's trackers on the hand-labelled long-term objects, scored as VOT-LT and OxUvA do.

    python3 scripts/opencv_longterm.py [--clip CLIP [--only OBJECT]]
        [--data /usr/share/doc/opencv-doc/examples/data] [--out fixtures/longterm/opencv]
    python3 scripts/opencv_longterm.py --sets [--coopwin target/release/coopwin]
        [--out fixtures/longterm/opencv]

Without --clip it runs every clip that has fixtures/longterm/<clip>/objects.csv (vtest,
Megamind, Megamind_bugy, tree; about 10 minutes on one core, TLD taking most of it).

With --sets it runs the semi-synthetic long-term sets instead (`coopwin experiment
long-term`'s, rendered by `coopwin scene --set NAME` into a temporary folder: frames, truth.csv
and fingerprint.txt), each from the target's box on frame 0 as `track --target-box` starts
(truth.csv's box rounded half up, as the testbench's start_box), to frame 299, into
--out/sets/: <tracker>_<set>.csv, <set>.fingerprint (the frames' fingerprint, which the
testbench compares with the frames it renders now: a stale fixture fails its test) and
summary.csv. They are scored as the testbench scores its own runs on them
(analysis/longterm.rs): a row with ok=1 is right only on a visible frame and within 5 px of
the target's centre (no "inside the box", and a hidden frame's row is wrong), over every
frame, the start frame's given box included; the rest as below. About 3 minutes on one core.

The objects are fixtures/longterm/<clip>/objects.csv (object,first,last,x,y,w,h) and their
hand labels fixtures/longterm/<clip>/<object>.csv (keyframes, interpolated by
scripts/longterm_annotate.py's interpolate()). Every tracker starts on frame `first` from the
object's box and runs to `last`. Frames are decoded by cv2.VideoCapture, converted to gray
(cv2.COLOR_BGR2GRAY, the picture coopwin sees) and given to the trackers as 3-channel BGR
(gray replicated), as scripts/opencv_footage.py does. OpenCV runs single-threaded
(cv2.setNumThreads(1)), and TLD, whose results depend on what ran before it in the same
process, runs each object in a fresh process, so reruns give identical files.

  csrt   cv2.TrackerCSRT_create(), default parameters; update() == False: ok=0.
  kcf    cv2.TrackerKCF_create(), default parameters; update() == False: ok=0.
  mosse  MOSSE as OpenCV's legacy tracker (cv2.legacy.TrackerMOSSE_create, opencv_contrib
         modules/tracking/src/mosseTracker.cpp) computes it, re-implemented here with the same
         OpenCV calls so that its PSR is visible (the API hides it): log, normalise, Hanning
         window, 8 training patches that are all the same warp (the legacy code re-seeds
         cv::RNG with 8031965 in every randWarp call; see Mosse.rand_warp for two more
         quirks reproduced), learning rate 0.2, and no update while
         PSR = (peak - mean) / (std + 1e-5) of the response < 5.7, which is then ok=0.
         The script runs OpenCV's own legacy MOSSE beside it and stops if the two disagree
         on any frame's ok or box (by more than 1e-6 px).
  tld    cv2.legacy.TrackerTLD_create() (opencv-contrib), default parameters, in a fresh
         process per object;
         update() == False (TLD's "not found"): ok=0.

Output: in --out for vtest, in --out/<clip>/ for the other clips: <tracker>_<object>.csv with frame,ok,x,y,w,h,score (x..h the box in
OpenCV's convention, columns x..x+w-1, empty when ok=0; score = MOSSE's PSR, which exists on
every frame, empty for the others, which expose no confidence), and summary.csv (per clip),
which the script also prints.

Scoring, per tracker and object, over the frames first+1..last (the start frame is given).
The labels say per frame `visible`, `hidden` (more than half covered; the box is where the
object is behind the cover, or empty) or `gone` (out of the view, no box). A row with ok=1 is right
when its centre (x + (w-1)/2, y + (h-1)/2) lies inside the labelled box (columns x..x+w-1,
rows y..y+h-1) or within 5 px of the labelled centre; on `gone` frames it is wrong.
  VOT-LT (Lukezic et al. 2020): precision = right rows / rows with ok=1, recall = right rows
  on visible frames / visible frames, F = 2PR / (P + R), at the confidence threshold that
  maximises F (rows with ok=1 and score >= threshold count as predictions; MOSSE's PSR is
  the only confidence; the others are scored on ok alone). No row with ok=1: precision is
  empty and F is 0. A hidden frame's row counts as right inside the box where the object is
  behind the cover (none when that box is empty).
  OxUvA (Valmadre et al. 2018): TPR = right rows on visible frames / visible frames (rows
  with ok=1 as they are), TNR = frames labelled hidden or gone with ok=0 / such frames
  (empty when the object is never hidden or gone).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import math
import multiprocessing
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from longterm_annotate import interpolate, read_labels

REPO = Path(__file__).resolve().parent.parent
DATA = Path("/usr/share/doc/opencv-doc/examples/data")
TRACKERS = ("csrt", "kcf", "mosse", "tld")
# The long-term sets (testbench/src/frames/scene/longterm.rs); the testbench's test fails on a
# set with no fixture here.
SETS = ("lookalike-front", "lookalike-behind", "turned-front", "identical-behind", "leaves",
        "leaves-identical", "crowd", "panel", "partial", "clutter")
NEAR_PX = 5.0
# OpenCV's legacy MOSSE (mosseTracker.cpp): its constants.
MOSSE_EPS = 0.00001
MOSSE_RATE = 0.2
MOSSE_PSR = 5.7
MOSSE_SEED = 8031965


class CvRng:
    """cv::RNG: multiply-with-carry, and uniform(double a, double b) as core/src/rand.cpp."""

    def __init__(self, seed: int):
        self.state = seed or 0xFFFFFFFF

    def next(self) -> int:
        self.state = ((self.state & 0xFFFFFFFF) * 4164903690 + (self.state >> 32)) & 0xFFFFFFFFFFFFFFFF
        return self.state & 0xFFFFFFFF

    def uniform(self, a: float, b: float) -> float:
        t = self.next()
        return (((t << 32) | self.next()) * 5.4210108624275221700372640043497e-20) * (b - a) + a


class Mosse:
    """OpenCV's legacy MOSSE, step for step, with the PSR of the last update kept."""

    def init(self, img: np.ndarray, box) -> None:
        gray = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
        w, h = cv2.getOptimalDFTSize(int(box[2])), cv2.getOptimalDFTSize(int(box[3]))
        x1 = math.floor((2 * box[0] + box[2] - w) / 2)
        y1 = math.floor((2 * box[1] + box[3] - h) / 2)
        self.center = [float(x1 + w // 2), float(y1 + h // 2)]
        self.size = (w, h)
        window = cv2.getRectSubPix(gray, self.size, tuple(self.center))
        self.han = cv2.createHanningWindow(self.size, cv2.CV_32F)
        g = np.zeros((h, w), np.float32)
        g[h // 2, w // 2] = 1
        g = cv2.GaussianBlur(g, (0, 0), 2.0)
        g = g / g.max()
        self.G = cv2.dft(g, flags=cv2.DFT_COMPLEX_OUTPUT)
        self.A = np.zeros_like(self.G)
        self.B = np.zeros_like(self.G)
        for _ in range(8):
            ww = self.pre(self.rand_warp(window))
            F = cv2.dft(ww, flags=cv2.DFT_COMPLEX_OUTPUT)
            self.A += cv2.mulSpectrums(self.G, F, 0, conjB=True)
            self.B += cv2.mulSpectrums(F, F, 0, conjB=True)
        self.H = self.div(self.A, self.B)
        self.psr = float("nan")

    def rand_warp(self, a: np.ndarray) -> np.ndarray:
        """randWarp() as the compiled legacy code behaves: the generator is re-seeded on every
        call (so all 8 training patches are the same warp); the four matrix terms of
        `W << c + u(), -s + u(), 0, s + u(), c + u(), 0` draw their numbers last term first
        (the overloaded comma operators' arguments are evaluated right to left); and
        `warpAffine(a, warped, W, a.size(), BORDER_REFLECT)` passes BORDER_REFLECT (2) as the
        interpolation flag, i.e. bicubic with a zero border. Drawing in source order or
        warping bilinearly with a reflected border gives other boxes than OpenCV's."""
        rng = CvRng(MOSSE_SEED)
        C = 0.1
        ang = rng.uniform(-C, C)
        c, s = math.cos(ang), math.sin(ang)
        u3, u2, u1, u0 = (rng.uniform(-C, C) for _ in range(4))
        W = np.array([[c + u0, -s + u1, 0], [s + u2, c + u3, 0]], np.float32)
        cw = np.array([a.shape[1] // 2, a.shape[0] // 2], np.float32)
        W[:, 2] = cw - W[:, :2] @ cw
        return cv2.warpAffine(a, W, (a.shape[1], a.shape[0]), flags=cv2.INTER_CUBIC)

    def pre(self, window: np.ndarray) -> np.ndarray:
        window = cv2.log(window.astype(np.float32) + np.float32(1.0))
        mean, std = cv2.meanStdDev(window)
        window = ((window - mean[0, 0]) / (std[0, 0] + MOSSE_EPS)).astype(np.float32)
        return cv2.multiply(window, self.han)

    @staticmethod
    def div(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        a0, a1 = cv2.split(a)
        b0, b1 = cv2.split(b)
        denom = cv2.add(cv2.multiply(b0, b0), cv2.multiply(b1, b1))
        re = cv2.divide(cv2.multiply(a0, b0) + cv2.multiply(a1, b1), denom, scale=1.0)
        im = cv2.divide(cv2.multiply(a1, b0) + cv2.multiply(a0, b1), denom, scale=-1.0)
        return cv2.merge([re, im])

    def update(self, img: np.ndarray):
        sub = cv2.cvtColor(cv2.getRectSubPix(img, self.size, tuple(self.center)), cv2.COLOR_BGR2GRAY)
        sub = self.pre(sub)
        resp = cv2.idft(cv2.mulSpectrums(cv2.dft(sub, flags=cv2.DFT_COMPLEX_OUTPUT), self.H, 0, conjB=True),
                        flags=cv2.DFT_SCALE | cv2.DFT_REAL_OUTPUT)
        _, peak, _, loc = cv2.minMaxLoc(resp)
        mean, std = cv2.meanStdDev(resp)
        self.psr = (peak - mean[0, 0]) / (std[0, 0] + MOSSE_EPS)
        if self.psr < MOSSE_PSR:
            return False, None
        w, h = self.size
        self.center[0] += loc[0] - w // 2
        self.center[1] += loc[1] - h // 2
        new = self.pre(cv2.cvtColor(cv2.getRectSubPix(img, self.size, tuple(self.center)), cv2.COLOR_BGR2GRAY))
        F = cv2.dft(new, flags=cv2.DFT_COMPLEX_OUTPUT)
        self.A = cv2.addWeighted(self.A, 1 - MOSSE_RATE, cv2.mulSpectrums(self.G, F, 0, conjB=True), MOSSE_RATE, 0)
        self.B = cv2.addWeighted(self.B, 1 - MOSSE_RATE, cv2.mulSpectrums(F, F, 0, conjB=True), MOSSE_RATE, 0)
        self.H = self.div(self.A, self.B)
        x, y = self.center
        return True, (x - 0.5 * w, y - 0.5 * h, float(w), float(h))


def read_clip(path: Path) -> list[np.ndarray]:
    """Every decodable frame as gray replicated to 3-channel BGR: a video's, or a folder's
    frame_*.png in order (`coopwin scene`'s)."""
    if path.is_dir():
        return [cv2.cvtColor(cv2.imread(str(f), cv2.IMREAD_GRAYSCALE), cv2.COLOR_GRAY2BGR)
                for f in sorted(path.glob("frame_*.png"))]
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        sys.exit(f"{path}: cv2.VideoCapture cannot open it (apt-get install opencv-doc)")
    frames = []
    while True:
        ok, bgr = cap.read()
        if not ok:
            break
        frames.append(cv2.cvtColor(cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY), cv2.COLOR_GRAY2BGR))
    return frames


def make(name: str):
    return {"csrt": cv2.TrackerCSRT_create, "kcf": cv2.TrackerKCF_create,
            "tld": cv2.legacy.TrackerTLD_create, "mosse": Mosse}[name]()


def run_fresh(name: str, clip: Path, first: int, last: int, box) -> list[tuple]:
    """run() in a new process that decodes the clip itself: TLD's results depend on what ran
    before it in the same process (cv2.setRNGSeed does not make them repeatable)."""
    ctx = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(max_workers=1, mp_context=ctx) as pool:
        return pool.submit(_run_clip, name, clip, first, last, box).result()


def _run_clip(name: str, clip: Path, first: int, last: int, box) -> list[tuple]:
    cv2.setNumThreads(1)
    return run(name, read_clip(clip), first, last, box)


def run(name: str, frames: list[np.ndarray], first: int, last: int, box) -> list[tuple]:
    """Rows (frame, ok, box or None, score or None) for frames first..last."""
    tr = make(name)
    tr.init(frames[first], tuple(int(v) for v in box))
    ref = None
    if name == "mosse":
        ref = cv2.legacy.TrackerMOSSE_create()
        ref.init(frames[first], tuple(float(v) for v in box))
    rows = [(first, 1, tuple(float(v) for v in box), None)]
    for f in range(first + 1, last + 1):
        ok, b = tr.update(frames[f])
        b = tuple(float(v) for v in b) if ok else None
        if ref is not None:
            rok, rb = ref.update(frames[f])
            if bool(rok) != bool(ok) or ok and max(abs(u - v) for u, v in zip(b, rb)) > 1e-6:
                sys.exit(f"frame {f}: this MOSSE ({ok}, {b}) differs from cv2.legacy's ({rok}, {rb})")
        rows.append((f, int(bool(ok)), b, tr.psr if name == "mosse" else None))
    return rows


def write_rows(path: Path, rows) -> None:
    with path.open("w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["frame", "ok", "x", "y", "w", "h", "score"])
        for f, ok, b, s in rows:
            w.writerow([f, ok, *(["", "", "", ""] if b is None else [f"{v:.3f}" for v in b]),
                        "" if s is None else f"{s:.4f}"])


def right(box, label, inside_counts: bool = True) -> bool:
    """Is a reported box's centre on the labelled object (inside its box, where
    `inside_counts`, or within 5 px of its centre)?"""
    lb, state = label
    if lb is None or state == "gone":
        return False
    cx, cy = box[0] + (box[2] - 1) / 2, box[1] + (box[3] - 1) / 2
    lx, ly = lb[0] + (lb[2] - 1) / 2, lb[1] + (lb[3] - 1) / 2
    inside = lb[0] <= cx <= lb[0] + lb[2] - 1 and lb[1] <= cy <= lb[1] + lb[3] - 1
    return (inside_counts and inside) or math.hypot(cx - lx, cy - ly) <= NEAR_PX


def score(rows, labels, inside_counts: bool = True, given_counts: bool = False) -> dict:
    """VOT-LT's and OxUvA's figures of `rows` against `labels`, from the frame after the
    given start box (or from it, where `given_counts`)."""
    right_ = lambda box, label: right(box, label, inside_counts)
    rows = [r for r in rows[0 if given_counts else 1:] if r[0] in labels]
    visible = sum(1 for r in rows if labels[r[0]][1] == "visible")
    absent = [r for r in rows if labels[r[0]][1] != "visible"]
    thresholds = sorted({r[3] for r in rows if r[1] and r[3] is not None}) or [None]
    best = None
    for t in thresholds:
        # The given start box has no score: it is predicted at every threshold.
        pred = [r for r in rows if r[1] and (t is None or r[3] is None or r[3] >= t)]
        good = [r for r in pred if right_(r[2], labels[r[0]])]
        p = len(good) / len(pred) if pred else None
        rc = sum(1 for r in good if labels[r[0]][1] == "visible") / visible if visible else 0.0
        f = 2 * p * rc / (p + rc) if p and p + rc else 0.0
        if best is None or f > best["F"]:
            best = {"threshold": t, "precision": p, "recall": rc, "F": f, "rows": len(pred), "wrong": len(pred) - len(good)}
    ok_rows = [r for r in rows if r[1]]
    tpr = sum(1 for r in ok_rows if labels[r[0]][1] == "visible" and right_(r[2], labels[r[0]])) / visible if visible else float("nan")
    tnr = sum(1 for r in absent if not r[1]) / len(absent) if absent else float("nan")
    return {**best, "frames": len(rows), "visible": visible, "absent": len(absent), "TPR": tpr, "TNR": tnr,
            "ok_rows": len(ok_rows), "ok_wrong": sum(1 for r in ok_rows if not right_(r[2], labels[r[0]]))}


def out_dir(base: Path, clip: str) -> Path:
    """vtest's fixtures sit in --out itself, every other clip's in a folder of its name."""
    return base if clip == "vtest" else base / clip


COLUMNS = ["tracker", "object", "frames", "visible", "absent", "ok_rows", "ok_wrong", "threshold",
           "precision", "recall", "F", "TPR", "TNR"]


def summary(table) -> list[str]:
    """summary.csv's lines: COLUMNS, then a row per (tracker, object, score)."""
    fmt = lambda v: "" if v is None or v != v else f"{v:.3f}" if isinstance(v, float) else str(v)
    return [",".join(COLUMNS)] + [",".join([n, o] + [fmt(s[c]) for c in COLUMNS[2:]]) for n, o, s in table]


def run_sets(coopwin: Path, out: Path) -> None:
    """Every long-term set, rendered by `coopwin scene --set`, through every tracker."""
    out.mkdir(parents=True, exist_ok=True)
    table = []
    for name in SETS:
        with tempfile.TemporaryDirectory() as tmp:
            seq = Path(tmp) / name
            done = subprocess.run([str(coopwin), "scene", "--set", name, "--out", str(seq)],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if done.returncode != 0:
                sys.exit(f"{coopwin} scene --set {name}: {done.stderr.strip()} (a set not in this binary: "
                         "rebuild it, or update SETS)")
            if not (seq / "fingerprint.txt").exists():
                sys.exit(f"{coopwin} wrote no fingerprint.txt: an older binary (cargo build --release)")
            with (seq / "truth.csv").open() as fh:
                truth = list(csv.DictReader(fh))
            # Only a visible target can be right (a row on a hidden one is wrong).
            labels = {int(r["frame"]): ((float(r["x"]), float(r["y"]), float(r["w"]), float(r["h"])) if r["state"] == "visible" else None,
                                        r["state"]) for r in truth}
            t0 = truth[0]
            box = tuple(math.floor(float(t0[k]) + 0.5) for k in ("x", "y")) + (int(t0["w"]), int(t0["h"]))
            frames = read_clip(seq)
            last = len(frames) - 1
            for tracker in TRACKERS:
                rows = run_fresh(tracker, seq, 0, last, box) if tracker == "tld" else run(tracker, frames, 0, last, box)
                write_rows(out / f"{tracker}_{name}.csv", rows)
                table.append((tracker, name, score(rows, labels, inside_counts=False, given_counts=True)))
            (out / f"{name}.fingerprint").write_text((seq / "fingerprint.txt").read_text())
            print(f"  {name}: {last + 1} frames", file=sys.stderr)
    lines = summary(table)
    (out / "summary.csv").write_text("\n".join(lines) + "\n")
    print("# long-term sets")
    print("\n".join(lines))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--clip", help="one clip (default: every clip with fixtures/longterm/<clip>/objects.csv)")
    ap.add_argument("--data", type=Path, default=DATA, help="folder of the clips (default: %(default)s)")
    ap.add_argument("--out", type=Path, default=REPO / "fixtures" / "longterm" / "opencv")
    ap.add_argument("--only", help="one object of --clip (no summary.csv is written)")
    ap.add_argument("--sets", action="store_true", help="the semi-synthetic long-term sets instead of the clips, into --out/sets")
    ap.add_argument("--coopwin", type=Path, default=REPO / "target" / "release" / "coopwin",
                    help="the coopwin binary that renders the sets (default: %(default)s; cargo build --release)")
    a = ap.parse_args()
    if a.only and not a.clip:
        ap.error("--only needs --clip")
    if a.sets and a.clip:
        ap.error("--sets runs the synthetic sets, --clip a clip: give one")
    cv2.setNumThreads(1)
    print(f"OpenCV {cv2.__version__}, numpy {np.__version__}", file=sys.stderr)
    if a.sets:
        if not a.coopwin.is_file():
            sys.exit(f"{a.coopwin}: no such binary (cargo build --release, or give --coopwin)")
        run_sets(a.coopwin, a.out / "sets")
        return
    base = REPO / "fixtures" / "longterm"
    clips = [a.clip] if a.clip else sorted(p.parent.name for p in base.glob("*/objects.csv"))
    for clip in clips:
        root = base / clip
        if not (root / "objects.csv").exists():
            sys.exit(f"{root / 'objects.csv'}: no such file (clips: {', '.join(p.parent.name for p in base.glob('*/objects.csv'))})")
        with (root / "objects.csv").open() as fh:
            objects = [(r["object"], int(r["first"]), int(r["last"]), tuple(int(r[k]) for k in "xywh"))
                       for r in csv.DictReader(fh)]
        if a.only:
            objects = [o for o in objects if o[0] == a.only]
            if not objects:
                sys.exit(f"{a.only}: not in {root / 'objects.csv'}")
        frames = read_clip(a.data / f"{clip}.avi")
        out = out_dir(a.out, clip)
        out.mkdir(parents=True, exist_ok=True)
        print(f"{clip}.avi: {len(frames)} frames", file=sys.stderr)
        table = []
        for obj, first, last, box in objects:
            labels = interpolate(read_labels(root / f"{obj}.csv"))
            for name in TRACKERS:
                t0 = time.perf_counter()
                rows = (run_fresh(name, a.data / f"{clip}.avi", first, last, box) if name == "tld"
                        else run(name, frames, first, last, box))
                write_rows(out / f"{name}_{obj}.csv", rows)
                table.append((name, obj, score(rows, labels)))
                print(f"  {name:5s} {obj:8s} {last - first} frames in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
        lines = summary(table)
        if not a.only:
            (out / "summary.csv").write_text("\n".join(lines) + "\n")
        print(f"# {clip}")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
