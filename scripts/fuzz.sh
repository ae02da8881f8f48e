#!/usr/bin/env bash
# momenta: fuzz model loading and building with libFuzzer (fuzz/fuzz_model.cc).
#
#   bash scripts/fuzz.sh [SECONDS]        (default 60)
#
# Builds the fuzz target with clang in build-fuzz/ (MOMENTA_BUILD_FUZZ=ON: ASan, UBSan with
# float-cast-overflow, libFuzzer coverage), seeds it with every model in models/ (recursively),
# the reliability reproducers in tests/data/reliability/ and the dictionary fuzz/momenta.dict,
# and runs it for SECONDS in fork mode, one process per core (2 by default), continuing after
# each finding. A finding is a crash or sanitizer report, an input that takes more than 10 s
# (-timeout=10), or one that needs more than 2 GiB (-rss_limit_mb=2048); each is written to a
# fresh directory build-fuzz/findings-<time>/ (crash-*, timeout-*, oom-*, leak-*), reproducible
# with: build-fuzz/fuzz/momenta_fuzz_model FILE. Prints the number of executions; exits 1 if
# anything was found, 2 if the target could not be built or run.
#
# Environment: MOMENTA_FUZZ_DIR (build-fuzz) build directory; MOMENTA_FUZZ_WORKERS (2) fuzzing
# processes; MOMENTA_JOBS (2) build jobs; MOMENTA_MEMORY_MB (64, set by the target) the memory
# budget that model sizes are checked against.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
SECONDS_TO_RUN="${1:-60}"
DIR="${MOMENTA_FUZZ_DIR:-build-fuzz}"
WORKERS="${MOMENTA_FUZZ_WORKERS:-2}"
JOBS="${MOMENTA_JOBS:-2}"
log() { printf '[fuzz] %s\n' "$*"; }

if ! [[ "$SECONDS_TO_RUN" =~ ^[0-9]+$ ]] || ((SECONDS_TO_RUN < 1)); then
  log "usage: scripts/fuzz.sh [SECONDS] (a whole number of seconds, default 60)"
  exit 2
fi
if ! command -v clang++ >/dev/null || ! command -v clang >/dev/null; then
  log "clang and clang++ are needed (Debian: apt-get install clang libclang-rt-14-dev; scripts/setup.sh installs them)"
  exit 2
fi

# ---- build ------------------------------------------------------------------------------------
log "building the fuzz target in $DIR/"
# Ninja, when installed, for a directory not configured yet (an existing one keeps its generator).
gen=()
if [[ ! -f "$DIR/CMakeCache.txt" ]] && command -v ninja >/dev/null; then gen=(-G Ninja); fi
mkdir -p "$DIR"
# -O1 with line tables: quicker to build than -O2 -g, and every report still names file:line.
CC=clang CXX=clang++ cmake -S . -B "$DIR" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOMENTA_BUILD_FUZZ=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DMOMENTA_BUILD_TESTS=OFF -DMOMENTA_BUILD_BENCH=OFF >"$DIR/configure.log" 2>&1 ||
  { tail -n 30 "$DIR/configure.log"; log "configure failed"; exit 2; }
cmake --build "$DIR" --target momenta_fuzz_model -j "$JOBS" >"$DIR/build.log" 2>&1 ||
  { tail -n 40 "$DIR/build.log"; log "build failed"; exit 2; }
TARGET="$DIR/fuzz/momenta_fuzz_model"

# ---- run --------------------------------------------------------------------------------------
# The first corpus directory collects what libFuzzer finds (kept between runs); the seeds are
# read only.
CORPUS="$DIR/corpus"
FINDINGS="$DIR/findings-$(date +%Y%m%d-%H%M%S)"
mkdir -p "$CORPUS" "$FINDINGS"
LOG="$FINDINGS/fuzz.log"
log "fuzzing for ${SECONDS_TO_RUN} s with $WORKERS processes; findings go to $FINDINGS/"
status=0
UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}" \
  "$TARGET" -fork="$WORKERS" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
  -max_total_time="$SECONDS_TO_RUN" -timeout=10 -rss_limit_mb=2048 -max_len=16384 \
  -dict=fuzz/momenta.dict -artifact_prefix="$FINDINGS/" -print_final_stats=1 \
  "$CORPUS" models tests/data/reliability >"$LOG" 2>&1 || status=$?

# ---- report -----------------------------------------------------------------------------------
execs=$(grep -oE '^#[0-9]+' "$LOG" | tail -n 1 | tr -d '#' || true)
mapfile -t found < <(find "$FINDINGS" -maxdepth 1 -type f \
  \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' -o -name 'leak-*' -o -name 'slow-unit-*' \) | sort)
log "${execs:-0} executions in ${SECONDS_TO_RUN} s; corpus: $(find "$CORPUS" -type f | wc -l) inputs"
if ((${#found[@]})); then
  log "FOUND ${#found[@]}:"
  printf '  %s\n' "${found[@]}"
  log "reproduce with: $TARGET FILE   (log: $LOG)"
  exit 1
fi
if [[ -z "$execs" ]]; then
  tail -n 30 "$LOG"
  log "libFuzzer did not run (exit $status); log: $LOG"
  exit 2
fi
log "nothing found"
