#!/usr/bin/env bash
# The benchmark in Node wasm next to the native one: ROUNDS alternating runs of each (default
# 5; this machine's speed drifts by ±30 % from minute to minute, so single runs of the two
# mislead), then the best time of every step and the wasm / native ratio.
# Run `cargo run --release --example bench` once first (it leaves the inputs in
# target/bench-inputs/; this script does it when they are missing). The built-in slicer's
# figure: examples/builtin_bench.rs's warped sphere (60 mm, 225 000 triangles, conic 30°),
# sliced natively (`builtin_bench --no-prusaslicer`) and in wasm (bench/wasm.mjs) each round.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh wasm
ROUNDS=${ROUNDS:-5}
# the native examples, where cargo builds them
BIN=${CARGO_TARGET_DIR:-target}/release/examples
[[ -f target/bench-inputs/ball.gcode ]] || cargo run --release --example bench
cargo build --release --example bench --example builtin_bench >/dev/null 2>&1
# the builtin's warped STL and job (written by every native run; the first before wasm needs it)
[[ -f target/bench-inputs/builtin-sphere-conic30.job.json ]] || $BIN/builtin_bench --no-prusaslicer >/dev/null
wasm-pack build --release --target nodejs --out-dir target/pkg-node >/dev/null 2>&1
LOG=$(mktemp)
for ((i = 1; i <= ROUNDS; i++)); do
  node bench/wasm.mjs "$(pwd)/target/pkg-node/warpslice.js" target/bench-inputs | tee -a "$LOG"
  # (the machine outputs of the bench's step 3 have no wasm figure here: one preset, no check)
  $BIN/bench --reuse-inputs --presets cartesian --no-collisions | tee -a "$LOG"
  $BIN/builtin_bench --no-prusaslicer | tee -a "$LOG"
done
echo "==== best of $ROUNDS rounds ===="
awk '
  /^wasm warp_model:/ { v = $3 + 0; if (!ww || v < ww) ww = v }
  /^wasm unwarp/ { for (i = 1; i <= NF; i++) if ($i == "in") { v = $(i + 1) + 0 }; if (!wu || v < wu) wu = v }
  /^warp_model/ { for (i = 1; i <= NF; i++) if ($i ~ /^[0-9.]+$/ && $(i + 1) == "s,") { v = $i + 0 }; if (!nw || v < nw) nw = v }
  /^unwarp \(2 streaming passes, into memory/ { for (i = 1; i <= NF; i++) if ($(i + 1) == "s") { v = $i + 0 }; if (!nu || v < nu) nu = v }
  /^wasm builtin slice: [0-9]/ { v = $4 + 0; if (!wb || v < wb) wb = v }
  /^builtin: [0-9]/ { v = $2 + 0; if (!nb || v < nb) nb = v }
  END {
    printf "warp_model: native %.3f s, wasm %.3f s, wasm/native %.2f\n", nw, ww, ww / nw
    printf "unwarp (into memory): native %.3f s, wasm %.3f s, wasm/native %.2f\n", nu, wu, wu / nu
    if (nb && wb) printf "builtin slice (225k-triangle sphere, conic 30°): native %.3f s, wasm %.3f s, wasm/native %.2f\n", nb, wb, wb / nb
  }' "$LOG"
rm -f "$LOG"
