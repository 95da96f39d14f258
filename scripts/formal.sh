#!/usr/bin/env bash
# Formal proofs of the window unit (hdl/verilog/window_unit.v) against the contract, with the
# harness hdl/formal/window_unit_props.sv. What is proven and how: docs/formal.md.
#
#   scripts/formal.sh                 proofs, covers, then the mutants
#   scripts/formal.sh --out DIR       also keep the VCD traces (covers, counterexamples) in DIR
#   scripts/formal.sh --mutants       only the mutants (hdl/formal/broken/*.sed)
#   scripts/formal.sh --no-mutants    everything but the mutants
#   scripts/formal.sh --jobs N        checks run N at a time (default 2)
#   scripts/formal.sh --axis          the AXI4-Stream wrapper (hdl/verilog/window_unit_axis.v)
#                                     instead: its harness hdl/formal/window_unit_axis_props.sv,
#                                     its mutants hdl/formal/broken-axis/*.sed
#
# Needs Debian's yosys (yosys, yosys-smtbmc, yosys-abc) and z3: apt-get install yosys z3.
# Nothing is written into the repository unless --out is given; work files live in a temp
# folder that is removed on exit. Exit status: 0 when every proof passes, every cover is
# reached and every mutant is caught; 1 otherwise; 2 on a usage or tool error.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
rtl="$root/hdl/verilog/window_unit.v"
props="$root/hdl/formal/window_unit_props.sv"
top=window_unit_props
broken="$root/hdl/formal/broken"
axis=0
mutant_defs=""   # the harness's defines for the mutants (the wrapper's: its probes)
out=""
jobs=2
run_proofs=1
run_mutants=1

usage() { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --out) [ $# -ge 2 ] || { echo "formal.sh: --out needs a folder" >&2; exit 2; }; out="$2"; shift 2 ;;
    --jobs) [ $# -ge 2 ] && [[ "$2" =~ ^[1-9][0-9]*$ ]] || { echo "formal.sh: --jobs needs a number" >&2; exit 2; }; jobs="$2"; shift 2 ;;
    --mutants) run_proofs=0; shift ;;
    --no-mutants) run_mutants=0; shift ;;
    --axis) axis=1; rtl="$root/hdl/verilog/window_unit_axis.v"; props="$root/hdl/formal/window_unit_axis_props.sv"
            top=window_unit_axis_props; broken="$root/hdl/formal/broken-axis"; mutant_defs="-DPROBES"; shift ;;
    *) echo "formal.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

missing=0
for tool in yosys yosys-smtbmc yosys-abc; do
  command -v "$tool" >/dev/null 2>&1 || { echo "formal.sh: $tool not found: apt-get install yosys" >&2; missing=1; }
done
command -v z3 >/dev/null 2>&1 || { echo "formal.sh: z3 not found: apt-get install z3" >&2; missing=1; }
[ "$missing" = 0 ] || exit 2
for f in "$rtl" "$props"; do [ -f "$f" ] || { echo "formal.sh: $f is missing" >&2; exit 2; }; done
if [ -n "$out" ]; then mkdir -p "$out"; out="$(cd "$out" && pwd)"; fi

tmp="$(mktemp -d "${TMPDIR:-/tmp}/formal.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/res"

# ---------------------------------------------------------------------------------------------
# Building a model: the RTL and the harness at one geometry, keeping only the named assertions
# (globs on the assert labels). Writes DIR/model.smt2 (for yosys-smtbmc) and DIR/model.aig with
# its map DIR/model.aim (for ABC's pdr and bmc3; yosys-smtbmc replays their traces into VCD).
# ---------------------------------------------------------------------------------------------
globs() { # "glob ..." -> a selection of the cells so named
  local sel="" first=1 g
  for g in $1; do
    sel="$sel n:$g"
    if [ $first = 1 ]; then first=0; else sel="$sel %u"; fi
  done
  echo "$sel"
}
# The harness's probes into the flattened RTL (define PROBES): yosys commands tying them.
probes() { # "defines"
  case " $1 " in
    *" -DPROBES "*) echo "connect -set probe_hit dut.win[0].hit; connect -set probe_drops dut.win[0].drops" ;;
  esac
}
build() { # dir rtl width height "defines" "assert globs" ["globs of assertions to assume"]
  local dir="$1" src="$2" w="$3" h="$4" defs="$5" keep="$6" assume="" sel
  mkdir -p "$dir"
  sel="t:\$assert $(globs "$keep") %d"
  if [ -n "${7:-}" ]; then assume="chformal -assert2assume $(globs "$7")"; fi
  yosys -q -l "$dir/yosys.log" -p "
    read_verilog -formal -sv $defs $src $props
    chparam -set WIDTH $w -set HEIGHT $h $top
    prep -flatten -top $top
    $(probes "$defs")
    memory_map
    check -assert
    chformal -cover -remove
    $assume
    chformal -assert -remove $sel
    async2sync
    opt -keepdc -fast
    dffunmap
    write_smt2 -wires $dir/model.smt2
    techmap
    opt -fast -nodffe -nosdff
    abc -g AND -fast
    opt_clean
    write_aiger -I -B -zinit -map $dir/model.aim $dir/model.aig" >/dev/null 2>&1 || {
      echo "build failed: see below" >"$dir/error"; tail -5 "$dir/yosys.log" >>"$dir/error"; return 1; }
}

# Replays an ABC trace (DIR/trace.aiw) through yosys-smtbmc into DIR/trace.vcd; prints the
# labels of the assertions that fail on it.
replay() { # dir
  local dir="$1"
  yosys-smtbmc --noprogress -s z3 --aig "$dir/model.aim:$dir/trace.aiw" --aig-noheader \
    --dump-vcd "$dir/trace.vcd" "$dir/model.smt2" >"$dir/replay.log" 2>&1 || true
  sed -n 's/.*Assert failed in [^:]*: \(.*\)$/\1/p' "$dir/replay.log" | sort -u | tr '\n' ' ' | sed 's/ $//'
}

keep_vcd() { # dir name
  if [ -n "$out" ] && [ -f "$1/trace.vcd" ]; then cp "$1/trace.vcd" "$out/$2.vcd"; fi
}

# One result line: order|property|geometry|method|result|seconds|note
result() { printf '%s|%s|%s|%s|%s|%s|%s\n' "$@" >"$tmp/res/$1"; }

# ---------------------------------------------------------------------------------------------
# The checks. Each runs as a background job and writes one result line.
# ---------------------------------------------------------------------------------------------
# Unbounded proof with ABC's PDR (IC3): the invariant it finds is checked inductive by ABC.
check_pdr() { # order label w h defines globs
  local n="$1" label="$2" w="$3" h="$4" defs="$5" keep="$6" d="$tmp/$1" t0 r note=""
  t0=$(date +%s)
  if ! build "$d" "$rtl" "$w" "$h" "$defs" "$keep"; then result "$n" "$label" "${w}x$h" "PDR" ERROR 0 "$(tr '\n' ' ' <"$d/error")"; return; fi
  yosys-abc -c "read_aiger $d/model.aig; fold; strash; pdr; write_cex -a $d/trace.aiw" >"$d/abc.log" 2>&1 || true
  if grep -q "Property proved" "$d/abc.log"; then r=PASS
  elif grep -q "was asserted in frame" "$d/abc.log"; then
    r=FAIL; note="counterexample: $(replay "$d") ($(grep -o 'asserted in frame [0-9]*' "$d/abc.log"))"; keep_vcd "$d" "cex-$n"
  else r=ERROR; note="$(tail -2 "$d/abc.log" | tr '\n' ' ')"; fi
  result "$n" "$label" "${w}x$h" "unbounded (PDR)" "$r" $(( $(date +%s) - t0 )) "$note"
}

# k-induction with yosys-smtbmc and z3: base case (BMC of depth k) and inductive step.
# Assertions named in "assumed" (already proven unbounded) are assumed, not checked.
check_kind() { # order label w h defines globs k [assumed]
  local n="$1" label="$2" w="$3" h="$4" defs="$5" keep="$6" k="$7" d="$tmp/$1" t0 r note=""
  t0=$(date +%s)
  if ! build "$d" "$rtl" "$w" "$h" "$defs" "$keep" "${8:-}"; then result "$n" "$label" "${w}x$h" "k-induction" ERROR 0 "$(tr '\n' ' ' <"$d/error")"; return; fi
  if ! yosys-smtbmc --noprogress -s z3 -t "$k" --dump-vcd "$d/trace.vcd" "$d/model.smt2" >"$d/base.log" 2>&1; then
    r=FAIL; note="base case: $(sed -n 's/.*Assert failed in [^:]*: \(.*\)$/\1/p' "$d/base.log" | sort -u | tr '\n' ' ')"; keep_vcd "$d" "cex-$n"
  elif yosys-smtbmc --noprogress -s z3 -i -t "$k" "$d/model.smt2" >"$d/ind.log" 2>&1; then
    r=PASS
  else r=FAIL; note="induction step fails at depth $k"; fi
  result "$n" "$label" "${w}x$h" "k-induction (k=$k)" "$r" $(( $(date +%s) - t0 )) "$note"
}

# Bounded model check with ABC's bmc3: no assertion fails in the first N clocks.
check_bmc() { # order label w h defines globs depth
  local n="$1" label="$2" w="$3" h="$4" defs="$5" keep="$6" depth="$7" d="$tmp/$1" t0 r note=""
  t0=$(date +%s)
  if ! build "$d" "$rtl" "$w" "$h" "$defs" "$keep"; then result "$n" "$label" "${w}x$h" "bounded" ERROR 0 "$(tr '\n' ' ' <"$d/error")"; return; fi
  yosys-abc -c "read_aiger $d/model.aig; fold; strash; bmc3 -F $depth; write_cex -a $d/trace.aiw" >"$d/abc.log" 2>&1 || true
  if grep -q "was asserted in frame" "$d/abc.log"; then
    r=FAIL; note="counterexample: $(replay "$d") ($(grep -o 'asserted in frame [0-9]*' "$d/abc.log"))"; keep_vcd "$d" "cex-$n"
  elif grep -q "No output asserted" "$d/abc.log"; then r=PASS
  else r=ERROR; note="$(tail -2 "$d/abc.log" | tr '\n' ' ')"; fi
  result "$n" "$label" "${w}x$h" "bounded, depth $depth" "$r" $(( $(date +%s) - t0 )) "$note"
}

# A cover: the harness's cover as a "bad state" (COVER_BAD) that bmc3 must reach.
check_cover() { # order label w h cover depth
  local n="$1" label="$2" w="$3" h="$4" cov="$5" depth="$6" d="$tmp/$1" t0 r note=""
  t0=$(date +%s)
  if ! build "$d" "$rtl" "$w" "$h" "-DCOVER_BAD" "$cov"; then result "$n" "$label" "${w}x$h" "cover" ERROR 0 "$(tr '\n' ' ' <"$d/error")"; return; fi
  yosys-abc -c "read_aiger $d/model.aig; fold; strash; bmc3 -F $depth; write_cex -a $d/trace.aiw" >"$d/abc.log" 2>&1 || true
  if grep -q "was asserted in frame" "$d/abc.log"; then
    # The wrapper's trace is replayed into VCD only for --out: z3 takes minutes on its model.
    if [ $axis = 0 ] || [ -n "$out" ]; then replay "$d" >/dev/null; fi
    r=REACHED; note="trace of $(grep -o 'frame [0-9]*' "$d/abc.log" | head -1 | cut -d' ' -f2) clocks"
    keep_vcd "$d" "cover-$cov"
  else r=FAIL; note="not reached in $depth clocks"; fi
  result "$n" "$label" "${w}x$h" "cover (bmc3)" "$r" $(( $(date +%s) - t0 )) "$note"
}

# A mutant: the RTL with one deliberate bug (a sed script); bmc3 must find a failing assertion.
check_mutant() { # order sedfile w h depth
  local n="$1" sedf="$2" w="$3" h="$4" depth="$5" d="$tmp/$1" t0 r note="" name
  name="$(basename "$sedf" .sed)"; t0=$(date +%s); mkdir -p "$d"
  sed -f "$sedf" "$rtl" >"$d/window_unit.v"
  if cmp -s "$d/window_unit.v" "$rtl"; then
    result "$n" "mutant $name" "${w}x$h" "bounded, depth $depth" ERROR 0 "the sed script changed nothing: update $sedf to the RTL"; return; fi
  # Only the assertions the mutant's "Caught by:" line names: a smaller problem for bmc3.
  local keep
  keep="$(sed -n 's/^# Caught by: *//p' "$sedf" | tr ',' ' ' | tr -s ' ' | sed 's/(.*//; s/\.$//')"
  [ -n "$keep" ] || keep="P_*"
  if ! build "$d" "$d/window_unit.v" "$w" "$h" "$mutant_defs" "$keep"; then result "$n" "mutant $name" "${w}x$h" "bounded" ERROR 0 "$(tr '\n' ' ' <"$d/error")"; return; fi
  yosys-abc -c "read_aiger $d/model.aig; fold; strash; bmc3 -F $depth; write_cex -a $d/trace.aiw" >"$d/abc.log" 2>&1 || true
  if grep -q "was asserted in frame" "$d/abc.log"; then
    if [ $axis = 0 ] || [ -n "$out" ]; then
      r=CAUGHT; note="$(replay "$d") fails ($(grep -o 'asserted in frame [0-9]*' "$d/abc.log"))"; keep_vcd "$d" "mutant-$name"
    else # the wrapper's trace is not replayed (z3 takes minutes on it): one of $keep fails
      r=CAUGHT; note="$keep fails ($(grep -o 'asserted in frame [0-9]*' "$d/abc.log"))"
    fi
  else r=MISSED; note="no assertion fails in $depth clocks"; fi
  result "$n" "mutant $name" "${w}x$h" "bounded, depth $depth" "$r" $(( $(date +%s) - t0 )) "$note"
}

throttle() { while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done; }

window="P_inside P_data P_complete P_bounds P_noset P_invalid P_invalid_error"
handshake="P_hs_rise P_hs_fall P_hs_answer_up P_hs_answer_down"
status="P_armed P_window_done P_set_accepted"
start=$(date +%s)
echo "formal.sh: $rtl"
if [ $axis = 1 ]; then
  # The wrapper at 4x4 with 2-beat FIFOs. Bit-level BMC of it grows fast with depth (ABC's
  # bmc3: 0.2 s to 8 clocks, 3 s to 10, 50 s to 12), so the accounting properties are checked
  # to 10 clocks: a commit, windows of a few beats and their reads, but no overflow (the
  # cocotb bench covers that). The stream rule is proven unbounded.
  axis_props="P_order P_accounted P_frames"
  if [ $run_proofs = 1 ]; then
    throttle; check_pdr 51 "stream: P_tready P_stable" 4 4 "" "P_tready P_stable" &
    throttle; check_bmc 52 "accounting: $axis_props" 4 4 "" "$axis_props" ${AXIS_DEPTH:-10} &
    # A window is at least 2x2, so two delivered rows and the idle read take more clocks than
    # the 10 above: the cover searches to 14 (bmc3 stops at the first trace).
    throttle; check_cover 53 "C_rows" 4 4 "C_rows" ${AXIS_COVER_DEPTH:-14} &
    throttle; check_pdr 54 "conservation: P_conserve P_drained" 4 4 "-DPROBES" "P_conserve P_drained" &
  fi
  if [ $run_mutants = 1 ]; then
    i=60
    for m in "$broken"/*.sed; do
      [ -e "$m" ] || continue
      throttle; check_mutant "$i" "$m" 4 4 ${AXIS_DEPTH:-10} &
      i=$((i + 1))
    done
  fi
fi
if [ $axis = 0 ] && [ $run_proofs = 1 ]; then
  # The long PDR runs first, so the short ones fill the other slot.
  throttle; check_pdr 01 "window: P_inside P_data P_complete P_bounds P_noset P_invalid P_invalid_error" 16 16 "" "$window" &
  throttle; check_pdr 08 "status: P_armed P_window_done P_set_accepted" 16 16 "" "$status" &
  throttle; check_kind 02 "count: P_count (full frames; assumes P_inside P_complete)" 16 16 "-DREGULAR" "P_count L_*" 8 "P_inside P_complete" &
  throttle; check_kind 03 "handshake: P_hs_rise P_hs_fall P_hs_answer_up P_hs_answer_down" 16 16 "" "$handshake" 8 &
  throttle; check_kind 04 "handshake" 256 256 "" "$handshake" 8 &
  throttle; check_kind 05 "handshake (8-byte sets)" 640 480 "" "$handshake" 8 &
  throttle; check_bmc 06 "window" 256 256 "" "$window" 32 &
  throttle; check_bmc 07 "window (8-byte sets)" 640 480 "" "$window" 44 &
  throttle; check_bmc 09 "status" 256 256 "" "$status" 32 &
  throttle; check_bmc 10 "status (8-byte sets)" 640 480 "" "$status" 44 &
  for c in C_left C_right C_top C_bottom C_decimated; do
    throttle; check_cover "1$c" "$c" 16 16 "$c" 100 &
  done
fi
if [ $axis = 0 ] && [ $run_mutants = 1 ]; then
  i=30
  for m in "$broken"/*.sed; do
    [ -e "$m" ] || continue
    throttle; check_mutant "$i" "$m" 16 16 90 &
    i=$((i + 1))
  done
fi
wait

# The table, and the verdict.
fail=0
printf '\n%-78s %-9s %-24s %-8s %5s  %s\n' "property" "geometry" "method" "result" "s" "note"
for f in $(ls "$tmp/res" | sort); do
  IFS='|' read -r _ label geom method res secs note <"$tmp/res/$f"
  printf '%-78s %-9s %-24s %-8s %5s  %s\n' "$label" "$geom" "$method" "$res" "$secs" "$note"
  case "$res" in PASS|REACHED|CAUGHT) ;; *) fail=1 ;; esac
done
echo
echo "total: $(( $(date +%s) - start )) s"
if [ -n "$out" ]; then echo "traces: $out"; fi
if [ $fail = 0 ]; then echo "formal.sh: all passed"; else echo "formal.sh: FAILED"; fi
exit $fail
