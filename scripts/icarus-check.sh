#!/usr/bin/env bash
# The window unit's contract, checked in Icarus Verilog for a list of sensor sizes: compiles
# hdl/verilog/tb/window_unit_tb.v with hdl/verilog/window_unit.v for each size and seed, runs
# it, prints its PASS line and the time it took, and stops at the first failure.
# docs/icarus-testbench.md says what the testbench checks.
#
#   scripts/icarus-check.sh                               every size in the list below
#   scripts/icarus-check.sh --size 640x480 --bits 10      one size (seed 1)
#   scripts/icarus-check.sh --help
#
# Needs only Icarus Verilog: apt-get install -y iverilog
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

usage() {
  cat <<EOF
usage: $0 [options]

Runs the self-checking window_unit testbench in Icarus Verilog. Without --size it runs the
default list (each size's seeds in brackets):
  16x16x8 [1 2 3 4]  17x300x12 [1 2]  256x256x8 [1 2]  640x480x10 [1]
  4096x16x16 [1]  1280x720x8 [1]  1920x1080x10 [1]
Exits 0 if every run passes, 1 at the first failure (its message is printed), 2 on bad usage.

options:
  --size WxH         run one size (16..4096 each); with --bits and --seed
  --bits P           pixel bits for --size, 8..16 (default 8)
  --seed S           seed (default 1); without --size, every listed size once with seed S
  --frames N         random frames after the directed scenarios (default: the testbench's 16;
                     8 for 4096x16, 1280x720 and 1920x1080 in the list)
  --rtl FILE         the window_unit Verilog to test (default hdl/verilog/window_unit.v)
  --verbose          print each scenario, set and frame as the testbench runs them
  -h, --help         this text
EOF
}

size="" bits=8 seed="" frames="" verbose=0
rtl="$root/hdl/verilog/window_unit.v"
tb="$root/hdl/verilog/tb/window_unit_tb.v"
while [ $# -gt 0 ]; do
  case "$1" in
    --size) size="${2:-}"; shift 2 ;;
    --bits) bits="${2:-}"; shift 2 ;;
    --seed) seed="${2:-}"; shift 2 ;;
    --frames) frames="${2:-}"; shift 2 ;;
    --rtl) rtl="${2:-}"; shift 2 ;;
    --verbose) verbose=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "icarus-check.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done

for tool in iverilog vvp; do
  command -v "$tool" >/dev/null || {
    echo "icarus-check.sh: $tool not found; install Icarus Verilog: apt-get install -y iverilog" >&2
    exit 2
  }
done
[ -f "$rtl" ] || { echo "icarus-check.sh: no such file: $rtl" >&2; exit 2; }
is_int() { [[ "$1" =~ ^[0-9]+$ ]]; }

# Runs: "WIDTHxHEIGHTxBITS SEEDS RANDOM_FRAMES" (RANDOM_FRAMES "-": the testbench's default).
runs=()
if [ -n "$size" ]; then
  [[ "$size" =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "icarus-check.sh: --size wants WxH, e.g. 640x480" >&2; exit 2; }
  w="${BASH_REMATCH[1]}" h="${BASH_REMATCH[2]}"
  if ! is_int "$bits" || [ "$w" -lt 16 ] || [ "$w" -gt 4096 ] || [ "$h" -lt 16 ] || [ "$h" -gt 4096 ] \
     || [ "$bits" -lt 8 ] || [ "$bits" -gt 16 ]; then
    echo "icarus-check.sh: the unit takes 16 <= WIDTH, HEIGHT <= 4096 and 8 <= bits <= 16" >&2; exit 2
  fi
  runs+=("${w}x${h}x${bits} ${seed:-1} -")
else
  # The contract's sizes, the cheap ones with several seeds. The three largest run 8 random
  # frames instead of 16, so the whole list takes about 1.5 minutes of one core.
  runs+=("16x16x8 1,2,3,4 -" "17x300x12 1,2 -" "256x256x8 1,2 -" "640x480x10 1 -"
         "4096x16x16 1 8" "1280x720x8 1 8" "1920x1080x10 1 8")
  if [ -n "$seed" ]; then
    for i in "${!runs[@]}"; do set -- ${runs[$i]}; runs[$i]="$1 $seed $3"; done
  fi
fi
is_int "${seed:-1}" || { echo "icarus-check.sh: --seed wants a number" >&2; exit 2; }
[ -z "$frames" ] || is_int "$frames" || { echo "icarus-check.sh: --frames wants a number" >&2; exit 2; }

work="$(mktemp -d "${TMPDIR:-/tmp}/icarus-check.XXXXXX")"
trap 'rm -rf "$work"' EXIT

total_start=$(date +%s.%N)
for run in "${runs[@]}"; do
  set -- $run
  IFS=x read -r w h p <<<"$1"
  n="$3"; [ -n "$frames" ] && n="$frames"
  for s in ${2//,/ }; do
    params=(-P "window_unit_tb.WIDTH=$w" -P "window_unit_tb.HEIGHT=$h" -P "window_unit_tb.PIXEL_BITS=$p"
            -P "window_unit_tb.SEED=$s")
    [ "$n" != "-" ] && params+=(-P "window_unit_tb.RANDOM_FRAMES=$n")
    vvp_file="$work/tb_${w}x${h}x${p}_$s.vvp"
    log="$work/tb_${w}x${h}x${p}_$s.log"
    if ! iverilog -g2012 -o "$vvp_file" "${params[@]}" "$tb" "$rtl" >"$log" 2>&1; then
      echo "icarus-check.sh: iverilog failed for ${w}x${h}x${p}:" >&2
      cat "$log" >&2
      exit 1
    fi
    start=$(date +%s.%N)
    set +e
    if [ "$verbose" = 1 ]; then
      vvp -n "$vvp_file" +verbose 2>&1 | tee "$log"
      status=${PIPESTATUS[0]}
    else
      vvp -n "$vvp_file" >"$log" 2>&1
      status=$?
    fi
    set -e
    secs=$(echo "$(date +%s.%N) $start" | awk '{printf "%.1f", $1 - $2}')
    pass=$(grep -m1 '^PASS ' "$log" || true)
    if [ "$status" != 0 ] || [ -z "$pass" ]; then
      echo "FAILED window_unit ${w}x${h} $p seed $s after $secs s:" >&2
      grep -v '^VCD info' "$log" | tail -n 25 >&2
      again="--size ${w}x${h} --bits $p --seed $s"
      [ "$n" != "-" ] && again+=" --frames $n"
      [ "$rtl" != "$root/hdl/verilog/window_unit.v" ] && again+=" --rtl $rtl"
      echo "to see the run scenario by scenario: $0 $again --verbose" >&2
      exit 1
    fi
    echo "$pass  [seed $s, $secs s]"
  done
done
echo "icarus-check.sh: all passed in $(echo "$(date +%s.%N) $total_start" | awk '{printf "%.0f", $1 - $2}') s"
