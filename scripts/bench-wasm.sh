#!/usr/bin/env bash
# The benchmark in Node wasm next to the native one: ROUNDS alternating runs of each (default
# 5; this machine's speed drifts by ±30 % from minute to minute, so single runs of the two
# mislead), then the best time of every step and the wasm / native ratio.
# Run `cargo run --release --example bench` once first (it leaves the inputs in
# target/bench-inputs/; this script does it when they are missing). The built-in slicer's
# figure: examples/builtin_bench.rs's warped sphere (60 mm, 225 000 triangles, conic 30°),
# sliced natively (`builtin_bench --no-prusaslicer`) and in wasm (bench/wasm.mjs) each round.
# The machine outputs (the bench's step 3): every preset's `unwarp --machine` in both
# interpolation modes and with the collision check, natively and through the page's streaming
# API; PRESETS=a,b runs only those.
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
  # step 3, every preset's `unwarp --machine` (both modes, then with the collision check), as
  # bench/wasm.mjs does it with the page's streaming API (PRESETS=a,b: only those, both sides)
  $BIN/bench --reuse-inputs ${PRESETS:+--presets "$PRESETS"} | tee -a "$LOG"
  $BIN/builtin_bench --no-prusaslicer | tee -a "$LOG"
done
echo "==== best of $ROUNDS rounds ===="
awk '
  /^wasm warp_model:/ { v = $3 + 0; if (!ww || v < ww) ww = v }
  /^wasm unwarp/ { for (i = 1; i <= NF; i++) if ($i == "in") { v = $(i + 1) + 0 }; if (!wu || v < wu) wu = v }
  /^warp_model/ { for (i = 1; i <= NF; i++) if ($i ~ /^[0-9.]+$/ && $(i + 1) == "s,") { v = $i + 0 }; if (!nw || v < nw) nw = v }
  /^unwarp \(2 streaming passes, into memory/ { for (i = 1; i <= NF; i++) if ($(i + 1) == "s") { v = $i + 0 }; if (!nu || v < nu) nu = v }
  # step 3: "[wasm ]unwarp --machine NAME [MODE]: T s …" and "… NAME with the collision check: T s …"
  /^(wasm )?unwarp --machine / && !/: refused:/ {
    w = ($1 == "wasm"); s = $0; sub(/^(wasm )?unwarp --machine /, "", s)
    k = substr(s, 1, index(s, ": ") - 1); v = substr(s, index(s, ": ") + 2) + 0
    if (!(k in seen)) { seen[k] = 1; order[++nk] = k }
    if (w) { if (!(k in mw) || v < mw[k]) mw[k] = v } else { if (!(k in mn) || v < mn[k]) mn[k] = v }
  }
  # the wall time: the first number followed by "s" (the CPU time follows it in parentheses)
  /^3-axis unwarp \(the reference/ { for (i = 1; i <= NF; i++) if ($i ~ /^[0-9.]+$/ && ($(i + 1) == "s," || $(i + 1) == "s")) { v = $i + 0; break }; if (!n3 || v < n3) n3 = v }
  /^wasm builtin slice: [0-9]/ { v = $4 + 0; if (!wb || v < wb) wb = v }
  /^builtin: [0-9]/ { v = $2 + 0; if (!nb || v < nb) nb = v }
  END {
    printf "warp_model: native %.3f s, wasm %.3f s, wasm/native %.2f\n", nw, ww, ww / nw
    printf "unwarp (into memory): native %.3f s, wasm %.3f s, wasm/native %.2f\n", nu, wu, wu / nu
    for (j = 1; j <= nk; j++) {
      k = order[j]
      if (!(k in mn) || !(k in mw)) { printf "unwarp --machine %s: native %s, wasm %s (refused or not run on one side)\n", k, (k in mn) ? mn[k] " s" : "-", (k in mw) ? mw[k] " s" : "-"; continue }
      printf "unwarp --machine %s: native %.2f s (×%.1f its 3-axis), wasm %.2f s (×%.1f its 3-axis), wasm/native %.2f\n", k, mn[k], mn[k] / n3, mw[k], mw[k] / wu, mw[k] / mn[k]
    }
    if (nb && wb) printf "builtin slice (225k-triangle sphere, conic 30°): native %.3f s, wasm %.3f s, wasm/native %.2f\n", nb, wb, wb / nb
  }' "$LOG"
rm -f "$LOG"
