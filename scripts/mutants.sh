#!/usr/bin/env bash
# The suite catches planted bugs (issue 17): each mutant below is planted in a scratch copy of
# HEAD (committed files only), the tests named with it are run there, and each must FAIL. Prints one line per
# mutant (caught / NOT CAUGHT) and exits non-zero if any escaped.
#
#   bash scripts/mutants.sh            # every mutant (≈ 5 min each on a 2-core machine)
#   bash scripts/mutants.sh e-scale    # one, by name
#
# Needs the real slicers (scripts/setup.sh all). Not part of scripts/test.sh (it rebuilds the
# crate once per mutant); run it after changing a check.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
work="${WARPSLICE_MUTANT_DIR:-/tmp/warpslice-mutants}"
export CARGO_TARGET_DIR="${WARPSLICE_MUTANT_TARGET:-$work/target}"

# name | file | perl substitution (must match exactly once) | tests that must fail (cargo test args)
mutants=(
  "split-off|src/unwarp/segment.rs|s/let needs = depth < MAX_DEPTH && \{/let needs = false \&\& depth < MAX_DEPTH \&\& {/|--test real_slicers prusaslicer_relative_generated"
  "tilted-sign|src/warp/tilted.rs|s/k: strength \* direction.sign\(\),/k: -strength * direction.sign(),/|--test real_slicers prusaslicer_relative_generated"
  "linear-blend|src/warp/base.rs|s/t \* t \* \(3.0 - 2.0 \* t\)/t/|--test real_slicers prusaslicer_relative_generated"
  "registration-0.05|src/register/mod.rs|s/translation: \[dx, dy, 0.0\],/translation: [dx + 0.05, dy, 0.0],/|--test real_slicers prusaslicer_relative_generated"
  "e-scale|src/unwarp/core.rs|s/let mut e = m.e \* \(t1 - t0\) \/ det/let mut e = 0.97 * m.e * (t1 - t0) \/ det/|--test real_slicers prusaslicer_relative_generated"
  "rtn-axis-mirror|src/machine/rtn.rs|s/num::sin\(t\) \* num::sin\(phi\),/-num::sin(t) * num::sin(phi),/|--test machine_laws"
  "rtn-azimuth-mirror|src/machine/rtn.rs|s/self.rotation_of\(num::deg\(num::atan2\(n.y, n.x\)\)\)$/self.rotation_of(num::deg(num::atan2(-n.y, n.x)))/|--test real_slicers prusaslicer_relative_generated"
  "lift-removed|src/unwarp/travel.rs|s/if above <= DIRECT_TRAVEL_SLACK \{/if above <= DIRECT_TRAVEL_SLACK + 1.0 {/|--test real_slicers prusaslicer_relative_generated"
)

only="${1:-}"
escaped=0
for m in "${mutants[@]}"; do
  IFS='|' read -r name file subst tests <<<"$m"
  [ -n "$only" ] && [ "$only" != "$name" ] && continue
  rm -rf "$work/tree" && mkdir -p "$work/tree"
  (cd "$here" && git archive HEAD) | tar -x -C "$work/tree"
  ln -sfn "$here/../shared" "$work/shared"
  n=$(perl -ne "\$n++ if $subst; END { print \$n+0 }" "$work/tree/$file")
  if [ "$n" != 1 ]; then
    echo "mutant $name: the substitution matches $n lines of $file (must be 1): update scripts/mutants.sh"
    escaped=1
    continue
  fi
  perl -pi -e "$subst" "$work/tree/$file"
  log="$work/$name.log"
  # shellcheck disable=SC2086
  if (cd "$work/tree" && cargo test --release $tests -- --test-threads 2) >"$log" 2>&1; then
    echo "mutant $name ($file): NOT CAUGHT by cargo test $tests (log: $log)"
    escaped=1
  elif grep -q "panicked at" "$log"; then
    # the matrix prints "N failures in M cases:" and then one line per failure
    # (`|| true`: with pipefail, a grep that finds nothing would end the script under set -e)
    why=$(grep -m1 -A1 -E "failures in [0-9]+ cases:" "$log" | tail -n1 || true)
    [ -n "$why" ] || why=$(grep -m1 -A1 "panicked at" "$log" | tail -n1 || true)
    echo "mutant $name ($file): caught by cargo test $tests: ${why:0:240}"
  else
    echo "mutant $name ($file): the test run failed without a test failing (build error, signal): see $log"
    escaped=1
  fi
done
exit $escaped
