#pragma once
/// The command line's subcommands. Each returns the process exit code: 0 success, 1 the model is
/// wrong, 2 usage, 3 the solver failed or the results could not be written (results so far kept),
/// 128 + the signal number when SIGINT or SIGTERM interrupted a simulation (results so far kept).

#include <string>
#include <vector>

#include "app/simulate_options.h"
#include "core/flat_system.h"

namespace momenta {

constexpr int kExitOk = 0, kExitModel = 1, kExitUsage = 2, kExitSolver = 3;

struct SimulateArgs {
  std::string model;
  std::vector<std::string> params;  ///< NAME=VALUE
  SimulateOverrides options;        ///< --stop, --rtol, --atol, --interval, --linear-solver
  std::string out;  ///< empty: <model file stem>.csv
  bool quiet = false;
};

struct CheckArgs {
  std::string model;
  std::vector<std::string> params;
  bool verbose = false;
};

int RunSimulate(const SimulateArgs& args);
int RunCheck(const CheckArgs& args);
int RunList(const std::string& name);

/// Parses NAME=VALUE pairs; throws std::invalid_argument with a usage message.
ParameterOverrides ParseOverrides(const std::vector<std::string>& pairs);

}  // namespace momenta
