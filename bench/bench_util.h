#pragma once
// What momenta's own benchmark programs (momenta_bench, reroll_bench, build_floor) share: the
// process's CPU time and the median of repeated figures. The hand-written IDA programs keep
// theirs in handwritten_ida.h, which depends on nothing of momenta's.

#include <algorithm>
#include <ctime>
#include <vector>

namespace momenta_bench {

/// CPU time used by this process so far (user + system), in seconds.
inline double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// The median (the mean of the two middle values for an even count); 0 for none.
inline double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace momenta_bench
