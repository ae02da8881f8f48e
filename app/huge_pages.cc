#include "app/huge_pages.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace momenta {

namespace {

/// A model file's name: .yaml or .yml. Results (-o out.csv), reports and trajectories written
/// by an earlier run may be large too, and say nothing of the model's size.
bool IsYamlName(const char* name) {
  std::string ext = std::filesystem::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".yaml" || ext == ".yml";
}

bool NamesLargeModelFile(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (!IsYamlName(argv[i])) continue;
    struct stat st {};
    if (stat(argv[i], &st) == 0 && S_ISREG(st.st_mode) && st.st_size >= kHugePagesFileBytes) return true;
  }
  return false;
}

/// "always [madvise] never": huge pages on request are available unless "never" is chosen.
bool TransparentHugePagesAvailable() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  return std::getline(in, line) && line.find("[never]") == std::string::npos;
}

/// The process's arguments, kept by MaybeRestartWithHugePages for a later restart.
char** saved_argv = nullptr;

/// MOMENTA_HUGE_PAGES: "0" never, "1" always, unset: by the model's size.
bool ChoiceIs(const char* value) {
  const char* choice = std::getenv("MOMENTA_HUGE_PAGES");
  return choice != nullptr && std::strcmp(choice, value) == 0;
}

bool TunableSet() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  return tunables != nullptr && std::strstr(tunables, "glibc.malloc.hugetlb") != nullptr;
}

/// execv of this program with the tunable added; returns only when that fails.
void Restart(char** argv) {
  if (!TransparentHugePagesAvailable()) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::string value = tunables != nullptr && *tunables != '\0' ? std::string(tunables) + ":" : std::string();
  // Huge pages, and freed memory kept for reuse: with mmap off and no trimming, the large arrays
  // a build frees and makes again (pass by pass) reuse pages already faulted in instead of being
  // unmapped and faulted anew (the RC ladder at n = 50 000: a quarter less CPU, 7 % more peak).
  value += "glibc.malloc.hugetlb=1:glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=4294967295";
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  std::cout.flush();  // (std::cerr is unit-buffered)
  std::fflush(nullptr);
  execv("/proc/self/exe", argv);
  // Not restarted (no /proc, say): go on with ordinary pages. The variable stays set, which only
  // tells a compiler momenta starts to use huge pages too.
}

}  // namespace

void MaybeRestartWithHugePages(int argc, char** argv) {
  saved_argv = argv;
  if (ChoiceIs("0") || TunableSet()) return;
  if (!ChoiceIs("1") && !NamesLargeModelFile(argc, argv)) return;
  Restart(argv);
}

void RestartWithHugePagesForLargeBuild() {
  if (saved_argv == nullptr || ChoiceIs("0") || TunableSet()) return;
  // A rank started by mpirun stays the process its launcher knows.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return;
  }
  Restart(saved_argv);
}

bool HugePagesInUse() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables == nullptr) return false;
  const char* at = std::strstr(tunables, "glibc.malloc.hugetlb=");
  return at != nullptr && at[std::strlen("glibc.malloc.hugetlb=")] != '0';
}

}  // namespace momenta
