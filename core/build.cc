#include "core/build.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <sstream>

#include "core/passes/alias_elimination.h"
#include "core/passes/causalization.h"
#include "core/compile/compile.h"
#include "core/passes/conditional_connectors.h"
#include "core/passes/discrete_partition.h"
#include "core/passes/dummy_derivatives.h"
#include "core/passes/index_reduction.h"
#include "core/passes/pantelides.h"
#include "core/passes/pruning.h"
#include "core/passes/state_select.h"
#include "core/passes/structural_analysis.h"
#include "core/passes/structural_conditions.h"
#include "core/flatten/flatten.h"

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// CPU time of the calling thread: on a shared machine a pass's wall time includes waiting for a
/// core, its CPU time does not.
double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

namespace {

/// BuildModel; `release`, when given, is `spec` itself, emptied once flattened.
std::shared_ptr<const CompiledModel> Build(const ModelSpec& spec, ModelSpec* release, const Library& library,
                                           const ParameterOverrides& overrides, BuildReport* report) {
  auto pass_start = Clock::now();
  double pass_cpu_start = ThreadCpuSeconds();
  auto record = [&](const std::string& name, size_t vars, size_t eqs, const std::string& note) {
    const double cpu = ThreadCpuSeconds();
    report->passes.push_back({name, Seconds(pass_start), cpu - pass_cpu_start, vars, eqs, note});
    pass_start = Clock::now();
    pass_cpu_start = cpu;
  };

  // Flatten.
  auto flat = std::make_shared<FlatSystem>(Flatten(spec, library, overrides, /*defer_equations=*/true));
  // The component equations left to the first alias elimination (FlatSystem::deferred).
  std::shared_ptr<const DeferredEquations> deferred = std::move(flat->deferred);
  if (release != nullptr) *release = ModelSpec();
  report->num_components = flat->instances.size();
  report->num_parameters = flat->parameters.size();
  {
    std::ostringstream note;
    note << flat->instances.size() << " components, " << flat->parameters.size() << " parameters";
    record("flatten", flat->variables.size(), flat->equations.size(), note.str());
  }
  // The passes after flattening about double the expression pool (1.7x on the RC ladder, 1.9x on
  // the chain, bench/RESULTS.md): its table is sized for that now, while the build is small, not
  // rehashed at the peak of compilation.
  flat->pool->Reserve(2 * flat->pool->size());
  // Parameters are evaluated now too, so a bad value is reported before any solving.
  const std::vector<double> params = EvaluateParameters(*flat, overrides);
  ExprPool& p = *flat->pool;
  // The system takes the flat system over: passes that extend it need not copy it.
  EquationSystem sys = MakeEquationSystem(std::move(flat));
  // Branches chosen by Boolean and Integer parameters are fixed before the structure is analysed;
  // then connectors whose condition is false leave, with the equations that hold only with them.
  const size_t folded = FoldStructuralConditions(&sys, params);
  const size_t absent = ResolveConditionalConnectors(&sys, params);
  if (folded + absent > 0) {
    std::ostringstream note;
    note << folded << " conditions on Boolean or Integer parameters fixed";
    if (absent > 0) note << ", " << absent << " conditional connectors absent";
    record("structural parameters", sys.num_unknowns(), sys.equations.size(), note.str());
  }

  // Simplify: aliases, derivative aliases and constrained states, until nothing changes.
  AliasStats alias;
  IndexStats index;
  // The equations' leaves, from one round's alias elimination to the next (collected in the
  // first, kept current by both passes); let go after the rounds.
  auto leaves = std::make_unique<EquationLeaves>();
  for (int round = 0; round < 20; ++round) {
    size_t before = sys.num_unknowns();
    sys = EliminateAliases(std::move(sys), &alias, deferred.get(), leaves.get());
    deferred.reset();  // every equation is made now
    size_t changes_before = index.derivative_aliases + index.constrained_states;
    size_t kept_before = index.kept_constraints;
    sys = ReduceIndex(std::move(sys), &index, leaves.get());
    // Only index reduction makes new alias equations: when it changed nothing, we are done. A
    // constraint kept as an equation removes no unknown but turns a derivative's definition into
    // a new constraint for the next round.
    if (index.derivative_aliases + index.constrained_states + index.kept_constraints ==
        changes_before + kept_before) {
      break;
    }
    if (sys.num_unknowns() == before && index.kept_constraints == kept_before) break;
  }
  leaves.reset();
  {
    std::ostringstream note;
    note << alias.aliases << " aliases, " << alias.constants << " constants";
    record("alias elimination", sys.num_unknowns() + index.constrained_states, sys.equations.size() + index.constrained_states, note.str());
    std::ostringstream note2;
    note2 << index.derivative_aliases << " derivative aliases, " << index.constrained_states
          << " constrained states";
    if (index.kept_constraints > 0) note2 << ", " << index.kept_constraints << " constraints kept as equations";
    record("index reduction", sys.num_unknowns(), sys.equations.size(), note2.str());
  }

  DiscreteStats discrete;
  sys = PartitionDiscrete(std::move(sys), &discrete);
  if (discrete.variables > 0 || !sys.whens.empty() || !sys.impacts.empty()) {
    std::ostringstream note;
    note << discrete.variables << " discrete variables, " << discrete.equations << " discrete equations, "
         << sys.whens.size() << " when-clauses, " << sys.impacts.size() << " impacts";
    record("discrete partition", sys.num_unknowns(), sys.equations.size(), note.str());
  }

  // Full index reduction where the linear fast path left index > 1, and the first-order form of
  // higher derivatives.
  {
    DifferentiatedSystem d = Pantelides(&sys);
    bool higher_order = std::any_of(d.max_order.begin(), d.max_order.end(), [](uint32_t k) { return k >= 2; });
    if (d.num_differentiated > 0 || higher_order) {
      StateSelection sel = SelectDummyDerivatives(&sys, d, params);
      // der(x) that the differentiated equations introduced -> the state v of v = der(x), so no
      // residual is nonlinear in a state's derivative (index_reduction.h).
      const size_t post_aliases = SubstituteDerivativeAliases(&sys);
      std::ostringstream note;
      note << "structural index " << d.structural_index << ", " << d.num_differentiated
           << " equations differentiated, " << sel.dummy_derivatives.size() << " dummy derivatives";
      if (!sel.new_states.empty()) note << ", " << sel.new_states.size() << " states for higher derivatives";
      if (post_aliases > 0) note << ", " << post_aliases << " derivative aliases";
      record("pantelides", sys.num_unknowns(), sys.equations.size(), note.str());
      report->structural_index = d.structural_index;
      for (const SystemEquation& eq : sys.equations) {
        if (sys.flat->equations[eq.origin].differentiated_from >= 0) {
          report->differentiated.push_back(sys.Describe(eq));
        }
      }
      report->dummy_derivatives = sel.dummy_derivatives;
      report->state_choices = sel.choices;
      report->warnings.insert(report->warnings.end(), sel.warnings.begin(), sel.warnings.end());
    }
  }
  // From here on the flat system is the one index reduction may have extended.
  std::shared_ptr<const FlatSystem> model = sys.flat;

  // Outputs default to every state.
  std::vector<std::string> output_names;
  for (const auto& o : model->outputs) output_names.push_back(o.text);

  Structure st = AnalyseStructure(sys);
  CheckStateSelect(sys, st, &report->warnings);
  {
    std::ostringstream note;
    note << st.num_states << " states, structurally regular, index <= 1";
    record("structural analysis", sys.num_unknowns(), sys.equations.size(), note.str());
  }
  if (output_names.empty()) {
    for (uint32_t v = 0; v < st.is_state.size(); ++v) {
      if (!st.is_state[v]) continue;
      output_names.push_back(model->VariableName(VarId(v)));
      sys.outputs.push_back(p.Var(VarId(v)));
    }
  }

  PruneStats pruned;
  sys = Prune(std::move(sys), &st, &pruned);
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] == VarRole::kPruned) report->pruned.push_back(model->VariableName(VarId(v)));
  }
  {
    std::ostringstream note;
    note << pruned.variables << " variables and " << pruned.equations << " equations not needed by the outputs";
    record("pruning", sys.num_unknowns(), sys.equations.size(), note.str());
  }

  CausalStats causal;
  sys = Causalize(std::move(sys), &st, &causal);
  {
    std::ostringstream note;
    note << causal.inlined << " solved explicitly, " << causal.algebraic_loops << " algebraic loops ("
         << causal.loop_variables << " unknowns)";
    record("causalisation", sys.num_unknowns(), sys.equations.size(), note.str());
  }

  auto m = CompileModel(std::move(sys), st, output_names, report);
  record("compilation", m->num_unknowns(), m->num_unknowns(), report->compile_note);
  return m;
}

}  // namespace

std::shared_ptr<const CompiledModel> BuildModel(const ModelSpec& spec, const Library& library,
                                                const ParameterOverrides& overrides,
                                                BuildReport* report) {
  return Build(spec, nullptr, library, overrides, report);
}

std::shared_ptr<const CompiledModel> BuildModel(ModelSpec&& spec, const Library& library,
                                                const ParameterOverrides& overrides,
                                                BuildReport* report) {
  return Build(spec, &spec, library, overrides, report);
}

}  // namespace momenta
