#!/usr/bin/env python3
"""Time OpenCV on the coopwin benchmark inputs and compare with the Rust
criterion results.

    python3 scripts/opencv_bench.py [--repo-root .] [--json out.json]

Inputs: fixtures/bench/*.pgm (regenerate with fixtures/bench/make_bench_inputs.py).
Rust numbers: target/criterion/<id>/new/estimates.json (median.point_estimate,
ns), produced by `cargo bench -p coopwin-firmware --bench kernels`.

Each OpenCV kernel is timed with timeit: the number of calls per repeat is
calibrated so one repeat lasts >= ~20 ms, then --repeats repeats are taken and
the median per-call time (microseconds) is reported.  Timings are taken once
with cv2.setNumThreads(1) and once with OpenCV's default thread count.  All
numbers include the Python -> C++ call overhead of every cv2/numpy call in the
pipeline (about 0.3-1 us per call), which matters at these tiny sizes.

Kernel equivalents (what exactly is timed):
  foveal_ncc_20in24          matchTemplate(24x24, 20x20, TM_CCORR_NORMED) + minMaxLoc
  peripheral_ssd_16in40      matchTemplate(40x40, 16x16, TM_SQDIFF) + minMaxLoc
  peripheral_ssd_16in40_dec  decimation INCLUDED in the timing:
                             np.ascontiguousarray(img[::2, ::2]) and of tpl[::2, ::2]
                             (20x20 and 8x8), then TM_SQDIFF + minMaxLoc.
                             The kernel-only time on pre-decimated arrays is
                             reported too (extra row *_predecimated, not compared).
  watch_motion_256           absdiff + threshold(30, 1, THRESH_BINARY)
                             + boundingRect(findNonZero(mask))  (256x256)
  corner_20 / corner_24      Sobel gx, gy (CV_16S, ksize 3)
                             + L2 magnitude > 50 (numpy int32: gx^2 + gy^2 > 2500)
                             + connectedComponentsWithStats(connectivity 8)
                             + keep the largest foreground label (numpy argmax + ==)
                             + morphologyEx(MORPH_OPEN, 3x3 MORPH_CROSS)
                             + boundingRect(opened mask)
  coop_decision              numpy least squares on 4 samples, x and y:
                             np.linalg.lstsq(A, Y) with A = [t, 1] (4x2) and
                             Y = 4x2 (x and y columns, i.e. 2 fits in one call),
                             plus SSE = sum of squared residuals per column.
                             This is pure numpy, dominated by Python overhead;
                             it is only an order-of-magnitude reference.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import timeit
from importlib.metadata import PackageNotFoundError, version as pkg_version
from pathlib import Path

import cv2
import numpy as np

IDS = ["foveal_ncc_20in24", "peripheral_ssd_16in40", "peripheral_ssd_16in40_dec",
       "watch_motion_256", "corner_20", "corner_24", "coop_decision"]
EXTRA_IDS = ["peripheral_ssd_16in40_predecimated"]
CROSS = cv2.getStructuringElement(cv2.MORPH_CROSS, (3, 3))


def read_pgm(path: Path) -> np.ndarray:
    data = path.read_bytes()
    # header: P5 <ws> width <ws> height <ws> maxval <single ws> raster
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while data[pos:pos + 1] not in (b"\n", b""):
                pos += 1
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    pos += 1
    if fields[0] != b"P5" or int(fields[3]) != 255:
        raise ValueError(f"{path}: not an 8-bit binary PGM")
    w, h = int(fields[1]), int(fields[2])
    return np.frombuffer(data[pos:pos + w * h], np.uint8).reshape(h, w).copy()


def build_kernels(bench_dir: Path):
    ld = lambda n: read_pgm(bench_dir / f"{n}.pgm")  # noqa: E731
    fw, ft = ld("foveal_window"), ld("foveal_template")
    pw, pt = ld("peripheral_window"), ld("peripheral_template")
    prev, nxt = ld("watch_prev"), ld("watch_next")
    c20, c24 = ld("corner_20"), ld("corner_24")
    pw_d = np.ascontiguousarray(pw[::2, ::2])
    pt_d = np.ascontiguousarray(pt[::2, ::2])

    def foveal():
        return cv2.minMaxLoc(cv2.matchTemplate(fw, ft, cv2.TM_CCORR_NORMED))

    def periph():
        return cv2.minMaxLoc(cv2.matchTemplate(pw, pt, cv2.TM_SQDIFF))

    def periph_dec():
        w = np.ascontiguousarray(pw[::2, ::2])
        t = np.ascontiguousarray(pt[::2, ::2])
        return cv2.minMaxLoc(cv2.matchTemplate(w, t, cv2.TM_SQDIFF))

    def periph_predec():
        return cv2.minMaxLoc(cv2.matchTemplate(pw_d, pt_d, cv2.TM_SQDIFF))

    def watch():
        d = cv2.absdiff(prev, nxt)
        _, m = cv2.threshold(d, 30, 1, cv2.THRESH_BINARY)
        pts = cv2.findNonZero(m)
        return None if pts is None else cv2.boundingRect(pts)

    def corner(img):
        def run():
            gx = cv2.Sobel(img, cv2.CV_16S, 1, 0, ksize=3).astype(np.int32)
            gy = cv2.Sobel(img, cv2.CV_16S, 0, 1, ksize=3).astype(np.int32)
            edges = ((gx * gx + gy * gy) > 2500).astype(np.uint8)
            n, labels, stats, _ = cv2.connectedComponentsWithStats(edges, connectivity=8)
            if n < 2:
                return None
            best = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
            mask = (labels == best).astype(np.uint8)
            opened = cv2.morphologyEx(mask, cv2.MORPH_OPEN, CROSS)
            return cv2.boundingRect(opened)
        return run

    a = np.array([[0.0, 1.0], [1.0, 1.0], [2.0, 1.0], [3.0, 1.0]])
    y = np.array([[100.0, 50.0], [103.2, 51.1], [106.1, 52.3], [109.3, 53.2]])

    def coop():
        sol, _, _, _ = np.linalg.lstsq(a, y, rcond=None)
        r = y - a @ sol
        return sol, (r * r).sum(axis=0)

    return {
        "foveal_ncc_20in24": foveal,
        "peripheral_ssd_16in40": periph,
        "peripheral_ssd_16in40_dec": periph_dec,
        "peripheral_ssd_16in40_predecimated": periph_predec,
        "watch_motion_256": watch,
        "corner_20": corner(c20),
        "corner_24": corner(c24),
        "coop_decision": coop,
    }


def time_us(fn, repeats: int, min_repeat_s: float) -> tuple[float, float]:
    """(median, min) microseconds per call."""
    t = timeit.Timer(fn)
    number, _ = t.autorange()          # calls taking >= 0.2 s in total
    number = max(1, int(number * min_repeat_s / 0.2))
    runs = t.repeat(repeat=repeats, number=number)
    return statistics.median(runs) / number * 1e6, min(runs) / number * 1e6


def read_criterion(root: Path, bench_id: str):
    crit = root / "target" / "criterion"
    p = crit / bench_id / "new" / "estimates.json"
    if not p.is_file():
        # benchmark groups nest one level deeper: <group>/<id>/new/estimates.json
        hits = sorted(crit.glob(f"*/{bench_id}/new/estimates.json")) if crit.is_dir() else []
        if len(hits) != 1:
            return None, None
        p = hits[0]
    est = json.loads(p.read_text())
    return est["median"]["point_estimate"] / 1000.0, str(p.relative_to(root))


def main() -> int:
    ap = argparse.ArgumentParser(description="OpenCV vs coopwin kernel timings")
    ap.add_argument("--repo-root", type=Path, default=Path(__file__).resolve().parent.parent)
    ap.add_argument("--json", type=Path, help="also write results as JSON to this file")
    ap.add_argument("--repeats", type=int, default=31, help="timeit repeats (median taken)")
    ap.add_argument("--min-repeat-ms", type=float, default=20.0,
                    help="target duration of one repeat")
    args = ap.parse_args()
    root = args.repo_root.resolve()
    bench_dir = root / "fixtures" / "bench"
    if not (bench_dir / "watch_prev.pgm").is_file():
        print(f"missing inputs in {bench_dir}; run python3 fixtures/bench/make_bench_inputs.py",
              file=sys.stderr)
        return 2

    kernels = build_kernels(bench_dir)
    outputs = {k: repr(fn()) for k, fn in kernels.items()}

    default_threads = cv2.getNumThreads()
    results: dict[str, dict] = {k: {} for k in kernels}
    for label, nthreads in (("opencv_1t_us", 1), ("opencv_default_us", default_threads)):
        cv2.setNumThreads(nthreads)
        for k, fn in kernels.items():
            med, best = time_us(fn, args.repeats, args.min_repeat_ms / 1000.0)
            results[k][label] = med
            results[k][label.replace("_us", "_min_us")] = best
    cv2.setNumThreads(default_threads)

    missing = []
    for k in IDS:
        us, src = read_criterion(root, k)
        results[k]["coopwin_us"] = us
        results[k]["criterion_file"] = src
        if us is None:
            missing.append(k)
        results[k]["ratio_1t_over_coopwin"] = (results[k]["opencv_1t_us"] / us) if us else None
    for k in kernels:
        results[k]["output"] = outputs[k]

    try:
        cvver = pkg_version("opencv-python-headless")
    except PackageNotFoundError:
        cvver = cv2.__version__
    meta = {"opencv": cvver, "cv2.__version__": cv2.__version__, "numpy": np.__version__,
            "python": platform.python_version(), "machine": platform.machine(),
            "cpu_count_opencv_default_threads": default_threads,
            "repeats": args.repeats, "min_repeat_ms": args.min_repeat_ms}

    def f(v):
        return "n/a" if v is None else f"{v:.2f}"

    print(f"OpenCV {cvver} (cv2 {cv2.__version__}), numpy {np.__version__}, "
          f"default threads = {default_threads}; median of {args.repeats} timeit repeats\n")
    print("| kernel | OpenCV 1-thread us | OpenCV default us | coopwin us | ratio (OpenCV-1t / coopwin) |")
    print("|---|---:|---:|---:|---:|")
    for k in IDS + EXTRA_IDS:
        r = results[k]
        ratio = "n/a" if r.get("ratio_1t_over_coopwin") is None else f"{r['ratio_1t_over_coopwin']:.2f}x"
        cw = f(r.get("coopwin_us")) if k in IDS else "(not a criterion id)"
        print(f"| {k} | {f(r['opencv_1t_us'])} | {f(r['opencv_default_us'])} | {cw} | {ratio} |")
    print()
    for k in IDS + EXTRA_IDS:
        print(f"  {k}: OpenCV output {results[k]['output']}")
    if missing:
        print(f"\nNo criterion results for: {', '.join(missing)} "
              f"(looked in {root / 'target' / 'criterion'}/<id>/new/estimates.json).\n"
              "Run `cargo bench -p coopwin-firmware --bench kernels` first to fill the coopwin column.")
    if args.json:
        args.json.write_text(json.dumps({"meta": meta, "results": results}, indent=2) + "\n")
        print(f"\nwrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
