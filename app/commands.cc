#include "app/commands.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "app/csv_writer.h"
#include "app/huge_pages.h"
#include "app/interrupt.h"
#include "app/mat_writer.h"
#include "app/progress.h"
#include "app/report_command.h"
#include "core/build.h"
#include "core/base/memory_budget.h"
#include "core/compile/model_state.h"
#include "core/lang/unit_check.h"
#include "core/lang/units.h"
#include "solver/simulator.h"
#include "solver/sundials_support.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string Ms(double seconds) { return FormatMs(seconds); }

std::string Stem(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  size_t dot = base.find_last_of('.');
  return dot == std::string::npos ? base : base.substr(0, dot);
}

/// Every parameter of the model (model and component parameters, as -p names them) with its value
/// in `state`, for a MAT file's data_1.
std::vector<MatParameter> MatParameters(const CompiledModel& model, const ModelState& state) {
  std::vector<MatParameter> out;
  const std::vector<double>& values = state.parameter_values();
  for (size_t k = 0; k < model.flat->parameters.size() && k < values.size(); ++k) {
    const FlatSystem& flat = *model.flat;
    const ParamId p(static_cast<uint32_t>(k));
    std::string description = flat.ParameterDoc(p);
    const std::string& unit = flat.ParameterUnit(p);
    if (!unit.empty()) description += (description.empty() ? "[" : " [") + unit + "]";
    out.push_back({flat.ParameterName(p), description, values[k]});
  }
  return out;
}

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
      try {
        size_t used = 0;
        v = std::stod(text, &used);
        if (used != text.size()) throw std::invalid_argument(text);
      } catch (const std::exception&) {
        throw std::invalid_argument("-p " + name + ": '" + text + "' is not a number");
      }
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
    LargeBuildWatch large_build([](double) { RestartWithHugePagesForLargeBuild(); });
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
    out->model = BuildModel(std::move(spec), BuiltinLibrary(), options, &out->report);
    out->overrides = out->report.overrides;
    out->build_s = Since(t1);
    // Native code for the programs (from the cache, or compiled now) where it pays.
    out->model = AttachNativeCode(std::move(out->model), out->codegen, &out->codegen_report);
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

int RunSimulate(const SimulateArgs& args) {
  LoadedModel loaded;
  loaded.with_scene = !args.report.empty() || args.scene_columns;
  try {
    loaded.codegen.mode = ResolveCodegenMode(args.options);
  } catch (const UsageError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  if (int code = LoadAndBuild(args.model, args.params, &loaded); code != kExitOk) return code;
  const std::shared_ptr<const CompiledModel>& model = loaded.model;
  const BuildReport& report = loaded.report;
  // The results file holds the model's outputs (and with --scene-columns the scene's too).
  ResolveSceneColumns(model->output_names, &loaded.scene);
  const size_t num_written = args.scene_columns || !loaded.with_scene ? model->output_names.size()
                                                                      : loaded.scene.num_model_columns;
  const std::vector<std::string> written_names(model->output_names.begin(), model->output_names.begin() + num_written);
  std::unique_ptr<ReportData> report_data;
  if (!args.report.empty()) {
    report_data = std::make_unique<ReportData>(ReportFromModel(args.model, loaded));
    report_data->columns = model->output_names;
    report_data->units = OutputUnits(*model->flat, model->output_names);
    report_data->num_plotted = loaded.scene.num_model_columns;
    report_data->scene = loaded.scene;
  }
  const double load_s = loaded.load_s, build_s = loaded.build_s;
  ModelState* state = loaded.state.get();
  SimulationOptions opt;
  if (int code = ResolveRunOptions(args.model, loaded, args.options, &opt); code != kExitOk) return code;

  // From here on SIGINT and SIGTERM stop the run between steps and keep its rows.
  InstallInterruptHandler();
  opt.interrupt = &InterruptRequested();
  std::string out_path = args.out.empty() ? Stem(args.model) + ".csv" : args.out;
  std::unique_ptr<ResultWriter> csv;
  try {
    if (IsMatPath(out_path)) {
      csv = std::make_unique<MatWriter>(out_path, written_names, MatParameters(*model, *state), opt.start,
                                        opt.stop, OutputUnits(*model->flat, written_names));
    } else {
      csv = std::make_unique<CsvWriter>(out_path, written_names);
      if (out_path != "-") {
        WriteUnitsFile(UnitsPath(out_path), written_names, OutputUnits(*model->flat, written_names));
      }
    }
  } catch (const ResultWriteError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitSolver;
  }
  std::vector<double> last(num_written);
  double last_t = opt.start;
  SolverStats stats;
  int code = kExitOk;
  std::string failure, write_failure;
  // On a terminal, after a second: how far the run has come, redrawn as rows arrive (not when the
  // rows themselves go to the terminal).
  ProgressLine progress(!args.quiet && !(out_path == "-" && isatty(STDOUT_FILENO)));
  try {
    Simulate(state, opt, [&](double t, const std::vector<double>& v) {
      if (report_data) report_data->Row(t, v);
      if (v.size() != num_written) {
        std::copy(v.begin(), v.begin() + num_written, last.begin());
        csv->Row(t, last);
      } else {
        csv->Row(t, v);
        last = v;
      }
      last_t = t;
      if (progress.Due()) progress.Show(FormatSimulationProgress(t, opt.start, opt.stop, progress.elapsed()));
    }, &stats);
  } catch (const SolverError& e) {
    failure = e.what();
    code = kExitSolver;
  } catch (const CsvWriteError& e) {
    write_failure = e.what();
  } catch (const ModelError& e) {
    failure = e.what();
    code = kExitModel;
  }
  progress.Clear();
  // Every row computed is written (or the write error reported).
  const size_t rows = csv->rows();
  try {
    csv->Close();
  } catch (const CsvWriteError& e) {
    if (write_failure.empty()) write_failure = e.what();
  }
  csv.reset();

  // The report, whatever became of the run: it shows the rows computed and why they end.
  std::string report_line;
  if (report_data) {
    AddRunStats(opt, stats, report_data.get());
    if (!failure.empty()) report_data->notes.push_back("the simulation failed " + failure);
    if (stats.interrupted) report_data->notes.push_back("interrupted at t = " + FormatDouble(stats.interrupted_at));
    if (int rc = SaveReport(args.report, *report_data, &report_line); rc != kExitOk) return rc;
  }

  if (!write_failure.empty()) {
    std::cerr << "momenta: " << write_failure << "\n";
    return kExitSolver;
  }
  if (!failure.empty()) {
    std::cerr << args.model << ": simulation failed " << failure << "\n";
    std::cerr << "  results up to t = " << FormatDouble(last_t) << " are kept in " << out_path << " ("
              << rows << " rows)\n";
    return code;
  }
  // Notes on what initialisation accepted (redundant initial conditions that hold).
  for (const auto& note : report.notes) std::cerr << args.model << ": note: " << note << "\n";
  if (stats.interrupted) {
    std::cerr << args.model << ": interrupted at t = " << FormatDouble(stats.interrupted_at) << "; " << rows
              << " rows kept in " << out_path << " (up to t = " << FormatDouble(last_t) << ")\n";
    return 128 + InterruptSignal();
  }
  if (args.quiet) return kExitOk;
  // With the CSV on standard output, the summary goes to standard error.
  std::ostream& o = out_path == "-" ? std::cerr : std::cout;
  o << model->flat->model_name << " (" << args.model << "): simulated " << FormatDouble(opt.start)
    << " to " << FormatDouble(stats.final_time) << " s\n";
  o << "  build " << Ms(load_s + build_s) << " (load " << Ms(load_s);
  for (const auto& p : report.passes) o << ", " << p.name << " " << Ms(p.seconds);
  o << "); initialise " << Ms(stats.init_seconds) << "; integrate " << Ms(stats.integrate_seconds) << "\n";
  o << "  code: " << loaded.codegen_report.Summary() << "\n";
  o << "  " << model->num_unknowns() << " unknowns (" << model->num_states() << " states), IDA with "
    << stats.linear_solver << " LU" << (SundialsOptimized() ? "" : " (unoptimised SUNDIALS)") << ": "
    << stats.steps << " steps, " << stats.residual_evals << " residual evaluations, "
    << stats.jacobian_evals << " Jacobians, " << stats.error_test_failures << " error-test failures, "
    << stats.nonlinear_failures << " convergence failures\n";
  if (stats.events > 0) {
    o << "  " << stats.events << " events (" << stats.time_events << " time events, " << stats.impacts
      << " impacts), " << stats.restarts << " restarts\n";
  }
  o << "  results: " << out_path << " (" << rows << " rows)\n" << report_line;
  if (!model->output_names.empty()) {
    o << "  final values at t = " << FormatDouble(last_t) << ":\n";
    for (size_t k = 0; k < last.size(); ++k) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.10g", last[k]);
      o << "    " << model->output_names[k] << " = " << buf << "\n";
    }
  }
  return kExitOk;
}

int RunCheck(const CheckArgs& args) {
  LoadedModel loaded;
  if (int code = LoadAndBuild(args.model, args.params, &loaded); code != kExitOk) return code;
  const std::shared_ptr<const CompiledModel>& model = loaded.model;
  const BuildReport& report = loaded.report;
  const double load_s = loaded.load_s;
  std::ostream& o = std::cout;
  o << "model " << model->flat->model_name << " (" << args.model << "): " << report.num_components
    << " components, " << report.num_parameters << " parameters\n";
  char line[256];
  std::snprintf(line, sizeof line, "  %-22s %10s %10s %10s  %s\n", "pass", "time", "unknowns", "equations", "");
  o << line;
  std::snprintf(line, sizeof line, "  %-22s %10s %10s %10s  %s\n", "load", Ms(load_s).c_str(), "", "", "");
  o << line;
  double total = load_s;
  for (const auto& p : report.passes) {
    std::snprintf(line, sizeof line, "  %-22s %10s %10zu %10zu  ", p.name.c_str(), Ms(p.seconds).c_str(),
                  p.variables, p.equations);
    o << line << p.note << "\n";
    total += p.seconds;
  }
  o << "  total " << Ms(total) << (HugePagesInUse() ? "  (memory on huge pages)" : "") << "\n";
  o << "code: " << loaded.codegen_report.Summary() << "\n";
  auto list = [&](const std::string& title, const std::vector<std::string>& names) {
    o << title << " (" << names.size() << ")";
    size_t limit = args.verbose ? names.size() : 20;
    for (size_t k = 0; k < names.size() && k < limit; ++k) o << (k ? ", " : ": ") << names[k];
    if (names.size() > limit) o << ", … (--verbose lists all)";
    o << "\n";
  };
  list("states", report.states);
  if (!report.differentiated.empty() || !report.dummy_derivatives.empty()) {
    o << "index reduction: structural index " << report.structural_index << "\n";
    list("differentiated equations", report.differentiated);
    list("dummy derivatives", report.dummy_derivatives);
    for (const auto& c : report.state_choices) o << "  state choice: " << c << "\n";
  }
  list("outputs", model->output_names);
  list("pruned", report.pruned);
  if (args.verbose) {
    // The DAE as IDA sees it, then the initial conditions, in the user's names.
    ExprNamer names = model->flat->Namer();
    o << "equations for IDA (" << model->num_unknowns() << "):\n";
    for (size_t k = 0; k < model->num_unknowns(); ++k) {
      o << "  0 = " << ToString(*model->pool, model->residual_exprs[k], names) << "\n      from "
        << model->residual_origin(k) << "\n";
    }
    o << "initial equations (" << model->initial_exprs.size() << "):\n";
    for (size_t k = 0; k < model->initial_exprs.size(); ++k) {
      o << "  0 = " << ToString(*model->pool, model->initial_exprs[k], names) << "\n      from "
        << model->initial_origin[k] << "\n";
    }
    if (!model->conditions.empty()) {
      o << "event conditions (" << model->conditions.size() << "), c<k> in the equations:\n";
      for (size_t k = 0; k < model->conditions.size(); ++k) {
        o << "  c" << k << ": " << model->conditions[k].text
          << (model->conditions[k].time_only ? "  (time event)" : "") << "\n";
      }
    }
    if (!model->discrete_equations.empty()) {
      o << "discrete equations, evaluated at events in this order:\n";
      for (const auto& [var, value] : model->discrete_equations) {
        o << "  " << model->flat->VariableName(var) << " = " << ToString(*model->pool, value, names) << "\n";
      }
    }
    for (const auto& w : model->whens) o << "when " << w.text << ": " << w.assigns.size() << " assignments, " << w.reinits.size() << " reinit\n";
    for (const auto& im : model->impacts) o << "impact of " << im.name << ": Newton's law replaces equation " << im.mode_row << "\n";
    o << "outputs:\n";
    for (size_t k = 0; k < model->output_names.size(); ++k) {
      o << "  " << model->output_names[k] << " = " << ToString(*model->pool, model->output_exprs[k], names) << "\n";
    }
  }
  for (const auto& w : report.warnings) o << "warning: " << w << "\n";
  for (const auto& note : report.notes) o << "note: " << note << "\n";
  return kExitOk;
}

int RunList(const std::string& name) {
  const Library& lib = BuiltinLibrary();
  std::ostream& o = std::cout;
  if (name.empty()) {
    std::map<std::string, std::vector<const ComponentType*>> by_file;
    for (const auto& n : lib.ComponentNames()) {
      const ComponentType* t = lib.FindComponent(n);
      by_file[t->loc.file()].push_back(t);
    }
    size_t width = 0;  // the names in one column, two spaces after the longest
    for (const auto& n : lib.ComponentNames()) width = std::max(width, n.size());
    for (const auto& [file, types] : by_file) {
      o << file << "\n";
      for (const ComponentType* t : types) {
        o << "  " << t->name << std::string(width + 2 - t->name.size(), ' ') << t->doc << "\n";
      }
    }
    o << "connectors: " << JoinNames(lib.ConnectorNames()) << "\n";
    return kExitOk;
  }
  const ComponentType* t = lib.FindComponent(name);
  if (!t) {
    if (const ConnectorType* c = lib.FindConnector(name)) {
      o << c->name << " (connector): " << c->doc << "\n";
      for (const auto& v : c->potentials) o << "  potential " << v.name << " [" << v.unit << "]: " << v.doc << "\n";
      for (const auto& v : c->flows) o << "  flow " << v.name << " [" << v.unit << "]: " << v.doc << "\n";
      if (c->is_signal) o << "  signal " << (c->is_input ? "input" : "output") << " of type " << ValueTypeName(c->signal_type) << "\n";
      return kExitOk;
    }
    auto close = ClosestNames(name, lib.ComponentNames());
    std::cerr << "momenta: no component named '" << name << "'"
              << (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") << " (valid: "
              << JoinNames(lib.ComponentNames(), 200) << ")\n";
    return kExitUsage;
  }
  o << t->name << ": " << t->doc << "\n";
  if (!t->parameters.empty()) o << "parameters:\n";
  for (const auto& p : t->parameters) {
    o << "  " << p.name << " = " << p.value_text << (p.unit.empty() ? "" : " [" + p.unit + "]");
    if (p.min) o << ", min " << FormatDouble(*p.min);
    if (p.max) o << ", max " << FormatDouble(*p.max);
    o << (p.doc.empty() ? "" : ": " + p.doc) << "\n";
  }
  if (!t->tables.empty()) o << "tables (sized by their value):\n";
  for (const auto& p : t->tables) {
    o << "  " << p.name << " = " << p.value_text << (p.unit.empty() ? "" : " [" + p.unit + "]") << (p.doc.empty() ? "" : ": " + p.doc) << "\n";
  }
  if (!t->connectors.empty()) o << "connectors:\n";
  for (const auto& c : t->connectors) {
    o << "  " << c.name << ": " << c.type << (c.condition.empty() ? "" : " if " + c.condition)
      << (c.doc.empty() ? "" : " — " + c.doc) << "\n";
  }
  if (!t->variables.empty()) o << "variables:\n";
  for (const auto& v : t->variables) {
    o << "  " << v.name << (v.unit.empty() ? "" : " [" + v.unit + "]") << (v.doc.empty() ? "" : ": " + v.doc) << "\n";
  }
  o << "equations:\n";
  for (const auto& e : t->equations) o << "  " << e.text << "\n";
  for (const auto& e : t->initial_equations) o << "  initial: " << e.text << "\n";
  return kExitOk;
}

}  // namespace momenta
