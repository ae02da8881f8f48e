// `momenta simulate MODEL`: load and build the model, integrate it, write every row computed (CSV
// or MAT, with the units file beside a CSV), optionally the HTML report, and print a summary. Rows
// computed before a solver failure, a write failure or an interrupt are kept and said so.

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "app/csv_writer.h"
#include "app/interrupt.h"
#include "app/mat_writer.h"
#include "app/progress.h"
#include "app/report_command.h"
#include "solver/simulator.h"

namespace momenta {

namespace {

std::string Ms(double seconds) { return FormatMs(seconds); }

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

/// The results file for `names`: MAT v4 for a .mat path, else CSV with its units file beside it
/// (not for standard output). Throws ResultWriteError when it cannot be opened.
std::unique_ptr<ResultWriter> OpenResults(const std::string& path, const std::vector<std::string>& names,
                                          const LoadedModel& loaded, const SimulationOptions& opt) {
  const CompiledModel& model = *loaded.model;
  if (IsMatPath(path)) {
    return std::make_unique<MatWriter>(path, names, MatParameters(model, *loaded.state), opt.start,
                                       opt.stop, OutputUnits(*model.flat, names));
  }
  auto csv = std::make_unique<CsvWriter>(path, names);
  if (path != "-") WriteUnitsFile(UnitsPath(path), names, OutputUnits(*model.flat, names));
  return csv;
}

/// What became of a run: its statistics, the last row written and why it ended early, if it did.
struct RunOutcome {
  SolverStats stats;
  std::vector<double> last;  ///< the last row's written values
  double last_t = 0;
  size_t rows = 0;
  int code = kExitOk;
  std::string failure;        ///< the solver's or the model's message
  std::string write_failure;  ///< the results file's
};

/// Integrates, writing each row's first `last.size()` values to `results` (and every value to the
/// report); closes the results file whatever happens.
RunOutcome Integrate(ModelState* state, const SimulationOptions& opt, ResultWriter* results,
                     size_t num_written, ReportData* report, bool show_progress) {
  RunOutcome run;
  run.last.resize(num_written);
  run.last_t = opt.start;
  // On a terminal, after a second: how far the run has come, redrawn as rows arrive.
  ProgressLine progress(show_progress);
  try {
    Simulate(state, opt, [&](double t, const std::vector<double>& v) {
      if (report) report->Row(t, v);
      if (v.size() != num_written) {
        std::copy(v.begin(), v.begin() + num_written, run.last.begin());
        results->Row(t, run.last);
      } else {
        results->Row(t, v);
        run.last = v;
      }
      run.last_t = t;
      if (progress.Due()) progress.Show(FormatSimulationProgress(t, opt.start, opt.stop, progress.elapsed()));
    }, &run.stats);
  } catch (const SolverError& e) {
    run.failure = e.what();
    run.code = kExitSolver;
  } catch (const CsvWriteError& e) {
    run.write_failure = e.what();
  } catch (const ModelError& e) {
    run.failure = e.what();
    run.code = kExitModel;
  }
  progress.Clear();
  // Every row computed is written (or the write error reported).
  run.rows = results->rows();
  try {
    results->Close();
  } catch (const CsvWriteError& e) {
    if (run.write_failure.empty()) run.write_failure = e.what();
  }
  return run;
}

/// The summary of a finished run: times, code, solver statistics, events and final values.
void PrintSummary(std::ostream& o, const SimulateArgs& args, const LoadedModel& loaded,
                  const SimulationOptions& opt, const RunOutcome& run, const std::string& out_path,
                  const std::string& report_line) {
  const CompiledModel& model = *loaded.model;
  const SolverStats& stats = run.stats;
  o << model.flat->model_name << " (" << args.model << "): simulated " << FormatDouble(opt.start)
    << " to " << FormatDouble(stats.final_time) << " s\n";
  o << "  build " << Ms(loaded.load_s + loaded.build_s) << " (load " << Ms(loaded.load_s);
  for (const auto& p : loaded.report.passes) o << ", " << p.name << " " << Ms(p.seconds);
  o << "); initialise " << Ms(stats.init_seconds) << "; integrate " << Ms(stats.integrate_seconds) << "\n";
  o << "  code: " << loaded.codegen_report.Summary() << "\n";
  o << "  " << model.num_unknowns() << " unknowns (" << model.num_states() << " states), IDA with "
    << stats.linear_solver << " LU" << (SolverBuildInfo().sundials_optimized ? "" : " (unoptimised SUNDIALS)") << ": "
    << stats.steps << " steps, " << stats.residual_evals << " residual evaluations, "
    << stats.jacobian_evals << " Jacobians, " << stats.error_test_failures << " error-test failures, "
    << stats.nonlinear_failures << " convergence failures\n";
  if (!stats.cost_note.empty()) o << "  note: " << stats.cost_note << "\n";
  if (stats.events > 0) {
    o << "  " << stats.events << " events (" << stats.time_events << " time events, " << stats.impacts
      << " impacts), " << stats.restarts << " restarts";
    if (stats.quiet_crossings) o << "; " << stats.quiet_crossings << " quiet crossings (no restart)";
    o << "\n";
  }
  o << "  results: " << out_path << " (" << run.rows << " rows)\n" << report_line;
  if (!model.output_names.empty()) {
    o << "  final values at t = " << FormatDouble(run.last_t) << ":\n";
    for (size_t k = 0; k < run.last.size(); ++k) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.10g", run.last[k]);
      o << "    " << model.output_names[k] << " = " << buf << "\n";
    }
  }
}

/// The exit code of a run that wrote its rows, after saying why it ended early if it did.
int ReportEnding(const SimulateArgs& args, const RunOutcome& run, const std::string& out_path) {
  if (!run.write_failure.empty()) {
    std::cerr << "momenta: " << run.write_failure << "\n";
    return kExitSolver;
  }
  if (!run.failure.empty()) {
    std::cerr << args.model << ": simulation failed " << run.failure << "\n";
    std::cerr << "  results up to t = " << FormatDouble(run.last_t) << " are kept in " << out_path << " ("
              << run.rows << " rows)\n";
    return run.code;
  }
  if (run.stats.interrupted) {
    std::cerr << args.model << ": interrupted at t = " << FormatDouble(run.stats.interrupted_at) << "; "
              << run.rows << " rows kept in " << out_path << " (up to t = " << FormatDouble(run.last_t)
              << ")\n";
    return 128 + InterruptSignal();
  }
  return kExitOk;
}

}  // namespace

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
  const CompiledModel& model = *loaded.model;
  // The results file holds the model's outputs (and with --scene-columns the scene's too).
  ResolveSceneColumns(model.output_names, &loaded.scene);
  const size_t num_written = args.scene_columns || !loaded.with_scene ? model.output_names.size()
                                                                      : loaded.scene.num_model_columns;
  const std::vector<std::string> written_names(model.output_names.begin(), model.output_names.begin() + num_written);
  std::unique_ptr<ReportData> report_data;
  if (!args.report.empty()) {
    report_data = std::make_unique<ReportData>(ReportFromModel(args.model, loaded));
    report_data->columns = model.output_names;
    report_data->units = OutputUnits(*model.flat, model.output_names);
    report_data->num_plotted = loaded.scene.num_model_columns;
    report_data->scene = loaded.scene;
  }
  SimulationOptions opt;
  if (int code = ResolveRunOptions(args.model, loaded, args.options, &opt); code != kExitOk) return code;

  // From here on SIGINT and SIGTERM stop the run between steps and keep its rows.
  InstallInterruptHandler();
  opt.interrupt = &InterruptRequested();
  const std::string out_path = args.out.empty() ? FileStem(args.model) + ".csv" : args.out;
  if (std::string space = ResultSpaceProblem(out_path, opt, num_written); !space.empty()) {
    std::cerr << "momenta: --interval " << FormatDouble(opt.interval) << " from " << FormatDouble(opt.start)
              << " to " << FormatDouble(opt.stop) << " s: " << space << "; choose a larger --interval\n";
    return kExitUsage;
  }
  std::unique_ptr<ResultWriter> results;
  try {
    results = OpenResults(out_path, written_names, loaded, opt);
  } catch (const ResultWriteError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitSolver;
  }
  // No progress line when the rows themselves go to the terminal.
  const bool show_progress = !args.quiet && !(out_path == "-" && isatty(STDOUT_FILENO));
  const RunOutcome run = Integrate(loaded.state.get(), opt, results.get(), num_written, report_data.get(),
                                   show_progress);
  results.reset();

  // The report, whatever became of the run: it shows the rows computed and why they end.
  std::string report_line;
  if (report_data) {
    AddRunStats(opt, run.stats, report_data.get());
    if (!run.failure.empty()) report_data->notes.push_back("the simulation failed " + run.failure);
    if (run.stats.interrupted) {
      report_data->notes.push_back("interrupted at t = " + FormatDouble(run.stats.interrupted_at));
    }
    if (int rc = SaveReport(args.report, *report_data, &report_line); rc != kExitOk) return rc;
  }
  if (!run.write_failure.empty() || !run.failure.empty()) return ReportEnding(args, run, out_path);
  // Notes on what initialisation accepted (redundant initial conditions that hold).
  for (const auto& note : loaded.report.notes) std::cerr << args.model << ": note: " << note << "\n";
  if (run.stats.interrupted) return ReportEnding(args, run, out_path);
  if (args.quiet) return kExitOk;
  // With the CSV on standard output, the summary goes to standard error.
  PrintSummary(out_path == "-" ? std::cerr : std::cout, args, loaded, opt, run, out_path, report_line);
  return kExitOk;
}

}  // namespace momenta
