#!/usr/bin/env bash
# momenta: build the Release tree and simulate the example models.
#
# Runs models/carrier_collision.yaml and models/ball_and_pendulum.yaml first (noting any that is
# missing), then every other models/*.yaml. Each result goes to build/examples/<model>.csv; the
# script prints its size and first lines, and exits non-zero if any simulation failed.
# Environment: MOMENTA_JOBS (default 2).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
JOBS="${MOMENTA_JOBS:-2}"
MOMENTA=build/app/momenta
OUT=build/examples

# ---- build ----------------------------------------------------------------------------------
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$JOBS"
[[ -x "$MOMENTA" ]] || { echo "no $MOMENTA after the build" >&2; exit 1; }
mkdir -p "$OUT"

# ---- list the models: the two seed examples first, then the rest -----------------------------
models=()
for m in models/carrier_collision.yaml models/ball_and_pendulum.yaml; do
  if [[ -f "$m" ]]; then models+=("$m"); else echo "note: $m does not exist, skipped"; fi
done
for m in models/*.yaml; do
  [[ -f "$m" ]] || continue
  case " ${models[*]} " in *" $m "*) continue ;; esac
  models+=("$m")
done

# ---- simulate each one ----------------------------------------------------------------------
failed=()
for m in "${models[@]}"; do
  name=$(basename "$m" .yaml)
  echo "== $MOMENTA simulate $m"
  t0=$(date +%s%N)
  if "$MOMENTA" simulate "$m" >"$OUT/$name.csv"; then
    echo "   ok in $(( ($(date +%s%N) - t0) / 1000000 )) ms, $(wc -l <"$OUT/$name.csv") lines -> $OUT/$name.csv"
    head -n 3 "$OUT/$name.csv" | cut -c1-200 | sed 's/^/   | /'
  else
    echo "   FAILED (exit $?)"
    failed+=("$m")
  fi
done

echo "${#models[@]} models run, ${#failed[@]} failed${failed[*]:+: ${failed[*]}}"
((${#failed[@]} == 0))
