#!/usr/bin/env bash
# momenta: the project's test command (what CI runs after scripts/setup.sh).
#
#   1. Release build in build/ and its tests;
#   2. ASan + UBSan build (RelWithDebInfo, no benchmarks) in build-asan/ and its tests;
#   3. a minute of fuzzing model loading and building (scripts/fuzz.sh: clang, build-fuzz/).
# A build failure stops at once; a test failure or a fuzz finding is remembered, the next stage
# still runs, and the script exits non-zero at the end.
#
# Environment: MOMENTA_JOBS (default 2) parallel jobs; MOMENTA_SKIP_ASAN=1 skips stage 2;
# MOMENTA_SKIP_FUZZ=1 skips stage 3; MOMENTA_FUZZ_SECONDS (default 60) its fuzzing time.
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
  # Without MPI: OpenMPI's own allocations at exit would be LeakSanitizer reports; the MPI sweep
  # tests run in the Release stage, and here the test that mpirun without MPI is refused runs.
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOMENTA_SANITIZE=ON -DMOMENTA_BUILD_BENCH=OFF \
    -DMOMENTA_USE_MPI=OFF
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

# ---- 3. Fuzzing ------------------------------------------------------------------------------
if [[ "${MOMENTA_SKIP_FUZZ:-0}" == 1 ]]; then
  log "MOMENTA_SKIP_FUZZ=1: skipping the fuzz stage"
else
  begin "fuzz model loading and building (build-fuzz/, ${MOMENTA_FUZZ_SECONDS:-60} s)"
  fuzz_status=0
  MOMENTA_JOBS="$JOBS" bash scripts/fuzz.sh "${MOMENTA_FUZZ_SECONDS:-60}" || fuzz_status=$?
  if ((fuzz_status == 0)); then
    end "nothing found"
  elif ((fuzz_status == 1)); then
    end "FOUND inputs that crash, hang or exhaust memory"
    failed+=("fuzzing")
  else
    end "FAILED to build or run"
    failed+=("fuzz build")
  fi
fi

# ---- summary --------------------------------------------------------------------------------
if ((${#failed[@]})); then
  log "FAILED: $(printf '%s; ' "${failed[@]}")"
  exit 1
fi
log "all test stages passed"
