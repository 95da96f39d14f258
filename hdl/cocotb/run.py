#!/usr/bin/env python3
"""Run the cocotb testbench of hdl/verilog/window_unit.v in Icarus Verilog.

With no arguments it builds and tests two configurations, 256x256 with 8-bit pixels and
640x480 with 10-bit pixels (two-byte coordinates), prints a summary with the functional
coverage, and exits non-zero if a test failed or a coverage goal was not reached. With --axis
it runs the bench of the AXI4-Stream wrapper hdl/verilog/window_unit_axis.v instead (three
windows, 8-beat FIFOs), at 80x40 with 16-bit pixels and 260x16 with 10-bit pixels (9-bit coordinates).

Examples:
  python3 hdl/cocotb/run.py                         # the default configurations
  python3 hdl/cocotb/run.py --size 1024x768 --bits 12
  python3 hdl/cocotb/run.py --frames 400 --seed 7   # a longer run with another seed
  python3 hdl/cocotb/run.py --test test_resets      # one test
  python3 hdl/cocotb/run.py --probes                # camera timing below the minimums
  python3 hdl/cocotb/run.py --rtl /tmp/mutant.v     # another copy of the module
  python3 hdl/cocotb/run.py --axis                  # the AXI4-Stream wrapper's bench
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path
from xml.etree import ElementTree

sys.dont_write_bytecode = True          # no __pycache__ in the repository

HERE = Path(__file__).resolve().parent
RTL = HERE.parent / "verilog" / "window_unit.v"
DEFAULT_CONFIGS = [(256, 256, 8), (640, 480, 10)]
AXIS_RTL = HERE.parent / "verilog" / "window_unit_axis.v"
AXIS_TOP = HERE / "tb_window_unit_axis.v"
AXIS_CONFIGS = [(80, 40, 16), (260, 16, 10)]
AXIS_FIFO_DEPTH = 8
INSTALL = ("install them with:\n"
           "  pip install -r hdl/cocotb/requirements.txt   (or: pip install cocotb cocotb-coverage cocotbext-axi)\n"
           "  apt-get install -y iverilog                  (Icarus Verilog 11 or later)")


def missing_tools() -> list[str]:
    missing = []
    try:
        import cocotb
        if int(cocotb.__version__.split(".")[0]) < 2:
            missing.append(f"cocotb 2.x (found {cocotb.__version__})")
        import cocotb_tools.runner  # noqa: F401
    except ImportError:
        missing.append("cocotb (Python package)")
    try:
        import cocotb_coverage  # noqa: F401
    except ImportError:
        missing.append("cocotb-coverage (Python package)")
    try:
        import cocotbext.axi  # noqa: F401
    except ImportError:
        missing.append("cocotbext-axi (Python package)")
    for tool in ("iverilog", "vvp"):
        if shutil.which(tool) is None:
            missing.append(f"{tool} (Icarus Verilog)")
    return missing


def size(text: str) -> tuple[int, int]:
    m = re.fullmatch(r"(\d+)x(\d+)", text)
    if not m:
        raise argparse.ArgumentTypeError(f"{text!r}: expected WIDTHxHEIGHT, e.g. 640x480")
    w, h = int(m.group(1)), int(m.group(2))
    if not (16 <= w <= 4096 and 16 <= h <= 4096):
        raise argparse.ArgumentTypeError(f"{text}: WIDTH and HEIGHT must be 16..4096")
    return w, h


def bits(text: str) -> int:
    p = int(text)
    if not 8 <= p <= 16:
        raise argparse.ArgumentTypeError(f"{text}: PIXEL_BITS must be 8..16")
    return p


def parse_args(argv):
    intro, defaults, examples = __doc__.split("\n\n")
    ap = argparse.ArgumentParser(
        description=f"{intro}\n\n{defaults} Build products and reports (results.xml, "
        "coverage.xml, coverage.yml) go to a new temporary directory unless --build is given.",
        epilog=examples, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=size, metavar="WxH",
                    help="WIDTH x HEIGHT, 16..4096 each (default: 256x256 and 640x480)")
    ap.add_argument("--bits", type=bits, metavar="P",
                    help="PIXEL_BITS, 8..16 (default 8; 10 for the default 640x480)")
    ap.add_argument("--build", metavar="DIR", type=Path,
                    help="build and report directory (default: a new temporary directory)")
    ap.add_argument("--frames", type=int, default=0, metavar="N",
                    help="frames of the random test (default 200 up to 256x256, else 80)")
    ap.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    ap.add_argument("--test", metavar="NAME[,NAME]",
                    help="run only these tests (add test_coverage to report coverage, "
                    "whose goal is then not enforced)")
    ap.add_argument("--probes", action="store_true",
                    help="run only the probes of camera timing below the documented minimums "
                    "(expected to fail)")
    ap.add_argument("--axis", action="store_true",
                    help="test the AXI4-Stream wrapper window_unit_axis instead of the unit")
    ap.add_argument("--rtl", type=Path, metavar="FILE",
                    help=f"the Verilog to test (default {RTL.relative_to(HERE.parent.parent)}, "
                    f"with --axis {AXIS_RTL.relative_to(HERE.parent.parent)})")
    ap.add_argument("--waves", action="store_true", help="write window_unit.fst in the build dir")
    ap.add_argument("--verbose", action="store_true", help="log every frame, set and reset")
    args = ap.parse_args(argv)
    if args.rtl is None:
        args.rtl = AXIS_RTL if args.axis else RTL
    if args.axis and args.probes:
        ap.error("--probes is for the unit's bench, not --axis")
    if args.size is None and args.bits is None:
        args.configs = AXIS_CONFIGS if args.axis else DEFAULT_CONFIGS
    else:
        w, h = args.size or (256, 256)
        args.configs = [(w, h, args.bits or 8)]
    if not args.rtl.is_file():
        ap.error(f"--rtl {args.rtl}: no such file")
    return args


def results(xml: Path):
    """(name, passed/failed/skipped, seconds, message) for each test in a results.xml."""
    out = []
    if not xml.is_file():
        return out
    for case in ElementTree.parse(xml).getroot().iter("testcase"):
        status, msg = "passed", ""
        for tag in ("failure", "error"):
            el = case.find(tag)
            if el is not None:
                status = "FAILED"
                msg = (el.get("message") or el.text or "").strip().splitlines()[0:1]
                msg = msg[0] if msg else ""
        if case.find("skipped") is not None:
            status = "skipped"
        out.append((case.get("name"), status, float(case.get("time", 0)), msg))
    return out


def coverage_summary(yml: Path) -> str:
    if not yml.is_file():
        return "no coverage report"
    import yaml
    db = yaml.safe_load(yml.read_text())
    top = db.get("top")
    if not top:
        return "no coverage report"
    missing = [f"{name}: {b}" for name, item in db.items() if "bins:_hits" in item
               for b, hits in item["bins:_hits"].items() if hits < item.get("at_least", 1)]
    text = f"{top['coverage']}/{top['size']} bins ({top['cover_percentage']}%)"
    if missing:
        text += ", not hit: " + "; ".join(missing)
    return text


def run_config(args, base: Path, width: int, height: int, pbits: int):
    from cocotb_tools.runner import get_runner
    name = f"{width}x{height}x{pbits}"
    build = base / name
    build.mkdir(parents=True, exist_ok=True)
    for old in ("results.xml", "coverage.xml", "coverage.yml"):   # none left from a last run
        (build / old).unlink(missing_ok=True)
    os.environ.update({
        "PYTHONDONTWRITEBYTECODE": "1",
        "COOPWIN_FRAMES": str(args.frames),
        "COOPWIN_SEED": str(args.seed),
        "COOPWIN_VERBOSE": "1" if args.verbose else "",
        "COOPWIN_PROBES": "1" if args.probes else "",
        "COOPWIN_COVERAGE_DIR": str(build),
    })
    parameters = {"WIDTH": width, "HEIGHT": height, "PIXEL_BITS": pbits}
    sources, top, module = [args.rtl.resolve()], "window_unit", "test_window_unit"
    if args.axis:
        parameters["FIFO_DEPTH"] = AXIS_FIFO_DEPTH
        sources, top, module = [args.rtl.resolve(), AXIS_TOP], "tb_window_unit_axis", "test_window_unit_axis"
        os.environ.update({f"COOPWIN_{k}": str(v) for k, v in parameters.items()})
    runner = get_runner("icarus")
    runner.build(sources=sources, hdl_toplevel=top, parameters=parameters,
                 build_dir=build, timescale=("1ns", "1ps"), always=True, waves=args.waves)
    testcase = args.test if args.test and not args.probes else None
    test_filter = r"\.probe_" if args.probes else None
    t0 = time.time()
    xml = runner.test(hdl_toplevel=top, test_module=module,
                      build_dir=build, test_dir=build, testcase=testcase, test_filter=test_filter,
                      seed=args.seed,
                      waves=args.waves, results_xml=str(build / "results.xml"))
    return name, build, results(Path(xml)), time.time() - t0


def main(argv=None) -> int:
    args = parse_args(sys.argv[1:] if argv is None else argv)
    missing = missing_tools()
    if missing:
        print("error: missing " + ", ".join(missing) + "\n" + INSTALL, file=sys.stderr)
        return 2
    if args.build is not None:
        base = args.build.resolve()
        base.mkdir(parents=True, exist_ok=True)
    else:
        base = Path(tempfile.mkdtemp(prefix="coopwin-cocotb-"))
    t0 = time.time()
    summary, failed = [], False
    for w, h, p in args.configs:
        try:
            name, build, tests, secs = run_config(args, base, w, h, p)
        except (SystemExit, RuntimeError, OSError) as e:     # build failed or simulator crashed
            summary.append((f"{w}x{h}x{p}", base, [], 0.0, f"simulation did not run: {e}"))
            failed = True
            continue
        cov = coverage_summary(build / "coverage.yml")
        if not tests:
            failed = True
        for _, status, _, _ in tests:
            failed |= status == "FAILED"
        summary.append((name, build, tests, secs, cov))

    print(f"\n==== {'window_unit_axis' if args.axis else 'window_unit'} cocotb summary " + "=" * 48)
    print(f"RTL: {args.rtl}   seed {args.seed}")
    for name, build, tests, secs, cov in summary:
        print(f"\n{name}  ({secs:.0f} s, reports in {build})")
        if not tests:
            print("  no results: the simulation did not run to the end")
        probes_skipped = [t for t in tests if t[0].startswith("probe_") and t[1] == "skipped"]
        for tname, status, tsecs, msg in tests:
            if (tname, status, tsecs, msg) not in probes_skipped:
                print(f"  {status:8} {tname:34} {tsecs:7.1f} s  {msg[:160]}")
        if probes_skipped:
            print(f"  ({len(probes_skipped)} probes of camera timing below the minimums skipped: "
                  "--probes runs them)")
        print(f"  coverage: {cov}")
    print(f"\n{'FAILED' if failed else 'PASSED'} in {time.time() - t0:.0f} s; build and reports in {base}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
