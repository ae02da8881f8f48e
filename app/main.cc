// momenta: acausal component models from YAML, simulated with SUNDIALS IDA.
// main stays thin: parse the command line, dispatch, return the exit code.

#include <CLI/CLI.hpp>

#include <iostream>

#include "app/commands.h"
#include "solver/sundials_support.h"

int main(int argc, char** argv) {
  using namespace momenta;
  CLI::App app{"momenta: acausal component-model simulation (YAML models, SUNDIALS IDA)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("momenta 0.1 (SUNDIALS 6.4.1") +
                                        (SundialsOptimized() ? ", optimised build)" : ", Debian build)"));

  SimulateArgs sim;
  auto* simulate = app.add_subcommand("simulate", "simulate a model and write its outputs as CSV");
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
  simulate->add_option("-o,--out", sim.out, "results file (CSV; '-' for standard output)");
  simulate->add_option("--linear-solver", sim.options.linear_solver, "auto, dense or klu")
      ->check(CLI::IsMember({"auto", "dense", "klu"}));
  simulate->add_flag("-q,--quiet", sim.quiet, "print nothing on success");

  CheckArgs chk;
  auto* check = app.add_subcommand("check", "validate a model and show what each pass made of it");
  check->add_option("model", chk.model, "model file (YAML)")->required();
  check->add_option("-p,--param", chk.params, "override a parameter: NAME=VALUE (repeatable)");
  check->add_flag("-v,--verbose", chk.verbose, "list every state and pruned variable");

  std::string list_name;
  auto* list = app.add_subcommand("list", "list the component library, or describe one component");
  list->add_option("name", list_name, "component or connector type");

  // An unknown command is named (CLI11 would only say that a subcommand is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string cmd = argv[1];
    if (cmd != "simulate" && cmd != "check" && cmd != "list") {
      std::cerr << "momenta: unknown command '" << cmd << "' (valid commands: simulate, check, list; see momenta --help)\n";
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
    if (*check) return RunCheck(chk);
    if (*list) return RunList(list_name);
  } catch (const std::exception& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitModel;
  }
  return kExitUsage;
}
