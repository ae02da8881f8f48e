// Reading a model file's root (core/lang/yaml_loader_model.h).

#include "core/lang/yaml_loader_model.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "core/lang/parser.h"
#include "core/lang/yaml_loader_declarations.h"
#include "core/lang/yaml_loader_parts.h"
#include "core/lang/yaml_loader_types.h"

namespace momenta {

namespace {

/// `uses:`: a list of YAML files whose types the model uses.
std::vector<UsesSpec> ReadUses(const ValueReader& reader, const YamlNode& uses) {
  if (!uses.IsSequence())
    reader.Fail(uses, "uses must be a list of YAML files, e.g. uses: [mylib.yaml]");
  std::vector<UsesSpec> out;
  for (const auto& f : uses) out.push_back({reader.Scalar(f, "a uses: file"), reader.TextLoc(f)});
  return out;
}

/// The model's `parameters:`; none of them may be a table (a size ':').
std::vector<ParameterDecl> ReadModelParameters(const ValueReader& reader,
                                               const YamlNode& parameters,
                                               const std::string& model) {
  std::vector<ParameterDecl> out;
  reader.ExpectMap(parameters, "parameters");
  for (auto it = parameters.begin(); it != parameters.end(); ++it) {
    out.push_back(ReadParameter(reader, reader.Name(it->first, "parameter"), it->second, model));
    if (IsOpen(out.back().shape)) {
      reader.Fail(it->second["shape"],
                  "the model parameter " + out.back().name +
                      " has a size ':'; only a component type's parameter (a table) may");
    }
  }
  return out;
}

/// The values of the `experiment:` section `e` each checked where it is written, into `x`.
void ReadExperimentValues(const ValueReader& reader, const YamlNode& e, ExperimentSpec* x) {
  if (e["start"]) x->start = reader.Number(e["start"], "experiment.start");
  if (e["stop"]) x->stop = reader.Number(e["stop"], "experiment.stop");
  if (e["tolerance"]) x->tolerance = reader.Number(e["tolerance"], "experiment.tolerance");
  if (e["interval"]) x->interval = reader.Number(e["interval"], "experiment.interval");
  if (e["max_order"]) {
    const double k = reader.Number(e["max_order"], "experiment.max_order");
    if (!(k >= 1 && k <= 5 && k == std::floor(k))) {
      reader.Fail(
          e["max_order"],
          "experiment.max_order must be a whole number from 1 to 5 (IDA's maximum BDF order; "
          "the default is 5), found '" +
              std::string(e["max_order"].Scalar()) + "'");
    }
    x->max_order = static_cast<int>(k);
  }
  if (e["linear_solver"]) {
    x->linear_solver = reader.Scalar(e["linear_solver"], "experiment.linear_solver");
    const std::string& s = x->linear_solver;
    if (s != "auto" && s != "dense" && s != "klu") {
      reader.Fail(e["linear_solver"],
                  "unknown linear_solver '" + s + "' (valid: auto, dense, klu)");
    }
  }
}

/// The values of the `experiment:` section `e` together: stop after start, a tolerance double
/// precision can meet, an output grid that can be written. Each is reported where it is written
/// (the section itself when it is missing).
void CheckExperiment(const ValueReader& reader, const YamlNode& e, const ExperimentSpec& x) {
  auto at = [&](const char* key) { return e[key] ? e[key] : e; };
  auto shown = [&](const char* key, double v) {
    std::ostringstream text;
    if (e[key]) {
      text << "'" << e[key].Scalar() << "'";
    } else {
      text << v << " (the default)";
    }
    return text.str();
  };
  if (!(x.stop > x.start)) {
    reader.Fail(at("stop"), "experiment.stop must be after experiment.start (" +
                                shown("start", x.start) + "), found " + shown("stop", x.stop));
  }
  if (!(x.tolerance >= kMinRelTolerance && x.tolerance < 1)) {
    reader.Fail(
        at("tolerance"),
        "experiment.tolerance must lie between 1e-15 and 1 (double precision resolves about "
        "2.2e-16), found " +
            shown("tolerance", x.tolerance));
  }
  if (e["interval"]) {
    if (!(x.interval > 0)) {
      reader.Fail(e["interval"],
                  "experiment.interval must be positive, found " + shown("interval", x.interval));
    }
    if (std::string grid = OutputGridProblem(x.start, x.stop, x.interval); !grid.empty()) {
      reader.Fail(e["interval"],
                  "experiment.interval " + shown("interval", x.interval) + ": " + grid);
    }
  }
}

/// `experiment:`: the simulated interval, tolerance, output interval and solver choices.
ExperimentSpec ReadExperiment(const ValueReader& reader, const YamlNode& e) {
  ExperimentSpec x;
  reader.ExpectMap(e, "experiment");
  reader.CheckKeys(e, "experiment",
                   {"start", "stop", "tolerance", "interval", "linear_solver", "max_order"});
  x.loc = reader.Loc(e);
  ReadExperimentValues(reader, e, &x);
  CheckExperiment(reader, e, x);
  return x;
}

/// `outputs:`: a list of expressions, each a column of the results.
std::vector<OutputSpec> ReadOutputs(const ValueReader& reader, const YamlNode& outputs) {
  if (!outputs.IsSequence()) reader.Fail(outputs, "outputs must be a list of paths such as A.v");
  std::vector<OutputSpec> out;
  for (const auto& o : outputs) {
    OutputSpec output;
    output.text = reader.Scalar(o, "an output");
    output.loc = reader.TextLoc(o);
    output.expr = ParseExpression(output.text, output.loc);
    out.push_back(std::move(output));
  }
  return out;
}

}  // namespace

ModelSpec ReadModel(const ValueReader& reader, const YamlNode& root) {
  ModelSpec m;
  m.file = reader.file();
  m.loc = reader.Loc(root);
  if (!root.IsMap()) {
    throw ModelError(
        reader.Loc(root),
        "a model file must be a mapping with keys such as model, components, connections");
  }
  reader.CheckKeys(
      root, "the model",
      {"model", "doc", "uses", "parameters", "define", "components", "connections", "variables",
       "equations", "initial_equations", "when", "experiment", "outputs"});
  if (!root["model"]) reader.Fail(root, "the model needs a name: 'model: MyModel'");
  m.name = reader.Scalar(root["model"], "model");
  if (root["doc"]) m.doc = reader.Scalar(root["doc"], "doc");
  if (root["uses"] && !root["uses"].IsNull()) m.uses = ReadUses(reader, root["uses"]);
  if (root["parameters"] && !root["parameters"].IsNull()) {
    m.parameters = ReadModelParameters(reader, root["parameters"], m.name);
  }
  if (root["define"] && !root["define"].IsNull()) {
    ReadLibraryEntries(reader, root["define"], m.own.get(), &m.defines, true);
  }
  ReadParts(reader, root, &m.components, &m.connections);
  if (root["variables"] && !root["variables"].IsNull()) {
    reader.ExpectMap(root["variables"], "variables");
    for (auto it = root["variables"].begin(); it != root["variables"].end(); ++it) {
      m.variables.push_back(
          ReadVariable(reader, reader.Name(it->first, "variable"), it->second, m.name));
    }
  }
  if (root["equations"])
    m.equations = ReadEquations(reader, root["equations"], "the model's equations");
  if (root["initial_equations"]) {
    m.initial_equations =
        ReadEquations(reader, root["initial_equations"], "the model's initial equations");
  }
  if (root["when"]) m.whens = ReadWhens(reader, root["when"], "the model");
  if (root["experiment"]) m.experiment = ReadExperiment(reader, root["experiment"]);
  if (root["outputs"] && !root["outputs"].IsNull())
    m.outputs = ReadOutputs(reader, root["outputs"]);
  return m;
}

}  // namespace momenta
