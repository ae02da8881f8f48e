#!/usr/bin/env bash
# momenta: the project's test command (what CI runs after scripts/setup.sh).
#
#   1. Release build in build/ and its tests;
#   2. ASan + UBSan build (RelWithDebInfo, no benchmarks) in build-asan/ and its tests.
# A build failure stops at once; a test failure is remembered, the next stage still runs, and
# the script exits non-zero at the end.
#
# Environment: MOMENTA_JOBS (default 2) parallel jobs; MOMENTA_SKIP_ASAN=1 skips stage 2.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
JOBS="${MOMENTA_JOBS:-2}"
failed=()

stage_start=0
log() { printf '[test] %s\n' "$*"; }
begin() { stage_start=$(date +%s); log "== $* =="; }
end() { log "   $1 in $(( $(date +%s) - stage_start )) s"; }

if [[ ! -f CMakeLists.txt ]]; then
  log "no top-level CMakeLists.txt in $(pwd)"
  exit 1
fi

# ---- 1. Release build and tests -------------------------------------------------------------
begin "configure + build Release (build/)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$JOBS"
end "built"

begin "ctest Release"
if ctest --test-dir build --output-on-failure --no-tests=error -j "$JOBS"; then
  end "passed"
else
  end "FAILED"
  failed+=("Release tests")
fi

# ---- 2. Sanitizer build and tests -----------------------------------------------------------
if [[ "${MOMENTA_SKIP_ASAN:-0}" == 1 ]]; then
  log "MOMENTA_SKIP_ASAN=1: skipping the sanitizer build"
else
  begin "configure + build ASan/UBSan (build-asan/)"
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOMENTA_SANITIZE=ON -DMOMENTA_BUILD_BENCH=OFF
  cmake --build build-asan -j "$JOBS"
  end "built"

  begin "ctest ASan/UBSan"
  if ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" \
     UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}" \
     ctest --test-dir build-asan --output-on-failure --no-tests=error -j "$JOBS"; then
    end "passed"
  else
    end "FAILED"
    failed+=("ASan/UBSan tests")
  fi
fi

# ---- summary --------------------------------------------------------------------------------
if ((${#failed[@]})); then
  log "FAILED: $(printf '%s; ' "${failed[@]}")"
  exit 1
fi
log "all test stages passed"
