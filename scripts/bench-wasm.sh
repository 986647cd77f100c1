#!/usr/bin/env bash
# The benchmark in Node wasm next to the native one: ROUNDS alternating runs of each (default
# 5; this machine's speed drifts by ±30 % from minute to minute, so single runs of the two
# mislead), then the best time of every step and the wasm / native ratio.
# Run `cargo run --release --example bench` once first (it leaves the inputs in
# target/bench-inputs/; this script does it when they are missing).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh wasm
ROUNDS=${ROUNDS:-5}
[[ -f target/bench-inputs/ball.gcode ]] || cargo run --release --example bench
cargo build --release --example bench >/dev/null 2>&1
wasm-pack build --release --target nodejs --out-dir target/pkg-node >/dev/null 2>&1
LOG=$(mktemp)
for ((i = 1; i <= ROUNDS; i++)); do
  node bench/wasm.mjs "$(pwd)/target/pkg-node/warpslice.js" target/bench-inputs | tee -a "$LOG"
  target/release/examples/bench --reuse-inputs | tee -a "$LOG"
done
echo "==== best of $ROUNDS rounds ===="
awk '
  /^wasm warp_model:/ { v = $3 + 0; if (!ww || v < ww) ww = v }
  /^wasm unwarp/ { for (i = 1; i <= NF; i++) if ($i == "in") { v = $(i + 1) + 0 }; if (!wu || v < wu) wu = v }
  /^warp_model/ { for (i = 1; i <= NF; i++) if ($i ~ /^[0-9.]+$/ && $(i + 1) == "s,") { v = $i + 0 }; if (!nw || v < nw) nw = v }
  /^unwarp \(2 streaming passes, into memory/ { for (i = 1; i <= NF; i++) if ($(i + 1) == "s") { v = $i + 0 }; if (!nu || v < nu) nu = v }
  END {
    printf "warp_model: native %.3f s, wasm %.3f s, wasm/native %.2f\n", nw, ww, ww / nw
    printf "unwarp (into memory): native %.3f s, wasm %.3f s, wasm/native %.2f\n", nu, wu, wu / nu
  }' "$LOG"
rm -f "$LOG"
