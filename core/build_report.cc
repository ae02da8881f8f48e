// The text of the build's report (core/build_report.h): every pass's note, and the notes and
// warnings the compiled model gives the user, worded in one place.

#include "core/build_report.h"

#include <sstream>

namespace momenta {

std::string FlattenNote(const FlatSystem& flat) {
  std::ostringstream note;
  note << flat.instances.size() << " components, " << flat.parameters.size() << " parameters";
  return note.str();
}

std::string StructuralParametersNote(size_t folded_conditions, size_t absent_connectors, size_t absent_parts) {
  std::ostringstream note;
  note << folded_conditions << " conditions on Boolean or Integer parameters fixed";
  if (absent_connectors > 0) note << ", " << absent_connectors << " conditional connectors absent";
  if (absent_parts > 0) note << ", " << absent_parts << " conditional parts absent";
  return note.str();
}

std::string AliasEliminationNote(const AliasStats& stats) {
  std::ostringstream note;
  note << stats.aliases << " aliases, " << stats.constants << " constants";
  return note.str();
}

std::string IndexReductionNote(const IndexStats& stats) {
  std::ostringstream note;
  note << stats.derivative_aliases << " derivative aliases, " << stats.constrained_states
       << " constrained states";
  if (stats.kept_constraints > 0) {
    note << ", " << stats.kept_constraints << " constraints kept as equations";
  }
  return note.str();
}

std::string DiscretePartitionNote(const DiscreteStats& stats, const EquationSystem& sys) {
  std::ostringstream note;
  note << stats.variables << " discrete variables, " << stats.equations << " discrete equations, "
       << sys.whens.size() << " when-clauses, " << sys.impacts.size() << " impacts";
  return note.str();
}

std::string PantelidesNote(const DifferentiatedSystem& differentiated,
                           const StateSelection& selection, size_t derivative_aliases) {
  std::ostringstream note;
  note << "structural index " << differentiated.structural_index << ", "
       << differentiated.num_differentiated << " equations differentiated, "
       << selection.dummy_derivatives.size() << " dummy derivatives";
  if (!selection.new_states.empty()) {
    note << ", " << selection.new_states.size() << " states for higher derivatives";
  }
  if (derivative_aliases > 0) note << ", " << derivative_aliases << " derivative aliases";
  return note.str();
}

std::string StructuralAnalysisNote(const Structure& structure) {
  std::ostringstream note;
  note << structure.num_states << " states, structurally regular, index <= 1";
  return note.str();
}

std::string PruningNote(const PruneStats& stats) {
  std::ostringstream note;
  note << stats.variables << " variables and " << stats.equations
       << " equations not needed by the outputs";
  return note.str();
}

std::string CausalisationNote(const CausalStats& stats) {
  std::ostringstream note;
  note << stats.inlined << " solved explicitly, " << stats.algebraic_loops << " algebraic loops ("
       << stats.loop_variables << " unknowns)";
  return note.str();
}

std::string CompilationNote(const CompiledModel& model) {
  const size_t num_conditions = model.conditions.size(), num_discrete = model.discrete_vars.size();
  std::ostringstream note;
  note << model.residual.size() << " residual, " << model.jacobian.size() << " Jacobian ("
       << model.jacobian_pattern.nnz() << " nonzeros), " << model.parameters.size()
       << " parameter instructions; " << model.initial_exprs.size() << " initial equations";
  if (!model.defaulted_starts.empty()) {
    note << " (" << model.defaulted_starts.size() << " start values taken)";
  }
  if (!model.redundant_exprs.empty()) {
    note << " (" << model.redundant_exprs.size() << " redundant left out)";
  }
  if (num_conditions || num_discrete) {
    note << "; " << num_conditions << " event conditions, " << num_discrete
         << " discrete variables";
  }
  return note.str();
}

void ReportIndexReduction(const EquationSystem& sys, const DifferentiatedSystem& differentiated,
                          const StateSelection& selection, BuildReport* report) {
  report->structural_index = differentiated.structural_index;
  for (const SystemEquation& eq : sys.equations) {
    if (sys.flat->equations[eq.origin].differentiated_from >= 0) {
      report->differentiated.push_back(sys.Describe(eq));
    }
  }
  report->dummy_derivatives = selection.dummy_derivatives;
  report->state_choices = selection.choices;
  report->warnings.insert(report->warnings.end(), selection.warnings.begin(),
                          selection.warnings.end());
}

namespace {

/// The redundant initial conditions, a note each for the first few (the rest counted).
void NoteRedundantInitialConditions(const CompiledModel& m, BuildReport* report) {
  constexpr size_t kNotesShown = 10;
  for (size_t k = 0; k < m.redundant_exprs.size() && k < kNotesShown; ++k) {
    std::string from = m.redundant_from[k];
    for (size_t pos = 0; (pos = from.find('\n', pos)) != std::string::npos; pos += 5) from.replace(pos, 1, "\n    ");
    report->notes.push_back(
        "initial conditions: the " + m.redundant_origin[k] +
        " is redundant: it follows from\n    " + from +
        "\n  It is left out of the initial system; initialisation checks that it holds.");
  }
  if (m.redundant_exprs.size() > kNotesShown) {
    report->notes.push_back(
        "initial conditions: " + std::to_string(m.redundant_exprs.size() - kNotesShown) +
        " more redundant ones are left out and checked the same way (`check -v` lists the "
        "initial equations kept)");
  }
}

/// The start values taken as initial conditions, with the degrees of freedom they complete.
void WarnDefaultedStarts(const CompiledModel& m, BuildReport* report) {
  if (m.defaulted_starts.empty()) return;
  std::ostringstream w;
  const size_t dof = m.state_y.size(), missing = m.defaulted_starts.size();
  w << "initial conditions: the model has " << dof << (dof == 1 ? " degree" : " degrees")
    << " of freedom and its fixed start values and initial equations determine " << dof - missing
    << "; the start " << (missing == 1 ? "value" : "values") << " of ";
  for (size_t k = 0; k < missing && k < 10; ++k) w << (k ? ", " : "") << m.defaulted_starts[k];
  if (missing > 10) w << " and " << missing - 10 << " more";
  w << (missing == 1 ? " is" : " are") << " used as well (add fixed: true to say so)";
  report->warnings.push_back(w.str());
}

}  // namespace

void ReportCompiledModel(const CompiledModel& model, BuildReport* report) {
  for (size_t y = 0; y < model.num_unknowns(); ++y) {
    if (model.is_state[y]) report->states.push_back(model.flat->VariableName(model.unknowns[y]));
  }
  NoteRedundantInitialConditions(model, report);
  WarnDefaultedStarts(model, report);
}

}  // namespace momenta
