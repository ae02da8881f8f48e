#!/usr/bin/env bash
# momenta: install build dependencies and an optimised SUNDIALS.
#
# Idempotent, non-interactive, run as root (Debian 12). Steps:
#   1. install the Debian packages the project needs (apt-get update only if something is missing);
#   2. build SUNDIALS 6.4.1 from Debian's source package with -O2 (IDA, KINSOL, serial NVector,
#      dense/sparse matrices, dense/KLU linear solvers; static, PIC, 64-bit indices) into
#      ${MOMENTA_DEPS_DIR:-/opt/momenta-deps}/sundials-6.4.1, skipped when a stamp file says the
#      install there is complete. Debian's libsundials is built without optimisation, and IDA
#      runs 2-3x faster with an -O2 build.
#   2b. build yaml-cpp 0.7.0 from Debian's source package, static and position-independent, into
#      ${MOMENTA_DEPS_DIR:-/opt/momenta-deps}/yaml-cpp-0.7.0-pic (stamp as for SUNDIALS): the FMU
#      runtime (fmu/) links it into a self-contained shared object, and Debian's libyaml-cpp.a is
#      not position-independent. Without it `momenta fmu` is not built (a warning).
#   3. fetch uPlot (the report's plots) from the npm registry with `npm pack` at a pinned version,
#      check its SHA-256 and unpack its dist files into third_party/uplot/ (git-ignored); the
#      build inlines them into momenta's reports. Skipped when third_party/uplot/VERSION already
#      names the pinned version; a failure is a warning (reports then have no plots).
#   3b. fetch three.js (the report's 3-D scenes) the same way into third_party/three/: its UMD
#      build (build/three.min.js, the last release that ships one), which the page inlines.
# If step 2 fails, a warning is printed and the build uses Debian's libsundials-dev instead
# (cmake/Dependencies.cmake picks whichever is present); the script still exits 0.
#
# Environment:
#   MOMENTA_DEPS_DIR        install root (default /opt/momenta-deps)
#   MOMENTA_SKIP_SUNDIALS=1 do not build SUNDIALS (use Debian's)
#   MOMENTA_JOBS            parallel build jobs (default 2)
set -euo pipefail

export DEBIAN_FRONTEND=noninteractive
DEPS_DIR="${MOMENTA_DEPS_DIR:-/opt/momenta-deps}"
SUNDIALS_VERSION="6.4.1"
SUNDIALS_PREFIX="${DEPS_DIR}/sundials-${SUNDIALS_VERSION}"
STAMP="${SUNDIALS_PREFIX}/.momenta-sundials-stamp"
JOBS="${MOMENTA_JOBS:-2}"
# Bump this when the SUNDIALS configuration below changes: a prefix with an older stamp is rebuilt.
STAMP_CONTENT="sundials ${SUNDIALS_VERSION} momenta-config 1 (Release -O2, static+PIC, IDA KINSOL, KLU, index 64)"

now_ms() { echo $(( $(date +%s%N) / 1000000 )); }
# seconds since a now_ms reading, one decimal
since() { local d=$(( $(now_ms) - $1 )); printf '%d.%d s' $((d / 1000)) $((d % 1000 / 100)); }
log() { printf '[setup] %s\n' "$*"; }
warn() { printf '[setup] WARNING: %s\n' "$*" >&2; }
begin() { step_start=$(now_ms); log "== $* =="; }
end() { log "   done in $(since "$step_start")"; }
SCRIPT_START=$(now_ms)
step_start=$SCRIPT_START

if [[ $(id -u) -ne 0 ]]; then
  warn "not running as root: package installation and the install into ${DEPS_DIR} may fail"
fi

# ---------------------------------------------------------------------------------------------
# 1. Debian packages. SUNDIALS' source build needs cmake, a C compiler, SuiteSparse (KLU) and
#    dpkg-dev (for 'apt-get source'); the rest are the project's own build dependencies. clang
#    builds the fuzz target (scripts/fuzz.sh); its libFuzzer, ASan and UBSan runtimes are in
#    libclang-rt-14-dev, which clang only recommends (and --no-install-recommends skips). Ninja
#    keeps both cores busy where Make waits between targets (scripts/test.sh uses it if present).
#    Python's headers, pybind11, numpy and pytest build and test the Python module (python/).
# ---------------------------------------------------------------------------------------------
PACKAGES=(
  build-essential cmake ninja-build
  libsundials-dev libsuitesparse-dev
  libeigen3-dev libyaml-cpp-dev libyaml-dev libcli11-dev pkg-config
  libgtest-dev libbenchmark-dev
  libmatio-dev
  libopenmpi-dev openmpi-bin
  dpkg-dev
  clang libclang-rt-14-dev
  chromium gnuplot-nox libpng-dev
  python3-dev python3-pybind11 python3-numpy python3-pytest
  # `momenta fmu` packs FMUs with libzip; its tests unpack them and validate their description
  libzip-dev libxml2-utils unzip
)
# The report's uPlot comes from the npm registry: npm (Debian's, unless an npm is already there,
# as a Node.js distribution's own npm would conflict with Debian's package).
command -v npm >/dev/null 2>&1 || PACKAGES+=(npm)

is_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q 'install ok installed'; }

begin "Debian packages"
missing=()
for p in "${PACKAGES[@]}"; do
  is_installed "$p" || missing+=("$p")
done
if ((${#missing[@]})); then
  log "installing: ${missing[*]}"
  apt-get update -q || warn "apt-get update reported errors; trying the install anyway"
  apt-get install -y -q --no-install-recommends -o DPkg::Lock::Timeout=300 "${missing[@]}"
else
  log "all ${#PACKAGES[@]} packages already installed"
fi
end

# ---------------------------------------------------------------------------------------------
# 2. Optimised SUNDIALS from Debian's source package. Everything runs in a function whose
#    failure only produces a warning.
# ---------------------------------------------------------------------------------------------

# Make 'apt-get source' work: add deb-src entries mirroring the machine's deb entries if none exist.
ensure_deb_src() {
  if apt-cache showsrc sundials 2>/dev/null | grep -q '^Package: sundials'; then
    return 0
  fi
  local added=0
  local list=/etc/apt/sources.list.d/momenta-deb-src.sources
  if [[ -f /etc/apt/sources.list.d/debian.sources ]]; then
    # deb822 format (Debian 12 default): same stanzas, deb-src instead of deb.
    sed -E 's/^Types:.*$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources >"$list"
    added=1
  elif [[ -f /etc/apt/sources.list ]] && grep -qE '^deb ' /etc/apt/sources.list; then
    # one-line format
    list=/etc/apt/sources.list.d/momenta-deb-src.list
    sed -nE 's/^deb (.*)$/deb-src \1/p' /etc/apt/sources.list >"$list"
    added=1
  fi
  if ((added)); then
    log "added deb-src entries in $list"
  else
    # no known Debian source list: fall back to the default Debian 12 mirrors
    cat >"$list" <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    log "added default Debian 12 deb-src entries in $list"
  fi
  apt-get update -q || warn "apt-get update reported errors"
  apt-cache showsrc sundials 2>/dev/null | grep -q '^Package: sundials'
}

build_sundials() {
  local work src
  work=$(mktemp -d /tmp/momenta-sundials.XXXXXX)
  chmod 755 "$work"   # lets apt's _apt user write the download there (avoids a warning)
  # build_sundials runs in a subshell: clean the scratch directory when it exits
  # shellcheck disable=SC2064
  trap "rm -rf '$work'" EXIT

  # -- fetch and unpack the source (applies Debian's patches)
  begin "fetch SUNDIALS source (apt-get source sundials=${SUNDIALS_VERSION}*)"
  ensure_deb_src || { warn "no deb-src entry for sundials can be found"; return 1; }
  local srcver
  srcver=$(apt-cache showsrc sundials | awk '/^Version:/ {print $2}' | grep "^${SUNDIALS_VERSION}" | head -n1)
  [[ -n "$srcver" ]] || { warn "Debian offers no sundials ${SUNDIALS_VERSION} source package"; return 1; }
  (cd "$work" && apt-get source -q "sundials=${srcver}") >"$work/fetch.log" 2>&1 ||
    { tail -n 20 "$work/fetch.log" >&2; return 1; }
  src=$(find "$work" -maxdepth 1 -mindepth 1 -type d -name 'sundials-*' | head -n1)
  [[ -n "$src" && -f "$src/CMakeLists.txt" ]] || { warn "unpacked source not found in $work"; return 1; }
  log "source: $src (Debian version $srcver)"
  end

  # -- configure: only what momenta uses (KLU from Debian's SuiteSparse)
  begin "configure SUNDIALS"
  local multiarch
  multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)
  rm -rf "$SUNDIALS_PREFIX"
  cmake -S "$src" -B "$work/build" -G "Unix Makefiles" \
    -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DCMAKE_INSTALL_PREFIX="$SUNDIALS_PREFIX" \
    -DCMAKE_INSTALL_LIBDIR=lib \
    -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
    -DBUILD_SHARED_LIBS=OFF -DBUILD_STATIC_LIBS=ON \
    -DSUNDIALS_INDEX_SIZE=64 -DSUNDIALS_PRECISION=double \
    -DBUILD_IDA=ON -DBUILD_KINSOL=ON \
    -DBUILD_ARKODE=OFF -DBUILD_CVODE=OFF -DBUILD_CVODES=OFF -DBUILD_IDAS=OFF \
    -DBUILD_FORTRAN_MODULE_INTERFACE=OFF \
    -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF \
    -DBUILD_BENCHMARKS=OFF -DSUNDIALS_TEST_UNITTESTS=OFF \
    -DENABLE_MPI=OFF -DENABLE_OPENMP=OFF -DENABLE_PTHREAD=OFF \
    -DSUNDIALS_BUILD_WITH_MONITORING=OFF -DSUNDIALS_BUILD_WITH_PROFILING=OFF \
    -DSUNDIALS_LOGGING_LEVEL=0 \
    -DENABLE_KLU=ON \
    -DKLU_INCLUDE_DIR=/usr/include/suitesparse \
    -DKLU_LIBRARY_DIR="/usr/lib/${multiarch}" \
    >"$work/configure.log" 2>&1 || { tail -n 30 "$work/configure.log" >&2; return 1; }
  end

  # -- build and install
  begin "build SUNDIALS (-j${JOBS})"
  cmake --build "$work/build" -j "$JOBS" >"$work/build.log" 2>&1 ||
    { tail -n 30 "$work/build.log" >&2; return 1; }
  end
  begin "install SUNDIALS into $SUNDIALS_PREFIX"
  cmake --install "$work/build" >"$work/install.log" 2>&1 ||
    { tail -n 30 "$work/install.log" >&2; return 1; }
  # sanity check: the libraries and the CMake package config momenta links against
  local lib
  for lib in ida kinsol nvecserial sunmatrixdense sunmatrixsparse sunlinsoldense sunlinsolklu; do
    [[ -f "$SUNDIALS_PREFIX/lib/libsundials_${lib}.a" ]] || { warn "missing libsundials_${lib}.a"; return 1; }
  done
  [[ -f "$SUNDIALS_PREFIX/lib/cmake/sundials/SUNDIALSConfig.cmake" ]] ||
    { warn "missing SUNDIALSConfig.cmake"; return 1; }
  # the stamp is written last: its presence means the install is complete
  echo "$STAMP_CONTENT" >"$STAMP" || return 1
  end
}

if [[ "${MOMENTA_SKIP_SUNDIALS:-0}" == 1 ]]; then
  log "MOMENTA_SKIP_SUNDIALS=1: not building SUNDIALS; Debian's libsundials-dev will be used"
elif [[ -f "$STAMP" && "$(cat "$STAMP")" == "$STAMP_CONTENT" ]]; then
  log "optimised SUNDIALS ${SUNDIALS_VERSION} already installed in $SUNDIALS_PREFIX (stamp ok): skipping build"
else
  t0=$(now_ms)
  # (set -e does not apply inside an 'if': every step in build_sundials checks its own status)
  if (build_sundials); then
    log "optimised SUNDIALS ${SUNDIALS_VERSION} built and installed in $SUNDIALS_PREFIX ($(since "$t0") in all)"
  else
    rm -rf "$SUNDIALS_PREFIX"
    warn "building SUNDIALS ${SUNDIALS_VERSION} from source FAILED after $(since "$t0")."
    warn "Falling back to Debian's libsundials-dev (unoptimised, slower); the build still works."
  fi
fi

# ---------------------------------------------------------------------------------------------
# 2b. yaml-cpp, static and position-independent, for the FMU runtime (fmu/CMakeLists.txt).
# ---------------------------------------------------------------------------------------------
YAMLCPP_PREFIX="${DEPS_DIR}/yaml-cpp-0.7.0-pic"
YAMLCPP_STAMP="${YAMLCPP_PREFIX}/.momenta-yaml-cpp-stamp"
YAMLCPP_STAMP_CONTENT="yaml-cpp 0.7.0 momenta-config 1 (Release -O2, static+PIC)"

build_yamlcpp() {
  local work src
  work=$(mktemp -d /tmp/momenta-yaml-cpp.XXXXXX)
  chmod 755 "$work"
  # shellcheck disable=SC2064
  trap "rm -rf '$work'" EXIT
  ensure_deb_src || { warn "no deb-src entries"; return 1; }
  (cd "$work" && apt-get source -q yaml-cpp) >"$work/fetch.log" 2>&1 || { tail -n 20 "$work/fetch.log" >&2; return 1; }
  src=$(find "$work" -maxdepth 1 -mindepth 1 -type d -name 'yaml-cpp-*' | head -n1)
  [[ -n "$src" && -f "$src/CMakeLists.txt" ]] || { warn "unpacked yaml-cpp source not found in $work"; return 1; }
  rm -rf "$YAMLCPP_PREFIX"
  cmake -S "$src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
    -DCMAKE_POSITION_INDEPENDENT_CODE=ON -DYAML_BUILD_SHARED_LIBS=OFF -DYAML_CPP_BUILD_TESTS=OFF \
    -DYAML_CPP_BUILD_TOOLS=OFF -DYAML_CPP_BUILD_CONTRIB=OFF -DCMAKE_INSTALL_PREFIX="$YAMLCPP_PREFIX" \
    -DCMAKE_INSTALL_LIBDIR=lib >"$work/configure.log" 2>&1 || { tail -n 30 "$work/configure.log" >&2; return 1; }
  cmake --build "$work/build" -j "$JOBS" >"$work/build.log" 2>&1 || { tail -n 30 "$work/build.log" >&2; return 1; }
  cmake --install "$work/build" >"$work/install.log" 2>&1 || { tail -n 30 "$work/install.log" >&2; return 1; }
  [[ -f "$YAMLCPP_PREFIX/lib/libyaml-cpp.a" ]] || { warn "missing libyaml-cpp.a"; return 1; }
  echo "$YAMLCPP_STAMP_CONTENT" >"$YAMLCPP_STAMP"
}

if [[ -f "$YAMLCPP_STAMP" && "$(cat "$YAMLCPP_STAMP")" == "$YAMLCPP_STAMP_CONTENT" ]]; then
  log "position-independent yaml-cpp already installed in $YAMLCPP_PREFIX (stamp ok): skipping build"
else
  begin "yaml-cpp 0.7.0, static and position-independent, for the FMU runtime (apt-get source yaml-cpp)"
  if (build_yamlcpp); then
    log "yaml-cpp installed in $YAMLCPP_PREFIX"
  else
    rm -rf "$YAMLCPP_PREFIX"
    warn "building yaml-cpp FAILED: the build leaves out the FMU runtime (momenta fmu)"
  fi
  end
fi

# ---------------------------------------------------------------------------------------------
# 3. uPlot for the HTML report: npm pack at a pinned version, checked against its SHA-256.
# ---------------------------------------------------------------------------------------------
UPLOT_VERSION="1.6.32"
UPLOT_SHA256="4b8a8191e425658e3ea8c8c1314b0fc679c861ee3a1af2b20c7b16ba50b5133d"
REPO_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
UPLOT_DIR="${REPO_DIR}/third_party/uplot"

vendor_uplot() {
  local work tgz
  work=$(mktemp -d /tmp/momenta-uplot.XXXXXX)
  # shellcheck disable=SC2064
  trap "rm -rf '$work'" EXIT
  (cd "$work" && npm pack --silent "uplot@${UPLOT_VERSION}") >"$work/pack.log" 2>&1 ||
    { tail -n 20 "$work/pack.log" >&2; return 1; }
  tgz="$work/uplot-${UPLOT_VERSION}.tgz"
  [[ -f "$tgz" ]] || { warn "npm pack made no $tgz"; return 1; }
  echo "${UPLOT_SHA256}  ${tgz}" | sha256sum --check --quiet ||
    { warn "uplot-${UPLOT_VERSION}.tgz does not have the pinned SHA-256"; return 1; }
  tar -xzf "$tgz" -C "$work" package/dist/uPlot.iife.min.js package/dist/uPlot.min.css package/LICENSE ||
    return 1
  mkdir -p "$UPLOT_DIR"
  cp "$work/package/dist/uPlot.iife.min.js" "$work/package/dist/uPlot.min.css" "$work/package/LICENSE" "$UPLOT_DIR/"
  # VERSION last: its presence means the files are complete (the build reconfigures on it).
  echo "uplot ${UPLOT_VERSION} sha256 ${UPLOT_SHA256}" >"$UPLOT_DIR/VERSION"
}

begin "uPlot ${UPLOT_VERSION} for the HTML report (npm pack)"
if [[ -f "$UPLOT_DIR/VERSION" && "$(cat "$UPLOT_DIR/VERSION")" == "uplot ${UPLOT_VERSION} sha256 ${UPLOT_SHA256}" ]]; then
  log "already in $UPLOT_DIR"
elif ! command -v npm >/dev/null 2>&1; then
  warn "npm is missing: reports will have no plots (install npm, then rerun scripts/setup.sh)"
elif (vendor_uplot); then
  log "uPlot ${UPLOT_VERSION} in $UPLOT_DIR"
else
  warn "fetching uPlot ${UPLOT_VERSION} FAILED: reports will have no plots until scripts/setup.sh is rerun"
fi
end

# ---------------------------------------------------------------------------------------------
# 3b. three.js for the report's 3-D scenes: npm pack at a pinned version, checked the same way.
#     0.159.0 is the last release with a UMD build (one classic script defining THREE), which a
#     self-contained page can inline as it is.
# ---------------------------------------------------------------------------------------------
THREE_VERSION="0.159.0"
THREE_SHA256="9282f12c4fd79ea7d35325ca2a3c86451bbb5c0c64a7120dbd4707617c004fcd"
THREE_DIR="${REPO_DIR}/third_party/three"

vendor_three() {
  local work tgz
  work=$(mktemp -d /tmp/momenta-three.XXXXXX)
  # shellcheck disable=SC2064
  trap "rm -rf '$work'" EXIT
  (cd "$work" && npm pack --silent "three@${THREE_VERSION}") >"$work/pack.log" 2>&1 ||
    { tail -n 20 "$work/pack.log" >&2; return 1; }
  tgz="$work/three-${THREE_VERSION}.tgz"
  [[ -f "$tgz" ]] || { warn "npm pack made no $tgz"; return 1; }
  echo "${THREE_SHA256}  ${tgz}" | sha256sum --check --quiet ||
    { warn "three-${THREE_VERSION}.tgz does not have the pinned SHA-256"; return 1; }
  tar -xzf "$tgz" -C "$work" package/build/three.min.js package/LICENSE || return 1
  mkdir -p "$THREE_DIR"
  cp "$work/package/build/three.min.js" "$work/package/LICENSE" "$THREE_DIR/"
  # VERSION last: its presence means the files are complete (the build reconfigures on it).
  echo "three ${THREE_VERSION} sha256 ${THREE_SHA256}" >"$THREE_DIR/VERSION"
}

begin "three.js ${THREE_VERSION} for the report's 3-D scenes (npm pack)"
if [[ -f "$THREE_DIR/VERSION" && "$(cat "$THREE_DIR/VERSION")" == "three ${THREE_VERSION} sha256 ${THREE_SHA256}" ]]; then
  log "already in $THREE_DIR"
elif ! command -v npm >/dev/null 2>&1; then
  warn "npm is missing: reports will not draw 3-D scenes (install npm, then rerun scripts/setup.sh)"
elif (vendor_three); then
  log "three.js ${THREE_VERSION} in $THREE_DIR"
else
  warn "fetching three.js ${THREE_VERSION} FAILED: reports will not draw 3-D scenes until scripts/setup.sh is rerun"
fi
end

log "setup finished in $(since "$SCRIPT_START")"
