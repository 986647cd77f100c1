#!/usr/bin/env bash
# The benchmark in Node wasm. Run `cargo run --release --example bench` first (it leaves the
# inputs in target/bench-inputs/).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/setup.sh wasm
[[ -f target/bench-inputs/ball.gcode ]] || cargo run --release --example bench
wasm-pack build --release --target nodejs --out-dir target/pkg-node >/dev/null
node bench/wasm.mjs "$(pwd)/target/pkg-node/warpslice.js" target/bench-inputs
