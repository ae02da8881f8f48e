#pragma once
/// The runs of `momenta sweep`: its -p NAME=SPEC options parsed, and the plan they make.
///
/// Each -p NAME=SPEC gives one parameter's values: a number (fixed), a list `0.5,0.8,1`, a linear
/// grid `a:b:n` (n points from a to b), a logarithmic grid `a:b:log:n`, or a distribution
/// `normal(mu,sigma)` or `uniform(a,b)` sampled --samples times. Lists and grids combine as a
/// Cartesian product (the first -p varies slowest); with distributions, every grid point is run
/// with the same --samples draws (common random numbers), the draw varying fastest. Draws come
/// from std::mt19937_64 seeded with --seed, all made up front on one thread, turned into numbers
/// by formulas of our own (uniform: a + (b - a) u with u = (x >> 11) 2^-53, or a (1 - u) + b u
/// where b - a overflows; normal: Box-Muller from two such u, the cosine branch) so the values are the same with every standard library,
/// every --jobs and every number of MPI ranks.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace momenta {

/// One -p NAME=SPEC of a sweep.
struct SweepAxis {
  enum class Kind { kValues, kNormal, kUniform };
  std::string name;
  std::string spec;  ///< as given
  Kind kind = Kind::kValues;
  std::vector<double> values;  ///< kValues: the values in order
  double a = 0, b = 0;         ///< kNormal: mu, sigma; kUniform: low, high
  bool swept() const { return kind != Kind::kValues || values.size() > 1; }
};

/// Parses NAME=SPEC; throws UsageError naming the option and what is wrong
/// ("-p eS=0:1:x: the number of grid points 'x' is not a whole number from 1 to 10000000").
/// Numbers are decimal as in expressions (no hex); one outside double's range (1e999, or the
/// subnormal 1e-320) is named as such.
SweepAxis ParseSweepAxis(const std::string& text);

/// The runs of a sweep: run k sets names[j] = values[k][j] (names in -p order).
struct SweepPlan {
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
};

/// What is wrong with `--seed TEXT` (empty when nothing is): a seed is a whole number from 0 to
/// 2^64 - 1, written in decimal digits only (no sign, no exponent).
std::string SeedProblem(const std::string& text);

/// What is wrong with `--trajectories TEXT` (empty when nothing is): an empty directory name.
std::string TrajectoriesProblem(const std::string& text);

/// At most this many runs in one sweep.
constexpr size_t kMaxSweepRuns = 10'000'000;

/// The runs of `axes` (see the file comment). Throws UsageError when a distribution has no
/// --samples, --samples has no distribution, a name is given twice, or there are too many runs.
SweepPlan MakeSweepPlan(const std::vector<SweepAxis>& axes, size_t samples, uint64_t seed);

}  // namespace momenta
