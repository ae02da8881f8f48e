#include "tests/support/test_models.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace momenta::testing {

std::string SourcePath(const std::string& relative) {
  return std::string(MOMENTA_SOURCE_DIR) + "/" + relative;
}

Built BuildFile(const std::string& relative_path, const ParameterOverrides& overrides) {
  Built b;
  ModelSpec spec = LoadModelFile(SourcePath(relative_path));
  b.model = BuildModel(spec, BuiltinLibrary(), overrides, &b.report);
  return b;
}

Built BuildYaml(const std::string& yaml, const ParameterOverrides& overrides) {
  Built b;
  ModelSpec spec = LoadModelString(yaml, "test.yaml");
  b.model = BuildModel(spec, BuiltinLibrary(), overrides, &b.report);
  return b;
}

double Trajectory::Column(const std::string& name, size_t row) const {
  return values.at(row).at(Index(name));
}

size_t Trajectory::Index(const std::string& name) const {
  for (size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name) return k;
  }
  throw std::out_of_range("no output " + name);
}

Trajectory Run(const Built& b, SimulationOptions options, const ParameterOverrides& overrides) {
  ModelState state(b.model);
  state.SetParameters(overrides);
  Trajectory tr;
  tr.names = b.model->output_names;
  Simulate(&state, options, [&](double t, const std::vector<double>& v) {
    tr.t.push_back(t);
    tr.values.push_back(v);
  }, &tr.stats);
  return tr;
}

Trajectory RunDefault(const Built& b, const ParameterOverrides& overrides) {
  return Run(b, OptionsFromExperiment(b.model->experiment), overrides);
}

size_t Csv::Index(const std::string& name) const {
  for (size_t k = 0; k < header.size(); ++k) {
    if (header[k] == name) return k;
  }
  throw std::out_of_range("no column " + name);
}

Csv ReadCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  Csv csv;
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  std::string cell;
  while (std::getline(hs, cell, ',')) csv.header.push_back(cell);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream rs(line);
    while (std::getline(rs, cell, ',')) row.push_back(std::stod(cell));
    csv.rows.push_back(std::move(row));
  }
  return csv;
}

std::string BuildError(const std::string& yaml, const ParameterOverrides& overrides) {
  try {
    Built b = BuildYaml(yaml, overrides);
    ModelState state(b.model);
    state.SetParameters(overrides);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

}  // namespace momenta::testing
