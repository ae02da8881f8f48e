// `momenta accuracy MODEL`: the model built once and run at each tolerance of the range (a copy of
// its state each time), every run's rows kept in memory and compared with the reference (a result
// file, or a run 100 times tighter than the tightest), the costs measured around each run, and the
// work-precision table printed, written and drawn.

#include "app/accuracy_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/csv_writer.h"
#include "app/plot.h"
#include "app/report_command.h"
#include "core/base/messages.h"
#include "core/lang/units.h"
#include "solver/simulator.h"

namespace momenta {

namespace {

/// The tightest tolerance a study runs at (its computed reference included): a decade above
/// kMinRelTolerance, where IDA still converges on ordinary models.
constexpr double kTightestTolerance = 1e-14;

/// A run shorter than this [s] is timed three times, the best kept.
constexpr double kRepeatBelow = 0.5;

/// One run of the study.
struct AccuracyRun {
  double rtol = 0;
  ResultTable rows;  ///< its output rows
  SolverStats stats;
  double seconds = 0;  ///< wall time of the run (initialisation and integration)
  double error = NAN;
  std::string failure;  ///< the solver's message when it failed
};

/// Runs a copy of the model's state at `rtol` (and atol = rtol) and keeps every row.
AccuracyRun RunAt(const LoadedModel& loaded, SimulationOptions opt, double rtol) {
  AccuracyRun run;
  run.rtol = rtol;
  opt.rtol = rtol;
  opt.atol = -1;  // atol follows rtol
  run.rows.names = loaded.model->output_names;
  run.rows.values.resize(run.rows.names.size());
  ModelState state = *loaded.state;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    Simulate(&state, opt, [&run](double t, const std::vector<double>& v) {
      run.rows.time.push_back(t);
      for (size_t k = 0; k < v.size(); ++k) run.rows.values[k].push_back(v[k]);
    }, &run.stats);
  } catch (const SolverError& e) {
    run.failure = e.what();
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // On a shared machine one run's wall time includes waiting for a core: a short run is timed
  // twice more and the best time kept.
  for (int repeat = 0; repeat < 2 && run.failure.empty() && run.seconds < kRepeatBelow; ++repeat) {
    ModelState again = *loaded.state;
    SolverStats stats;
    const auto t1 = std::chrono::steady_clock::now();
    Simulate(&again, opt, [](double, const std::vector<double>&) {}, &stats);
    run.seconds = std::min(run.seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
  }
  return run;
}

/// Whether row i of `time` is one of an event's two rows.
bool AtEvent(const std::vector<double>& time, size_t i) {
  return (i > 0 && time[i - 1] == time[i]) || (i + 1 < time.size() && time[i + 1] == time[i]);
}

/// The reference's value of column c at t, linearly interpolated; false when t is outside its
/// span or at one of its events.
bool ReferenceAt(const ResultTable& ref, size_t c, double t, double* value) {
  const std::vector<double>& time = ref.time;
  const auto it = std::lower_bound(time.begin(), time.end(), t);
  if (it == time.end()) return false;
  const auto i = static_cast<size_t>(it - time.begin());
  if (*it == t) {
    if (AtEvent(time, i)) return false;
    *value = ref.values[c][i];
    return true;
  }
  if (i == 0) return false;
  const double w = (t - time[i - 1]) / (time[i] - time[i - 1]);
  *value = (1 - w) * ref.values[c][i - 1] + w * ref.values[c][i];
  return true;
}

/// "5.2e-3" style, three significant digits.
std::string Short(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

/// The table as the terminal shows it.
std::string TableText(const std::vector<AccuracyRun>& runs) {
  std::ostringstream o;
  char line[160];
  std::snprintf(line, sizeof line, "  %8s  %10s  %12s  %9s  %11s\n", "rtol", "error", "time [ms]", "steps",
                "residuals");
  o << line;
  for (const AccuracyRun& r : runs) {
    std::snprintf(line, sizeof line, "  %8.0e  %10s  %12.3f  %9ld  %11ld%s\n", r.rtol, Short(r.error).c_str(),
                  r.seconds * 1e3, r.stats.steps, r.stats.residual_evals, r.failure.empty() ? "" : "  (failed)");
    o << line;
  }
  return o.str();
}

/// Writes the table as CSV: rtol, error, wall time, steps, residual evaluations, Jacobians.
void WriteTable(const std::string& path, const std::vector<AccuracyRun>& runs) {
  std::ofstream f(path);
  f << "rtol,error,wall_time_s,steps,residual_evals,jacobian_evals\n";
  for (const AccuracyRun& r : runs) {
    f << FormatDouble(r.rtol) << "," << (std::isfinite(r.error) ? FormatDouble(r.error) : "") << ","
      << FormatDouble(r.seconds) << "," << r.stats.steps << "," << r.stats.residual_evals << ","
      << r.stats.jacobian_evals << "\n";
  }
  f.flush();
  if (!f) throw CsvWriteError("cannot write the table " + path);
}

/// The gnuplot program of the work-precision plot: error against residual evaluations (left
/// axis) and wall time (right axis), both logarithmic, each point labelled with its rtol.
std::string WorkPrecisionScript(const std::string& title, const std::vector<AccuracyRun>& runs, bool png) {
  std::ostringstream g;
  g.precision(17);
  g << "set terminal " << (png ? "pngcairo" : "svg dynamic") << " noenhanced size 900,500 font 'sans,11'\n";
  g << "$momenta_text << EOD\n" << GnuplotTextLine(title) << "\nEOD\nset title $momenta_text[1][2:]\n";
  g << "set logscale xy\nset logscale y2\nset grid\nset key top right\nset format x '%.0e'\n"
       "set xlabel 'error (relative to the largest magnitude of each output)'\nset ylabel 'residual evaluations'\n"
       "set y2label 'wall time [ms]'\nset ytics nomirror\nset y2tics\n";
  g << "$momenta << EOD\n";
  for (const AccuracyRun& r : runs) {
    if (!(r.error > 0) || !r.failure.empty()) continue;
    char label[16];
    std::snprintf(label, sizeof label, "%.0e", r.rtol);
    g << r.error << ' ' << r.stats.residual_evals << ' ' << r.seconds * 1e3 << ' ' << label << '\n';
  }
  g << "EOD\nplot $momenta using 1:2 with linespoints pointtype 7 title 'residual evaluations', "
       "$momenta using 1:2:4 with labels offset 0,1 notitle, "
       "$momenta using 1:3 axes x1y2 with linespoints pointtype 6 dashtype 2 title 'wall time'\n";
  return g.str();
}

/// The reference's columns that the model outputs (`*columns` the run's, `*ref_columns` the
/// reference's); throws UsageError when it has none of them.
void MatchColumns(const std::string& path, const std::vector<std::string>& outputs, const ResultTable& ref,
                  std::vector<size_t>* columns, std::vector<size_t>* ref_columns) {
  for (size_t k = 0; k < outputs.size(); ++k) {
    const auto it = std::find(ref.names.begin(), ref.names.end(), outputs[k]);
    if (it == ref.names.end()) continue;
    columns->push_back(k);
    ref_columns->push_back(static_cast<size_t>(it - ref.names.begin()));
  }
  if (columns->empty()) {
    throw UsageError("momenta: --reference " + path + " has none of the model's outputs (its columns: " +
                     JoinNames(ref.names, 10) + "; the model's outputs: " + JoinNames(outputs, 10) + ")");
  }
}

/// The study under way: the model, the run's options, the reference and the runs.
struct Study {
  LoadedModel loaded;
  SimulationOptions opt;
  std::vector<double> tolerances;
  ResultTable reference;
  std::vector<size_t> columns, ref_columns;  ///< the outputs compared, in the runs and the reference
  std::string reference_text;                ///< what the reference is, in words
  AccuracyRun reference_run;                 ///< the computed reference (no --reference)
  std::vector<AccuracyRun> runs;
};

/// The reference: the file given, or a run 100 times tighter than the tightest. Throws
/// UsageError for a file that cannot be read or holds none of the outputs, and returns the
/// reference run's failure ("" when none).
std::string FindReference(const AccuracyArgs& args, Study* study) {
  const std::vector<std::string>& outputs = study->loaded.model->output_names;
  if (!args.reference.empty()) {
    try {
      study->reference = ReadResult(args.reference);
    } catch (const std::runtime_error& e) {
      throw UsageError("momenta: --reference " + args.reference + ": " + e.what());
    }
    study->reference_text = "the result file " + args.reference;
    MatchColumns(args.reference, outputs, study->reference, &study->columns, &study->ref_columns);
    return "";
  }
  const double tight = std::max(study->tolerances.back() / 100, kTightestTolerance);
  if (tight >= study->tolerances.back()) {
    throw UsageError("momenta: --rtol " + args.rtol + ": too tight for a computed reference (its run would be at " +
                     Short(tight) + "); give --reference");
  }
  study->reference_run = RunAt(study->loaded, study->opt, tight);
  study->reference = study->reference_run.rows;
  study->reference_text = "a run at rtol " + Short(tight) + " (no --reference given)";
  for (size_t k = 0; k < outputs.size(); ++k) {
    study->columns.push_back(k);
    study->ref_columns.push_back(k);
  }
  return study->reference_run.failure;
}

/// The study's header and table, as the terminal shows them.
void PrintStudy(std::ostream& o, const AccuracyArgs& args, const Study& study) {
  o << study.loaded.model->flat->model_name << " (" << args.model << "): work-precision from "
    << FormatDouble(study.opt.start) << " to " << FormatDouble(study.opt.stop) << " s, atol = rtol\n"
    << "  reference: " << study.reference_text << "\n"
    << "  error: the largest |y - y_ref| over " << Counted(study.columns.size(), "output")
    << " and the output rows, relative to each output's largest |y_ref|; time: wall time, the best of 3 "
       "for runs under 0.5 s\n"
    << TableText(study.runs);
  for (const AccuracyRun& r : study.runs) {
    if (!r.failure.empty()) o << "  rtol " << Short(r.rtol) << " failed " << r.failure << "\n";
  }
}

/// The HTML report: the reference's curves, the model, and the table among the solver's lines.
int SaveStudyReport(const AccuracyArgs& args, const Study& study) {
  ReportData report = ReportFromModel(args.model, study.loaded);
  if (!args.reference.empty()) {
    report.result_file = args.reference;
  } else {
    SimulationOptions reference_options = study.opt;
    reference_options.rtol = study.reference_run.rtol;
    AddRunStats(reference_options, study.reference_run.stats, &report);
  }
  report.columns = study.reference.names;
  report.units = OutputUnits(*study.loaded.model->flat, study.reference.names);
  report.num_plotted = study.reference.names.size();
  report.time = study.reference.time;
  report.values = study.reference.values;
  report.notes.push_back("work-precision: the plots show the reference, " + study.reference_text);
  for (const AccuracyRun& r : study.runs) {
    report.solver.push_back({"rtol " + Short(r.rtol), "error " + Short(r.error) + " · " + FormatMs(r.seconds) +
                                                          " · " + std::to_string(r.stats.steps) + " steps · " +
                                                          std::to_string(r.stats.residual_evals) + " residuals" +
                                                          (r.failure.empty() ? "" : " · failed")});
  }
  std::string line;
  if (int code = SaveReport(args.report, report, &line); code != kExitOk) return code;
  std::cout << line;
  return kExitOk;
}

}  // namespace

std::vector<double> ToleranceRange(const std::string& text) {
  const size_t colon = text.find(':');
  const std::string first = text.substr(0, colon), last = colon == std::string::npos ? first : text.substr(colon + 1);
  auto parse = [&text](const std::string& part) {
    std::optional<double> v;
    try {
      v = ParseDecimal(part);
    } catch (const std::exception&) {
      v.reset();
    }
    if (!v || !(*v >= kTightestTolerance && *v < 1)) {
      throw UsageError("momenta: --rtol " + text + ": '" + part + "' is not a tolerance from 1e-14 to below 1 "
                       "(give LOOSE:TIGHT, e.g. 1e-3:1e-10)");
    }
    return *v;
  };
  const double loose = std::max(parse(first), parse(last)), tight = std::min(parse(first), parse(last));
  if (loose / tight > 1.01e15) throw UsageError("momenta: --rtol " + text + ": more than 15 decades");
  std::vector<double> range;
  for (int k = 0; loose * std::pow(10.0, -k) >= tight * (1 - 1e-9); ++k) range.push_back(loose * std::pow(10.0, -k));
  return range;
}

double ResultError(const ResultTable& run, const std::vector<size_t>& columns, const ResultTable& reference,
                   const std::vector<size_t>& ref_columns) {
  double error = NAN;
  for (size_t k = 0; k < columns.size(); ++k) {
    const std::vector<double>& ref = reference.values[ref_columns[k]];
    double scale = 0;
    for (double v : ref) scale = std::max(scale, std::fabs(v));
    if (!(scale > 0) || !std::isfinite(scale)) scale = 1;
    for (size_t i = 0; i < run.time.size(); ++i) {
      double value = 0;
      if (AtEvent(run.time, i) || !ReferenceAt(reference, ref_columns[k], run.time[i], &value)) continue;
      const double e = std::fabs(run.values[columns[k]][i] - value) / scale;
      error = std::isnan(error) ? e : std::max(error, e);
    }
  }
  return error;
}

int RunAccuracy(const AccuracyArgs& args) {
  // The options first, then the model and the reference.
  Study study;
  const std::string plot = args.out.empty() ? FileStem(args.model) + ".accuracy.svg" : args.out;
  const bool png = plot.size() > 4 && plot.compare(plot.size() - 4, 4, ".png") == 0;
  try {
    study.tolerances = ToleranceRange(args.rtol);
    if (!png && !(plot.size() > 4 && plot.compare(plot.size() - 4, 4, ".svg") == 0)) {
      throw UsageError("momenta: -o " + plot + ": the plot is written as SVG or PNG, chosen by the extension");
    }
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return kExitUsage;
  }
  if (int code = LoadAndBuild(args.model, args.params, &study.loaded); code != kExitOk) return code;
  if (int code = ResolveRunOptions(args.model, study.loaded, {}, &study.opt); code != kExitOk) return code;
  try {
    if (std::string failure = FindReference(args, &study); !failure.empty()) {
      std::cerr << args.model << ": the reference run at rtol " << Short(study.reference_run.rtol) << " failed "
                << failure << "\n";
      return kExitSolver;
    }
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return kExitUsage;
  }

  // The runs, each compared with the reference as it ends.
  for (double rtol : study.tolerances) {
    study.runs.push_back(RunAt(study.loaded, study.opt, rtol));
    AccuracyRun& run = study.runs.back();
    run.error = ResultError(run.rows, study.columns, study.reference, study.ref_columns);
    run.rows = {};  // the table needs no more of it
  }

  // The table, on the terminal and as CSV; the plot; the report.
  PrintStudy(std::cout, args, study);
  try {
    if (!args.table.empty()) WriteTable(args.table, study.runs);
  } catch (const CsvWriteError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitSolver;
  }
  const std::string title = study.loaded.model->flat->model_name + ": work-precision (" + study.reference_text + ")";
  if (std::string failure = RunGnuplot(WorkPrecisionScript(title, study.runs, png), plot); !failure.empty()) {
    std::cerr << "momenta: " << failure << "\n";
    return kExitSolver;
  }
  std::cout << "  plot: " << plot << (args.table.empty() ? "" : ", table: " + args.table) << "\n";
  return args.report.empty() ? kExitOk : SaveStudyReport(args, study);
}

}  // namespace momenta
