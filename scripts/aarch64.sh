#!/usr/bin/env bash
# The kernels on aarch64 (issue 39 item 7: "NEON where the package builds for aarch64, tested
# bit for bit against the portable path"). NEON is aarch64's baseline, so the portable code is
# the aarch64 path: LLVM vectorises it into NEON as it does into SSE2 on x86-64 (the AVX-512 and
# AVX2 paths are x86-64's alone). This script builds coopwin-firmware's library tests for
# aarch64-unknown-linux-gnu in release (the optimised code that ships, without the test
# profile's overflow checks, which keep LLVM from vectorising) with Debian's rustc (std built
# from source, RUSTC_BOOTSTRAP for -Zbuild-std; std's own dependencies come from crates.io),
# links them with aarch64-linux-gnu-gcc and runs them under qemu-aarch64 (user mode): every
# test must pass, the kernels' against their hand formulas and reference paths, exact integers
# and bits as on x86-64. Then it disassembles that same test binary and fails unless the hot
# loops are NEON vector code:
#   the dot products' strips (dot_long4, dot_long): widening multiply-adds smlal/smlal2 (or
#     udot/sdot) into .4s lanes;
#   the SSD elimination's bounds (elimination::search): smlal/smlal2 of box differences;
#   the motion row scan (scan_row_blocks): uabd and cmhi on .16b (16 pixels at a time);
#   the Sobel pass (sobel_rows): smull/smlal of gx, gy into .4s, and cmgt against the threshold.
#
#   scripts/aarch64.sh      build, run under QEMU, check the disassembly
#
# QEMU emulates, so its run time says nothing about speed on aarch64 hardware.
#
# Needs: apt-get install rustc-web cargo-web rust-web-src gcc-aarch64-linux-gnu
#        libc6-dev-arm64-cross binutils-aarch64-linux-gnu qemu-user
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
sysroot=/usr/aarch64-linux-gnu
for tool in /usr/bin/rustc /usr/bin/cargo aarch64-linux-gnu-gcc aarch64-linux-gnu-objdump qemu-aarch64; do
  command -v "$tool" >/dev/null || { echo "aarch64.sh: $tool is missing (see the header of $0)" >&2; exit 2; }
done
[ -d /usr/lib/rustlib/src/rust/library/std ] && [ -e "$sysroot/lib/ld-linux-aarch64.so.1" ] ||
  { echo "aarch64.sh: std's sources or the aarch64 C library are missing (see the header of $0)" >&2; exit 2; }

out="$root/target/aarch64"
mkdir -p "$out"
target=aarch64-unknown-linux-gnu
# The host's rustup toolchain stays the workspace's; only this build uses Debian's, whose
# library sources build std for the target.
export CARGO_TARGET_DIR="$out" RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="qemu-aarch64 -L $sysroot"
cargo=(/usr/bin/cargo test --release --locked -p coopwin-firmware --lib --target "$target" -Zbuild-std=std,panic_unwind)

cd "$root"
"${cargo[@]}" --no-run -q --message-format=json >"$out/build.json"
exe=$(python3 -c 'import json, sys
for line in open(sys.argv[1]):
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == "coopwin_firmware":
        print(m["executable"])' "$out/build.json" | tail -1)
[ -n "$exe" ] || { echo "aarch64.sh: no test binary in cargo's output ($out/build.json)" >&2; exit 1; }

run="$out/run.txt"
status=0
timeout 1200 "${cargo[@]}" >"$run" 2>&1 || status=$?
if [ "$status" != 0 ] || ! grep -q '^test result: ok\.' "$run"; then
  echo "aarch64.sh: the tests failed or timed out under qemu-aarch64; the output's end:" >&2
  tail -30 "$run" >&2
  exit 1
fi
passed=$(sed -n 's/^test result: ok\. \([0-9]*\) passed.*/\1/p' "$run")
kernels=$(grep -c '^test kernels::.* \.\.\. ok$' "$run" || true)
echo "aarch64.sh: $passed tests passed under qemu-aarch64 ($kernels of them the kernels')"

# The disassembly of the tested binary; `neon FUNCTION INSTRUCTIONS WHAT` fails unless the
# functions whose (demangled) names match the awk regex FUNCTION hold at least one instruction
# whose mnemonic matches INSTRUCTIONS and whose operands are NEON vector registers
# (v<n>.16b/.8b/.8h/.4h/.4s/.2d).
dis="$out/disasm.txt"
aarch64-linux-gnu-objdump -d --no-show-raw-insn -C "$exe" >"$dis"
neon() {
  local fn=$1 insn=$2 what=$3 found
  found=$(awk -F'\t' -v fn="$fn" -v insn="^($insn)\$" '
    /^[0-9a-f]+ </ { name = $0; sub(/^[0-9a-f]+ </, "", name); sub(/>:$/, "", name); inside = name ~ fn; if (inside) fns++; next }
    inside && $2 ~ insn && $3 ~ /v[0-9]+\.(16b|8b|8h|4h|4s|2d)/ { n[$2]++ }
    END { if (!fns) { print "none"; exit } s = ""; for (m in n) s = s " " m " x" n[m]; print fns "" s }' "$dis")
  if [ "$found" = none ]; then
    echo "aarch64.sh: no function matching /$fn/ in $exe (renamed, or inlined into its callers?)" >&2
    exit 1
  fi
  if [ "${found#* }" = "$found" ]; then
    echo "aarch64.sh: $what (/$fn/, $found functions) has no NEON $insn: not vectorised on aarch64 (disassembly in $dis)" >&2
    exit 1
  fi
  echo "aarch64.sh: NEON in $what: ${found#* }"
}
neon 'kernels::matching::dot::dot_long4$' 'smlal2?|umlal2?|udot|sdot' "the dot products' strips (dot_long4)"
neon 'kernels::matching::dot::dot_long$' 'smlal2?|umlal2?|udot|sdot' "a strip's dot product (dot_long)"
neon 'kernels::matching::elimination::search::<' 'smlal2?|smull2?' "the SSD elimination's bounds (elimination::search)"
neon 'kernels::motion::scan_row_blocks$' 'uabd' "the motion row scan (scan_row_blocks)"
neon 'kernels::motion::scan_row_blocks$' 'cmhi' "the motion row scan's threshold (scan_row_blocks)"
neon 'kernels::corner::sobel::sobel_rows::<' 'smull2?|smlal2?|mul|mla' "the Sobel pass (sobel_rows)"
neon 'kernels::corner::sobel::sobel_rows::<' 'cmgt' "the Sobel threshold (sobel_rows)"
