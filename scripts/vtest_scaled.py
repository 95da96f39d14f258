#!/usr/bin/env python3
"""vtest.avi's labelled people (fixtures/longterm/vtest/) tracked by `coopwin track` on the clip
scaled to another size, as a user with a larger (or smaller) camera would give it: the clip is
scaled by FFmpeg (`scale=WxH`, lossless FFV1 in a temporary folder), each person's start box and
labels are scaled alike, and the rows are scored as `coopwin experiment long-term` scores them
(a row is right inside the labelled box or within 5 px of its centre; `ok` 1 rows on frames
labelled hidden or gone count against TNR).

    python3 scripts/vtest_scaled.py --size 1920x1080            # the default binning
    python3 scripts/vtest_scaled.py --size 1920x1080 -- --bin 1  # extra `track` options
    python3 scripts/vtest_scaled.py --size 512x384 --flags area  # FFmpeg's area averaging

docs/results.md ("Objects larger than the template") quotes its output. Needs ffmpeg and a
release build (`cargo build --release`); about 20-60 s a person at 1080p.
"""
import argparse
import csv
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
LABELS = ROOT / "fixtures" / "longterm" / "vtest"
CLIP = pathlib.Path("/usr/share/doc/opencv-doc/examples/data/vtest.avi")


def keyframes(name):
    with open(LABELS / f"{name}.csv") as f:
        return [row for row in csv.DictReader(f)]


def truth(keys, frame):
    """(state, box) of `frame` as the fixtures' README interpolates the keyframes."""
    for a, b in zip(keys, keys[1:]):
        k0, k1 = int(a["frame"]), int(b["frame"])
        if k0 <= frame < k1:
            if a["x"] == "":
                return a["state"], None
            t = (frame - k0) / (k1 - k0)
            box0 = [float(a[c]) for c in "xywh"]
            box1 = [float(b[c]) for c in "xywh"] if b["x"] != "" else box0
            return a["state"], [p + (q - p) * t for p, q in zip(box0, box1)]
    last = keys[-1]
    return last["state"], ([float(last[c]) for c in "xywh"] if last["x"] else None)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", required=True, help="WxH to scale vtest.avi's 768x576 to")
    parser.add_argument("--flags", help="FFmpeg's scaling algorithm (e.g. area; default: FFmpeg's bicubic)")
    parser.add_argument("--clip", type=pathlib.Path, default=CLIP)
    parser.add_argument("--coopwin", type=pathlib.Path, default=ROOT / "target" / "release" / "coopwin")
    parser.add_argument("track", nargs="*", help="extra `coopwin track` options, after --")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    sx, sy = width / 768, height / 576
    with tempfile.TemporaryDirectory() as tmp:
        video = pathlib.Path(tmp) / "scaled.mkv"
        scale = f"scale={width}:{height}" + (f":flags={args.flags}" if args.flags else "")
        subprocess.run(["ffmpeg", "-loglevel", "error", "-i", str(args.clip), "-vf", scale, "-c:v", "ffv1", str(video)], check=True)
        print("| person | box | visible | vouched | wrong | longest wrong run | vouched where hidden or gone | binning |")
        print("|---|---|---|---|---|---|---|---|")
        with open(LABELS / "objects.csv") as f:
            people = list(csv.DictReader(f))
        for p in people:
            first, last = int(p["first"]), int(p["last"])
            box = ",".join(str(round(float(p[c]) * s)) for c, s in zip("xywh", (sx, sy, sx, sy)))
            out = pathlib.Path(tmp) / f"{p['object']}.csv"
            run = subprocess.run(
                [str(args.coopwin), "track", "--frames", str(video), "--target-box", box, "--start-frame", str(first), "--end-frame", str(last + 1), "--out", str(out), *args.track],
                capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"{p['object']}: {run.stderr.strip()}")
            binning = next((line.split(" for ")[0].removeprefix("note: the frames are ") for line in run.stderr.splitlines() if "the frames are binned" in line), "unbinned")
            keys = keyframes(p["object"])
            visible = vouched = wrong = run_ = longest = hidden = 0
            with open(out) as f:
                for row in csv.DictReader(f):
                    frame = int(row["frame"])
                    if frame == first:
                        continue  # the start box is given, not tracked
                    state, b = truth(keys, frame)
                    visible += state == "visible"
                    if row["ok"] != "1":
                        run_ = 0
                        continue
                    vouched += 1
                    hidden += state != "visible"
                    x, y = float(row["x"]), float(row["y"])
                    right = False
                    if b is not None:
                        # Pixel centres at integers: pixel x of the clip covers x - 0.5..x + 0.5.
                        bx, by, bw, bh = (b[0] + 0.5) * sx - 0.5, (b[1] + 0.5) * sy - 0.5, b[2] * sx, b[3] * sy
                        cx, cy = bx + (bw - 1) / 2, by + (bh - 1) / 2
                        right = (bx <= x <= bx + bw - 1 and by <= y <= by + bh - 1) or ((x - cx) ** 2 + (y - cy) ** 2) ** 0.5 <= 5
                    wrong += not right
                    run_ = 0 if right else run_ + 1
                    longest = max(longest, run_)
            print(f"| {p['object']} | {box} | {visible} | {vouched} | {wrong} | {longest} | {hidden} | {binning} |", flush=True)


if __name__ == "__main__":
    main()
