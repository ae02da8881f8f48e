#!/usr/bin/env bash
# Native model code against the interpreter and the hand-written IDA programs: the spring-damper
# chain and the RC ladder, the same options as bench/run.sh. Per size: one run compiling into an
# empty cache (code_compile_s), then K runs each of native (from the cache), interpreted and
# hand-written; medians of CPU times. Prints a Markdown table; raw outputs go to $BENCH_OUT.
# The last two columns (chain only): the hand-written program reading each spring-damper's and
# mass's parameters from arrays (`--params arrays`), as momenta's code must (parameters are data),
# its residual and simulate CPU time, and native's ratios to it.
#
# usage: bench/codegen.sh [CASE...]   CASE = chain:N or rc:N (default chain:1000 chain:10000 rc:10000 rc:100000)
# environment: MOMENTA_BUILD_DIR (default <repo>/build), BENCH_OUT, BENCH_REPEAT (default 3)
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$HERE/.." && pwd)
BUILD=${MOMENTA_BUILD_DIR:-$REPO/build}
OUT=${BENCH_OUT:-$(mktemp -d /tmp/momenta-codegen-bench.XXXXXX)}
K=${BENCH_REPEAT:-3}
mkdir -p "$OUT"
MB=$BUILD/bench/momenta_bench
CASES=("$@")
((${#CASES[@]})) || CASES=(chain:1000 chain:10000 rc:10000 rc:100000)

get() { awk -v k="$2" '/^median/ { for (i = 2; i <= NF; i++) { p = index($i, "="); if (substr($i, 1, p - 1) == k) print substr($i, p + 1) } }' "$1"; }
run1() { awk -v k="$2" '/^run=1 / { for (i = 2; i <= NF; i++) { p = index($i, "="); if (substr($i, 1, p - 1) == k) print substr($i, p + 1) } }' "$1"; }
fmt() { if [[ -z ${1:-} ]]; then echo "—"; else awk -v x="$1" 'BEGIN { printf "%.3g", x }'; fi; }
ratio() { if [[ -z ${1:-} || -z ${2:-} ]]; then echo "—"; else awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "—" }'; fi; }
sum() { awk -v a="${1:-0}" -v b="${2:-0}" 'BEGIN { printf "%.6f", a + b }'; }

echo "| model | n | native instr | compile s | cache hit ms | residual ns interp / native / hand | ratio native / hand | simulate CPU s interp / native / hand | ratio native / hand | steps momenta / hand | hand, params from arrays: residual ns / simulate CPU s | native / it: residual, simulate |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for c in "${CASES[@]}"; do
  kind=${c%%:*}
  n=${c#*:}
  if [[ $kind == chain ]]; then
    model=$REPO/models/spring_damper_chain.yaml
    opts=(--stop 10 --interval 0.1 --rtol 1e-6 --atol 1e-6 --linear-solver klu --unit-nominals)
    hand=("$BUILD/bench/handwritten_chain" --n "$n" --stop 10 --interval 0.1 --rtol 1e-6 --atol 1e-6 --linear-solver klu)
  else
    model=$REPO/models/rc_ladder.yaml
    opts=()
    hand=("$BUILD/bench/handwritten_rc" --n "$n" --stop 10 --interval 0.01 --rtol 1e-6 --atol 1e-6 --linear-solver klu)
  fi
  cache=$OUT/cache-$kind-$n
  rm -rf "$cache"
  MOMENTA_CACHE_DIR=$cache "$MB" --model "$model" -p n="$n" "${opts[@]}" --codegen native --repeat 1 --build-only >"$OUT/${c/:/_}_compile.txt"
  MOMENTA_CACHE_DIR=$cache "$MB" --model "$model" -p n="$n" "${opts[@]}" --codegen native --repeat "$K" --build-repeat 1 >"$OUT/${c/:/_}_native.txt"
  "$MB" --model "$model" -p n="$n" "${opts[@]}" --codegen interp --repeat "$K" --build-repeat 1 >"$OUT/${c/:/_}_interp.txt"
  "${hand[@]}" --repeat "$K" >"$OUT/${c/:/_}_hand.txt"
  f=$OUT/${c/:/_}
  arrays="— | —"
  if [[ $kind == chain ]]; then
    "${hand[@]}" --params arrays --repeat "$K" >"${f}_hand_arrays.txt"
    ares=$(awk -F= '/^res_eval_ns=/ { print $2 }' "${f}_hand_arrays.txt")
    acpu=$(sum "$(get "${f}_hand_arrays.txt" setup_cpu_s)" "$(get "${f}_hand_arrays.txt" solve_cpu_s)")
    arrays="$(fmt "$ares") / $(fmt "$acpu") | $(ratio "$(get "${f}_native.txt" res_eval_ns)" "$ares"), $(ratio "$(get "${f}_native.txt" simulate_cpu_s)" "$acpu")"
  fi
  hres=$(awk -F= '/^res_eval_ns=/ { print $2 }' "${f}_hand.txt")
  hcpu=$(sum "$(get "${f}_hand.txt" setup_cpu_s)" "$(get "${f}_hand.txt" solve_cpu_s)")
  echo "| $kind | $n | $(run1 "${f}_compile.txt" code_instr) | $(fmt "$(run1 "${f}_compile.txt" code_compile_s)") |" \
    "$(fmt "$(awk -v x="$(run1 "${f}_native.txt" code_s)" 'BEGIN { print 1e3 * x }')") |" \
    "$(fmt "$(get "${f}_interp.txt" res_eval_ns)") / $(fmt "$(get "${f}_native.txt" res_eval_ns)") / $(fmt "$hres") |" \
    "$(ratio "$(get "${f}_native.txt" res_eval_ns)" "$hres") |" \
    "$(fmt "$(get "${f}_interp.txt" simulate_cpu_s)") / $(fmt "$(get "${f}_native.txt" simulate_cpu_s)") / $(fmt "$hcpu") |" \
    "$(ratio "$(get "${f}_native.txt" simulate_cpu_s)" "$hcpu") |" \
    "$(get "${f}_native.txt" steps) / $(get "${f}_hand.txt" steps) | $arrays |"
done
echo
echo "raw outputs: $OUT"
