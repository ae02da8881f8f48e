#!/usr/bin/env bash
# Same behaviour as commit BASE: the oracle for changes that must not change what momenta computes
# (a move, a split, a rename, a cheaper pass).
#
#   scripts/same-behaviour.sh [--programs] [BASE] [MOMENTA]
#
# BASE (a commit, default HEAD) is built into build-same/<sha>/ (once;
# later calls reuse it), MOMENTA (default build/app/momenta) is the binary under test. For every
# model under models/ both binaries are run the same way and these must be identical:
#   results   `simulate --codegen interp`: the CSV and its units file, byte for byte, and the
#             exit code;
#   native    `simulate --codegen native`: the CSV byte for byte (native code is the interpreter's
#             to the bit), and the key of the compiled object, a hash of every program's
#             instructions and the register layout: equal keys mean identical programs;
#   check     `check -v`: the structure each pass made (its counts, what was removed, states,
#             index), with the times and memory figures masked.
# With --programs only what the build makes is compared, not what a run computes: `check -v` (the
# structure, and every equation handed to IDA as text, in the order of its row: the programs'
# source) and the key of the compiled object (its programs' instructions), from a native build
# whose run stops at once (--stop 1e-9; its exit code is not compared). A few seconds a model
# instead of two runs each: the guard for steps that must not change programs (a faster pass, a new
# order of making nodes), and the first thing to look at when results differ.
# Prints one line per model and a summary `N passed, N failed`; exits 1 on any difference, with
# the first lines of each diff and, where results differ, how far they moved in the model's
# integration tolerance (scripts/result-difference.py). Records are kept in build-same/<sha>/record
# (programs) and build-same/current(-programs)/ for a closer look.
#
# Environment: MOMENTA_JOBS (default 2) for the base build; SAME_MODELS to restrict the models
# (a glob under models/, e.g. 'models/msl/*.yaml').
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
ROOT=$(pwd)
JOBS="${MOMENTA_JOBS:-2}"
PROGRAMS_ONLY=0
if [[ "${1:-}" == "--programs" ]]; then
  PROGRAMS_ONLY=1
  shift
fi
BASE_REV="${1:-HEAD}"
MOMENTA="${2:-build/app/momenta}"
BASE_SHA=$(git rev-parse --verify "$BASE_REV^{commit}")
CACHE="$ROOT/build-same"
BASE_DIR="$CACHE/$BASE_SHA"

[[ -x "$MOMENTA" ]] || { echo "same-behaviour: no binary $MOMENTA (build first)" >&2; exit 2; }
MOMENTA=$(realpath "$MOMENTA")

# ---- the base binary, built once per commit ----------------------------------------------------
if [[ ! -x "$BASE_DIR/build/app/momenta" ]]; then
  echo "same-behaviour: building $BASE_SHA into $BASE_DIR/build"
  rm -rf "$BASE_DIR/src"
  mkdir -p "$BASE_DIR/src"
  git archive "$BASE_SHA" | tar -x -C "$BASE_DIR/src"
  # Third-party browser files are fetched at set-up, not committed: the page is not compared here.
  [[ -d third_party ]] && cp -r third_party "$BASE_DIR/src/"
  gen=()
  command -v ninja >/dev/null && gen=(-G Ninja)
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$BASE_DIR/src" -B "$BASE_DIR/build" "${gen[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DMOMENTA_BUILD_TESTS=OFF -DMOMENTA_BUILD_BENCH=OFF >"$BASE_DIR/configure.log" 2>&1 ||
    { cat "$BASE_DIR/configure.log"; exit 2; }
  cmake --build "$BASE_DIR/build" -j "$JOBS" --target momenta >"$BASE_DIR/build.log" 2>&1 ||
    { tail -40 "$BASE_DIR/build.log"; exit 2; }
fi

# ---- one record: every model's results, program key and structure -----------------------------
# Times and memory in `check -v` differ from run to run: mask every number followed by a unit of
# time or memory, and squeeze the spaces that align the table's columns around them. The line of
# the peak memory is left out (a binary before it printed none).
mask_figures() {
  grep -v '^  peak memory ' |
  sed -E 's/[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)? ?(s|ms|us|µs|ns|MB|KB|kB|GB|B|MiB|KiB|GiB)\b/<fig>/g' |
    tr -s ' '
}

record_runs() {  # BINARY MODEL OUTDIR: the runs, interpreted and native (its cache left in OUTDIR)
  local bin=$1 model=$2 out=$3 code
  code=0
  "$bin" simulate "$ROOT/$model" --codegen interp -q -o "$out/interp.csv" \
    >/dev/null 2>"$out/interp.err" || code=$?
  echo "$code" >"$out/interp.code"
  code=0
  MOMENTA_CACHE_DIR="$out/cache" "$bin" simulate "$ROOT/$model" --codegen native -q \
    -o "$out/native.csv" >/dev/null 2>"$out/native.err" || code=$?
  echo "$code" >"$out/native.code"
}

record() {  # BINARY OUTDIR
  local bin=$1 out=$2 model name code
  rm -rf "$out"
  mkdir -p "$out"
  for model in ${SAME_MODELS:-$(cd "$ROOT" && find models -name '*.yaml' | sort)}; do
    name=${model#models/}
    name=${name%.yaml}
    name=${name//\//_}
    mkdir -p "$out/$name"
    if ((PROGRAMS_ONLY)); then
      # Only the compiled object's key is kept of this run.
      MOMENTA_CACHE_DIR="$out/$name/cache" "$bin" simulate "$ROOT/$model" --codegen native -q --stop 1e-9 \
        -o "$out/$name/native.csv" >/dev/null 2>&1 || true
      rm -f "$out/$name/native.csv"
    else
      record_runs "$bin" "$model" "$out/$name"
    fi
    # The key of each compiled object (its file name in the cache; not the digest beside it), then
    # the objects go.
    (cd "$out/$name/cache" 2>/dev/null && find . -type f -name '*.so' | sed 's|^\./||' | sort) \
      >"$out/$name/native.keys" || true
    rm -rf "$out/$name/cache"
    code=0
    "$bin" check "$ROOT/$model" -v 2>&1 | mask_figures >"$out/$name/check.txt" || code=$?
    echo "$code" >"$out/$name/check.code"
  done
}

# A record of programs only is kept apart from a full one.
KIND=record
((PROGRAMS_ONLY)) && KIND=programs
echo "same-behaviour: recording the base ($BASE_SHA)"
if [[ ! -f "$BASE_DIR/$KIND.done" || "${SAME_MODELS:-}" != "" ]]; then
  record "$BASE_DIR/build/app/momenta" "$BASE_DIR/$KIND"
  [[ -z "${SAME_MODELS:-}" ]] && touch "$BASE_DIR/$KIND.done"
fi
echo "same-behaviour: recording $MOMENTA"
CURRENT="$CACHE/current"
((PROGRAMS_ONLY)) && CURRENT="$CACHE/current-programs"
record "$MOMENTA" "$CURRENT"

# ---- compare ------------------------------------------------------------------------------------
passed=0
failed=0
what=results
((PROGRAMS_ONLY)) && what=programs
for dir in "$CURRENT"/*/; do
  name=$(basename "$dir")
  if diff -r "$BASE_DIR/$KIND/$name" "$CURRENT/$name" >"$CACHE/diff.txt" 2>&1; then
    keys=$(wc -l <"$CURRENT/$name/native.keys")
    printf 'same  %-44s %s, %s program key(s), check\n' "$name" "$what" "$keys"
    passed=$((passed + 1))
  else
    printf 'DIFF  %s\n' "$name"
    head -20 "$CACHE/diff.txt" | sed 's/^/      /'
    # How far the results moved, in the model's integration tolerance.
    if ((!PROGRAMS_ONLY)) && [[ -s "$BASE_DIR/$KIND/$name/interp.csv" && -s "$CURRENT/$name/interp.csv" ]] &&
      ! cmp -s "$BASE_DIR/$KIND/$name/interp.csv" "$CURRENT/$name/interp.csv"; then
      model=$(cd "$ROOT" && find models -name '*.yaml' | sort | while read -r m; do
        n=${m#models/}; n=${n%.yaml}; if [[ "${n//\//_}" == "$name" ]]; then echo "$m"; fi; done)
      printf '      results: '
      python3 scripts/result-difference.py "$BASE_DIR/$KIND/$name/interp.csv" "$CURRENT/$name/interp.csv" \
        ${model:+"$ROOT/$model"} || true
    fi
    failed=$((failed + 1))
  fi
done
echo "$passed passed, $failed failed"
((failed == 0))
