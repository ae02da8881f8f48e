// `momenta fmu MODEL`: build the model (as `momenta simulate` does, so a wrong model or -p is
// reported the same way), describe it and pack the FMU with libzip.

#include "app/fmu_command.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>

#include "app/commands.h"
#include "app/plugin.h"
#include "app/zip_plugin.h"
#include "core/base/messages.h"
#include "core/lang/yaml_loader.h"
#include "fmu/fmu_resources.h"

namespace momenta {

namespace {

std::string XmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\n':
        out += "&#10;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v + 0.0);
  return buf;
}

/// A unit the description declares: "" and "1" (dimensionless) are none.
bool HasUnit(const std::string& unit) { return !unit.empty() && unit != "1"; }

std::string VariableXml(const fmu::FmuVariable& v, const fmu::FmuLayout& layout) {
  std::string xml = "    <ScalarVariable name=\"" + XmlEscape(v.name) + "\" valueReference=\"" +
                    std::to_string(v.value_reference) + "\"";
  if (!v.description.empty()) xml += " description=\"" + XmlEscape(v.description) + "\"";
  std::string real = "<Real";
  switch (v.kind) {
    case fmu::VariableKind::kParameter:
      // Set before the initialisation (as -p), or during the run (tunable: Model Exchange in event
      // mode, Co-Simulation between steps); one that shaped the structure is fixed at export.
      xml += std::string(" causality=\"parameter\" variability=\"") + (v.structural ? "fixed" : "tunable") +
             "\" initial=\"exact\"";
      real += " start=\"" + Number(v.start) + "\"";
      break;
    case fmu::VariableKind::kOutput:
      xml += " causality=\"output\" variability=\"continuous\" initial=\"calculated\"";
      break;
    case fmu::VariableKind::kState:
      xml += " causality=\"local\" variability=\"continuous\" initial=\"calculated\"";
      break;
    case fmu::VariableKind::kDerivative:
      xml += " causality=\"local\" variability=\"continuous\" initial=\"calculated\"";
      real += " derivative=\"" + std::to_string(layout.state_refs[v.index] + 1) + "\"";
      break;
  }
  if (HasUnit(v.unit)) real += " unit=\"" + XmlEscape(v.unit) + "\"";
  return xml + ">\n      " + real + "/>\n    </ScalarVariable>\n";
}

std::string UnknownsXml(const char* element, const std::vector<uint32_t>& refs) {
  if (refs.empty()) return "";
  std::string xml = std::string("    <") + element + ">\n";
  for (uint32_t r : refs) xml += "      <Unknown index=\"" + std::to_string(r + 1) + "\"/>\n";
  return xml + "    </" + element + ">\n";
}

/// The FMU's files: name in the archive -> (text, or the path of a file to copy).
struct FmuContents {
  std::vector<std::pair<std::string, std::string>> texts, files;
};

/// Writes `contents` to `path` through the zip plugin; returns "" or what went wrong.
std::string WriteZip(const std::string& path, const FmuContents& contents) {
  std::string why;
  const auto* zip =
      static_cast<const ZipPluginTable*>(LoadPlugin("momenta-zip.so", "momenta_zip_plugin", false, &why));
  if (zip == nullptr) return "the zip plugin is not available (" + why + ")";
  std::vector<ZipEntry> entries;
  for (const auto& [name, text] : contents.texts) entries.push_back({name.c_str(), text.data(), text.size(), nullptr});
  for (const auto& [name, file] : contents.files) entries.push_back({name.c_str(), nullptr, 0, file.c_str()});
  char reason[512] = "";
  if (zip->write(path.c_str(), entries.data(), entries.size(), reason, sizeof reason) != 0) return reason;
  return "";
}

}  // namespace

std::string ModelDescriptionXml(const CompiledModel& model, const fmu::FmuLayout& layout,
                                const std::string& doc, bool model_exchange, bool co_simulation) {
  const std::string id = fmu::ModelIdentifier(model.flat->model_name);
  std::string xml =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription fmiVersion=\"2.0\" "
      "modelName=\"" +
      XmlEscape(model.flat->model_name) + "\" guid=\"" + layout.guid + "\"";
  if (!doc.empty()) xml += " description=\"" + XmlEscape(doc) + "\"";
  xml +=
      " generationTool=\"momenta 0.1\" variableNamingConvention=\"structured\" "
      "numberOfEventIndicators=\"" +
      std::to_string(layout.num_event_indicators) + "\">\n";
  const std::string common =
      " modelIdentifier=\"" + id +
      "\" canNotUseMemoryManagementFunctions=\"true\" canGetAndSetFMUstate=\"false\" "
      "canSerializeFMUstate=\"false\" providesDirectionalDerivative=\"false\"";
  if (model_exchange) xml += "  <ModelExchange" + common + "/>\n";
  if (co_simulation) {
    xml += "  <CoSimulation" + common + " canHandleVariableCommunicationStepSize=\"true\"/>\n";
  }
  std::set<std::string> units;
  for (const auto& v : layout.variables) {
    if (HasUnit(v.unit)) units.insert(v.unit);
  }
  if (!units.empty()) {
    xml += "  <UnitDefinitions>\n";
    for (const std::string& u : units) xml += "    <Unit name=\"" + XmlEscape(u) + "\"/>\n";
    xml += "  </UnitDefinitions>\n";
  }
  const ExperimentSpec& e = model.experiment;
  xml += "  <DefaultExperiment startTime=\"" + Number(e.start) + "\" stopTime=\"" + Number(e.stop) +
         "\" tolerance=\"" + Number(e.tolerance) + "\"" +
         (e.interval > 0 ? " stepSize=\"" + Number(e.interval) + "\"" : "") + "/>\n";
  xml += "  <ModelVariables>\n";
  for (const auto& v : layout.variables) xml += VariableXml(v, layout);
  xml += "  </ModelVariables>\n  <ModelStructure>\n";
  std::vector<uint32_t> outputs, initial;
  for (const auto& v : layout.variables) {
    if (v.kind == fmu::VariableKind::kOutput) outputs.push_back(v.value_reference);
    if (v.kind != fmu::VariableKind::kParameter) initial.push_back(v.value_reference);
  }
  xml += UnknownsXml("Outputs", outputs) + UnknownsXml("Derivatives", layout.derivative_refs) +
         UnknownsXml("InitialUnknowns", initial);
  return xml + "  </ModelStructure>\n</fmiModelDescription>\n";
}

int RunFmu(const FmuArgs& args) {
  if (args.kind != "me" && args.kind != "cs" && args.kind != "both") {
    std::cerr << "momenta: --kind " << args.kind
              << ": the choices are me (Model Exchange), cs (Co-Simulation) "
              << "and both\n";
    return kExitUsage;
  }
  const std::string runtime = FindPlugin("momenta-fmu.so");
  if (runtime.empty()) {
    std::cerr
        << "momenta: the FMU runtime momenta-fmu.so is not in this build (lib/momenta/ beside the "
        << "binary): sanitizer builds leave it out, and so does a build without a position-independent "
        << "yaml-cpp (scripts/setup.sh builds one; then configure and build again)\n";
    return kExitSolver;
  }
  LoadedModel loaded;
  if (int code = LoadAndBuild(args.model, args.params, &loaded); code != kExitOk) return code;
  for (const auto& w : loaded.report.warnings)
    std::cerr << args.model << ": warning: " << w << "\n";
  const CompiledModel& model = *loaded.model;
  const fmu::FmuLayout layout = fmu::MakeLayout(model, loaded.state->parameter_values());
  const std::string id = fmu::ModelIdentifier(model.flat->model_name);
  const std::string out = args.out.empty() ? FileStem(args.model) + ".fmu" : args.out;

  // The resources: the model file, the files its uses: names (beside it, as written) and the
  // manifest.
  namespace fs = std::filesystem;
  const fs::path model_path(args.model);
  FmuContents contents;
  fmu::ResourceManifest manifest;
  manifest.model_file = model_path.filename().string();
  manifest.overrides = loaded.report.overrides;
  contents.files.emplace_back("resources/" + manifest.model_file, args.model);
  for (const UsesSpec& u : LoadModelFile(args.model).uses) {
    const fs::path used = fs::path(u.path).lexically_normal();
    if (used.is_absolute() || used.string().rfind("..", 0) == 0) {
      std::cerr << args.model << ":" << u.loc.line << ":" << u.loc.column << ": uses: " << u.path
                << ": an FMU carries files beside the model or below its folder only\n";
      return kExitModel;
    }
    contents.files.emplace_back("resources/" + used.string(),
                                (model_path.parent_path() / used).string());
  }
  contents.texts.emplace_back("resources/" + std::string(fmu::kManifestName),
                              fmu::ManifestText(manifest));
  contents.texts.emplace_back(
      "modelDescription.xml",
      ModelDescriptionXml(model, layout, loaded.doc, args.kind != "cs", args.kind != "me"));
  contents.files.emplace_back("binaries/linux64/" + id + ".so", runtime);
  if (std::string why = WriteZip(out, contents); !why.empty()) {
    std::cerr << "momenta: cannot write " << out << ": " << why << "\n";
    return kExitSolver;
  }
  std::cout << "wrote " << out << " (FMI 2.0 "
            << (args.kind == "both" ? "Model Exchange and Co-Simulation"
                : args.kind == "me" ? "Model Exchange"
                                    : "Co-Simulation")
            << ", " << model.num_states() << " states, " << layout.num_event_indicators
            << " event indicators, " << layout.variables.size() << " variables)\n";
  return kExitOk;
}

}  // namespace momenta
