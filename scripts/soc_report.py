#!/usr/bin/env python3
"""The SoC co-simulation's figures (scripts/soc.sh): reads target/soc/{realtime,everyframe}/sim.log
and prints a Markdown table a run: the frames measured, cycles a window, instructions and CPI,
bus occupancy, the capture DMA's, and the latency from a window's last pixel to its position
update's last UART byte, measured twice: by the firmware (its cycle counter) and by the
testbench (the clock it took the UART byte on). Fails if the two disagree by more than the
1,000 clocks (the firmware's own read of the counter takes a few hundred), or if a window did not wake the
sleeping core exactly once (its interrupt).

    scripts/soc_report.py target/soc
"""
import re
import statistics
import sys

CLOCK_MHZ = 100  # the clock the camera's timing assumes (hdl/soc/tb/sim_main.cpp)
UPDATE_BYTES = 16  # sync, length, 13-byte payload, CRC (firmware/src/ports/position.rs)


def run(path):
    windows, uart, period = [], [], None
    for line in open(path):
        if line.startswith("uart "):
            uart.append(int(line.split()[1]))
        elif line.startswith("camera "):
            period = int(re.search(r"frame_period=(\d+)", line).group(1))
        elif " window " in line:
            windows.append({k: int(v) for k, v in re.findall(r"(\w+)=(\d+)", line)})
        elif line.startswith("end "):
            end = int(re.search(r"cycle=(\d+)", line).group(1))
    if any(w["wakes"] != 1 for w in windows):
        sys.exit(f"soc_report: {path}: a window did not wake the core exactly once: {[w['wakes'] for w in windows]}")
    if not windows or len(uart) != UPDATE_BYTES * len(windows):
        sys.exit(f"soc_report: {path}: {len(windows)} windows but {len(uart)} UART bytes")
    # The testbench's own clock of each update's last byte, less the unit's done clock.
    seen = [uart[UPDATE_BYTES * (i + 1) - 1] - w["done"] for i, w in enumerate(windows)]
    for w, s in zip(windows, seen):
        if abs(s - w["latency_cycles"]) > 1000:
            sys.exit(f"soc_report: {path}: window {w['n']}: firmware latency {w['latency_cycles']}, testbench {s}")
    return windows, seen, period, end


def span(xs):
    return f"{min(xs):,} / {statistics.median(xs):,.0f} / {max(xs):,}"


def main():
    out = sys.argv[1]
    print("| figure (min / median / max where three) | realtime | everyframe |")
    print("|---|---:|---:|")
    runs = [run(f"{out}/{name}/sim.log") for name in ("realtime", "everyframe")]
    rows = []
    rows.append(("camera frame period, clocks (fps at 100 MHz)", [f"{p:,} ({CLOCK_MHZ * 1e6 / p:.1f})" for _, _, p, _ in runs]))
    rows.append(("frames measured (one window each)", [" ".join(str(w["frame"]) for w in ws) for ws, _, _, _ in runs]))
    rows.append(("lock-on window (template + first NCC), cycles", [f"{ws[0]['compute_cycles']:,}" for ws, _, _, _ in runs]))
    rows.append(("NCC window, cycles", [span([w["compute_cycles"] for w in ws[1:]]) for ws, _, _, _ in runs]))
    rows.append(("NCC window, instructions", [span([w["compute_insns"] for w in ws[1:]]) for ws, _, _, _ in runs]))
    rows.append(("cycles per instruction (median window)", [f"{statistics.median(w['compute_cycles'] / w['compute_insns'] for w in ws[1:]):.2f}" for ws, _, _, _ in runs]))
    rows.append(("I-bus busy, % of a window's cycles", [f"{100 * statistics.median(w['ibus_busy'] / w['compute_cycles'] for w in ws[1:]):.1f}" for ws, _, _, _ in runs]))
    rows.append(("D-bus busy, % of a window's cycles", [f"{100 * statistics.median(w['dbus_busy'] / w['compute_cycles'] for w in ws[1:]):.1f}" for ws, _, _, _ in runs]))
    rows.append(("coordinate set over MMIO (driver handshake), cycles", [span([w["set_cycles"] for w in ws]) for ws, _, _, _ in runs]))
    rows.append(("capture DMA: pixels a window / write-port busy, % of the run", [f"{ws[0]['pixels']} / {100 * ws[-1]['dma_total'] / end:.3f}" for ws, _, _, end in runs]))
    rows.append(("last pixel to UART update, cycles (firmware)", [span([w["latency_cycles"] for w in ws]) for ws, _, _, _ in runs]))
    rows.append(("last pixel to UART update, cycles (testbench)", [span(seen) for _, seen, _, _ in runs]))
    rows.append(("last pixel to UART update, ms at 100 MHz (median NCC window)", [f"{statistics.median(seen[1:]) / CLOCK_MHZ / 1000:.2f}" for _, seen, _, _ in runs]))
    for name, cells in rows:
        print(f"| {name} | {cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
