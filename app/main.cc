// momenta: acausal component models from YAML, simulated with SUNDIALS IDA.
// main stays thin: define the command line, parse it, dispatch, return the exit code.

#include <CLI/CLI.hpp>

#include <iostream>

#include "app/accuracy_command.h"
#include "app/commands.h"
#include "app/fmu_command.h"
#include "app/linearize_command.h"
#include "app/huge_pages.h"
#include "app/mat_file.h"
#include "app/plugin.h"
#include "app/plot.h"
#include "app/report_command.h"
#include "app/sweep.h"
#include "app/sweep_cluster.h"
#include "app/sweep_plan.h"
#include "app/terminal_output.h"
#include "core/lang/compiled_types.h"
#include "solver/simulator.h"

namespace momenta {
namespace {

/// `momenta --version`: the SUNDIALS build, and which of the plugins' features (app/plugin.h) this
/// installation has. Computed only when asked, since it loads the plugins.
std::string VersionText() {
  const SolverBuild solver = SolverBuildInfo();
  std::string text = "momenta 0.1 (SUNDIALS " + solver.sundials_version +
                     (solver.sundials_optimized ? ", optimised build)" : ", Debian build)");
  auto feature = [&text](const char* what, const char* file, bool available) {
    text += std::string("\n") + what + (available ? ": yes (" + FindPlugin(file) + ")" : ": no");
  };
  feature("MAT result files", "momenta-mat.so", HaveMat());
  feature("sweeps under mpirun", "momenta-mpi.so", HaveMpi());
  feature("FMU export", "momenta-fmu.so", !FindPlugin("momenta-fmu.so").empty() && !FindPlugin("momenta-zip.so").empty());
  return text;
}

/// The options simulate and sweep share: the run's tolerances, interval, solver and code.
/// Values not given stay empty (the experiment's apply); given ones are checked by the command.
void AddRunOptions(CLI::App* command, SimulateOverrides* options, const char* max_order_help) {
  auto number = [command](const char* name, std::optional<double>* to, const char* help) {
    command->add_option_function<double>(name, [to](const double& v) { *to = v; }, help);
  };
  number("--stop", &options->stop, "stop time [s]");
  number("--rtol", &options->rtol, "relative tolerance (default: the experiment's tolerance, else 1e-6)");
  number("--atol", &options->atol,
         "absolute tolerance (default: the relative one); each variable's is atol*nominal, its nominal 1 unless "
         "its type or component entry sets one (e.g. w_rel: {nominal: 1e-4})");
  number("--interval", &options->interval, "output interval [s]");
  number("--max-order", &options->max_order, max_order_help);
  number("--max-steps", &options->max_steps,
         "steps allowed between two output rows before the run stops and names the model's fastest modes "
         "(default 500000)");
}

void AddSolverChoices(CLI::App* command, SimulateOverrides* options) {
  command->add_option("--linear-solver", options->linear_solver, "auto, dense or klu")
      ->check(CLI::IsMember({"auto", "dense", "klu"}));
  command->add_option("--error-test", options->error_test,
                      "which unknowns IDA's local error test covers: states (default, as an ODE solver would; an "
                      "index-reduced model keeps all) or all (also forces, accelerations and currents, which "
                      "follow from the states)")
      ->check(CLI::IsMember({"states", "all"}));
  command->add_option("--codegen", options->codegen,
                      "auto (native code where it pays), native (compile the model to native code) or interp")
      ->check(CLI::IsMember({"auto", "native", "interp"}));
}

CLI::App* AddSimulate(CLI::App* app, SimulateArgs* sim, const std::string& named) {
  auto* simulate = app->add_subcommand("simulate", "simulate a model and write its outputs as CSV (or a MAT v4 result file: -o FILE.mat)");
  if (simulate->get_name() != named) return simulate;
  simulate->add_option("model", sim->model, "model file (YAML)")->required();
  simulate->add_option("-p,--param", sim->params, "override a parameter: NAME=VALUE (repeatable)");
  AddRunOptions(simulate, &sim->options,
                "IDA's maximum BDF order, 1 to 5 (default: the experiment's max_order, else 5; 3 can save steps on "
                "lightly damped oscillations, but an undamped one gains energy at it: bench/RESULTS.md)");
  simulate->add_option("-o,--out", sim->out, "results file (CSV; '-' for standard output)");
  AddSolverChoices(simulate, &sim->options);
  simulate->add_flag("-q,--quiet", sim->quiet, "print nothing on success");
  simulate->add_option("--report", sim->report, "also write an HTML report (plots, statistics, the scene's animation)");
  simulate->add_flag("--scene-columns", sim->scene_columns,
                     "also write the quantities the scene is drawn from into the results file (for momenta report)");
  return simulate;
}

CLI::App* AddReport(CLI::App* app, ReportArgs* rep, const std::string& named) {
  auto* report = app->add_subcommand("report", "write the HTML report of a result file simulate wrote");
  if (report->get_name() != named) return report;
  report->add_option("result", rep->result, "result file (CSV or MAT)")->required();
  report->add_option("-m,--model", rep->model, "the model file the result was simulated from")->required();
  report->add_option("-p,--param", rep->params, "the -p values it was simulated with (repeatable)");
  report->add_option("-o,--out", rep->out, "the report (default: <result stem>.html)");
  return report;
}

CLI::App* AddPlot(CLI::App* app, PlotArgs* plt, const std::string& named) {
  auto* plot = app->add_subcommand("plot", "plot columns of a result file as SVG or PNG (with gnuplot)");
  if (plot->get_name() != named) return plot;
  plot->add_option("result", plt->result, "result file (CSV or MAT)")->required();
  plot->add_option("-y", plt->columns, "columns to plot: A.v,B.v (repeatable)")->required();
  plot->add_option("-o,--out", plt->out, "the image, .svg or .png (default: <result stem>.svg)");
  plot->add_option("--title", plt->title, "title (default: the result's file name)");
  plot->add_option("--width", plt->width, "width in pixels (height: 5/9 of it)")->check(CLI::Range(200, 8000));
  return plot;
}

CLI::App* AddCheck(CLI::App* app, CheckArgs* chk, const std::string& named) {
  auto* check = app->add_subcommand("check", "validate a model and show what each pass made of it");
  if (check->get_name() != named) return check;
  check->add_option("model", chk->model, "model file (YAML)")->required();
  check->add_option("-p,--param", chk->params, "override a parameter: NAME=VALUE (repeatable)");
  check->add_flag("-v,--verbose", chk->verbose, "list every state and pruned variable");
  return check;
}

CLI::App* AddSweep(CLI::App* app, SweepArgs* swp, const std::string& named) {
  auto* sweep = app->add_subcommand("sweep", "simulate a model for many parameter values on several threads (and MPI ranks under mpirun)");
  if (sweep->get_name() != named) return sweep;
  sweep->add_option("model", swp->model, "model file (YAML)")->required();
  sweep->add_option("-p,--param", swp->params,
                    "NAME=SPEC: a value, a list a,b,c, a grid a:b:n or a:b:log:n, normal(mu,sigma) or "
                    "uniform(a,b) (repeatable; lists and grids combine as a Cartesian product)");
  AddRunOptions(sweep, &swp->options, "IDA's maximum BDF order, 1 to 5 (default: the experiment's max_order, else 5)");
  AddSolverChoices(sweep, &swp->options);
  sweep->add_option("-j,--jobs", swp->jobs, "threads per process (default: one per core, shared by the MPI ranks on the machine)")->check(CLI::Range(1u, 4096u));
  sweep->add_option("-o,--out", swp->out, "summary CSV, one row per run ('-' for standard output)");
  sweep->add_option("--trajectories", swp->trajectories, "directory for each run's CSV (DIR/run-<k>.csv)")
      ->check(CLI::Validator([](std::string& s) { return TrajectoriesProblem(s); }, "DIR", "directory"));
  sweep->add_option("--seed", swp->seed, "seed of the Monte Carlo draws (std::mt19937_64; default 0)")
      ->check(CLI::Validator([](std::string& s) { return SeedProblem(s); }, "UINT64", "seed"));
  sweep->add_option("--samples", swp->samples, "Monte Carlo draws of the distributions")
      ->check(CLI::Range(size_t{1}, kMaxSweepRuns));
  sweep->add_flag("-q,--quiet", swp->quiet, "print nothing on success");
  return sweep;
}

CLI::App* AddLinearize(CLI::App* app, LinearizeArgs* lin, const std::string& named) {
  auto* linearize = app->add_subcommand(
      "linearize", "the model's state-space form A, B, C, D at a time (JSON, or a MAT file in Dymola's dslin layout)");
  if (linearize->get_name() != named) return linearize;
  linearize->add_option("model", lin->model, "model file (YAML)")->required();
  linearize->add_option("-p,--param", lin->params, "override a parameter: NAME=VALUE (repeatable)");
  linearize->add_option_function<double>("--at", [lin](const double& t) { lin->at = t; },
                                         "linearise at this time [s], after simulating to it (default: the start, "
                                         "after the initialisation)");
  linearize->add_option("-u,--input", lin->inputs,
                        "an unconnected signal input, NAME or NAME=VALUE (its operating value, default 0; "
                        "repeatable; default: every unconnected input)");
  linearize->add_option("-y,--output", lin->outputs,
                        "an output, a variable's name (repeatable, or A,B; default: the model's outputs)");
  linearize->add_option("-o,--out", lin->out, "lin.json or lin.mat (default: JSON on standard output)");
  return linearize;
}

CLI::App* AddAccuracy(CLI::App* app, AccuracyArgs* acc, const std::string& named) {
  auto* accuracy = app->add_subcommand(
      "accuracy", "run a model at a range of tolerances: each run's error and cost (the work-precision table and plot)");
  if (accuracy->get_name() != named) return accuracy;
  accuracy->add_option("model", acc->model, "model file (YAML)")->required();
  accuracy->add_option("-p,--param", acc->params, "override a parameter: NAME=VALUE (repeatable)");
  accuracy->add_option("--rtol", acc->rtol, "the tolerances, LOOSE:TIGHT a decade apart (default 1e-3:1e-10)");
  accuracy->add_option("--reference", acc->reference,
                       "the reference result (CSV or MAT; default: a run at a tolerance 100 times tighter than the "
                       "tightest)");
  accuracy->add_option("-o,--out", acc->out, "the plot, .svg or .png (default: <model stem>.accuracy.svg)");
  accuracy->add_option("--table", acc->table, "also write the table as CSV");
  accuracy->add_option("--report", acc->report, "also write an HTML report (the reference run and the table)");
  return accuracy;
}

CLI::App* AddFmu(CLI::App* app, FmuArgs* fmu, const std::string& named) {
  auto* cmd = app->add_subcommand("fmu", "export the model as an FMI 2.0 FMU (Model Exchange and Co-Simulation)");
  if (cmd->get_name() != named) return cmd;
  cmd->add_option("model", fmu->model, "model file (YAML)")->required();
  cmd->add_option("-p,--param", fmu->params, "override a parameter: NAME=VALUE (repeatable); the FMU's start value");
  cmd->add_option("-o,--out", fmu->out, "the FMU (default: <model stem>.fmu)");
  cmd->add_option("--kind", fmu->kind, "me (Model Exchange), cs (Co-Simulation) or both (default)");
  return cmd;
}

/// An unknown command is named (CLI11 would only say that a subcommand is required).
bool KnownCommand(int argc, char** argv) {
  if (argc <= 1 || argv[1][0] == '-') return true;
  const std::string cmd = argv[1];
  if (cmd == "simulate" || cmd == "check" || cmd == "list" || cmd == "sweep" || cmd == "report" || cmd == "plot" ||
      cmd == "linearize" || cmd == "accuracy" || cmd == "fmu") {
    return true;
  }
  std::cerr << "momenta: unknown command '" << cmd
            << "' (valid commands: simulate, sweep, linearize, accuracy, fmu, report, plot, check, list; see momenta "
               "--help)\n";
  return false;
}

}  // namespace
}  // namespace momenta

int main(int argc, char** argv) {
  using namespace momenta;
  MaybeRestartWithHugePages(argc, argv);
  // The library's types as the build parsed them: a run reads none of their text.
  UseCompiledLibraryTypes(CompiledBuiltinTypes());
  // Every message and summary from here on reaches the terminal with its control characters
  // escaped (app/terminal_output.h).
  TerminalOutput terminal;
  CLI::App app{"momenta: acausal component-model simulation (YAML models, SUNDIALS IDA)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", VersionText);
  SimulateArgs sim;
  ReportArgs rep;
  PlotArgs plt;
  CheckArgs chk;
  SweepArgs swp;
  LinearizeArgs lin;
  AccuracyArgs acc;
  FmuArgs fmu;
  std::string list_name;
  // Every command is defined (the help lists them), but only the one being run gets its options:
  // adding every command's options was 0.7 M instructions, about 5 % of the carrier collision's
  // whole run (14.9 M instructions; callgrind, bench/RESULTS.md, "Read this first").
  const std::string named = argc > 1 ? argv[1] : "";
  CLI::App* simulate = AddSimulate(&app, &sim, named);
  CLI::App* report = AddReport(&app, &rep, named);
  CLI::App* plot = AddPlot(&app, &plt, named);
  CLI::App* check = AddCheck(&app, &chk, named);
  CLI::App* sweep = AddSweep(&app, &swp, named);
  CLI::App* linearize = AddLinearize(&app, &lin, named);
  CLI::App* accuracy = AddAccuracy(&app, &acc, named);
  CLI::App* fmu_cmd = AddFmu(&app, &fmu, named);
  CLI::App* list = app.add_subcommand("list", "list the component library, or describe one component");
  list->add_option("name", list_name, "component or connector type");

  if (!KnownCommand(argc, argv)) return kExitUsage;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  try {
    if (*simulate) return RunSimulate(sim);
    if (*sweep) return RunSweep(swp);
    if (*linearize) return RunLinearize(lin);
    if (*accuracy) return RunAccuracy(acc);
    if (*fmu_cmd) return RunFmu(fmu);
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
