#!/usr/bin/env bash
# momenta: fuzz model loading and building, and result-file reading, with libFuzzer.
#
#   bash scripts/fuzz.sh [SECONDS]        (default 60)
#
# Builds the two fuzz targets with clang in build-fuzz/ (MOMENTA_BUILD_FUZZ=ON: ASan, UBSan with
# float-cast-overflow, libFuzzer coverage) and runs them one after the other, SECONDS in all:
# two thirds for fuzz/fuzz_model.cc (any bytes as a model file, loaded and built; seeded with
# every model in models/ (recursively), the reliability reproducers in tests/data/reliability/
# and the dictionary fuzz/momenta.dict), one third for fuzz/fuzz_result.cc (any bytes as a result
# file, CSV or MAT, read as report and plot read it; seeded with fuzz/seeds/results/ and the
# reproducers, dictionary fuzz/result.dict). Each runs in fork mode, one process per core (2 by
# default), continuing after each finding. A finding is a crash or sanitizer report, an input
# that takes more than 10 s (-timeout=10), or one that needs more than 2 GiB (-rss_limit_mb=2048);
# each is written to a fresh directory build-fuzz/findings-<time>/<target>/ (crash-*, timeout-*,
# oom-*, leak-*), reproducible with: build-fuzz/fuzz/momenta_fuzz_<target> FILE. Prints the
# number of executions of each; exits 1 if anything was found, 2 if a target could not be built
# or run.
#
# Environment: MOMENTA_FUZZ_DIR (build-fuzz) build directory; MOMENTA_FUZZ_WORKERS (2) fuzzing
# processes; MOMENTA_JOBS (2) build jobs; MOMENTA_MEMORY_MB (64, set by the targets) the memory
# budget that model sizes and result files are checked against.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
SECONDS_TO_RUN="${1:-60}"
DIR="${MOMENTA_FUZZ_DIR:-build-fuzz}"
WORKERS="${MOMENTA_FUZZ_WORKERS:-2}"
JOBS="${MOMENTA_JOBS:-2}"
log() { printf '[fuzz] %s\n' "$*"; }

if ! [[ "$SECONDS_TO_RUN" =~ ^[0-9]+$ ]] || ((SECONDS_TO_RUN < 2)); then
  log "usage: scripts/fuzz.sh [SECONDS] (a whole number of seconds, at least 2; default 60)"
  exit 2
fi
if ! command -v clang++ >/dev/null || ! command -v clang >/dev/null; then
  log "clang and clang++ are needed (Debian: apt-get install clang libclang-rt-14-dev; scripts/setup.sh installs them)"
  exit 2
fi

# ---- build ------------------------------------------------------------------------------------
log "building the fuzz targets in $DIR/"
# Ninja, when installed, for a directory not configured yet (an existing one keeps its generator).
gen=()
if [[ ! -f "$DIR/CMakeCache.txt" ]] && command -v ninja >/dev/null; then gen=(-G Ninja); fi
mkdir -p "$DIR"
# -O1 with line tables: quicker to build than -O2 -g, and every report still names file:line.
CC=clang CXX=clang++ cmake -S . -B "$DIR" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOMENTA_BUILD_FUZZ=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DMOMENTA_BUILD_TESTS=OFF -DMOMENTA_BUILD_BENCH=OFF >"$DIR/configure.log" 2>&1 ||
  { tail -n 30 "$DIR/configure.log"; log "configure failed"; exit 2; }
cmake --build "$DIR" --target momenta_fuzz_model momenta_fuzz_result momenta_mat_plugin -j "$JOBS" >"$DIR/build.log" 2>&1 ||
  { tail -n 40 "$DIR/build.log"; log "build failed"; exit 2; }

# ---- run --------------------------------------------------------------------------------------
# Each target's first corpus directory collects what libFuzzer finds (kept between runs); the
# seeds are read only.
FINDINGS="$DIR/findings-$(date +%Y%m%d-%H%M%S)"
found_any=0
run_target() {  # NAME SECONDS DICT SEED_DIR...
  local name=$1 seconds=$2 dict=$3
  shift 3
  local target="$DIR/fuzz/momenta_fuzz_$name" corpus="$DIR/corpus-$name" findings="$FINDINGS/$name"
  # The model target's corpus kept its old name.
  [[ $name == model ]] && corpus="$DIR/corpus"
  mkdir -p "$corpus" "$findings"
  local log_file="$findings/fuzz.log" status=0
  log "$name: fuzzing for ${seconds} s with $WORKERS processes; findings go to $findings/"
  UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}" \
    "$target" -fork="$WORKERS" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
    -dict="$dict" -artifact_prefix="$findings/" -print_final_stats=1 \
    "$corpus" "$@" >"$log_file" 2>&1 || status=$?
  local execs found
  execs=$(grep -oE '^#[0-9]+' "$log_file" | tail -n 1 | tr -d '#' || true)
  mapfile -t found < <(find "$findings" -maxdepth 1 -type f \
    \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'leak-*' -o -name 'slow-unit-*' \) | sort)
  log "$name: ${execs:-0} executions in ${seconds} s; corpus: $(find "$corpus" -type f | wc -l) inputs"
  if ((${#found[@]})); then
    log "$name: FOUND ${#found[@]}:"
    printf '  %s\n' "${found[@]}"
    log "reproduce with: $target FILE   (log: $log_file)"
    # What a clean clone's log must show: the input (base64) and the report of the first finding,
    # since build-fuzz/ does not outlive a CI machine.
    log "first finding, base64: $(base64 -w0 "${found[0]}" | head -c 4000)"
    UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}" timeout 60 "$target" "${found[0]}" 2>&1 |
      grep -v '^INFO:' | head -n 40 | sed 's/^/  | /' || true
    found_any=1
  elif [[ -z "$execs" ]]; then
    tail -n 30 "$log_file"
    log "$name: libFuzzer did not run (exit $status); log: $log_file"
    exit 2
  fi
}
# The split of the time: models are the larger input language (types, units, expressions, passes).
MODEL_SECONDS=$((SECONDS_TO_RUN * 2 / 3))
run_target model "$MODEL_SECONDS" fuzz/momenta.dict models tests/data/reliability
run_target result $((SECONDS_TO_RUN - MODEL_SECONDS)) fuzz/result.dict fuzz/seeds/results tests/data/reliability

# ---- report -----------------------------------------------------------------------------------
if ((found_any)); then exit 1; fi
log "nothing found"
