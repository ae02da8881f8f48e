# momenta: third-party dependencies.
#
# Included by the top-level CMakeLists.txt after project(). Defines INTERFACE targets so the rest
# of the build does not care where a dependency came from:
#   momenta_sundials  SUNDIALS 6.4.x: IDA, KINSOL, serial NVector, dense + sparse SUNMatrix,
#                     dense + KLU SUNLinearSolver (and KLU). Compile definition
#                     MOMENTA_SUNDIALS_OPTIMIZED=1 (our -O2 build) or =0 (Debian's).
#   momenta_yaml      yaml-cpp, and libyaml (Debian's libyaml-dev, via pkg-config): the faster
#                     reader of large model files (core/lang/yaml_tree.h)
#   momenta_eigen     Eigen3::Eigen
#   momenta_cli11     CLI11::CLI11
#   momenta_matio     libmatio (MAT v4 result files; Debian's libmatio-dev)
#   momenta_mpi       MPI's C interface (OpenMPI: libopenmpi-dev) with MOMENTA_HAVE_MPI=1, or
#                     nothing but MOMENTA_HAVE_MPI=0 when MPI is not found or MOMENTA_USE_MPI=OFF:
#                     momenta then builds without it, and `mpirun … momenta sweep` says so
# and, when tests / benchmarks are enabled, finds GTest (GTest::gtest_main), libpng (PNG::PNG:
# the report and plot tests decode screenshots) and Google Benchmark (benchmark::benchmark).
# Programs used at run time, not linked: gnuplot (`momenta plot`; Debian's gnuplot-nox) and, in
# the tests only, chromium (headless, to render reports). uPlot, inlined into reports, is fetched
# by scripts/setup.sh into third_party/uplot/ (app/CMakeLists.txt).
#
# Options / cache variables:
#   MOMENTA_BUILD_TESTS          (ON)  find GTest, enable_testing()
#   MOMENTA_BUILD_BENCH          (ON)  find Google Benchmark
#   MOMENTA_SANITIZE             (OFF) ASan + UBSan (with float-cast-overflow, which GCC's
#                                      'undefined' leaves out) on everything defined after this file
#   MOMENTA_BUILD_FUZZ           (OFF) the libFuzzer target in fuzz/ (clang only; implies the
#                                      sanitizers and adds libFuzzer's coverage instrumentation)
#   MOMENTA_SUNDIALS_ROOT        optimised SUNDIALS prefix made by scripts/setup.sh
#   MOMENTA_USE_SYSTEM_SUNDIALS  (OFF) ignore MOMENTA_SUNDIALS_ROOT, use the system SUNDIALS
#   MOMENTA_USE_MPI              (ON)  sweeps under mpirun when MPI is found
#   MOMENTA_TESTS_PCH            (OFF) precompile the tests' common headers (scripts/test.sh;
#                                      not with ccache, which would then compile them uncached)
#   MOMENTA_TESTS_COMPILE_OPTIONS  ("") extra compile options of the test sources only
#                                      (scripts/test.sh: -O0 in the sanitizer build)
#   MOMENTA_LEAN_LINK            (ON)  the momenta binary links libstdc++, libgcc, yaml-cpp, libyaml
#                                      and SuiteSparse statically (momenta_lean_link() below)
#   MOMENTA_TESTS_SHARDS         (0)   0: one ctest test per GoogleTest test; N: N ctest tests,
#                                      each a GoogleTest shard run in one process (scripts/test.sh:
#                                      in the sanitizer build, whose start-up is slow)
# Sets MOMENTA_SUNDIALS_OPTIMIZED (ON/OFF) and MOMENTA_SUNDIALS_VERSION in the including scope,
# MOMENTA_HAVE_MPI (1/0: app/ builds the MPI plugin) and MOMENTA_MPIEXEC (mpirun's path, empty
# without MPI) for the tests.

include_guard(GLOBAL)

option(MOMENTA_BUILD_TESTS "Build the unit tests (needs GTest)" ON)
option(MOMENTA_BUILD_BENCH "Build the benchmarks (needs Google Benchmark)" ON)
option(MOMENTA_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(MOMENTA_BUILD_FUZZ "Build the libFuzzer target in fuzz/ (needs clang; implies the sanitizers)" OFF)
option(MOMENTA_USE_SYSTEM_SUNDIALS "Use the system SUNDIALS even if the optimised build exists" OFF)
option(MOMENTA_USE_MPI "Run sweeps under mpirun when MPI is found" ON)
option(MOMENTA_LEAN_LINK "Link the momenta binary's C++ runtime, yaml-cpp and SuiteSparse statically (start-up)" ON)
option(MOMENTA_TESTS_PCH "Precompile the common headers of the tests (not with ccache)" OFF)
set(MOMENTA_TESTS_COMPILE_OPTIONS "" CACHE STRING "Extra compile options of the test sources only")
set(MOMENTA_TESTS_SHARDS 0 CACHE STRING "0: a ctest test per GoogleTest test; N: N GoogleTest shards")

# ---- Sanitizers: compile and link flags of every target defined after this point -------------
# float-cast-overflow: a double converted to an integer type it does not fit (1e300 to int64_t).
if(MOMENTA_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "momenta: MOMENTA_BUILD_FUZZ needs clang (libFuzzer): configure a separate "
                        "build directory with CC=clang CXX=clang++, e.g. build-fuzz/ (scripts/fuzz.sh)")
  endif()
  # Coverage instrumentation for libFuzzer everywhere; the fuzz target itself links the driver.
  add_compile_options(-fsanitize=fuzzer-no-link -Wno-unknown-warning-option)
endif()
if(MOMENTA_SANITIZE OR MOMENTA_BUILD_FUZZ)
  set(_momenta_san_flags -fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer
                         -fno-sanitize-recover=undefined,float-cast-overflow)
  add_compile_options(${_momenta_san_flags})
  add_link_options(${_momenta_san_flags})
  list(JOIN _momenta_san_flags " " _momenta_san_text)
  message(STATUS "momenta: sanitizers ON (${_momenta_san_text})")
endif()

# ---- SUNDIALS ------------------------------------------------------------------------------
# Default root of the optimised build: $MOMENTA_DEPS_DIR/sundials-6.4.1 or /opt/momenta-deps/...
if(DEFINED ENV{MOMENTA_DEPS_DIR} AND NOT "$ENV{MOMENTA_DEPS_DIR}" STREQUAL "")
  set(_momenta_sundials_default_root "$ENV{MOMENTA_DEPS_DIR}/sundials-6.4.1")
else()
  set(_momenta_sundials_default_root "/opt/momenta-deps/sundials-6.4.1")
endif()
set(MOMENTA_SUNDIALS_ROOT "${_momenta_sundials_default_root}" CACHE PATH
    "Prefix of the optimised SUNDIALS build made by scripts/setup.sh")

# Components momenta links, in link order (solvers before what they use).
set(_momenta_sundials_components
    ida kinsol sunlinsolklu sunlinsoldense sunmatrixsparse sunmatrixdense nvecserial)

# The search is redone at every configure: forget what the last run found, so that an optimised
# build installed (or removed) since then is noticed.
unset(SUNDIALS_DIR CACHE)
unset(SUNDIALS_DIR)

set(MOMENTA_SUNDIALS_OPTIMIZED OFF)
set(_momenta_sundials_why "")

# 1. The optimised build, if its install is complete (scripts/setup.sh writes the stamp last).
set(_momenta_sundials_stamp "${MOMENTA_SUNDIALS_ROOT}/.momenta-sundials-stamp")
if(MOMENTA_USE_SYSTEM_SUNDIALS)
  set(_momenta_sundials_why "MOMENTA_USE_SYSTEM_SUNDIALS=ON")
elseif(NOT EXISTS "${_momenta_sundials_stamp}")
  set(_momenta_sundials_why "no complete optimised build in ${MOMENTA_SUNDIALS_ROOT} (run scripts/setup.sh)")
else()
  find_package(SUNDIALS 6.4 CONFIG QUIET
               COMPONENTS ${_momenta_sundials_components}
               PATHS "${MOMENTA_SUNDIALS_ROOT}" NO_DEFAULT_PATH)
  if(SUNDIALS_FOUND AND SUNDIALS_VERSION VERSION_GREATER_EQUAL 6.4 AND SUNDIALS_VERSION VERSION_LESS 6.5)
    set(MOMENTA_SUNDIALS_OPTIMIZED ON)
  elseif(SUNDIALS_FOUND)
    message(FATAL_ERROR "momenta: ${MOMENTA_SUNDIALS_ROOT} holds SUNDIALS ${SUNDIALS_VERSION}, need 6.4.x; "
                        "remove it and rerun scripts/setup.sh, or set -DMOMENTA_USE_SYSTEM_SUNDIALS=ON")
  else()
    set(_momenta_sundials_why "the SUNDIALS package in ${MOMENTA_SUNDIALS_ROOT} could not be loaded")
    unset(SUNDIALS_DIR CACHE)
    unset(SUNDIALS_DIR)
  endif()
endif()

# 2. Otherwise the system SUNDIALS (Debian's libsundials-dev, built without optimisation).
if(NOT MOMENTA_SUNDIALS_OPTIMIZED)
  find_package(SUNDIALS 6.4 CONFIG REQUIRED COMPONENTS ${_momenta_sundials_components})
  if(SUNDIALS_VERSION VERSION_LESS 6.4 OR NOT SUNDIALS_VERSION VERSION_LESS 6.5)
    message(FATAL_ERROR "momenta: found SUNDIALS ${SUNDIALS_VERSION} in ${SUNDIALS_DIR}, need 6.4.x")
  endif()
endif()

add_library(momenta_sundials INTERFACE)
foreach(_c IN LISTS _momenta_sundials_components)
  # The optimised prefix holds static libraries only (PIC, so they also go into shared objects):
  # nothing to find at run time, no LD_LIBRARY_PATH or RPATH needed. The system package's
  # un-suffixed names are aliases of its shared libraries in /usr/lib.
  if(MOMENTA_SUNDIALS_OPTIMIZED)
    set(_t SUNDIALS::${_c}_static)
  else()
    set(_t SUNDIALS::${_c})
  endif()
  if(NOT TARGET ${_t})
    message(FATAL_ERROR "momenta: SUNDIALS in ${SUNDIALS_DIR} has no target ${_t}")
  endif()
  target_link_libraries(momenta_sundials INTERFACE ${_t})
endforeach()
# KLU itself (SuiteSparse); sunlinsolklu already brings it, listed so its headers are always seen.
if(TARGET SUNDIALS::KLU)
  target_link_libraries(momenta_sundials INTERFACE SUNDIALS::KLU)
endif()
if(MOMENTA_SUNDIALS_OPTIMIZED)
  target_compile_definitions(momenta_sundials INTERFACE MOMENTA_SUNDIALS_OPTIMIZED=1)
  message(STATUS "momenta: SUNDIALS ${SUNDIALS_VERSION}: optimised build (static, -O2) in ${MOMENTA_SUNDIALS_ROOT}")
else()
  target_compile_definitions(momenta_sundials INTERFACE MOMENTA_SUNDIALS_OPTIMIZED=0)
  message(STATUS "momenta: SUNDIALS ${SUNDIALS_VERSION}: system package in ${SUNDIALS_DIR} "
                 "(not optimised; ${_momenta_sundials_why})")
endif()
set(MOMENTA_SUNDIALS_VERSION "${SUNDIALS_VERSION}")

# ---- yaml-cpp (Debian 12: 0.7, target 'yaml-cpp'; newer releases: yaml-cpp::yaml-cpp) --------
find_package(yaml-cpp CONFIG REQUIRED)
add_library(momenta_yaml INTERFACE)
if(TARGET yaml-cpp::yaml-cpp)
  target_link_libraries(momenta_yaml INTERFACE yaml-cpp::yaml-cpp)
else()
  target_link_libraries(momenta_yaml INTERFACE yaml-cpp)
endif()
find_package(PkgConfig REQUIRED)
pkg_check_modules(LIBYAML REQUIRED IMPORTED_TARGET yaml-0.1)
target_link_libraries(momenta_yaml INTERFACE PkgConfig::LIBYAML)

# ---- Eigen ---------------------------------------------------------------------------------
find_package(Eigen3 3.3 CONFIG REQUIRED)
add_library(momenta_eigen INTERFACE)
target_link_libraries(momenta_eigen INTERFACE Eigen3::Eigen)

# ---- CLI11 (header-only) -------------------------------------------------------------------
find_package(CLI11 CONFIG REQUIRED)
add_library(momenta_cli11 INTERFACE)
target_link_libraries(momenta_cli11 INTERFACE CLI11::CLI11)

# ---- libmatio (Debian 12: 1.5.23; no CMake package, so found by header and library) ---------
find_path(MOMENTA_MATIO_INCLUDE_DIR matio.h)
find_library(MOMENTA_MATIO_LIBRARY NAMES matio)
if(NOT MOMENTA_MATIO_INCLUDE_DIR OR NOT MOMENTA_MATIO_LIBRARY)
  message(FATAL_ERROR "momenta: libmatio not found (MAT result files); install libmatio-dev (scripts/setup.sh)")
endif()
add_library(momenta_matio INTERFACE)
target_include_directories(momenta_matio INTERFACE ${MOMENTA_MATIO_INCLUDE_DIR})
target_link_libraries(momenta_matio INTERFACE ${MOMENTA_MATIO_LIBRARY})
message(STATUS "momenta: libmatio ${MOMENTA_MATIO_LIBRARY}")

# ---- Threads (parameter sweeps) ------------------------------------------------------------
find_package(Threads REQUIRED)

# ---- MPI (sweeps across processes and machines; optional) ----------------------------------
add_library(momenta_mpi INTERFACE)
set(MOMENTA_MPIEXEC "")
if(MOMENTA_USE_MPI)
  find_package(MPI COMPONENTS C QUIET)
endif()
if(MOMENTA_USE_MPI AND MPI_C_FOUND)
  target_link_libraries(momenta_mpi INTERFACE MPI::MPI_C)
  target_compile_definitions(momenta_mpi INTERFACE MOMENTA_HAVE_MPI=1)
  set(MOMENTA_HAVE_MPI 1)
  set(MOMENTA_MPIEXEC "${MPIEXEC_EXECUTABLE}")
  message(STATUS "momenta: MPI ${MPI_C_VERSION} (${MPI_C_LIB_NAMES}); mpirun: ${MPIEXEC_EXECUTABLE}")
else()
  target_compile_definitions(momenta_mpi INTERFACE MOMENTA_HAVE_MPI=0)
  set(MOMENTA_HAVE_MPI 0)
  message(STATUS "momenta: MPI not used (MOMENTA_USE_MPI=${MOMENTA_USE_MPI}; install libopenmpi-dev and "
                 "openmpi-bin for sweeps under mpirun): sweeps run on threads only")
endif()

# ---- Test and benchmark frameworks, only when those are built ------------------------------
if(MOMENTA_BUILD_TESTS)
  find_package(GTest REQUIRED)   # GTest::gtest, GTest::gtest_main
  find_package(PNG REQUIRED)     # PNG::PNG (Debian's libpng-dev)
  enable_testing()
endif()
if(MOMENTA_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)   # benchmark::benchmark
endif()

# ---- Lean link of the momenta binary (start-up time) ---------------------------------------
# A small model's whole run is a few milliseconds, of which the dynamic loader's symbol lookups in
# libstdc++, yaml-cpp and SuiteSparse were a fifth (bench/RESULTS.md, "time to a first result").
# momenta_lean_link(TARGET) links that executable with those libraries' static archives (where
# they are installed; the shared ones otherwise), libstdc++ and libgcc static, and the linker's
# section garbage collection: it then loads only libc and libm. Everything else (the tests, the
# Python module, the plugins, which talk to momenta through plain C tables) links as before. The
# swap is a generator expression on the consuming target's property MOMENTA_STATIC_LIBRARIES.
set(_momenta_static_when "$<BOOL:$<TARGET_PROPERTY:MOMENTA_STATIC_LIBRARIES>>")
function(_momenta_static_swap target)
  get_target_property(_libs ${target} INTERFACE_LINK_LIBRARIES)
  if(NOT _libs)
    return()
  endif()
  set(_swapped "")
  foreach(_lib IN LISTS _libs)
    string(REGEX REPLACE "\\.so(\\.[0-9.]+)?$" ".a" _archive "${_lib}")
    if(NOT _archive STREQUAL _lib AND EXISTS "${_archive}")
      list(APPEND _swapped "$<IF:${_momenta_static_when},${_archive},${_lib}>")
    else()
      list(APPEND _swapped "${_lib}")
      set(MOMENTA_LEAN_LINK_COMPLETE OFF PARENT_SCOPE)
    endif()
  endforeach()
  set_property(TARGET ${target} PROPERTY INTERFACE_LINK_LIBRARIES "${_swapped}")
endfunction()
if(MOMENTA_LEAN_LINK AND NOT MOMENTA_SANITIZE AND NOT MOMENTA_BUILD_FUZZ
   AND CMAKE_SYSTEM_NAME STREQUAL "Linux" AND CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  set(MOMENTA_LEAN_LINK_ACTIVE ON)
  # OFF when a library's archive is not installed (its shared library is linked instead); the
  # system SUNDIALS is Debian's shared libraries.
  set(MOMENTA_LEAN_LINK_COMPLETE ${MOMENTA_SUNDIALS_OPTIMIZED})
  if(TARGET SUNDIALS::KLU)
    _momenta_static_swap(SUNDIALS::KLU)
  endif()
  # yaml-cpp's imported target names the shared library: the archive beside it, when installed.
  foreach(_t yaml-cpp::yaml-cpp yaml-cpp)
    if(TARGET ${_t})
      get_target_property(_so ${_t} LOCATION)
      string(REGEX REPLACE "\\.so(\\.[0-9.]+)?$" ".a" _a "${_so}")
      if(EXISTS "${_a}")
        set_property(TARGET momenta_yaml PROPERTY INTERFACE_LINK_LIBRARIES "$<IF:${_momenta_static_when},${_a},${_t}>")
        target_link_libraries(momenta_yaml INTERFACE PkgConfig::LIBYAML)
      else()
        set(MOMENTA_LEAN_LINK_COMPLETE OFF)
      endif()
      break()
    endif()
  endforeach()
  _momenta_static_swap(PkgConfig::LIBYAML)
else()
  set(MOMENTA_LEAN_LINK_ACTIVE OFF)
  set(MOMENTA_LEAN_LINK_COMPLETE OFF)
endif()
function(momenta_lean_link target)
  if(MOMENTA_LEAN_LINK_ACTIVE)
    set_property(TARGET ${target} PROPERTY MOMENTA_STATIC_LIBRARIES ON)
    target_link_options(${target} PRIVATE -static-libstdc++ -static-libgcc
                        "LINKER:-O1,--hash-style=gnu,--as-needed,--gc-sections")
  endif()
endfunction()
