#!/usr/bin/env bash
# momenta: build the Release tree and simulate the example models.
#
# Runs the seed examples models/carrier_collision.yaml and models/ball_and_pendulum.yaml first
# (noting any that is missing), then every other models/*.yaml and models/msl/*.yaml. Each result
# goes to build/examples/<model>.csv; momenta prints its summary and final values. Exits non-zero
# if any simulation failed.
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
for m in models/*.yaml models/msl/*.yaml; do
  [[ -f "$m" ]] || continue
  case " ${models[*]} " in *" $m "*) continue ;; esac
  models+=("$m")
done

# ---- simulate each one ----------------------------------------------------------------------
failed=()
for m in "${models[@]}"; do
  name=$(basename "$m" .yaml)
  echo "== $MOMENTA simulate $m -o $OUT/$name.csv"
  if "$MOMENTA" simulate "$m" -o "$OUT/$name.csv"; then
    :
  else
    echo "   FAILED (exit $?)"
    failed+=("$m")
  fi
done

echo "${#models[@]} models run, ${#failed[@]} failed${failed[*]:+: ${failed[*]}}"
((${#failed[@]} == 0))
