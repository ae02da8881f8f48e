#pragma once
/// `momenta sweep`: one model built once, simulated for many parameter values on several threads.
///
/// Each -p NAME=SPEC gives one parameter's values: a number (fixed), a list `0.5,0.8,1`, a linear
/// grid `a:b:n` (n points from a to b), a logarithmic grid `a:b:log:n`, or a distribution
/// `normal(mu,sigma)` or `uniform(a,b)` sampled --samples times. Lists and grids combine as a
/// Cartesian product (the first -p varies slowest); with distributions, every grid point is run
/// with the same --samples draws (common random numbers), the draw varying fastest. Draws come
/// from std::mt19937_64 seeded with --seed, all made up front on one thread, turned into numbers
/// by formulas of our own (uniform: a + (b - a) u with u = (x >> 11) 2^-53; normal: Box-Muller
/// from two such u, the cosine branch) so the values are the same with every standard library.
///
/// Fixed values are applied when the model is built (so a fixed value may be a structural
/// parameter: a count, a connection index, a Boolean or Integer `if` condition); swept parameters
/// must not be structural (a usage error naming them): every run shares the one CompiledModel and
/// has its own ModelState, so the table is the same for any --jobs.

#include <cstdint>
#include <string>
#include <vector>

#include "app/simulate_options.h"

namespace momenta {

struct SweepArgs {
  std::string model;
  std::vector<std::string> params;  ///< NAME=SPEC
  SimulateOverrides options;        ///< --stop, --rtol, --atol, --interval, --linear-solver
  unsigned jobs = 0;                ///< threads; 0: one per core
  std::string out;                  ///< summary CSV; empty: <model file stem>_sweep.csv; "-": stdout
  std::string trajectories;         ///< directory for run-<k>.csv; empty: none written
  uint64_t seed = 0;
  size_t samples = 0;               ///< Monte Carlo draws (needs a distribution)
  bool quiet = false;
};

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
SweepAxis ParseSweepAxis(const std::string& text);

/// The runs of a sweep: run k sets names[j] = values[k][j] (names in -p order).
struct SweepPlan {
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
};

/// At most this many runs in one sweep.
constexpr size_t kMaxSweepRuns = 10'000'000;

/// The runs of `axes` (see the file comment). Throws UsageError when a distribution has no
/// --samples, --samples has no distribution, a name is given twice, or there are too many runs.
SweepPlan MakeSweepPlan(const std::vector<SweepAxis>& axes, size_t samples, uint64_t seed);

/// Runs the sweep and writes the summary: one row per run in run order, columns `run`, each -p
/// parameter, each output's final value, `steps`, `events`, `status` (0, or the exit code the run
/// alone would have had: 1 a parameter value the model refuses, 3 the solver failed) and
/// `message`. Returns 0 when every run succeeded, 3 when some failed (their rows say why), 2 for
/// usage errors, 1 for a wrong model, 128 + signal when interrupted (the finished rows kept).
int RunSweep(const SweepArgs& args);

}  // namespace momenta
