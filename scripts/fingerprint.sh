#!/usr/bin/env bash
# Every output the refactors must keep byte-identical, hashed: the exported Verilog, the main
# job's report, tracking CSVs of each strategy, policy and window backend, the waves VCD, and
# every experiment under docs/results. Run it before and after a change and diff the two lists:
#   scripts/fingerprint.sh /tmp/before > before.txt; ...; scripts/fingerprint.sh /tmp/after > after.txt
#   diff before.txt after.txt
set -euo pipefail
out=${1:?usage: scripts/fingerprint.sh OUT_DIR (a new or empty folder)}
cd "$(dirname "$0")/.."
cargo build --release -q 2>/dev/null
bin=${CARGO_TARGET_DIR:-$PWD/target}/release/coopwin
mkdir -p "$out"/verilog "$out"/results "$out"/report "$out"/scene "$out"/photo
(cd "$out" && "$bin" > main.txt)                      # the main job writes report/
"$bin" verilog --out "$out"/verilog > /dev/null
"$bin" waves --out "$out"/waves.vcd > /dev/null
"$bin" scene --path triangle --speed 100 --frames 120 --lighting ramp --out "$out"/scene --force > /dev/null
"$bin" scene --photo --path swing --speed 80 --noise 2 --frames 120 --out "$out"/photo --force > /dev/null
for s in spmf tpdf mpdf coop; do
  "$bin" track --frames "$out"/scene --strategy "$s" --target 56.32,56.32 --out "$out/track-$s.csv" > "$out/track-$s.txt"
done
for p in sse kalman; do
  "$bin" track --frames "$out"/scene --strategy coop --policy "$p" --target 56.32,56.32 --out "$out/track-coop-$p.csv" > /dev/null
done
"$bin" track --frames "$out"/photo --strategy coop --out "$out/track-photo.csv" > /dev/null
"$bin" track --frames "$out"/scene --strategy coop --target 56.32,56.32 --hdl rust-hdl --vcd "$out/hdl.vcd" --vcd-frames 10..12 --out "$out/track-hdl.csv" > /dev/null
"$bin" experiment all --out "$out"/results > /dev/null
cd "$out" && find . -type f -print0 | sort -z | xargs -0 sha256sum
