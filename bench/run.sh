#!/usr/bin/env bash
# momenta benchmarks: momenta (momenta_bench) against the hand-written IDA programs
# (handwritten_rc, handwritten_chain) on the RC ladder and the spring-damper chain, plus build-time
# scaling. Writes Markdown tables to stdout; the raw key=value output of every program goes to
# $BENCH_OUT (default: a new directory under /tmp), named in the last line.
#
# usage: bench/run.sh [full|quick]
#   full  (default) RC ladder n = 10 .. 100 000, chain n = 10 .. 10 000; about 10-15 minutes on 2 cores
#   quick RC ladder n = 10 .. 1 000, chain n = 10, 100; under a minute
# environment:
#   MOMENTA_BUILD_DIR  build directory holding bench/momenta_bench, bench/handwritten_*
#                      (default: <repo>/build; configure with -DMOMENTA_BUILD_BENCH=ON)
#   MOMENTA_SRC_DIR    source tree whose models/ are used (default: <repo>)
#   BENCH_OUT          where the raw outputs go
#   BENCH_SOURCE_NOTE  text describing the source measured (default: git commit of MOMENTA_SRC_DIR)
#   BENCH_TIMEOUT      seconds allowed for one momenta_bench invocation on the chain (default 120);
#                      a size that does not finish is reported as such and larger sizes are skipped
#
# Benchmarks are not tests: nothing here is part of ctest.
set -euo pipefail

MODE=${1:-full}
case "$MODE" in full | quick) ;; *) echo "usage: $0 [full|quick]" >&2; exit 2 ;; esac

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$HERE/.." && pwd)
BUILD=${MOMENTA_BUILD_DIR:-$REPO/build}
SRC=${MOMENTA_SRC_DIR:-$REPO}
OUT=${BENCH_OUT:-$(mktemp -d /tmp/momenta-bench.XXXXXX)}
TIMEOUT=${BENCH_TIMEOUT:-120}
mkdir -p "$OUT"

MB=$BUILD/bench/momenta_bench
HRC=$BUILD/bench/handwritten_rc
HCH=$BUILD/bench/handwritten_chain
for p in "$MB" "$HRC" "$HCH"; do
  [[ -x $p ]] || { echo "missing $p: cmake --build $BUILD --target momenta_bench handwritten_rc handwritten_chain" >&2; exit 1; }
done
RC_MODEL=$SRC/models/rc_ladder.yaml
CHAIN_MODEL=$SRC/models/spring_damper_chain.yaml

if [[ $MODE == quick ]]; then
  RC_SIZES=(10 100 1000)
  CHAIN_SIZES=(10 100)
  CHAIN_BUILD_SIZES=(10 30 100)
  REF=0
else
  RC_SIZES=(10 100 1000 10000 100000)
  CHAIN_SIZES=(10 100 1000 10000)
  CHAIN_BUILD_SIZES=(10 100 1000 10000 100000)
  REF=1
fi

# Runs per size: medians of 5 (small), 3 (n = 10 000), 1 (n = 100 000).
runs_for() {
  local n=$1
  if [[ $MODE == quick ]]; then echo 3; elif ((n >= 100000)); then echo 1; elif ((n >= 10000)); then echo 3; else echo 5; fi
}

# get FILE KEY: the value of KEY on the "median" line of FILE (empty when absent).
get() {
  [[ -f $1 ]] || return 0
  awk -v k="$2" '/^median/ { for (i = 2; i <= NF; i++) { p = index($i, "="); if (substr($i, 1, p - 1) == k) print substr($i, p + 1) } }' "$1"
}
# header FILE KEY: a key=value of the "# momenta_bench" header line.
header() {
  [[ -f $1 ]] || return 0
  awk -v k="$2" '/^# momenta_bench/ { for (i = 2; i <= NF; i++) { p = index($i, "="); if (substr($i, 1, p - 1) == k) print substr($i, p + 1) } }' "$1"
}
# fmt X: 3 significant digits, "—" when empty.
fmt() { if [[ -z ${1:-} ]]; then echo "—"; else awk -v x="$1" 'BEGIN { printf "%.3g", x }'; fi; }
# ratio A B: A/B with 2 decimals.
ratio() { if [[ -z ${1:-} || -z ${2:-} ]]; then echo "—"; else awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "—" }'; fi; }
# sum A B
sum() { awk -v a="${1:-0}" -v b="${2:-0}" 'BEGIN { printf "%.6f", a + b }'; }
# reldiff A B: |A-B|/max(|B|, 1e-300), 2 significant digits
reldiff() { if [[ -z ${1:-} || -z ${2:-} ]]; then echo "—"; else awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; m = b < 0 ? -b : b; if (m < 1e-300) m = 1e-300; printf "%.2g", d / m }'; fi; }
absdiff() { if [[ -z ${1:-} || -z ${2:-} ]]; then echo "—"; else awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; printf "%.2g", d }'; fi; }

# run_timed FILE CMD...: runs CMD > FILE under the timeout; returns 0, or 124 on timeout.
run_timed() {
  local file=$1
  shift
  local rc=0
  timeout --signal=KILL "$TIMEOUT" "$@" >"$file" 2>"$file.err" || rc=$?
  if ((rc == 137 || rc == 124)); then return 124; fi
  if ((rc != 0)); then
    echo "error: $* failed (exit $rc):" >&2
    cat "$file.err" >&2
    return $rc
  fi
  return 0
}

START=$(date +%s)
echo "# momenta benchmarks ($MODE)"
echo
echo "- date: $(date -u +%FT%TZ)"
echo "- CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores; load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "- $("$BUILD/app/momenta" --version 2>/dev/null || echo "momenta (version unknown)")"
if [[ -n ${BENCH_SOURCE_NOTE:-} ]]; then
  echo "- source: $BENCH_SOURCE_NOTE"
elif git -C "$SRC" rev-parse HEAD >/dev/null 2>&1; then
  echo "- source: $(git -C "$SRC" rev-parse --short HEAD)$(git -C "$SRC" diff --quiet HEAD 2>/dev/null || echo ' + uncommitted changes')"
fi
echo "- build: $BUILD ($(grep -m1 '^CMAKE_BUILD_TYPE' "$BUILD/CMakeCache.txt" 2>/dev/null | cut -d= -f2)); raw outputs: $OUT"
echo

declare -A RC_FAILED=()
# ---- 1. RC ladder -------------------------------------------------------------------------------
echo "## RC ladder (models/rc_ladder.yaml vs handwritten_rc)"
echo
echo "Model defaults: stop 10 s, output interval 0.01 s, rtol = atol = 1e-6 (all nominals are 1);"
echo "momenta uses its default (auto) linear solver and the hand-written program the same one."
echo "load+build = LoadModelFile + BuildModel; simulate = initialisation + IDA set-up + integration"
echo "(momenta_bench simulate_cpu_s); hand-written = set-up + integration (setup_cpu_s + solve_cpu_s)."
echo "All times in this report are CPU times of the process (CLOCK_PROCESS_CPUTIME_ID), medians over"
echo "the runs: on a shared machine they leave out time spent waiting for a core (wall-clock medians"
echo "are in the raw outputs)."
echo "Published n = 1000 build + solve: ModelingToolkit 52 s, OpenModelica 67 s, Dymola 6.8 s."
echo
echo "| n | unknowns | runs | load+build (s) | momenta init (wall, s) | momenta simulate (s) | hand-written (s) | simulate ratio | build+simulate (s) | steps m / h | res evals m / h | Jac evals m / h | C[1].v m / h |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|---|"
for n in "${RC_SIZES[@]}"; do
  k=$(runs_for "$n")
  f=$OUT/rc_m_$n.txt
  h=$OUT/rc_h_$n.txt
  mrc=0
  "$MB" --model "$RC_MODEL" -p n="$n" --repeat "$k" >"$f" 2>"$f.err" || mrc=$?
  ls=$(awk '/^# linear solver used:/ { print $5 }' "$f")
  # momenta's auto rule (kDenseLimit = 40 unknowns), for when momenta failed before choosing.
  [[ -n $ls ]] || { ((n <= 40)) && ls=dense || ls=klu; }
  "$HRC" --n "$n" --stop 10 --interval 0.01 --rtol 1e-6 --atol 1e-6 --linear-solver "$ls" --repeat "$k" >"$h" 2>"$h.err"
  hw=$(sum "$(get "$h" setup_cpu_s)" "$(get "$h" solve_cpu_s)")
  if ((mrc != 0)); then
    RC_FAILED[$n]=1
    msg=$(grep -m1 '^# run .*failed' "$f" | sed 's/^# //' || true)
    [[ -n $msg ]] || msg="momenta_bench failed (exit $mrc): $(tr '|\n' '/ ' <"$f.err" | head -c 300)"
    echo "| $n | $n ($ls) | 1 | $(fmt "$(get "$f" load_build_cpu_s)") | failed | ${msg//|//} | $(fmt "$hw") | — | — | — / $(get "$h" steps) | — / $(get "$h" res_evals) | — / $(get "$h" jac_evals) | — / $(get "$h" u_1) |"
    continue
  fi
  lb=$(get "$f" load_build_cpu_s)
  sim=$(get "$f" simulate_cpu_s)
  echo "| $n | $(header "$f" unknowns) ($ls) | $k | $(fmt "$lb") | $(fmt "$(get "$f" init_s)") | $(fmt "$sim") | $(fmt "$hw") | $(ratio "$sim" "$hw") | $(fmt "$(sum "$lb" "$sim")") | $(get "$f" steps) / $(get "$h" steps) | $(get "$f" res_evals) / $(get "$h" res_evals) | $(get "$f" jac_evals) / $(get "$h" jac_evals) | $(get "$f" 'C[1].v') / $(get "$h" u_1) |"
done
echo
if ((REF)); then
  echo "Accuracy: |C[1].v(10) - reference| where the reference is handwritten_rc at rtol = atol = 1e-9."
  echo
  echo "| n | reference C[1].v | momenta error | hand-written error |"
  echo "|---:|---:|---:|---:|"
  for n in "${RC_SIZES[@]}"; do
    ((n <= 10000)) || continue
    [[ -z ${RC_FAILED[$n]:-} ]] || continue
    r=$OUT/rc_ref_$n.txt
    ls=$(awk '/^# linear solver used:/ { print $5 }' "$OUT/rc_m_$n.txt")
    "$HRC" --n "$n" --stop 10 --interval 0.01 --rtol 1e-9 --atol 1e-9 --linear-solver "$ls" --repeat 1 >"$r" 2>"$r.err"
    ref=$(get "$r" u_1)
    echo "| $n | $ref | $(absdiff "$(get "$OUT/rc_m_$n.txt" 'C[1].v')" "$ref") | $(absdiff "$(get "$OUT/rc_h_$n.txt" u_1)" "$ref") |"
  done
  echo
fi

# ---- 2. Spring-damper chain -----------------------------------------------------------------
echo "## Spring-damper chain (models/spring_damper_chain.yaml vs handwritten_chain)"
echo
echo "Both: stop 10 s, output interval 0.1 s, rtol = atol = 1e-6, linear solver dense for n = 10 and"
echo "klu otherwise (passed explicitly to both). The library's SpringDamper gives s_rel nominal 1e-4,"
echo "so by default momenta's absolute tolerance on the n relative positions is 1e-10; the main columns"
echo "use momenta_bench --unit-nominals (every nominal 1, one scalar atol as in IDASStolerances of the"
echo "hand-written program); the last column is the model's own nominals. The hand-written"
echo "program's states are mass[i].s and mass[i].v; momenta's are listed below the table: where they"
echo "differ the error test weighs different variables, so step counts differ; per-step cost is also"
echo "shown. momenta's build is timed once per size (--build-repeat 1)."
echo
echo "| n | runs | load+build (s) | momenta simulate (s) | hand-written (s) | simulate ratio | µs/step m / h | per-step ratio | steps m / h | res evals m / h | Jac evals m / h | mass[n].v m / h | rel. diff | steps, model nominals |"
echo "|---:|---:|---:|---:|---:|---:|---|---:|---|---|---|---|---:|---:|"
chain_skip=""
declare -A CHAIN_STATES=()
for n in "${CHAIN_SIZES[@]}"; do
  k=$(runs_for "$n")
  ls=klu
  ((n <= 10)) && ls=dense
  f=$OUT/chain_m_$n.txt
  g=$OUT/chain_m_nom_$n.txt
  h=$OUT/chain_h_$n.txt
  "$HCH" --n "$n" --stop 10 --interval 0.1 --rtol 1e-6 --atol 1e-6 --linear-solver "$ls" --repeat "$k" >"$h" 2>"$h.err"
  hw=$(sum "$(get "$h" setup_cpu_s)" "$(get "$h" solve_cpu_s)")
  hstep=$(awk -v t="$hw" -v s="$(get "$h" steps)" 'BEGIN { printf "%.1f", 1e6 * t / s }')
  if [[ -n $chain_skip ]]; then
    echo "| $n | $k | not run ($chain_skip) | — | $(fmt "$hw") | — | — / $hstep | — | — / $(get "$h" steps) | — / $(get "$h" res_evals) | — / $(get "$h" jac_evals) | — / $(get "$h" v_n) | — | — |"
    continue
  fi
  rc=0
  run_timed "$f" "$MB" --model "$CHAIN_MODEL" -p n="$n" --repeat "$k" --build-repeat 1 --stop 10 --interval 0.1 \
    --rtol 1e-6 --atol 1e-6 --linear-solver "$ls" --unit-nominals || rc=$?
  if ((rc == 124)); then
    chain_skip="n = $n did not build and simulate within ${TIMEOUT} s"
    echo "| $n | $k | > ${TIMEOUT} (timed out) | — | $(fmt "$hw") | — | — / $hstep | — | — / $(get "$h" steps) | — / $(get "$h" res_evals) | — / $(get "$h" jac_evals) | — / $(get "$h" v_n) | — | — |"
    chain_skip="skipped: n = $n did not finish within ${TIMEOUT} s"
    continue
  fi
  nomsteps="—"
  if run_timed "$g" "$MB" --model "$CHAIN_MODEL" -p n="$n" --repeat 1 --stop 10 --interval 0.1 \
    --rtol 1e-6 --atol 1e-6 --linear-solver "$ls"; then
    nomsteps=$(get "$g" steps)
  fi
  sim=$(get "$f" simulate_cpu_s)
  mstep=$(awk -v t="$sim" -v s="$(get "$f" steps)" 'BEGIN { printf "%.1f", 1e6 * t / s }')
  CHAIN_STATES[$n]=$(awk '/^# states by kind:/ { sub(/^# states by kind: /, ""); print }' "$f")
  echo "| $n | $k | $(fmt "$(get "$f" load_build_cpu_s)") | $(fmt "$sim") | $(fmt "$hw") | $(ratio "$sim" "$hw") | $mstep / $hstep | $(ratio "$mstep" "$hstep") | $(get "$f" steps) / $(get "$h" steps) | $(get "$f" res_evals) / $(get "$h" res_evals) | $(get "$f" jac_evals) / $(get "$h" jac_evals) | $(get "$f" 'mass[n].v') / $(get "$h" v_n) | $(reldiff "$(get "$f" 'mass[n].v')" "$(get "$h" v_n)") | $nomsteps |"
done
echo
for n in "${CHAIN_SIZES[@]}"; do
  [[ -n ${CHAIN_STATES[$n]:-} ]] && echo "- momenta's states at n = $n: ${CHAIN_STATES[$n]}"
done
echo
if ((REF)); then
  echo "Accuracy: error of the final mass[n].s and mass[n].v against handwritten_chain at rtol = atol = 1e-10."
  echo
  echo "| n | reference s_n | reference v_n | momenta error s / v | hand-written error s / v |"
  echo "|---:|---:|---:|---|---|"
  for n in "${CHAIN_SIZES[@]}"; do
    ls=klu
    ((n <= 10)) && ls=dense
    r=$OUT/chain_ref_$n.txt
    "$HCH" --n "$n" --stop 10 --interval 0.1 --rtol 1e-10 --atol 1e-10 --linear-solver "$ls" --repeat 1 >"$r" 2>"$r.err"
    rs=$(get "$r" s_n)
    rv=$(get "$r" v_n)
    f=$OUT/chain_m_$n.txt
    h=$OUT/chain_h_$n.txt
    echo "| $n | $rs | $rv | $(absdiff "$(get "$f" 'mass[n].s')" "$rs") / $(absdiff "$(get "$f" 'mass[n].v')" "$rv") | $(absdiff "$(get "$h" s_n)" "$rs") / $(absdiff "$(get "$h" v_n)" "$rv") |"
  done
  echo
fi

# ---- 3. Build scaling -------------------------------------------------------------------------
echo "## Build time (load -> compiled) against model size"
echo
echo "Target: linear in size, 100 000 components in under 1 s. Components as counted by the build"
echo "report; exponent = log(t2/t1)/log(n2/n1) against the previous row (1 = linear)."
echo
build_table() {  # build_table NAME MODEL SIZES...
  local name=$1 model=$2
  shift 2
  echo "| model | n | components | runs | load+build (s) | µs / component | exponent | slowest pass |"
  echo "|---|---:|---:|---:|---:|---:|---:|---|"
  local prev_c="" prev_t="" skip=""
  for n in "$@"; do
    local k f
    k=$(runs_for "$n")
    f=$OUT/build_${name}_$n.txt
    if [[ -n $skip ]]; then
      echo "| $name | $n | — | — | not run ($skip) | | | |"
      continue
    fi
    # Reuse the RC ladder's runs of section 1 (same model, same build).
    if [[ $name == rc && -n $(get "$OUT/rc_m_$n.txt" load_build_cpu_s) ]]; then
      cp "$OUT/rc_m_$n.txt" "$f"
    else
      local rc=0
      run_timed "$f" "$MB" --model "$model" -p n="$n" --repeat "$k" --build-only || rc=$?
      if ((rc == 124)); then
        echo "| $name | $n | — | — | > ${TIMEOUT} (timed out) | | | |"
        skip="n = $n timed out"
        continue
      fi
    fi
    local t c per ex slow
    t=$(get "$f" load_build_cpu_s)
    c=$(header "$f" components)
    per=$(awk -v t="$t" -v c="$c" 'BEGIN { printf "%.1f", 1e6 * t / c }')
    ex="—"
    [[ -n $prev_t ]] && ex=$(awk -v t1="$prev_t" -v t2="$t" -v c1="$prev_c" -v c2="$c" 'BEGIN { printf "%.2f", log(t2 / t1) / log(c2 / c1) }')
    slow=$(awk '/^median/ { best = ""; bv = -1; for (i = 2; i <= NF; i++) { p = index($i, "="); key = substr($i, 1, p - 1); v = substr($i, p + 1) + 0; if (key ~ /^pass_/ && v > bv) { bv = v; best = key } } sub(/^pass_/, "", best); sub(/_s$/, "", best); printf "%s %.3g s", best, bv }' "$f")
    echo "| $name | $n | $c | $k | $(fmt "$t") | $per | $ex | $slow |"
    prev_t=$t
    prev_c=$c
    LAST_BUILT[$name]=$f
  done
}
declare -A LAST_BUILT=()
build_table rc "$RC_MODEL" "${RC_SIZES[@]}"
echo
build_table chain "$CHAIN_MODEL" "${CHAIN_BUILD_SIZES[@]}"
echo
echo "Pass times (median, seconds) of the largest size built of each model:"
echo
for name in rc chain; do
  last=${LAST_BUILT[$name]:-}
  [[ -n $last ]] || continue
  echo "- $name n = $(basename "$last" .txt | sed 's/.*_//') (wall clock): load $(fmt "$(get "$last" load_s)"), $(awk '/^median/ { s = ""; for (i = 2; i <= NF; i++) { p = index($i, "="); key = substr($i, 1, p - 1); if (key ~ /^pass_/) { v = substr($i, p + 1); sub(/^pass_/, "", key); sub(/_s$/, "", key); s = s (s == "" ? "" : ", ") key " " sprintf("%.3g", v) } } print s }' "$last"); BuildModel wall $(fmt "$(get "$last" build_s)")"
done
echo
echo "Total run time of this script: $(($(date +%s) - START)) s; load average at the end: $(cut -d' ' -f1-3 /proc/loadavg). Raw outputs: $OUT"
