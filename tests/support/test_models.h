#pragma once
// Helpers shared by the tests: build models from files or inline YAML, run them, read CSVs.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/build.h"
#include "core/compile/model_state.h"
#include "solver/simulator.h"

namespace momenta::testing {

std::string SourcePath(const std::string& relative);

struct Built {
  std::shared_ptr<const CompiledModel> model;
  BuildReport report;
};

Built BuildFile(const std::string& relative_path, const ParameterOverrides& overrides = {});
Built BuildYaml(const std::string& yaml, const ParameterOverrides& overrides = {});

/// Simulated rows: times and outputs (by output name).
struct Trajectory {
  std::vector<double> t;
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;  ///< values[row][output]
  SolverStats stats;
  double Column(const std::string& name, size_t row) const;
  size_t Index(const std::string& name) const;
};

Trajectory Run(const Built& b, SimulationOptions options, const ParameterOverrides& overrides = {});
Trajectory RunDefault(const Built& b, const ParameterOverrides& overrides = {});

/// A CSV file with a header row.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  size_t Index(const std::string& name) const;
};
Csv ReadCsv(const std::string& path);

/// The error message of building (or setting the parameters of) a model from inline YAML; empty
/// when it builds.
std::string BuildError(const std::string& yaml, const ParameterOverrides& overrides = {});

}  // namespace momenta::testing
