#include "app/huge_pages.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
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

}  // namespace

void MaybeRestartWithHugePages(int argc, char** argv) {
  const char* choice = std::getenv("MOMENTA_HUGE_PAGES");
  if (choice != nullptr && std::strcmp(choice, "0") == 0) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables != nullptr && std::strstr(tunables, "glibc.malloc.hugetlb") != nullptr) return;
  const bool forced = choice != nullptr && std::strcmp(choice, "1") == 0;
  if (!forced && !NamesLargeModelFile(argc, argv)) return;
  if (!TransparentHugePagesAvailable()) return;
  std::string value = tunables != nullptr && *tunables != '\0' ? std::string(tunables) + ":" : std::string();
  value += "glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Not restarted (no /proc, say): go on with ordinary pages. The variable stays set, which only
  // tells a compiler momenta starts to use huge pages too.
}

bool HugePagesInUse() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables == nullptr) return false;
  const char* at = std::strstr(tunables, "glibc.malloc.hugetlb=");
  return at != nullptr && at[std::strlen("glibc.malloc.hugetlb=")] != '0';
}

}  // namespace momenta
