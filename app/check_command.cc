// `momenta check MODEL`: build the model and show what each pass made of it — the pass table
// (time, unknowns and equations after each pass, and its note), states, index reduction, outputs,
// what was pruned and, with --verbose, the DAE as IDA sees it in the user's names.

#include <sys/resource.h>

#include <cstdio>
#include <iostream>
#include <string>

#include "app/commands.h"
#include "app/huge_pages.h"

namespace momenta {

namespace {

/// The pass table: load, then each pass's time, size afterwards and note, then the total.
void PrintPasses(std::ostream& o, const LoadedModel& loaded) {
  char line[256];
  std::snprintf(line, sizeof line, "  %-22s %10s %10s %10s  %s\n", "pass", "time", "unknowns", "equations", "");
  o << line;
  std::snprintf(line, sizeof line, "  %-22s %10s %10s %10s  %s\n", "load", FormatMs(loaded.load_s).c_str(), "",
                "", "");
  o << line;
  double total = loaded.load_s;
  for (const auto& p : loaded.report.passes) {
    std::snprintf(line, sizeof line, "  %-22s %10s %10zu %10zu  ", p.name.c_str(), FormatMs(p.seconds).c_str(),
                  p.variables, p.equations);
    o << line << p.note << "\n";
    total += p.seconds;
  }
  o << "  total " << FormatMs(total) << (HugePagesInUse() ? "  (memory on huge pages)" : "") << "\n";
}

/// The process's peak resident memory so far in bytes (getrusage's ru_maxrss, KiB on Linux);
/// 0 if the system does not say.
double PeakResidentBytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<double>(usage.ru_maxrss) * 1024.0;
}

/// A figure to three significant digits, without an exponent from 1 000 on ("6.46", "4224").
std::string ThreeDigits(double x) {
  char text[32];
  std::snprintf(text, sizeof text, x < 1000 ? "%.3g" : "%.0f", x);
  return text;
}

/// The memory line: the whole process's peak resident memory (the built-in library and the
/// program included) and that peak divided by the number of components, in decimal MB and KB.
void PrintMemory(std::ostream& o, size_t num_components) {
  double peak = PeakResidentBytes();
  if (peak <= 0) return;
  o << "  peak memory " << ThreeDigits(peak / 1e6) << " MB";
  if (num_components > 0) {
    o << ", " << ThreeDigits(peak / 1e3 / static_cast<double>(num_components)) << " KB per component";
  }
  o << "\n";
}

/// The DAE as IDA sees it, then the initial conditions, events, whens, impacts and outputs, in
/// the user's names.
void PrintEquations(std::ostream& o, const CompiledModel& model) {
  ExprNamer names = model.flat->Namer();
  o << "equations for IDA (" << model.num_unknowns() << "):\n";
  for (size_t k = 0; k < model.num_unknowns(); ++k) {
    o << "  0 = " << ToString(*model.pool, model.residual_exprs[k], names) << "\n      from "
      << model.residual_origin(k) << "\n";
  }
  o << "initial equations (" << model.initial_exprs.size() << "):\n";
  for (size_t k = 0; k < model.initial_exprs.size(); ++k) {
    o << "  0 = " << ToString(*model.pool, model.initial_exprs[k], names) << "\n      from "
      << model.initial_origin[k] << "\n";
  }
  if (!model.conditions.empty()) {
    o << "event conditions (" << model.conditions.size() << "), c<k> in the equations:\n";
    for (size_t k = 0; k < model.conditions.size(); ++k) {
      o << "  c" << k << ": " << model.conditions[k].text << (model.conditions[k].time_only ? "  (time event)" : "")
        << "\n";
    }
  }
  if (!model.discrete_equations.empty()) {
    o << "discrete equations, evaluated at events in this order:\n";
    for (const auto& [var, value] : model.discrete_equations) {
      o << "  " << model.flat->VariableName(var) << " = " << ToString(*model.pool, value, names) << "\n";
    }
  }
  for (const auto& w : model.whens) {
    o << "when " << w.text << ": " << w.assigns.size() << " assignments, " << w.reinits.size() << " reinit\n";
  }
  for (const auto& im : model.impacts) {
    o << "impact of " << im.name << ": Newton's law replaces equation " << im.mode_row << "\n";
  }
  o << "outputs:\n";
  for (size_t k = 0; k < model.output_names.size(); ++k) {
    o << "  " << model.output_names[k] << " = " << ToString(*model.pool, model.output_exprs[k], names) << "\n";
  }
}

}  // namespace

int RunCheck(const CheckArgs& args) {
  LoadedModel loaded;
  if (int code = LoadAndBuild(args.model, args.params, &loaded); code != kExitOk) return code;
  const CompiledModel& model = *loaded.model;
  const BuildReport& report = loaded.report;
  std::ostream& o = std::cout;
  o << "model " << model.flat->model_name << " (" << args.model << "): " << report.num_components
    << " components, " << report.num_parameters << " parameters\n";
  PrintPasses(o, loaded);
  PrintMemory(o, report.num_components);
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
  list("outputs", model.output_names);
  list("pruned", report.pruned);
  if (args.verbose) PrintEquations(o, model);
  for (const auto& w : report.warnings) o << "warning: " << w << "\n";
  for (const auto& note : report.notes) o << "note: " << note << "\n";
  return kExitOk;
}

}  // namespace momenta
