// What every command that runs a model starts from: the -p values parsed (with their units),
// the model loaded and built once, native code attached where it pays, and the parameters set;
// plus the small formats the commands share (milliseconds, the units file beside a CSV).

#include "app/commands.h"

#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/csv_writer.h"
#include "app/huge_pages.h"
#include "app/interrupt.h"
#include "core/build.h"
#include "core/base/memory_budget.h"
#include "core/base/messages.h"
#include "core/compile/model_state.h"
#include "core/lang/units.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// `text` as a number with a unit, or nullopt for a plain number; an unparsable unit is an error.
std::optional<Quantity> QuantityOf(const std::string& name, const std::string& text) {
  try {
    return SplitQuantity(text);
  } catch (const UnitError& e) {
    throw std::invalid_argument("-p " + name + ": " + e.what());
  }
}

}  // namespace

std::string FormatMs(double seconds) {
  std::ostringstream s;
  s.precision(3);
  s << seconds * 1e3 << " ms";
  return s.str();
}

std::string FileStem(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  size_t dot = base.find_last_of('.');
  return dot == std::string::npos ? base : base.substr(0, dot);
}

std::string WithExtension(const std::string& path, const std::string& extension) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const bool has = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return (has ? path.substr(0, dot) : path) + extension;
}

std::string UnitsPath(const std::string& csv_path) {
  const std::string ext = ".csv";
  bool csv = csv_path.size() > ext.size() && csv_path.compare(csv_path.size() - ext.size(), ext.size(), ext) == 0;
  return (csv ? csv_path.substr(0, csv_path.size() - ext.size()) : csv_path) + ".units.csv";
}

void WriteUnitsFile(const std::string& path, const std::vector<std::string>& names,
                    const std::vector<std::string>& units) {
  std::ofstream f(path);
  f << "name,unit\n" << "time,s\n";
  for (size_t k = 0; k < names.size(); ++k) {
    f << CsvField(names[k]) << "," << CsvField(k < units.size() ? units[k] : "") << "\n";
  }
  f.flush();
  if (!f) throw CsvWriteError("cannot write the units file " + path);
}

ParameterOverrides ParseOverrides(const std::vector<std::string>& pairs, OverrideUnits* units) {
  ParameterOverrides out;
  for (const auto& p : pairs) {
    size_t eq = p.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == p.size()) {
      throw std::invalid_argument("-p takes NAME=VALUE, found '" + p + "'");
    }
    std::string name = p.substr(0, eq), text = p.substr(eq + 1);
    double v;
    if (text == "true") {
      v = 1;
    } else if (text == "false") {
      v = 0;
    } else if (std::optional<Quantity> q = QuantityOf(name, text)) {
      // A value with a unit (10kN/m): SI for now; the build converts it to the parameter's
      // own unit once the flattened model tells it.
      if (!units) throw std::invalid_argument("-p " + name + ": this command takes plain numbers, found '" + text + "'");
      (*units)[name] = *q;
      const Unit unit = ParseUnit(q->unit);
      v = q->value * unit.factor + unit.offset;
    } else {
      // Decimal only, as values in a model file are written (no hex, inf or nan).
      std::optional<double> number;
      try {
        number = ParseDecimal(text);
      } catch (const UnitError& e) {
        throw std::invalid_argument("-p " + name + ": " + e.what());
      }
      if (!number) throw std::invalid_argument("-p " + name + ": '" + text + "' is not a number");
      v = *number;
    }
    out[name] = v;
  }
  return out;
}

/// Parses -p, loads, builds and sets the parameters; returns an exit code (kExitOk on success)
/// after printing what went wrong.
int LoadAndBuild(const std::string& path, const std::vector<std::string>& params, LoadedModel* out) {
  ParameterOverrides overrides;
  OverrideUnits units;
  try {
    overrides = ParseOverrides(params, &units);
  } catch (const std::invalid_argument& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  return LoadAndBuild(path, overrides, out, units);
}

int ResolveRunOptions(const std::string& model_path, const LoadedModel& loaded, const SimulateOverrides& overrides,
                      SimulationOptions* out) {
  try {
    *out = ResolveSimulationOptions(loaded.model->experiment, overrides);
  } catch (const UsageError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  for (const auto& w : loaded.report.warnings) std::cerr << model_path << ": warning: " << w << "\n";
  return kExitOk;
}

int LoadAndBuild(const std::string& path, const ParameterOverrides& overrides, LoadedModel* out,
                 const OverrideUnits& units) {
  out->overrides = overrides;
  try {
    auto t0 = Clock::now();
    ModelSpec spec = LoadModelFile(path);
    out->load_s = Since(t0);
    out->doc = spec.doc;
    // An array model's file is small: a large build shows once its counts are known.
    LargeBuildWatch large_build([](double) { RestartWithHugePagesForLargeBuild(); },
                                [&path](double bytes, const MemoryBudget& budget) {
                                  std::cerr << path << ": note: building this model takes about " << ByteText(bytes)
                                            << " of memory (an estimate), more than half of the "
                                            << ByteText(budget.bytes) << " available (" << budget.source << ")\n";
                                });
    auto t1 = Clock::now();
    BuildOptions options;
    options.overrides = out->overrides;
    options.override_units = units;
    // The report's scene: outputs added for what the parts draw, once the build has flattened
    // the model.
    if (out->with_scene) {
      options.add_outputs = [out](const FlatSystem& flat, ModelSpec* model) {
        out->scene = AddSceneOutputs(flat, model);
      };
    }
    if (out->configure_build) out->configure_build(&options);
    out->model = BuildModel(std::move(spec), BuiltinLibrary(), options, &out->report);
    out->overrides = out->report.overrides;
    out->build_s = Since(t1);
    // Native code for the programs (from the cache, or compiled now) where it pays; SIGINT or
    // SIGTERM meanwhile stops the compilers and the command.
    {
      ScopedInterruptHandler handler;
      out->codegen.interrupt = &InterruptRequested();
      out->model = AttachNativeCode(std::move(out->model), out->codegen, &out->codegen_report);
      out->codegen.interrupt = nullptr;
      if (InterruptRequested().load()) {
        std::cerr << "momenta: " << path << ": interrupted by " << InterruptSignalName(InterruptSignal())
                  << (out->codegen_report.interrupted ? " while compiling the model's native code: the compiler was "
                                                        "stopped and its temporary files removed\n"
                                                      : " while preparing the model's native code\n");
        return 128 + InterruptSignal();
      }
    }
    if (!out->codegen_report.note.empty()) std::cerr << path << ": note: " << out->codegen_report.note << "\n";
    out->state = std::make_unique<ModelState>(out->model);
    out->state->SetParameters(out->overrides);
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return kExitUsage;
  } catch (const ModelError& e) {
    std::cerr << e.what() << "\n";
    return kExitModel;
  }
  return kExitOk;
}

}  // namespace momenta
