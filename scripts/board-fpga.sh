#!/usr/bin/env bash
# The board build for the window unit on a Lattice iCE40-HX8K breakout board (ct256) with an
# OV7670-style camera and the FT2232H UART (docs/board.md), in one command:
#   1. Icarus simulation of the whole top with the camera and host models (self-checking):
#      the synthesised configuration (640 x 480, 8-byte coordinates, small and VGA frames,
#      frames started 0-3 clocks after a set completes), then a 128 x 96 configuration
#      (4-byte coordinates)
#   2. Yosys synth_ice40
#   3. nextpnr-ice40 --hx8k --package ct256, pins from hdl/board/coopwin_ice40_hx8k.pcf,
#      both clocks constrained (clk12 12 MHz, cam_pclk --pclk-mhz)
#   4. icetime timing report
#   5. icepack: the bitstream
# Prints utilisation, Fmax per clock, the bitstream's path and size; exits non-zero if the
# simulation fails, a tool fails, or a clock misses its constraint.
# The bitstream has not been run on hardware.
# With --axis, the same steps for the AXI4-Stream example integration instead
# (coopwin_ice40_axis_top: camera -> coopwin_dvp_axis -> window_unit_axis -> capture buffers,
# registers over the UART), simulated by hdl/board/tb/coopwin_ice40_axis_tb.v.
#
# Usage: scripts/board-fpga.sh [--axis] [--out DIR] [--seed N] [--pclk-mhz F] [--no-sim]
#                              [--quick-sim] [--netlist-sim] [--sim-only] [--with FILE=COPY]
#   --axis         the AXI4-Stream top (outputs coopwin_ice40_axis_hx8k.*)
#   --out DIR      outputs here (default: target/board-fpga, which git ignores)
#   --seed N       nextpnr placement seed (default 1)
#   --pclk-mhz F   pixel-clock constraint (default 48: twice the OV7670's 24 MHz VGA PCLK)
#   --no-sim       skip the simulation
#   --quick-sim    skip the VGA-size frames and the 4-byte configuration
#   --netlist-sim  also simulate Yosys's synthesised netlist with its ice40 cell models
#                  (small frames; about 3 CPU minutes, so not by default; not with --axis)
#   --sim-only     stop after the simulation
#   --with FILE=COPY  simulate COPY in place of the design source FILE (a path as the script
#                  names it, e.g. hdl/board/coopwin_dvp_axis.v): a mutant must make it fail
# Needs: apt-get install -y iverilog yosys nextpnr-ice40 fpga-icestorm
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$root/target/board-fpga"
seed=1
pclk_mhz=48
sim=1
quick=0
netlist=0
axis=0
sim_only=0
swap_from=""
swap_to=""

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --out) [ $# -ge 2 ] || { echo "board-fpga.sh: --out needs a directory" >&2; exit 2; }; out="$2"; shift 2 ;;
    --seed) [ $# -ge 2 ] || { echo "board-fpga.sh: --seed needs a number" >&2; exit 2; }; seed="$2"; shift 2 ;;
    --pclk-mhz) [ $# -ge 2 ] || { echo "board-fpga.sh: --pclk-mhz needs a number" >&2; exit 2; }; pclk_mhz="$2"; shift 2 ;;
    --no-sim) sim=0; shift ;;
    --quick-sim) quick=1; shift ;;
    --netlist-sim) netlist=1; shift ;;
    --axis) axis=1; shift ;;
    --sim-only) sim_only=1; shift ;;
    --with) [ $# -ge 2 ] && [ "${2#*=}" != "$2" ] || { echo "board-fpga.sh: --with needs FILE=COPY" >&2; exit 2; }
      swap_from="$root/${2%%=*}"; swap_to="${2#*=}"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "board-fpga.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

missing=""
need() { # tool, apt package
  command -v "$1" >/dev/null 2>&1 || missing="$missing $1 (apt package $2);"
}
[ "$sim" = 1 ] && { need iverilog iverilog; need vvp iverilog; }
if [ "$sim_only" = 0 ]; then
  need yosys yosys
  need nextpnr-ice40 nextpnr-ice40
  need icetime fpga-icestorm
  need icepack fpga-icestorm
fi
if [ -n "$missing" ]; then
  echo "board-fpga.sh: missing tools:$missing" >&2
  echo "  install with: sudo apt-get install -y iverilog yosys nextpnr-ice40 fpga-icestorm" >&2
  exit 2
fi

top="$root/hdl/board/coopwin_ice40_top.v"   # with --axis too: its UART, SCCB and synchronisers
pcf="$root/hdl/board/coopwin_ice40_hx8k.pcf"
tb="$root/hdl/board/tb"
if [ "$axis" = 1 ]; then
  [ "$netlist" = 0 ] || { echo "board-fpga.sh: --netlist-sim is not available with --axis" >&2; exit 2; }
  topmod=coopwin_ice40_axis_top
  base=coopwin_ice40_axis_hx8k
  srcs="$root/hdl/verilog/window_unit_axis.v $root/hdl/board/coopwin_dvp_axis.v $top $root/hdl/board/coopwin_ice40_axis_top.v"
  tbmod=coopwin_ice40_axis_tb
else
  topmod=coopwin_ice40_top
  base=coopwin_ice40_hx8k
  srcs="$root/hdl/verilog/window_unit.v $top"
  tbmod=coopwin_ice40_tb
fi
if [ -n "$swap_from" ]; then
  case " $srcs " in *" $swap_from "*) ;; *) echo "board-fpga.sh: --with: $swap_from is not a design source of this build" >&2; exit 2 ;; esac
  [ -f "$swap_to" ] || { echo "board-fpga.sh: --with: no file $swap_to" >&2; exit 2; }
  sim_srcs="$(echo " $srcs " | sed "s| $swap_from | $swap_to |")"
else
  sim_srcs="$srcs"
fi
mkdir -p "$out"
out="$(cd "$out" && pwd)"
t0=$(date +%s)
step() { echo "board-fpga.sh: $*"; }
die() { echo "board-fpga.sh: $*" >&2; exit 1; }

# 1. Simulation --------------------------------------------------------------------------
if [ "$sim" = 1 ]; then
  run_sim() { # name, vvp plusargs, iverilog options and design sources...
    local name="$1" plus="$2"; shift 2
    iverilog -Wall -Wno-timescale -I "$tb" "$@" -o "$out/$name.vvp" -s "$tbmod" \
      "$tb/ov7670_model.v" "$tb/$tbmod.v" 2>"$out/$name.iverilog.log" ||
      { cat "$out/$name.iverilog.log" >&2; die "iverilog failed ($name)"; }
    local ts=$(date +%s) rc=0
    (cd "$out" && vvp -n "$name.vvp" $plus) >"$out/$name.log" 2>&1 || rc=$?
    if [ "$rc" != 0 ] || ! tail -1 "$out/$name.log" | grep -q '^PASS$'; then
      grep -E 'FAIL|pixel \(' "$out/$name.log" | head -20 >&2
      die "simulation $name failed (exit $rc); log: $out/$name.log"
    fi
    step "simulation $name: $(grep -c '^  window' "$out/$name.log") windows, $(grep -o '[0-9]* checks, 0 errors' "$out/$name.log"), $(grep -o '[0-9.]* ms simulated' "$out/$name.log") in $(( $(date +%s) - ts )) s: PASS"
  }
  if [ "$axis" = 1 ]; then
    run_sim sim-axis-640x480 "" -g2005 $sim_srcs
  elif [ "$quick" = 1 ]; then
    run_sim sim-640x480 +novga -g2005 $sim_srcs
  else
    run_sim sim-640x480 "" -g2005 $sim_srcs
    run_sim sim-128x96 "" -g2005 -P coopwin_ice40_tb.WIDTH=128 -P coopwin_ice40_tb.HEIGHT=96 $sim_srcs
  fi
  if [ "$netlist" = 1 ]; then
    # Yosys's synthesised netlist (SB_LUT4, SB_DFF*, SB_RAM40_4K, SB_GB_IO, SB_IO cells) with
    # Yosys's own simulation models, the testbench's 87 ms timeout, small frames only.
    datdir="$(cd "$(dirname "$(command -v yosys)")/../share/yosys" && pwd)"
    [ -f "$datdir/ice40/cells_sim.v" ] || die "no Yosys ice40 cell models in $datdir/ice40"
    yosys -q -p "read_verilog $sim_srcs; chparam -set TIMEOUT_LOG2 20 coopwin_ice40_top; synth_ice40 -top coopwin_ice40_top; write_verilog -noattr $out/netlist-sim.v" \
      >"$out/netlist-sim.yosys.log" 2>&1 || die "yosys failed (netlist simulation); log: $out/netlist-sim.yosys.log"
    run_sim sim-netlist +novga -g2012 -DNO_ICE40_DEFAULT_ASSIGNMENTS -DNETLIST -Wno-portbind -Wno-implicit \
      "$out/netlist-sim.v" "$datdir/ice40/cells_sim.v" "$datdir/simcells.v"
  fi
fi

if [ "$sim_only" = 1 ]; then step "done in $(( $(date +%s) - t0 )) s (simulation only)"; exit 0; fi

# 2. Synthesis ---------------------------------------------------------------------------
# (One expected warning: Yosys's "limited support for tri-state logic", for SIOD's
# `pull ? 1'b0 : 1'bz`; nextpnr packs it into the pin's SB_IO output enable.)
yosys -q -l "$out/yosys.log" -p "read_verilog $srcs; synth_ice40 -top $topmod -json $out/$base.json; tee -q -o $out/yosys-stat.txt stat" >/dev/null 2>"$out/yosys.stderr" ||
  { cat "$out/yosys.stderr" >&2; die "yosys failed; log: $out/yosys.log"; }
cells() { awk -v c="$1" '$1 == c {print $2; f=1} END {if (!f) print 0}' "$out/yosys-stat.txt"; }
ffs=$(awk '$1 ~ /^SB_DFF/ {n += $2} END {print n + 0}' "$out/yosys-stat.txt")
step "yosys synth_ice40: $(cells SB_LUT4) SB_LUT4, $(cells SB_CARRY) SB_CARRY, $ffs flip-flops, $(cells SB_RAM40_4K) SB_RAM40_4K ($(grep -c '^Warning' "$out/yosys.stderr" || true) warning(s), in $out/yosys.stderr)"

# 3. Place and route ---------------------------------------------------------------------
cat >"$out/clocks.py" <<EOF
# nextpnr-ice40 --pre-pack: the two clock domains (written by scripts/board-fpga.sh)
ctx.addClock("clk", 12)     # clk12 through its SB_GB_IO
ctx.addClock("pclk", $pclk_mhz)  # cam_pclk through its SB_GB_IO
EOF
nextpnr-ice40 --hx8k --package ct256 --json "$out/$base.json" --pcf "$pcf" \
  --pre-pack "$out/clocks.py" --seed "$seed" --asc "$out/$base.asc" \
  --report "$out/nextpnr-report.json" >"$out/nextpnr.log" 2>&1 ||
  { tail -20 "$out/nextpnr.log" >&2; die "nextpnr-ice40 failed; log: $out/nextpnr.log"; }
step "nextpnr-ice40 --hx8k --package ct256 --seed $seed, utilisation:"
grep -E '^Info:[[:space:]]+(ICESTORM_LC|ICESTORM_RAM|SB_IO|SB_GB):[[:space:]]+[0-9]+/' "$out/nextpnr.log" | head -4 |
  sed 's/^Info:[[:space:]]*/    /'
fmax=$(grep -E "^Info: Max frequency for clock" "$out/nextpnr.log" | tail -2)
[ -n "$fmax" ] || die "no Fmax in the nextpnr log: $out/nextpnr.log"
echo "$fmax" | sed "s/^Info: Max frequency for clock *'\([^$']*\)[^']*': */    Fmax \1: /"
if echo "$fmax" | grep -q FAIL; then die "a clock misses its constraint (see $out/nextpnr.log)"; fi

# 4. Timing report -----------------------------------------------------------------------
icetime -d hx8k -P ct256 -p "$pcf" -t -r "$out/icetime.rpt" "$out/$base.asc" >"$out/icetime.log" 2>&1 ||
  die "icetime failed; log: $out/icetime.log"
step "icetime: worst register-to-register path over both clocks: $(grep -o 'Total path delay: .*' "$out/icetime.rpt" | sed 's/Total path delay: //') (report: $out/icetime.rpt)"

# 5. Bitstream ---------------------------------------------------------------------------
icepack "$out/$base.asc" "$out/$base.bin" || die "icepack failed"
step "bitstream: $out/$base.bin ($(stat -c %s "$out/$base.bin") bytes; flash: iceprog $out/$base.bin)"
step "done in $(( $(date +%s) - t0 )) s (not run on hardware)"
