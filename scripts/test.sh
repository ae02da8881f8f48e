#!/usr/bin/env bash
# momenta: the project's test command (what CI runs after scripts/setup.sh).
#
#   1. Release build in build/ and its tests, and the Python module's (pytest, python/tests);
#   2. ASan + UBSan build (-O1 with line tables, no benchmarks) in build-asan/ and its tests;
#   3. a minute of fuzzing model loading and building (scripts/fuzz.sh: clang, build-fuzz/).
# A build failure stops at once; a test failure or a fuzz finding is remembered, the next stage
# still runs, and the script exits non-zero at the end.
#
# Builds use Ninja when it is installed (a fresh build directory only: an existing one keeps its
# generator): it compiles the tests while the libraries and the momenta binary are still being
# finished, where Make leaves one of two cores idle. Both builds precompile the tests' common
# headers (MOMENTA_TESTS_PCH). The sanitizer build is -O1 with line tables only (-g1), as the fuzz
# build, and the test sources themselves -O0: every report still names file:line. Its tests run
# as 8 GoogleTest shards per job (MOMENTA_TESTS_SHARDS) rather than a process per test, as an
# instrumented process takes half a second to start: every test still runs under ASan, UBSan and
# LeakSanitizer, and a failing shard's output names the failing tests (run one alone with
# build-asan/tests/momenta_tests --gtest_filter=NAME). Rehearsed on the shared 2-core machine:
# 20 min in all (Release 453 + 100 s, sanitizer 360 + 100 s, fuzzing 171 s), where the sanitizer
# stage alone had taken 2139 + 790 s under similar load (951 + 252 s on idle cores).
#
# Environment: MOMENTA_JOBS (default 2) parallel jobs; MOMENTA_SKIP_ASAN=1 skips stage 2;
# MOMENTA_SKIP_FUZZ=1 skips stage 3; MOMENTA_FUZZ_SECONDS (default 60) its fuzzing time.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
JOBS="${MOMENTA_JOBS:-2}"
failed=()

# "-G Ninja" for a build directory not configured yet, when ninja is installed.
generator() {
  if [[ ! -f "$1/CMakeCache.txt" ]] && command -v ninja >/dev/null; then
    printf '%s\n' -G Ninja
  fi
}

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
mapfile -t gen < <(generator build)
cmake -S . -B build "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DMOMENTA_TESTS_PCH=ON
cmake --build build -j "$JOBS"
end "built"

begin "ctest Release"
if ctest --test-dir build --output-on-failure --no-tests=error -j "$JOBS"; then
  end "passed"
else
  end "FAILED"
  failed+=("Release tests")
fi

# The Python module's tests (python/tests) with the python it was built for; skipped, saying so,
# only when the build left the module out (no pybind11: build/python/interpreter.txt is absent).
if [[ -f build/python/interpreter.txt ]]; then
  begin "pytest Release (python/tests, PYTHONPATH=build/python)"
  if PYTHONPATH=build/python PYTHONDONTWRITEBYTECODE=1 "$(cat build/python/interpreter.txt)" -m pytest -q \
       -p no:cacheprovider python/tests; then
    end "passed"
  else
    end "FAILED"
    failed+=("Python tests")
  fi
else
  log "the Python module was not built (pybind11 or Python's headers not found): skipping python/tests"
fi

# ---- 2. Sanitizer build and tests -----------------------------------------------------------
if [[ "${MOMENTA_SKIP_ASAN:-0}" == 1 ]]; then
  log "MOMENTA_SKIP_ASAN=1: skipping the sanitizer build"
else
  begin "configure + build ASan/UBSan (build-asan/)"
  # Without MPI: OpenMPI's own allocations at exit would be LeakSanitizer reports; the MPI sweep
  # tests run in the Release stage, and here the test that mpirun without MPI is refused runs.
  # -g1 is GCC's line-tables-only level (clang's -gline-tables-only).
  mapfile -t gen < <(generator build-asan)
  cmake -S . -B build-asan "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOMENTA_SANITIZE=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DMOMENTA_TESTS_PCH=ON -DMOMENTA_TESTS_COMPILE_OPTIONS=-O0 -DMOMENTA_TESTS_SHARDS=$((8 * JOBS)) \
    -DMOMENTA_BUILD_BENCH=OFF -DMOMENTA_USE_MPI=OFF
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
