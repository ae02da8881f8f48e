#!/usr/bin/env bash
# momenta: build the Release tree and simulate the example models.
#
# Runs the seed examples first (models/carrier_collision.yaml, models/ball_pendulum_impact.yaml,
# models/ball_pendulum.yaml and their 3-D versions models/ball_pendulum_3d_impact.yaml,
# models/ball_pendulum_3d.yaml; noting any that is missing), then every other models/*.yaml and
# models/msl/*.yaml. Each result goes to build/examples/<model>.csv; momenta prints its summary and
# final values. Ends with the seed's figures read from the CSVs (carrier B's final speed; the
# ball and pendulum's speeds just after the impact divided by A's speed v0 just before, exact and
# penalty, planar and 3-D). Exits non-zero if any simulation failed.
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
for m in models/carrier_collision.yaml models/ball_pendulum_impact.yaml models/ball_pendulum.yaml \
         models/ball_pendulum_3d_impact.yaml models/ball_pendulum_3d.yaml; do
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

# ---- the seed's figures ---------------------------------------------------------------------
# Ball and pendulum: v0 is A's speed on the last row before contact, the velocities after it those
# of the first row after it (the exact impact's right limit; the end of the penalty force). The
# planar models' velocities are A.v and B.v, the 3-D models' A.v_0 and B.v_0 (world frame; they
# stay in the x-y plane).
ball_pendulum() {  # CSV, "exact" or "penalty", the velocity's name (v or v_0), a label
  awk -F, -v kind="$2" -v v="$3" -v label="$4" '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { n++; t[n] = $1; ax[n] = $c["A." v "[1]"]; ay[n] = $c["A." v "[2]"]; bx[n] = $c["B." v "[1]"]; by[n] = $c["B." v "[2]"]
      if (kind == "penalty") { on[n] = $c["touching.y"] + 0 } }
    END {
      for (k = 2; k <= n; k++) {
        if (kind == "exact" && t[k] == t[k - 1]) { b = k - 1; a = k; break }
        if (kind == "penalty" && on[k] > 0.5 && !b) b = k - 1
        if (kind == "penalty" && b && on[k] < 0.5) { a = k; break }
      }
      if (!a) { print "  (no impact found)"; exit }
      v0 = sqrt(ax[b] ^ 2 + ay[b] ^ 2)
      printf "  %-14s v0 = %.6f m/s at t = %.6f s; after: A %.4f v0 at %.2f deg above the x axis, B %.4f v0 along %s\n",
             label, v0, t[b], sqrt(ax[a] ^ 2 + ay[a] ^ 2) / v0, atan2(ay[a], ax[a]) * 45 / atan2(1, 1),
             sqrt(bx[a] ^ 2 + by[a] ^ 2) / v0, (bx[a] < 0 ? "-x" : "+x")
    }' "$1"
}
echo
echo "== the seed's examples"
if [[ -f "$OUT/carrier_collision.csv" ]]; then
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } { v = $c["B.v"] }
           END { printf "Carrier collision: carrier B ends at %.6f m/s (closed form 2.904545...)\n", v }' "$OUT/carrier_collision.csv"
fi
echo "Ball and pendulum (closed form for e = 1: A 0.7211 v0 at 16.1 deg, B 0.6928 v0 along -x):"
[[ -f "$OUT/ball_pendulum_impact.csv" ]] && ball_pendulum "$OUT/ball_pendulum_impact.csv" exact v "exact"
[[ -f "$OUT/ball_pendulum.csv" ]] && ball_pendulum "$OUT/ball_pendulum.csv" penalty v "penalty"
[[ -f "$OUT/ball_pendulum_3d_impact.csv" ]] && ball_pendulum "$OUT/ball_pendulum_3d_impact.csv" exact v_0 "3-D exact"
[[ -f "$OUT/ball_pendulum_3d.csv" ]] && ball_pendulum "$OUT/ball_pendulum_3d.csv" penalty v_0 "3-D penalty"
echo
echo "${#models[@]} models run, ${#failed[@]} failed${failed[*]:+: ${failed[*]}}"
((${#failed[@]} == 0))
