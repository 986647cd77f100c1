#!/usr/bin/env bash
# Builds the wasm package and the app's vendored files, then serves www/ on 127.0.0.1.
#
#   bash scripts/serve.sh [PORT]      # default 8080; open http://127.0.0.1:PORT/
#
# Works from any static host too: copy www/ (with pkg/ and vendor/) anywhere, any sub-path.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=setup.sh
source scripts/setup.sh wasm web
wasm-pack build --release --target web --out-dir www/pkg
(cd www && npm ci --no-audit --no-fund)
exec node www/scripts/serve.mjs "${1:-8080}"
