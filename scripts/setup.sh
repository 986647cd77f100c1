#!/usr/bin/env bash
# Installs what warpslice needs and is missing; prints one line per step. Idempotent and fast
# (a few seconds) when everything is already there.
#
#   bash scripts/setup.sh [COMPONENT...]       # run on its own
#   source scripts/setup.sh [COMPONENT...]     # from run.sh / test.sh: also exports PATH, CURA_RES
#
# Components (default: all):
#   core     Rust toolchain (cargo on PATH) and PrusaSlicer: what `scripts/run.sh` needs
#   slicers  PrusaSlicer, Slic3r, CuraEngine (Debian packages) and Cura's definitions (CURA_RES)
#   wasm     wasm32-unknown-unknown target, wasm-pack, wasm-bindgen-cli (version from Cargo.lock)
#   web      node/npm, chromium and chromium-driver (for the browser tests)
#   rs274    LinuxCNC's RS274NGC interpreter (Debian's linuxcnc-uspace and libboost-python,
#            downloaded and extracted, not installed: ~375 packages otherwise) into
#            WARPSLICE_RS274_DIR (default ~/.cache/warpslice/rs274), the oracle of
#            tests/rs274_oracle.rs (native tier); exports WARPSLICE_RS274_ROOT
#   all      core slicers wasm rs274, g++ (the fuzz tier), plus web once www/package.json exists
#
# Needs Debian/Ubuntu (apt-get) and root or sudo for the system packages; everything else goes
# to ~/.cargo/bin. Environment: CURA_RES (use this Cura resources folder instead of installing),
# WARPSLICE_CURA_RES_DIR (where to extract the cura package; default /opt/cura-res when
# writable, else target/cura-res in the repository).

_ws_sourced=0
[[ "${BASH_SOURCE[0]}" != "$0" ]] && _ws_sourced=1
if [[ $_ws_sourced == 0 ]]; then
  set -euo pipefail
fi

WS_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WS_WASM_PACK_VERSION=0.15.1
WS_SETUP_LOG="${TMPDIR:-/tmp}/warpslice-setup.$$.log"
_ws_apt_updated=0
_ws_started=$(date +%s.%N)

ws_say() { echo "setup: $*"; }
ws_die() {
  echo "setup: ERROR: $*" >&2
  return 1
}

# Runs "$@" with its output in the log; on failure prints the log's tail.
ws_logged() {
  local rc=0
  "$@" >>"$WS_SETUP_LOG" 2>&1 || rc=$?
  [[ $rc == 0 ]] && return 0
  echo "setup: '$*' failed (exit $rc); last lines of $WS_SETUP_LOG:" >&2
  tail -n 15 "$WS_SETUP_LOG" >&2
  return $rc
}

ws_sudo() {
  if [[ $(id -u) == 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null 2>&1; then
    sudo -n "$@"
  else
    ws_die "need root or sudo to run: $*"
  fi
}

ws_apt_get() {
  command -v apt-get >/dev/null 2>&1 ||
    ws_die "apt-get not found: install by hand: $*"
  # Once more after a pause if the first attempt fails (apt locked by another process, a
  # flaky mirror).
  local attempt
  for attempt in 1 2; do
    if ws_logged ws_sudo env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 "$@"; then
      return 0
    fi
    if [[ $attempt == 1 ]]; then
      ws_say "apt-get $1 failed, retrying in ${WS_APT_RETRY_PAUSE:-15} s"
      sleep "${WS_APT_RETRY_PAUSE:-15}"
    fi
  done
  return 1
}

ws_apt_update_once() {
  [[ $_ws_apt_updated == 1 ]] && return 0
  ws_say "apt-get update"
  ws_apt_get update -qq
  _ws_apt_updated=1
}

# ws_apt_install PACKAGE:COMMAND ... : installs the packages whose command is missing.
ws_apt_install() {
  local spec pkg cmd missing=()
  for spec in "$@"; do
    pkg=${spec%%:*}
    cmd=${spec#*:}
    if command -v "$cmd" >/dev/null 2>&1; then
      ws_say "$pkg present ($(command -v "$cmd"))"
    else
      missing+=("$pkg")
    fi
  done
  [[ ${#missing[@]} == 0 ]] && return 0
  ws_apt_update_once
  ws_say "installing ${missing[*]} (apt-get)"
  ws_apt_get install -y -qq --no-install-recommends "${missing[@]}"
  hash -r
  for spec in "$@"; do
    cmd=${spec#*:}
    command -v "$cmd" >/dev/null 2>&1 || ws_die "${spec%%:*} installed but '$cmd' is still not on PATH"
  done
}

ws_rust() {
  export PATH="${CARGO_HOME:-$HOME/.cargo}/bin:$PATH"
  if command -v cargo >/dev/null 2>&1; then
    ws_say "rust present ($(cargo --version))"
  elif command -v rustup >/dev/null 2>&1; then
    ws_say "installing the stable Rust toolchain (rustup)"
    ws_logged rustup toolchain install stable --profile minimal
    ws_logged rustup default stable
  else
    ws_die "no cargo and no rustup: install Rust from https://rustup.rs"
  fi
}

# clippy and rustfmt: the clippy and fmt tiers fail without them.
ws_clippy() {
  local c
  for c in clippy rustfmt; do
    if cargo "${c/rustfmt/fmt}" --version >/dev/null 2>&1; then
      ws_say "$c present"
    elif command -v rustup >/dev/null 2>&1 && ws_logged rustup component add "$c"; then
      ws_say "installed $c"
    else
      ws_die "$c is missing and rustup cannot add it: install the Rust component '$c'"
    fi
  done
}

ws_cura_res_ok() { [[ -n "${1:-}" && -f "$1/definitions/fdmprinter.def.json" ]]; }

ws_cura_definitions() {
  if [[ -n "${CURA_RES:-}" ]]; then
    ws_cura_res_ok "$CURA_RES" ||
      ws_die "CURA_RES=$CURA_RES has no definitions/fdmprinter.def.json: unset it to let setup install them"
    ws_say "cura definitions present (CURA_RES=$CURA_RES)"
    return 0
  fi
  local dest="${WARPSLICE_CURA_RES_DIR:-}"
  if [[ -z "$dest" ]]; then
    if [[ -w /opt || -w /opt/cura-res ]]; then dest=/opt/cura-res; else dest="$WS_ROOT/target/cura-res"; fi
  fi
  local candidate
  for candidate in "$dest/usr/share/cura/resources" /opt/cura-res/usr/share/cura/resources /usr/share/cura/resources; do
    if ws_cura_res_ok "$candidate"; then
      export CURA_RES="$candidate"
      ws_say "cura definitions present (CURA_RES=$CURA_RES)"
      return 0
    fi
  done
  ws_apt_update_once
  ws_say "installing cura definitions into $dest (apt-get download cura)"
  mkdir -p "$dest"
  # Download inside the destination and extract at once (the package cache may be cleaned).
  (
    cd "$dest" &&
      rm -f cura_*.deb &&
      ws_logged apt-get download -qq cura &&
      ws_logged dpkg-deb -x cura_*.deb . &&
      rm -f cura_*.deb
  ) || ws_die "could not download/extract the cura package into $dest"
  ws_cura_res_ok "$dest/usr/share/cura/resources" ||
    ws_die "the cura package in $dest has no usr/share/cura/resources/definitions/fdmprinter.def.json"
  export CURA_RES="$dest/usr/share/cura/resources"
  ws_say "cura definitions installed (CURA_RES=$CURA_RES)"
}

ws_wasm_target() {
  if rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
    ws_say "wasm32-unknown-unknown target present"
  else
    ws_say "installing the wasm32-unknown-unknown target (rustup)"
    ws_logged rustup target add wasm32-unknown-unknown
  fi
}

# Waits while another process is already running `cargo install CRATE` (two concurrent
# installs of the same binary waste minutes and race on ~/.cargo/bin).
ws_wait_for_other_install() {
  command -v pgrep >/dev/null 2>&1 || return 0
  if pgrep -f "cargo install $1" >/dev/null 2>&1; then
    ws_say "waiting for a running 'cargo install $1' to finish"
    while pgrep -f "cargo install $1" >/dev/null 2>&1; do sleep 5; done
  fi
}

ws_lock_version() {
  awk -v n="$1" '$0 == "name = \"" n "\"" { getline; gsub(/version = |"/, ""); print; exit }' \
    "$WS_ROOT/Cargo.lock"
}

ws_wasm_tools() {
  ws_wait_for_other_install wasm-pack
  if command -v wasm-pack >/dev/null 2>&1; then
    ws_say "wasm-pack present ($(wasm-pack --version))"
  else
    ws_say "installing wasm-pack $WS_WASM_PACK_VERSION (cargo install, a few minutes)"
    ws_logged cargo install wasm-pack --version "$WS_WASM_PACK_VERSION" --locked
  fi
  local want have
  want=$(ws_lock_version wasm-bindgen)
  [[ -n "$want" ]] || ws_die "no wasm-bindgen in Cargo.lock"
  ws_wait_for_other_install wasm-bindgen-cli
  have=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)
  if [[ "$have" == "$want" ]]; then
    ws_say "wasm-bindgen-cli $want present"
  else
    # wasm-pack cannot download it here; the CLI must match Cargo.lock's wasm-bindgen exactly.
    ws_say "installing wasm-bindgen-cli $want (cargo install, a few minutes${have:+; found $have})"
    ws_logged cargo install wasm-bindgen-cli --version "$want" --force
  fi
}

ws_node() {
  ws_apt_install nodejs:node npm:npm
}

# LinuxCNC's `gcode` Python module (scripts/rs274_oracle.py): extracted from the two Debian
# packages that hold it and its one library, never installed (linuxcnc-uspace would pull ~375
# packages, systemd among them). Idempotent: nothing is downloaded when the module imports.
ws_rs274() {
  local dest="${WARPSLICE_RS274_DIR:-$HOME/.cache/warpslice/rs274}"
  export WARPSLICE_RS274_ROOT="$dest/root"
  if python3 "$WS_ROOT/scripts/rs274_oracle.py" --probe >/dev/null 2>&1; then
    ws_say "rs274 interpreter present (WARPSLICE_RS274_ROOT=$WARPSLICE_RS274_ROOT)"
    return 0
  fi
  command -v python3 >/dev/null 2>&1 || ws_apt_install python3:python3
  ws_apt_update_once
  ws_say "extracting LinuxCNC's RS274NGC interpreter into $dest (apt-get download linuxcnc-uspace libboost-python1.74.0)"
  mkdir -p "$dest"
  (
    cd "$dest" &&
      rm -rf root ./*.deb &&
      ws_logged apt-get -o DPkg::Lock::Timeout=900 download -qq linuxcnc-uspace libboost-python1.74.0 &&
      for deb in ./*.deb; do ws_logged dpkg-deb -x "$deb" root || exit 1; done &&
      rm -f ./*.deb
  ) || ws_die "could not download/extract linuxcnc-uspace into $dest"
  python3 "$WS_ROOT/scripts/rs274_oracle.py" --probe ||
    ws_die "LinuxCNC's gcode module in $WARPSLICE_RS274_ROOT does not import (python3 $(python3 -c 'import sys; print(sys.version.split()[0])'))"
  ws_say "rs274 interpreter installed (WARPSLICE_RS274_ROOT=$WARPSLICE_RS274_ROOT)"
}

ws_web() {
  ws_node
  ws_apt_install chromium:chromium chromium-driver:chromedriver
}

ws_setup() {
  local components=("$@") c
  [[ ${#components[@]} == 0 ]] && components=(all)
  : >"$WS_SETUP_LOG"
  for c in "${components[@]}"; do
    case $c in
    core)
      ws_rust
      ws_apt_install prusa-slicer:prusa-slicer
      ;;
    slicers)
      ws_apt_install prusa-slicer:prusa-slicer slic3r:slic3r cura-engine:CuraEngine
      ws_cura_definitions
      ;;
    wasm)
      ws_rust
      ws_wasm_target
      ws_wasm_tools
      ws_node
      ;;
    web) ws_web ;;
    rs274) ws_rs274 ;;
    all)
      ws_rust
      ws_clippy
      # the fuzz targets (fuzz/, libfuzzer-sys) build libFuzzer with a C++ compiler
      ws_apt_install g++:g++
      ws_apt_install prusa-slicer:prusa-slicer slic3r:slic3r cura-engine:CuraEngine
      ws_cura_definitions
      ws_rs274
      ws_wasm_target
      ws_wasm_tools
      ws_node
      if [[ -f "$WS_ROOT/www/package.json" ]]; then ws_web; fi
      ;;
    *) ws_die "unknown component '$c' (core, slicers, wasm, web, rs274, all)" ;;
    esac
  done
  rm -f "$WS_SETUP_LOG"
  ws_say "done in $(awk -v a="$_ws_started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s"
}

ws_setup "$@"
