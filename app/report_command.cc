#include "app/report_command.h"

#include <chrono>
#include <iostream>
#include <sstream>

#include "app/csv_writer.h"
#include "app/result_reader.h"
#include "solver/simulator.h"

namespace momenta {

ReportData ReportFromModel(const std::string& model_path, const LoadedModel& loaded) {
  const CompiledModel& model = *loaded.model;
  ReportData d;
  d.model_name = model.flat->model_name;
  d.model_file = model_path;
  d.doc = loaded.doc;
  const std::vector<double>& values = loaded.state->parameter_values();
  for (size_t k = 0; k < model.flat->parameters.size() && k < values.size(); ++k) {
    const ParamId p(static_cast<uint32_t>(k));
    d.parameters.push_back({model.flat->ParameterName(p), model.flat->ParameterUnit(p), model.flat->ParameterDoc(p), values[k]});
  }
  const BuildReport& r = loaded.report;
  d.build.push_back({"components", std::to_string(r.num_components)});
  d.build.push_back({"unknowns (states)", std::to_string(model.num_unknowns()) + " (" +
                                              std::to_string(model.num_states()) + ")"});
  d.build.push_back({"load", FormatMs(loaded.load_s)});
  for (const auto& p : r.passes)
    d.build.push_back({p.name, FormatMs(p.seconds) + (p.note.empty() ? "" : " · " + p.note)});
  d.build.push_back({"build in all", FormatMs(loaded.load_s + loaded.build_s)});
  for (const auto& w : r.warnings) d.notes.push_back("warning: " + w);
  return d;
}

void AddRunStats(const SimulationOptions& o, const SolverStats& s, ReportData* d) {
  ReportTable& t = d->solver;
  t.push_back({"interval", FormatDouble(o.start) + " to " + FormatDouble(s.final_time) +
                               " s, output every " + FormatDouble(o.interval) + " s"});
  t.push_back({"tolerances", "rtol " + FormatDouble(o.rtol) + ", atol " + FormatDouble(o.atol)});
  const SolverBuild build = SolverBuildInfo();
  t.push_back({"integrator", "IDA (SUNDIALS " + build.sundials_version +
                                 (build.sundials_optimized ? "" : ", unoptimised") + "), " + s.linear_solver + " LU"});
  t.push_back({"initialise", FormatMs(s.init_seconds)});
  t.push_back({"integrate", FormatMs(s.integrate_seconds)});
  t.push_back({"steps", std::to_string(s.steps)});
  t.push_back({"residual evaluations", std::to_string(s.residual_evals)});
  t.push_back({"Jacobians", std::to_string(s.jacobian_evals)});
  t.push_back({"error-test failures", std::to_string(s.error_test_failures)});
  t.push_back({"convergence failures", std::to_string(s.nonlinear_failures)});
  t.push_back({"events", std::to_string(s.events) + " (" + std::to_string(s.time_events) + " time events, " +
                             std::to_string(s.impacts) + " impacts), " + std::to_string(s.restarts) + " restarts, " +
                             std::to_string(s.quiet_crossings) + " quiet crossings (no restart)"});
}

int SaveReport(const std::string& path, const ReportData& data, std::string* summary) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string html;
  try {
    html = ReportHtml(data);
    WriteReport(path, html);
  } catch (const ResultWriteError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitSolver;
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ostringstream line;
  line << "  report: " << path << " (" << (html.size() + 512) / 1024 << " KiB, " << data.time.size()
       << " rows, " << data.scene.shapes.size() << " scene shapes; written in " << FormatMs(s)
       << ")\n";
  *summary = line.str();
  if (!ReportHasPlots()) {
    std::cerr
        << "momenta: note: this build has no uPlot (run scripts/setup.sh and rebuild): the report "
        << path << " has no plots\n";
  }
  return kExitOk;
}

int RunReport(const ReportArgs& args) {
  // The result first: a missing or broken file is found before the model is built.
  ResultTable result;
  try {
    result = ReadResult(args.result);
  } catch (const std::runtime_error& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  // The model gives the name, doc, parameters and geometry; its scene is drawn when the result
  // holds the scene's columns (simulate --scene-columns writes them).
  LoadedModel loaded;
  loaded.with_scene = true;
  if (int code = LoadAndBuild(args.model, args.params, &loaded); code != kExitOk) return code;
  ReportData d = ReportFromModel(args.model, loaded);
  d.result_file = args.result;
  d.scene = loaded.scene;
  d.columns = result.names;
  d.units = OutputUnits(*loaded.model->flat, d.columns);
  d.time = std::move(result.time);
  d.values = std::move(result.values);
  // Plotted: the model's own outputs the result holds, in the result's order; then the rest.
  const size_t before = d.scene.shapes.size();
  const size_t dropped = ResolveSceneColumns(d.columns, &d.scene);
  if (dropped > 0) {
    d.notes.push_back("the result holds the positions of " + std::to_string(before - dropped) +
                      " of the scene's " + std::to_string(before) +
                      " shapes (simulate with --scene-columns to record them all)");
  }
  d.num_plotted = d.scene.num_model_columns;
  d.solver.push_back(
      {"solver statistics", "not recorded in a result file (simulate --report records them)"});
  const std::string out = args.out.empty() ? WithExtension(args.result, ".html") : args.out;
  std::string summary;
  const int code = SaveReport(out, d, &summary);
  std::cout << summary;
  return code;
}

}  // namespace momenta
