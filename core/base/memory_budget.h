#pragma once
/// How much memory building and simulating a model may take, and what a component costs: sizes
/// given by the model (`count:`) are checked against this before anything is allocated, so a
/// count that cannot fit is refused at once with the estimate, instead of the process being
/// killed (or swapping) half-way through flattening.

#include <cstddef>
#include <functional>
#include <string>

namespace momenta {

struct MemoryBudget {
  double bytes = 0;
  std::string source;  ///< where the figure comes from, for messages
};

/// The budget: MOMENTA_MEMORY_MB if set (a positive number of MiB), otherwise the memory the
/// system reports available (MemAvailable in /proc/meminfo, or the cgroup's remaining limit if
/// that is lower), otherwise the physical memory.
MemoryBudget BuildMemoryBudget();

/// Bytes one component instance takes through the build (flat variables and equations, their
/// expressions, the simplified and compiled model), from its type's size. Calibrated on the
/// benchmark models (bench/RESULTS.md: the RC ladder with n = 100 000, i.e. 200 002 components
/// and 1.2 million variables, peaks at 0.98 GB in `momenta check`).
double EstimatedComponentBytes(size_t num_variables, size_t num_parameters,
                               size_t num_expression_nodes);

/// Builds planned above this many bytes (sizes given by the model's `count:`) are large: their
/// time goes largely to page faults and TLB misses. Huge pages took 0.28 → 0.23 s of CPU off the
/// RC ladder at n = 2 500 (about 40 MB at its peak), 0.91 → 0.70 s at n = 10 000 and 5.2 → 3.4 s
/// at n = 50 000 (3 interleaved runs each, medians); this estimate (core/flatten/type_layout.cc, EstimatedBytes) reaches
/// 32 MiB near n = 4 000.
constexpr double kLargeBuildBytes = 32.0 * 1024 * 1024;

/// While one lives, a build on this thread whose planned size passes kLargeBuildBytes calls
/// `on_large` with the planned bytes, once, before it makes the components (the command line
/// restarts itself on huge pages then: app/huge_pages.h); one that plans more than half the
/// memory budget calls `on_most_of_budget` once, before it takes it (the command line says so).
/// Watches do not nest.
class LargeBuildWatch {
 public:
  explicit LargeBuildWatch(std::function<void(double bytes)> on_large,
                           std::function<void(double bytes, const MemoryBudget& budget)> on_most_of_budget = nullptr);
  ~LargeBuildWatch();
  LargeBuildWatch(const LargeBuildWatch&) = delete;
  LargeBuildWatch& operator=(const LargeBuildWatch&) = delete;
};

/// Called by the flattener with the bytes planned so far and the budget they were checked
/// against (core/flatten/type_layout.cc, CheckedCount).
void NotePlannedBuild(double bytes, const MemoryBudget& budget);

}  // namespace momenta
