#!/usr/bin/env bash
# The main job: installs what is missing (Rust, PrusaSlicer), builds warpslice, runs it on a
# generated overhang block (conic warp 30° outward, sliced by PrusaSlicer, unwarped to G-code),
# then builds and serves the web app on 127.0.0.1 (PORT, default 8080; WARPSLICE_NO_SERVE=1
# stops after the CLI demo).
#
#   bash scripts/run.sh
#
# Output: examples/out/ (ignored by git). CARGO_TARGET_DIR is honoured.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
ROOT=$(pwd)

echo "==== setup ===="
# shellcheck source=setup.sh
source scripts/setup.sh core

echo "==== build ===="
cargo build --release
BIN="${CARGO_TARGET_DIR:-$ROOT/target}/release/warpslice"
[[ -x "$BIN" ]] || { echo "run: the build produced no $BIN" >&2; exit 1; }

echo "==== run: the generated overhang block, conic 30° outward, sliced by PrusaSlicer ===="
OUT_DIR="$ROOT/examples/out"
mkdir -p "$OUT_DIR"
IN="$OUT_DIR/overhang.stl"
OUT="$OUT_DIR/overhang-conic30.gcode"
rm -f "$OUT"
"$BIN" example overhang -o "$IN"
"$BIN" run "$IN" --slicer prusaslicer --warp conic --angle 30 --direction outward -o "$OUT"

if [[ ! -s "$OUT" ]]; then
  echo "run: warpslice finished but wrote no $OUT (is the CLI implemented yet?)" >&2
  exit 1
fi
echo
echo "run: input   $IN"
echo "run: output  $OUT ($(wc -l <"$OUT") lines)"
ls -l "$OUT_DIR"

echo
if [[ "${WARPSLICE_NO_SERVE:-}" == 1 || -n "${CI:-}" ]]; then
  echo "run: not serving the web app (WARPSLICE_NO_SERVE=1 or CI)"
  exit 0
fi
echo "==== the web app: http://127.0.0.1:${PORT:-8080}/ (Ctrl-C to stop) ===="
exec bash scripts/serve.sh "${PORT:-8080}"
