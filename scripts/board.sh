#!/usr/bin/env bash
# The firmware on a Cortex-M4F (thesis 2.6: the tracking code on the window processors):
# builds firmware/board for thumbv7em-none-eabihf with Debian's rustc (core built from source),
# runs it on QEMU's mps2-an386 with one instruction per virtual nanosecond, and fails unless
# its result lines equal fixtures/board/expected.txt, which the host computes
# (firmware/parity/tests/board_parity.rs). Then the same for an image linked for an STM32F405
# (QEMU netduinoplus2: flash at 0x08000000, 128 KB of SRAM), which runs the same suite, the COOP
# pairs' replays included: its lines must equal expected.txt's too, and its static RAM plus its
# static stack bound (scripts/stack_bound.py) must fit the 128 KiB. Then each processor's own
# image (issue 22), linked into 64 KiB: the COOP partner's (`partner`), the Peripheral's
# (`peripheral`), a Watch strip processor's (`watch`) and the NCC master's (`master`), each
# printing its lines of expected.txt, in RAM <= 64 KiB and flash <= 256 KiB. Last, the adapting
# tracker's worst frames must keep 5x inside the thesis's 8.8 ms at 168 MHz (issues 21, 22);
# the covered replay's (the object in doubt, issue 38) is reported, not held to it.
#
#   scripts/board.sh             build, run, compare
#   scripts/board.sh --profile   also profile the COOP frames (QEMU's execution trace, through
#                                scripts/board_profile.py) into target/board/profile.md;
#                                COOPWIN_PROFILE_FRAMES=K:A-B profiles only frames A to B of
#                                replay K (2:30-44: the covered replay's frames in doubt)
#   scripts/board.sh --figures   also profile, and regenerate docs/firmware-target.md
#
# Needs: apt-get install rustc-web cargo-web rust-web-src qemu-system-arm binutils-arm-none-eabi
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
figures=0
profile=0
case "${1:-}" in
  --figures) figures=1 profile=1 ;;
  --profile) profile=1 ;;
  "") ;;
  *) echo "usage: $0 [--figures | --profile]" >&2; exit 2 ;;
esac
for tool in /usr/bin/rustc /usr/bin/cargo qemu-system-arm arm-none-eabi-ld arm-none-eabi-size; do
  command -v "$tool" >/dev/null || { echo "board.sh: $tool is missing (see the header of $0)" >&2; exit 2; }
done

out="$root/target/board"
mkdir -p "$out"
elf="$out/thumbv7em-none-eabihf/release/coopwin-board"
# The host's rustup toolchain stays the workspace's; only this build uses Debian's, whose
# core sources build `core` for the target (RUSTC_BOOTSTRAP for -Zbuild-std).
(cd "$root/firmware/board" &&
  CARGO_TARGET_DIR="$out" RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 /usr/bin/cargo build --release --locked -q)

run="$out/run.txt"
qemu=(qemu-system-arm -cpu cortex-m4 -machine mps2-an386 -nographic
  -semihosting-config enable=on,target=native -icount shift=0 -kernel "$elf")
trace=()
if [ "$profile" = 1 ]; then
  # The trace (about a gigabyte) goes through a FIFO straight into the profiler. Virtual
  # time counts instructions, so the traced run's results and counts are the plain run's.
  fifo="$out/trace.fifo"
  rm -f "$fifo"
  mkfifo "$fifo"
  only=()
  if [ -n "${COOPWIN_PROFILE_FRAMES:-}" ]; then
    [ "$figures" = 0 ] || { echo "board.sh: --figures profiles every frame: unset COOPWIN_PROFILE_FRAMES" >&2; exit 2; }
    only=(--frames "$COOPWIN_PROFILE_FRAMES")
  fi
  python3 "$root/scripts/board_profile.py" "$elf" "$fifo" --lines 25 "${only[@]}" >"$out/profile.md" &
  reader=$!
  trace=(-d exec,nochain,in_asm -D "$fifo")
fi
# A hang (a fault handler spinning) ends at the timeout, as a failure.
status=0
timeout 600 "${qemu[@]}" "${trace[@]}" >"$run" 2>&1 || status=$?
if [ "$profile" = 1 ]; then
  wait "$reader" || { echo "board.sh: the profiler failed" >&2; status=1; }
  rm -f "$fifo"
  [ "$status" = 0 ] && echo "board.sh: wrote $out/profile.md"
fi
if [ "$status" != 0 ]; then
  echo "board.sh: the board run failed or timed out; its output:" >&2
  tail -20 "$run" >&2
  exit 1
fi
# `#` lines are measurements (instruction counts, stack); everything else is compared.
if ! grep -v '^#' "$run" | diff -u "$root/fixtures/board/expected.txt" - >"$out/diff.txt"; then
  echo "board.sh: the Cortex-M4 output differs from the host's (fixtures/board/expected.txt):" >&2
  head -40 "$out/diff.txt" >&2
  exit 1
fi
echo "board.sh: $(grep -vc '^#' "$run") result lines bit-identical to the host's; $(grep '^# pins' "$run" | sed 's/^# //')"

# An STM32F405 image: built with `features` (in one target folder for all of them, so `core`
# and the crates build once) and copied into `dir`, run on netduinoplus2, its result lines
# compared with `expected` (a file), and its static RAM plus its static stack bound
# (scripts/stack_bound.py, with the exceptions) held to `ram` bytes, its flash to `flash`.
stm32_image() {
  local name=$1 dir=$2 features=$3 expected=$4 ram=$5 flash=$6
  local elf="$dir/thumbv7em-none-eabihf/release/coopwin-board" run="$dir/run.txt" status=0
  local build="$root/target/board-stm32-build"
  (cd "$root/firmware/board" &&
    CARGO_TARGET_DIR="$build" RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 /usr/bin/cargo build --release --locked -q --features "$features")
  mkdir -p "$(dirname "$elf")"
  cp "$build/thumbv7em-none-eabihf/release/coopwin-board" "$elf"
  timeout 600 qemu-system-arm -machine netduinoplus2 -nographic -semihosting-config enable=on,target=native \
    -icount shift=0 -kernel "$elf" >"$run" 2>&1 || status=$?
  if [ "$status" != 0 ]; then
    echo "board.sh: the $name run failed or timed out; its output:" >&2
    tail -20 "$run" >&2
    exit 1
  fi
  if ! grep -v '^#' "$run" | diff -u "$expected" - >"$dir/diff.txt"; then
    echo "board.sh: the $name output differs from the host's (fixtures/board/expected.txt):" >&2
    head -40 "$dir/diff.txt" >&2
    exit 1
  fi
  local static bound size
  static=$(arm-none-eabi-size -A "$elf" | awk '$1 ~ /^\.(data|bss|uninit)$/ { s += $2 } END { print s + 0 }')
  size=$(arm-none-eabi-size -A "$elf" | awk '$1 ~ /^\.(vector_table|text|rodata|data)$/ { s += $2 } END { print s + 0 }')
  bound=$(python3 "$root/scripts/stack_bound.py" "$elf" --run "$run" | sed -n 's/.*; with exceptions \([0-9,]*\)$/\1/p' | tr -d ,)
  if [ -z "$bound" ] || [ $((static + bound)) -gt "$ram" ]; then
    echo "board.sh: the $name image's RAM (static ${static} + stack bound ${bound:-?}) exceeds its $ram bytes" >&2
    exit 1
  fi
  if [ "$size" -gt "$flash" ]; then
    echo "board.sh: the $name image's flash ($size bytes) exceeds its $flash" >&2
    exit 1
  fi
  echo "board.sh: $name: $(grep -vc '^#' "$run") result lines bit-identical to the host's; $(grep '^# stack' "$run" | sed 's/^# //'); RAM static + stack bound $((static + bound)) of $ram; flash $size of $flash"
}

# The STM32F405 image (`stm32f405` feature: its memory map, the same suite, 128 KiB of SRAM).
stm="$root/target/board-stm32"
stm32_image STM32F405 "$stm" stm32f405 "$root/fixtures/board/expected.txt" 131072 1048576
# Each processor's own image (issue 22): built with `stm32f405,FEATURE` into
# target/board-FEATURE, its lines of expected.txt selected by their first words (`ids`, as
# coopwin-parity's board_parity.rs selects them), in 64 KiB of RAM and 256 KiB of flash.
one_image() {
  local feature=$1 name=$2 ids=$3 ram=${4:-65536}
  grep -E "^($ids) " "$root/fixtures/board/expected.txt" >"$out/expected-$feature.txt"
  stm32_image "$name" "$root/target/board-$feature" "stm32f405,$feature" "$out/expected-$feature.txt" "$ram" 262144
}
# The COOP partner: the corner kernels and the partner's corner each frame.
one_image partner "COOP partner image" 'corner_20|corner_24|corner_24_literal|info|tracker_cd|adaptive_cd'
# The Peripheral: its kernels, its lock-on, its Detection-mode search and an adapting sweep.
one_image peripheral "Peripheral image" 'peripheral_ssd_16in40|peripheral_sad_16in40|peripheral_ssd_16in40_dec|peripheral_lockon|peripheral_lost|peripheral_sweep'
# A Watch strip processor: each strip's motion and their merge, the whole frame's line.
one_image watch "Watch image" 'watch_strip|watch_motion_256'
# The NCC master: the pair's decisions, its partner's corners read from the partner's lines.
one_image master "NCC master image" 'tracker|tracker_total|adaptive|adaptive_total'
images=(partner peripheral watch master)

# Issues 21 and 22's margin: the default (adapting) tracker's worst frame on each processor that
# runs it, and the COOP pair's on one core, in at most a fifth of the thesis's 8.8 ms frame at
# 168 MHz, at one instruction a cycle (QEMU counts instructions; docs/firmware-target.md
# gives the cycles too).
limit=$((8800 * 168 / 5))
worst_of() {
  awk -v id="$2" '$1 == "#" && $2 == "icount" && $3 == id { if ($4 + 0 > m) m = $4 + 0 } END { print m + 0 }' "$1"
}
margin() {
  local run=$1 id=$2 worst
  worst=$(worst_of "$run" "$id")
  if [ "$worst" = 0 ] || [ "$worst" -gt "$limit" ]; then
    echo "board.sh: the worst \`$id\` frame ($worst instructions, $run) is not within 5x of the 8.8 ms frame at 168 MHz ($limit)" >&2
    exit 1
  fi
  echo "board.sh: worst $id frame $worst instructions, within 5x ($limit)"
}
margin "$stm/run.txt" coop_frame_adaptive
margin "$root/target/board-master/run.txt" master_frame_adaptive
margin "$root/target/board-partner/run.txt" partner_frame
margin "$root/target/board-peripheral/run.txt" peripheral_sweep
# The covered replay (issue 38): the adapting pair in doubt, its object partly covered. Its
# worst frame is measured and reported, not held to the margin: it is outside it
# (docs/firmware-target.md).
covered=$(worst_of "$stm/run.txt" coop_frame_covered)
[ "$covered" != 0 ] || { echo "board.sh: no \`coop_frame_covered\` frame in $stm/run.txt" >&2; exit 1; }
# The frames in doubt: from the first `covered` row not vouched for (as board_figures.py finds it).
doubt=$(awk -v limit="$limit" '
  $1 == "covered" && at == "" && ($0 ~ / unconfirmed/ || $0 !~ / x=/) { at = $2 }
  $1 == "#" && $2 == "icount" && $3 == "coop_frame_covered" { n[k++] = $4 }
  END { for (i = at; at != "" && i < k; i++) { s += n[i]; m++; if (n[i] > limit) over++ }
        if (m) printf "%d of its %d frames in doubt (from frame %d) over the line, %.0f on average", over, m, at, s / m }' "$stm/run.txt")
echo "board.sh: worst coop_frame_covered frame $covered instructions; ${doubt:-no frame in doubt} (an object in doubt: measured, not held to 5x)"

if [ "$figures" = 1 ]; then
  arm-none-eabi-size -A "$elf" >"$out/size.txt"
  arm-none-eabi-objdump -d --no-show-raw-insn -C "$elf" >"$out/disasm.txt"
  extra=()
  for d in "$stm" "${images[@]/#/$root/target/board-}"; do
    e="$d/thumbv7em-none-eabihf/release/coopwin-board"
    arm-none-eabi-size -A "$e" >"$d/size.txt"
    arm-none-eabi-objdump -d --no-show-raw-insn -C "$e" >"$d/disasm.txt"
    extra+=("$d/run.txt" "$d/size.txt" "$d/disasm.txt" "$e")
  done
  python3 "$root/scripts/board_figures.py" "$run" "$out/size.txt" "$out/disasm.txt" "$out/profile.md" "$elf" \
    "${extra[@]}" >"$root/docs/firmware-target.md"
  echo "board.sh: wrote docs/firmware-target.md"
fi
