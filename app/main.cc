// momenta: acausal component models from YAML, simulated with SUNDIALS IDA.
// main stays thin: parse the command line, dispatch, return the exit code.

#include <CLI/CLI.hpp>

#include <iostream>

#include "app/commands.h"
#include "app/huge_pages.h"
#include "app/plot.h"
#include "app/report_command.h"
#include "app/sweep.h"
#include "solver/simulator.h"

int main(int argc, char** argv) {
  using namespace momenta;
  MaybeRestartWithHugePages(argc, argv);
  CLI::App app{"momenta: acausal component-model simulation (YAML models, SUNDIALS IDA)"};
  app.require_subcommand(1);
  const SolverBuild solver_build = SolverBuildInfo();
  app.set_version_flag("--version", "momenta 0.1 (SUNDIALS " + solver_build.sundials_version +
                                        (solver_build.sundials_optimized ? ", optimised build)" : ", Debian build)"));

  SimulateArgs sim;
  auto* simulate = app.add_subcommand("simulate", "simulate a model and write its outputs as CSV (or a MAT v4 result file: -o FILE.mat)");
  simulate->add_option("model", sim.model, "model file (YAML)")->required();
  simulate->add_option("-p,--param", sim.params, "override a parameter: NAME=VALUE (repeatable)");
  // Values not given stay empty (the experiment's apply); given ones are checked in RunSimulate.
  auto number = [&](const char* name, std::optional<double>* to, const char* help) {
    simulate->add_option_function<double>(name, [to](const double& v) { *to = v; }, help);
  };
  number("--stop", &sim.options.stop, "stop time [s]");
  number("--rtol", &sim.options.rtol, "relative tolerance");
  number("--atol", &sim.options.atol, "absolute tolerance (scaled by each variable's nominal)");
  number("--interval", &sim.options.interval, "output interval [s]");
  number("--max-order", &sim.options.max_order,
         "IDA's maximum BDF order, 1 to 5 (default: the experiment's max_order, else 5; 2 or 3 for lightly "
         "damped oscillations)");
  simulate->add_option("-o,--out", sim.out, "results file (CSV; '-' for standard output)");
  simulate->add_option("--linear-solver", sim.options.linear_solver, "auto, dense or klu")
      ->check(CLI::IsMember({"auto", "dense", "klu"}));
  simulate->add_option("--codegen", sim.options.codegen,
                       "auto (native code where it pays), native (compile the model to native code) or interp")
      ->check(CLI::IsMember({"auto", "native", "interp"}));
  simulate->add_flag("-q,--quiet", sim.quiet, "print nothing on success");
  simulate->add_option("--report", sim.report, "also write an HTML report (plots, statistics, the scene's animation)");
  simulate->add_flag("--scene-columns", sim.scene_columns,
                     "also write the quantities the scene is drawn from into the results file (for momenta report)");

  ReportArgs rep;
  auto* report = app.add_subcommand("report", "write the HTML report of a result file simulate wrote");
  report->add_option("result", rep.result, "result file (CSV or MAT)")->required();
  report->add_option("-m,--model", rep.model, "the model file the result was simulated from")->required();
  report->add_option("-p,--param", rep.params, "the -p values it was simulated with (repeatable)");
  report->add_option("-o,--out", rep.out, "the report (default: <result stem>.html)");

  PlotArgs plt;
  auto* plot = app.add_subcommand("plot", "plot columns of a result file as SVG or PNG (with gnuplot)");
  plot->add_option("result", plt.result, "result file (CSV or MAT)")->required();
  plot->add_option("-y", plt.columns, "columns to plot: A.v,B.v (repeatable)")->required();
  plot->add_option("-o,--out", plt.out, "the image, .svg or .png (default: <result stem>.svg)");
  plot->add_option("--title", plt.title, "title (default: the result's file name)");
  plot->add_option("--width", plt.width, "width in pixels (height: 5/9 of it)")->check(CLI::Range(200, 8000));

  CheckArgs chk;
  auto* check = app.add_subcommand("check", "validate a model and show what each pass made of it");
  check->add_option("model", chk.model, "model file (YAML)")->required();
  check->add_option("-p,--param", chk.params, "override a parameter: NAME=VALUE (repeatable)");
  check->add_flag("-v,--verbose", chk.verbose, "list every state and pruned variable");

  SweepArgs swp;
  auto* sweep = app.add_subcommand("sweep", "simulate a model for many parameter values on several threads (and MPI ranks under mpirun)");
  sweep->add_option("model", swp.model, "model file (YAML)")->required();
  sweep->add_option("-p,--param", swp.params,
                    "NAME=SPEC: a value, a list a,b,c, a grid a:b:n or a:b:log:n, normal(mu,sigma) or "
                    "uniform(a,b) (repeatable; lists and grids combine as a Cartesian product)");
  auto sweep_number = [&](const char* name, std::optional<double>* to, const char* help) {
    sweep->add_option_function<double>(name, [to](const double& v) { *to = v; }, help);
  };
  sweep_number("--stop", &swp.options.stop, "stop time [s]");
  sweep_number("--rtol", &swp.options.rtol, "relative tolerance");
  sweep_number("--atol", &swp.options.atol, "absolute tolerance (scaled by each variable's nominal)");
  sweep_number("--interval", &swp.options.interval, "output interval [s]");
  sweep_number("--max-order", &swp.options.max_order, "IDA's maximum BDF order, 1 to 5 (default: the experiment's max_order, else 5)");
  sweep->add_option("--linear-solver", swp.options.linear_solver, "auto, dense or klu")
      ->check(CLI::IsMember({"auto", "dense", "klu"}));
  sweep->add_option("--codegen", swp.options.codegen,
                    "auto (native code where it pays), native (compile the model to native code) or interp")
      ->check(CLI::IsMember({"auto", "native", "interp"}));
  sweep->add_option("-j,--jobs", swp.jobs, "threads per process (default: one per core, shared by the MPI ranks on the machine)")->check(CLI::Range(1u, 4096u));
  sweep->add_option("-o,--out", swp.out, "summary CSV, one row per run ('-' for standard output)");
  sweep->add_option("--trajectories", swp.trajectories, "directory for each run's CSV (DIR/run-<k>.csv)");
  sweep->add_option("--seed", swp.seed, "seed of the Monte Carlo draws (std::mt19937_64; default 0)");
  sweep->add_option("--samples", swp.samples, "Monte Carlo draws of the distributions")
      ->check(CLI::Range(size_t{1}, kMaxSweepRuns));
  sweep->add_flag("-q,--quiet", swp.quiet, "print nothing on success");

  std::string list_name;
  auto* list = app.add_subcommand("list", "list the component library, or describe one component");
  list->add_option("name", list_name, "component or connector type");

  // An unknown command is named (CLI11 would only say that a subcommand is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string cmd = argv[1];
    if (cmd != "simulate" && cmd != "check" && cmd != "list" && cmd != "sweep" && cmd != "report" && cmd != "plot") {
      std::cerr << "momenta: unknown command '" << cmd
                << "' (valid commands: simulate, sweep, report, plot, check, list; see momenta --help)\n";
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  try {
    if (*simulate) return RunSimulate(sim);
    if (*sweep) return RunSweep(swp);
    if (*report) return RunReport(rep);
    if (*plot) return RunPlot(plt);
    if (*check) return RunCheck(chk);
    if (*list) return RunList(list_name);
  } catch (const std::exception& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitModel;
  }
  return kExitUsage;
}
