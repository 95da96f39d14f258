#!/usr/bin/env bash
# The soft-CPU SoC co-simulation (issue 40, docs/soc.md): the project's Rust firmware
# (firmware/soc, riscv32imac) on a VexRiscv (pythondata-cpu-vexriscv) with RAM, a UART and the
# window unit (hdl/verilog/window_unit.v) as an MMIO peripheral with a capture DMA
# (hdl/soc/coopwin_soc.v), in Verilator, the camera fed from a built-in scene's frames. It
# fails unless the firmware exits cleanly, the hostile coordinate sets are refused, and the
# UART's position updates equal, byte for byte, those the same tracker sends on the host from
# windows a model of the unit cuts from the same frames (firmware/soc's `soc-replay`), and,
# where the SoC measures every frame, `coopwin track`'s rows (frame, x, y). The program RAM is
# firmware/soc/memory.x's LENGTH (the bitstream's too, scripts/soc-ecp5.sh); each run fails if
# the stack's deepest point (the lowest RAM address written) reaches the image.
#
#   scripts/soc.sh                 21 frames of the default scene (triangle path, 256x256)
#   scripts/soc.sh --frames N      N frames (N >= 8: the figures need windows after the lock-on; 8 and 21 were run)
#   COOPWIN=path/to/coopwin scripts/soc.sh   use that build of the CLI (scene, track) instead
#                                  of building target/release/coopwin
#
# Outputs in target/soc/: realtime/, everyframe/ and audit/ (sim.log: every UART byte with its
# clock and the firmware's lines; firmware.log: those lines; uart.bin; audit/unit.vcd and
# requests.csv, what `coopwin audit` checks), track.csv (the host's rows),
# report.md (the measured cycles, scripts/soc_report.py).
# Needs: apt-get install verilator binutils-riscv64-unknown-elf rustc-web cargo-web rust-web-src;
# pip install pythondata-cpu-vexriscv (the versions .ci/run pins).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
frames=21
case "${1:-}" in
  --frames) frames="${2:?--frames N}"; [[ "$frames" =~ ^[0-9]+$ && "$frames" -ge 8 ]] || { echo "soc.sh: --frames takes a whole number >= 8 (the figures need windows after the lock-on)" >&2; exit 2; } ;;
  "") ;;
  *) echo "usage: $0 [--frames N]" >&2; exit 2 ;;
esac
for tool in verilator riscv64-unknown-elf-objcopy riscv64-unknown-elf-ld /usr/bin/rustc /usr/bin/cargo cargo python3; do
  command -v "$tool" >/dev/null || { echo "soc.sh: $tool is missing (see the header of $0)" >&2; exit 2; }
done
vex="$(python3 -c 'import pythondata_cpu_vexriscv as p; print(p.data_location)' 2>/dev/null)/VexRiscv_IMAC.v" ||
  { echo "soc.sh: pip install pythondata-cpu-vexriscv" >&2; exit 2; }
[ -f "$vex" ] || { echo "soc.sh: $vex is missing" >&2; exit 2; }
out="$root/target/soc"
mkdir -p "$out"
# The program RAM the firmware is linked for is the one simulated (and the bitstream's,
# scripts/soc-ecp5.sh): firmware/soc/memory.x's LENGTH.
ram_kib="$(sed -n 's/^ *RAM *:.*LENGTH *= *\([0-9][0-9]*\)K *$/\1/p' "$root/firmware/soc/memory.x")"
[ -n "$ram_kib" ] || { echo "soc.sh: no 'RAM : ... LENGTH = <N>K' line in firmware/soc/memory.x" >&2; exit 1; }

echo "soc.sh: scene ($frames frames)" >&2
if [ -z "${COOPWIN:-}" ]; then
  (cd "$root" && nice -n 10 cargo build --release --locked -q --bin coopwin)
  COOPWIN="$root/target/release/coopwin"
fi
# A scene's frames as the camera's raw rows; prints the target (its first centre, rounded).
scene() { # folder frames
  rm -rf "$out/$1" "$out/$1-raw"
  mkdir -p "$out/$1-raw"
  "$COOPWIN" scene --frames "$2" --out "$out/$1" >/dev/null
  python3 "$root/scripts/soc_frames.py" "$out/$1" "$out/$1-raw" "$2"
}
# The firmware image for a camera of N frames, as hex words for $readmemh. Source paths (in
# its panic messages) are remapped: the image, and so where the hot code falls in the 4 KiB
# instruction cache and every cycle count, is the same from any checkout.
firmware() { # frames target hex
  local fw="$out/fw" cargo_home="${CARGO_HOME:-$HOME/.cargo}"
  (cd "$root/firmware/soc" &&
    COOPWIN_SOC_FRAMES="$1" COOPWIN_SOC_TARGET="$2" CARGO_TARGET_DIR="$fw" RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 \
    nice -n 10 /usr/bin/cargo build --release --locked -q --features board --bin soc \
      --target riscv32imac-unknown-none-elf -Zbuild-std=core \
      --config 'target.riscv32imac-unknown-none-elf.linker="riscv64-unknown-elf-ld"' \
      --config "target.riscv32imac-unknown-none-elf.rustflags=[\"-C\",\"link-arg=-melf32lriscv\",\"-C\",\"link-arg=-T$root/firmware/soc/memory.x\",\"--remap-path-prefix=$root=/coopwin\",\"--remap-path-prefix=$cargo_home=/cargo\"]")
  local elf="$fw/riscv32imac-unknown-none-elf/release/soc"
  # No .data or .bss: every data-bus write to RAM is then the stack's (simulate's measure).
  [ -z "$(riscv64-unknown-elf-size -A "$elf" | awk '$1 ~ /^\.(s?data|s?bss)/ && $2 > 0')" ] ||
    { echo "soc.sh: the firmware has .data or .bss, which the stack's measure (ram_low_write) takes for stack" >&2; exit 1; }
  riscv64-unknown-elf-objcopy -O binary "$elf" "$out/fw.bin"
  python3 - "$out/fw.bin" "$3" <<'PY'
import struct, sys
b = open(sys.argv[1], "rb").read()
b += b"\0" * (-len(b) % 4)
open(sys.argv[2], "w").write("".join("%08x\n" % w for w in struct.unpack("<%dI" % (len(b) // 4), b)))
PY
}
target="$(scene scene "$frames")"
# The audit's run has a camera of its own (below): the scene's first frame, 64 times, so that
# the target stays where the firmware, far slower than that camera, looks for it.
audit_frames=64
rm -rf "$out/still-raw" && mkdir -p "$out/still-raw"
for k in $(seq 0 $((audit_frames - 1))); do
  cp "$out/scene-raw/frame0000.raw" "$out/still-raw/$(printf 'frame%04d.raw' "$k")"
done
echo "soc.sh: firmware (riscv32imac, target $target)" >&2
firmware "$audit_frames" "$target" "$out/fw-audit.hex"
firmware "$frames" "$target" "$out/fw.hex"

echo "soc.sh: Verilator model (program RAM $ram_kib KiB)" >&2
(cd "$out" && nice -n 10 verilator --cc --exe --build -O2 -j 1 --top-module coopwin_soc \
  -Wall --timescale 1ns/1ps --Mdir obj -GRAM_BYTES=$((ram_kib * 1024)) \
  "$root/hdl/soc/tb/verilator.vlt" "$vex" "$root/hdl/verilog/window_unit.v" "$root/hdl/soc/soc_ram.v" "$root/hdl/soc/coopwin_soc.v" "$root/hdl/soc/tb/sim_main.cpp" \
  -o Vcoopwin_soc >verilator.log 2>&1) || { tail -20 "$out/verilator.log" >&2; exit 1; }

# Two runs of the same model and image. "realtime": a 100 MHz clock and the thesis's camera
# (256x256 at 114 frames/s: a pixel every 12 clocks, 874,632 clocks a frame); the firmware
# takes longer than a frame, so it measures every 2nd frame or so. "everyframe": the camera
# slowed (a pixel every 48 clocks, 4,153,928 clocks a frame: 24.1 frames/s at 100 MHz) until
# the firmware measures every frame; its updates must equal `coopwin track`'s rows.
simulate() { # name image frames-folder count every vblank [testbench options]
  local dir="$out/$1" image="$2" raw="$3" count="$4" every="$5" vblank="$6" status=0
  shift 6
  mkdir -p "$dir"
  echo "soc.sh: co-simulation, $(basename "$dir") (a pixel every $every clocks)" >&2
  (cd "$dir" && nice -n 10 "$out/obj/Vcoopwin_soc" +firmware="$image" --frames "$raw" --count "$count" \
    --every "$every" --vblank "$vblank" --uart "$dir/uart.bin" --log "$dir/sim.log" "$@") || status=$?
  grep -v '^uart ' "$dir/sim.log" >"$dir/firmware.log"
  # The stack's deepest point (the lowest RAM address written) must stay above the image.
  local low image_end
  low="$(sed -n 's/^end .* ram_low_write=\(0x[0-9a-f]*\)$/\1/p' "$dir/sim.log")"
  [ -n "$low" ] || { tail -5 "$dir/sim.log" >&2; echo "soc.sh: $dir/sim.log has no end line (the testbench stopped)" >&2; exit 1; }
  low=$((low))
  image_end=$(( $(grep -c . "$image") * 4 ))
  [ "$low" -ge "$image_end" ] ||
    { echo "soc.sh: $dir: the stack reached $low, below the image's end $image_end: it overran the code" >&2; exit 1; }
  echo "soc.sh: $(basename "$dir"): stack $((ram_kib * 1024 - low)) bytes deep, $((low - image_end)) bytes between it and the image ($ram_kib KiB RAM)" >&2
  [ "$status" = 0 ] || { cat "$dir/firmware.log" >&2; echo "soc.sh: $dir: the SoC's firmware ended with status $status" >&2; exit 1; }
  grep -q 'hostile over_edge_refused_by_driver=true reversed_refused_by_unit=true' "$dir/sim.log" ||
    { echo "soc.sh: $dir: the hostile sets were not refused" >&2; exit 1; }
  sed -n 's/^fw [0-9]* \(hostile .*\)/soc.sh: '"$(basename "$dir")"': \1/p; s/^fw [0-9]* \(end .*\)/soc.sh: '"$(basename "$dir")"': \1/p' "$dir/firmware.log" >&2
}
simulate realtime "$out/fw.hex" "$out/scene-raw" "$frames" 12 80000
simulate everyframe "$out/fw.hex" "$out/scene-raw" "$frames" 48 1000000
# A third run traces the window unit for `coopwin audit`, whose pixel columns are clocks of
# lval: a pixel every clock and 2,000 clocks between frames (75,736 clocks a frame), 64
# frames of a still scene, so that the firmware gets through a few windows after its lock-on
# (2.4 M clocks); the unit's signals in unit.vcd.
simulate audit "$out/fw-audit.hex" "$out/still-raw" "$audit_frames" 1 2000 --vcd "$out/audit/unit.vcd"

echo "soc.sh: host references" >&2
(cd "$root/firmware/soc" && CARGO_TARGET_DIR="$out/host" nice -n 10 cargo build --release --locked -q --features host --bin soc-replay)
"$COOPWIN" track --frames "$out/scene" --strategy tpdf --target "$target" --fixed-template \
  --out "$out/track.csv" >"$out/track.txt"
"$out/host/release/soc-replay" --frames "$out/scene-raw" --log "$out/realtime/sim.log" --uart "$out/realtime/uart.bin" --target "$target"
"$out/host/release/soc-replay" --frames "$out/scene-raw" --log "$out/everyframe/sim.log" --uart "$out/everyframe/uart.bin" \
  --target "$target" --track "$out/track.csv"
# The audit's requests: the coordinate sets as the firmware queued them (its `set` lines), the
# hostile one included; the VCD's sets, windows and event order are checked against them.
python3 - "$out/audit/sim.log" >"$out/audit/requests.csv" <<'PY'
import re, sys
print("unit,clock,xmin,xmax,ymin,ymax,decimate")
for line in open(sys.argv[1]):
    m = re.search(r" set cycle=(\d+) bytes=(\d+),(\d+),(\d+),(\d+) dec=(\d)$", line.rstrip("\n"))
    if m:
        print("0," + ",".join(m.groups()))
PY
"$COOPWIN" audit --requests "$out/audit/requests.csv" "$out/audit/unit.vcd"
python3 "$root/scripts/soc_report.py" "$out" | tee "$out/report.md"
