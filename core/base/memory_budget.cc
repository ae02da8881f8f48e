#include "core/base/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>

namespace momenta {

namespace {

// Bytes per item of a component through the whole build (see EstimatedComponentBytes).
constexpr double kBytesPerComponent = 256;
constexpr double kBytesPerVariable = 512;
constexpr double kBytesPerParameter = 128;
constexpr double kBytesPerExpressionNode = 64;

/// A whole-number field of a /proc or /sys file, or -1.
double ReadNumber(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string word;
  while (in >> word) {
    if (key.empty() || word == key) {
      double v = -1;
      if (!key.empty() && !(in >> v)) return -1;
      if (key.empty()) v = std::strtod(word.c_str(), nullptr);  // "max" reads as 0
      return v > 0 ? v : -1;
    }
  }
  return -1;
}

}  // namespace

MemoryBudget BuildMemoryBudget() {
  MemoryBudget b;
  if (const char* env = std::getenv("MOMENTA_MEMORY_MB")) {
    char* end = nullptr;
    double mb = std::strtod(env, &end);
    if (end != env && *end == '\0' && mb > 0) {
      b.bytes = mb * 1024 * 1024;
      b.source = std::string("MOMENTA_MEMORY_MB=") + env;
      return b;
    }
  }
  double available = ReadNumber("/proc/meminfo", "MemAvailable:");
  if (available > 0) {
    b.bytes = available * 1024;
    b.source = "the memory available; MOMENTA_MEMORY_MB sets another budget";
  } else {
    b.bytes = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
    b.source = "the physical memory; MOMENTA_MEMORY_MB sets another budget";
  }
  // In a container the cgroup's limit may be lower than what the system has available.
  double limit = ReadNumber("/sys/fs/cgroup/memory.max", "");
  double used = ReadNumber("/sys/fs/cgroup/memory.current", "");
  if (limit > 0 && limit - std::max(used, 0.0) < b.bytes) {
    b.bytes = limit - std::max(used, 0.0);
    b.source = "the container's memory limit; MOMENTA_MEMORY_MB sets another budget";
  }
  if (!(b.bytes > 0)) {
    b.bytes = 4.0 * 1024 * 1024 * 1024;
    b.source = "a default; MOMENTA_MEMORY_MB sets another budget";
  }
  return b;
}

double EstimatedComponentBytes(size_t num_variables, size_t num_parameters,
                               size_t num_expression_nodes) {
  return kBytesPerComponent + kBytesPerVariable * static_cast<double>(num_variables) +
         kBytesPerParameter * static_cast<double>(num_parameters) +
         kBytesPerExpressionNode * static_cast<double>(num_expression_nodes);
}

namespace {
/// The watches of this thread's build; each empty when there is none or it has been told.
thread_local std::function<void(double)> large_build_watch;
thread_local std::function<void(double, const MemoryBudget&)> most_of_budget_watch;
}  // namespace

LargeBuildWatch::LargeBuildWatch(std::function<void(double bytes)> on_large,
                                 std::function<void(double bytes, const MemoryBudget& budget)> on_most_of_budget) {
  large_build_watch = std::move(on_large);
  most_of_budget_watch = std::move(on_most_of_budget);
}

LargeBuildWatch::~LargeBuildWatch() {
  large_build_watch = nullptr;
  most_of_budget_watch = nullptr;
}

void NotePlannedBuild(double bytes, const MemoryBudget& budget) {
  // Each told once: a callback leaves its watch before it runs (on_large may not return: it
  // restarts the process, whose build then tells the other).
  if (large_build_watch && bytes >= kLargeBuildBytes) {
    std::function<void(double)> on_large = std::move(large_build_watch);
    large_build_watch = nullptr;
    on_large(bytes);
  }
  if (most_of_budget_watch && bytes > budget.bytes / 2) {
    std::function<void(double, const MemoryBudget&)> on_most = std::move(most_of_budget_watch);
    most_of_budget_watch = nullptr;
    on_most(bytes, budget);
  }
}

}  // namespace momenta
