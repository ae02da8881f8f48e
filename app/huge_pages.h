#pragma once
/// Huge pages for large builds. Building a model of 100 000 components touches more than a
/// gigabyte of freshly allocated memory; with 4 KiB pages a large share of the build is spent in
/// page faults and TLB misses. glibc's malloc backs its heap with transparent huge pages when the
/// tunable glibc.malloc.hugetlb=1 is set, but tunables are read only when a process starts, so
/// momenta restarts itself once (execv of /proc/self/exe, same arguments) with it set when a
/// model file (.yaml, .yml) is large, or when the model's sizes (`count:`) make a large build.

namespace momenta {

/// Model files (.yaml, .yml) of at least this many bytes make momenta restart with huge pages.
constexpr long kHugePagesFileBytes = 1L << 20;

/// Restarts the process with GLIBC_TUNABLES=…:glibc.malloc.hugetlb=1 (and malloc's large
/// blocks kept in its heap: mmap_max=0, no trimming) when an argument names a
/// YAML file of at least kHugePagesFileBytes (or MOMENTA_HUGE_PAGES=1), the tunable is not set
/// yet, transparent huge pages are not disabled and MOMENTA_HUGE_PAGES is not 0. Returns (and the
/// run goes on as before) whenever it does not restart or the restart fails. Call first in main.
void MaybeRestartWithHugePages(int argc, char** argv);

/// Restarts the process as MaybeRestartWithHugePages does, for a build that turned out large
/// once the model's sizes were known (core/base/memory_budget.h, LargeBuildWatch: an array model's
/// file is small). Not under mpirun, nor when MOMENTA_HUGE_PAGES is 0 or huge pages are in use;
/// returns when it does not restart. Nothing may have been written that a restart would repeat.
void RestartWithHugePagesForLargeBuild();

/// glibc's malloc uses huge pages in this process (GLIBC_TUNABLES has glibc.malloc.hugetlb=1 or 2).
bool HugePagesInUse();

}  // namespace momenta
