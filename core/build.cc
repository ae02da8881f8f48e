// The build as a list of steps over one shared record (BuildState), each timed and recorded the
// same way (PassLog::RunPass), as marco's FrontendActions or ModelingToolkit's mtkcompile! list
// their passes. The notes the steps record are written in core/build_report.cc.

#include "core/build.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <optional>
#include <sstream>

#include "core/base/messages.h"
#include "core/compile/compile.h"
#include "core/flatten/build_time_values.h"
#include "core/flatten/flatten.h"
#include "core/lang/parser.h"
#include "core/passes/alias_elimination.h"
#include "core/passes/causalization.h"
#include "core/passes/conditional_connectors.h"
#include "core/passes/discrete_partition.h"
#include "core/passes/dummy_derivatives.h"
#include "core/passes/index_reduction.h"
#include "core/passes/pantelides.h"
#include "core/passes/pruning.h"
#include "core/passes/state_select.h"
#include "core/passes/structural_analysis.h"
#include "core/passes/structural_conditions.h"

namespace momenta {

namespace {

// ---- timing and recording: one mechanism for every step -----------------------------------------

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

/// What a step tells the report: the system's size after it and what it did. A step that had
/// nothing to do tells nothing (std::nullopt), and is left out of the report.
struct StepResult {
  size_t variables = 0, equations = 0;
  std::string note;
};
using StepOutcome = std::optional<StepResult>;

/// Runs the steps and records each one's PassReport. The time of a step left out of the report
/// counts to the next one recorded.
class PassLog {
 public:
  explicit PassLog(BuildReport* report) : report_(report) {}

  template <class Step>
  void RunPass(const char* name, Step step) {
    const StepOutcome outcome = step();
    if (!outcome) return;
    const double cpu = ThreadCpuSeconds();
    report_->passes.push_back({name, Seconds(start_), cpu - cpu_start_, outcome->variables,
                               outcome->equations, outcome->note});
    start_ = Clock::now();
    cpu_start_ = cpu;
  }

 private:
  BuildReport* report_;
  Clock::time_point start_ = Clock::now();
  double cpu_start_ = ThreadCpuSeconds();
};

// ---- the record the steps share -----------------------------------------------------------------

/// The build under way: the model as the steps hand it on (flat system, then equation system,
/// then compiled model) and what a later step needs of an earlier one.
struct BuildState {
  BuildReport* report = nullptr;
  ParameterOverrides overrides;  ///< the -p values, converted to their parameters' units
  /// The flattened model, until the equation system takes it over.
  std::shared_ptr<FlatSystem> flat;
  /// The component equations left to the first alias elimination (FlatSystem::deferred).
  std::shared_ptr<const DeferredEquations> deferred;
  std::vector<double> params;  ///< parameter values, evaluated once flattened
  EquationSystem sys;
  AliasStats alias;
  IndexStats index;
  Structure structure;
  std::vector<std::string> output_names;
  std::shared_ptr<CompiledModel> model;
};

// ---- the steps after flattening, in order -------------------------------------------------------

/// Parameters evaluated, the equation system set up, and the branches chosen by Boolean and
/// Integer parameters fixed before the structure is analysed; then connectors and parts whose
/// condition is false leave, with the equations that hold only with them.
StepOutcome FixStructuralParameters(BuildState* state) {
  // The passes after flattening about double the expression pool (bench/RESULTS.md): its table is
  // sized for that now, while the build is small, not rehashed at the peak of compilation.
  state->flat->pool->Reserve(2 * state->flat->pool->size());
  // Parameters are evaluated now too, so a bad value is reported before any solving.
  state->params = EvaluateParameters(*state->flat, state->overrides);
  CheckIntegerValues(*state->flat);
  // The system takes the flat system over: passes that extend it need not copy it.
  state->sys = MakeEquationSystem(std::move(state->flat));
  EquationSystem& sys = state->sys;
  // With the conditions folded when the instances were made (decided conditional connectors).
  const size_t folded = FoldStructuralConditions(&sys, state->params) + sys.flat->conditions_decided;
  size_t absent_parts = 0;
  const size_t absent = ResolveConditionalConnectors(&sys, state->params, &absent_parts);
  if (folded + absent + absent_parts == 0) return std::nullopt;
  return StepResult{sys.num_unknowns(), sys.equations.size(),
                    StructuralParametersNote(folded, absent, absent_parts)};
}

/// Aliases, derivative aliases and constrained states, in rounds until nothing changes: only
/// index reduction makes new alias equations. Recorded as alias elimination; the next step
/// records index reduction's part of the rounds.
StepOutcome EliminateAliasesInRounds(BuildState* state) {
  EquationSystem& sys = state->sys;
  IndexStats& index = state->index;
  // The equations' leaves, from one round's alias elimination to the next (collected in the
  // first, kept current by both passes); let go after the rounds.
  auto leaves = std::make_unique<EquationLeaves>();
  for (int round = 0; round < 20; ++round) {
    size_t before = sys.num_unknowns();
    sys = EliminateAliases(std::move(sys), &state->alias, state->deferred.get(), leaves.get());
    state->deferred.reset();  // every equation is made now
    size_t changes_before = index.derivative_aliases + index.constrained_states;
    size_t kept_before = index.kept_constraints;
    sys = ReduceIndex(std::move(sys), &index, leaves.get());
    // When index reduction changed nothing, we are done. A constraint kept as an equation removes
    // no unknown but turns a derivative's definition into a new constraint for the next round.
    if (index.derivative_aliases + index.constrained_states + index.kept_constraints ==
        changes_before + kept_before) {
      break;
    }
    if (sys.num_unknowns() == before && index.kept_constraints == kept_before) break;
  }
  leaves.reset();
  // The constrained states count as unknowns still, removed by index reduction (the next row).
  return StepResult{sys.num_unknowns() + index.constrained_states,
                    sys.equations.size() + index.constrained_states,
                    AliasEliminationNote(state->alias)};
}

/// Index reduction's part of the rounds above (its time is theirs).
StepOutcome RecordIndexReduction(BuildState* state) {
  return StepResult{state->sys.num_unknowns(), state->sys.equations.size(),
                    IndexReductionNote(state->index)};
}

StepOutcome PartitionDiscreteVariables(BuildState* state) {
  DiscreteStats discrete;
  state->sys = PartitionDiscrete(std::move(state->sys), &discrete);
  const EquationSystem& sys = state->sys;
  if (discrete.variables == 0 && sys.whens.empty() && sys.impacts.empty()) return std::nullopt;
  return StepResult{sys.num_unknowns(), sys.equations.size(), DiscretePartitionNote(discrete, sys)};
}

/// Full index reduction where the linear fast path left index > 1, and the first-order form of
/// higher derivatives.
StepOutcome ReduceIndexFully(BuildState* state) {
  EquationSystem& sys = state->sys;
  DifferentiatedSystem differentiated = Pantelides(&sys);
  const bool higher_order =
      std::any_of(differentiated.max_order.begin(), differentiated.max_order.end(),
                  [](uint32_t k) { return k >= 2; });
  if (differentiated.num_differentiated == 0 && !higher_order) return std::nullopt;
  StateSelection selection = SelectDummyDerivatives(&sys, differentiated, state->params);
  // der(x) that the differentiated equations introduced -> the state v of v = der(x), so no
  // residual is nonlinear in a state's derivative (index_reduction.h).
  const size_t derivative_aliases = SubstituteDerivativeAliases(&sys);
  ReportIndexReduction(sys, differentiated, selection, state->report);
  return StepResult{sys.num_unknowns(), sys.equations.size(),
                    PantelidesNote(differentiated, selection, derivative_aliases)};
}

/// States and the matching; a model that lists no outputs outputs its states.
StepOutcome AnalyseCausalStructure(BuildState* state) {
  EquationSystem& sys = state->sys;
  // From here on the flat system is the one index reduction may have extended.
  const FlatSystem& flat = *sys.flat;
  for (const auto& o : flat.outputs) state->output_names.push_back(o.text);
  state->structure = AnalyseStructure(sys);
  CheckStateSelect(sys, state->structure, &state->report->warnings);
  StepResult result{sys.num_unknowns(), sys.equations.size(),
                    StructuralAnalysisNote(state->structure)};
  if (state->output_names.empty()) {
    for (uint32_t v = 0; v < state->structure.is_state.size(); ++v) {
      if (!state->structure.is_state[v]) continue;
      state->output_names.push_back(flat.VariableName(VarId(v)));
      sys.outputs.push_back(sys.pool->Var(VarId(v)));
    }
  }
  return result;
}

StepOutcome PruneUnneeded(BuildState* state) {
  PruneStats pruned;
  state->sys = Prune(std::move(state->sys), &state->structure, &pruned);
  const EquationSystem& sys = state->sys;
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] == VarRole::kPruned) {
      state->report->pruned.push_back(sys.flat->VariableName(VarId(v)));
    }
  }
  return StepResult{sys.num_unknowns(), sys.equations.size(), PruningNote(pruned)};
}

StepOutcome CausalizeSystem(BuildState* state) {
  CausalStats causal;
  state->sys = Causalize(std::move(state->sys), &state->structure, &causal);
  return StepResult{state->sys.num_unknowns(), state->sys.equations.size(),
                    CausalisationNote(causal)};
}

StepOutcome CompileSystem(BuildState* state) {
  state->model = CompileModel(std::move(state->sys), state->structure, state->output_names);
  ReportCompiledModel(*state->model, state->report);
  const size_t n = state->model->num_unknowns();
  return StepResult{n, n, CompilationNote(*state->model)};
}

struct Step {
  const char* name;
  StepOutcome (*run)(BuildState*);
};

/// The steps after flattening. The states are known after "structural analysis".
constexpr Step kSteps[] = {
    {"structural parameters", FixStructuralParameters},
    {"alias elimination", EliminateAliasesInRounds},
    {"index reduction", RecordIndexReduction},
    {"discrete partition", PartitionDiscreteVariables},
    {"pantelides", ReduceIndexFully},
    {"structural analysis", AnalyseCausalStructure},
    {"pruning", PruneUnneeded},
    {"causalisation", CausalizeSystem},
    {"compilation", CompileSystem},
};
constexpr size_t kStepsToStates = 6;

constexpr bool SameText(const char* a, const char* b) {
  return *a == *b && (*a == '\0' || SameText(a + 1, b + 1));
}
static_assert(SameText(kSteps[kStepsToStates - 1].name, "structural analysis"),
              "kStepsToStates counts the steps up to the structural analysis");

// ---- flattening, with the -p values' units and added outputs ------------------------------------

/// Converts the values of `units` into their parameters' declared units in `*overrides`; returns
/// whether any value changed.
bool ConvertOverrideUnits(const FlatSystem& flat, const OverrideUnits& units,
                          ParameterOverrides* overrides) {
  bool changed = false;
  for (const auto& [name, q] : units) {
    std::optional<ParamId> p = flat.FindParameter(name);
    if (!p) continue;  // reported by the build as an unknown parameter
    const std::string& unit = flat.ParameterUnit(*p);
    std::ostringstream given;
    given << "-p " << name << "=" << q.value << " " << q.unit;
    if (unit.empty()) {
      throw UsageError("momenta: " + given.str() + ": " + name + " declares no unit, so a value in " + q.unit +
                       " cannot be converted; give it as a plain number");
    }
    double v;
    try {
      v = ConvertValue(q.value, q.unit, unit);
    } catch (const UnitError& e) {
      throw UsageError("momenta: " + given.str() + ": " + name + " is in " + unit + ": " + e.what());
    }
    changed = changed || v != (*overrides)[name];
    (*overrides)[name] = v;
  }
  return changed;
}

/// `spec` flattened with the -p values, those given with units converted to the units the
/// flattened model declares. Flattening reads the values that shape the structure (counts, a
/// table's jumps), so it is done with them in SI first and, should a conversion change one, again.
std::shared_ptr<FlatSystem> FlattenWithOverrides(const ModelSpec& spec, const Library& library,
                                                 const OverrideUnits& units,
                                                 ParameterOverrides* overrides) {
  auto flat =
      std::make_shared<FlatSystem>(Flatten(spec, library, *overrides, /*defer_equations=*/true));
  if (!units.empty() && ConvertOverrideUnits(*flat, units, overrides)) {
    flat =
        std::make_shared<FlatSystem>(Flatten(spec, library, *overrides, /*defer_equations=*/true));
  }
  return flat;
}

/// The names of the states of `flat`'s model: the steps up to the structural analysis, run on
/// their own (a model that lists no outputs outputs its states).
std::vector<std::string> StateNames(std::shared_ptr<FlatSystem> flat,
                                    const ParameterOverrides& overrides) {
  BuildReport unused;
  BuildState probe;
  probe.report = &unused;
  probe.overrides = overrides;
  // A copy of the deferred equations' owner: `flat` itself stays as flattened for its holders.
  probe.deferred = flat->deferred;
  probe.flat = std::move(flat);
  for (size_t k = 0; k < kStepsToStates; ++k) kSteps[k].run(&probe);
  return probe.output_names;
}

/// `options.add_outputs`' outputs appended to `*spec` (after its states, when it lists no
/// outputs), and `spec` flattened again with them; `flat` when nothing is added.
std::shared_ptr<FlatSystem> FlattenWithAddedOutputs(std::shared_ptr<FlatSystem> flat,
                                                    ModelSpec* spec, const Library& library,
                                                    const BuildOptions& options,
                                                    const ParameterOverrides& overrides) {
  const size_t listed = spec->outputs.size();
  if (listed == 0) {
    for (const std::string& name : StateNames(flat, overrides)) {
      OutputSpec o;
      o.text = name;
      o.loc = spec->loc;
      o.expr = ParseName(name, spec->loc);
      spec->outputs.push_back(std::move(o));
    }
  }
  options.add_outputs(*flat, spec);
  if (listed > 0 && spec->outputs.size() == listed) return flat;
  return std::make_shared<FlatSystem>(Flatten(*spec, library, overrides, /*defer_equations=*/true));
}

/// The free signal inputs of `flat` held as inputs (BuildOptions::hold_free_inputs): for each
/// input u, `der(u) = 0` and the initial equation `u = value` appended to `*spec`, which is then
/// flattened again; `flat` when the model has none. Their names go to `report->inputs`.
std::shared_ptr<FlatSystem> FlattenWithHeldInputs(std::shared_ptr<FlatSystem> flat, ModelSpec* spec,
                                                  const Library& library, const BuildOptions& options,
                                                  const ParameterOverrides& overrides, BuildReport* report) {
  std::vector<std::string> names;
  for (VarId v : flat->free_inputs) names.push_back(flat->VariableName(v));
  for (const auto& [name, value] : options.input_values) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      throw UsageError("momenta: -u " + name + ": " + flat->model_name + " has no unconnected signal input " + name +
                       (names.empty() ? " (it has none)" : " (its unconnected inputs: " + JoinNames(names) + ")"));
    }
  }
  if (names.empty()) return flat;
  for (size_t k = 0; k < names.size(); ++k) {
    const FlatVariable& v = flat->variables[flat->free_inputs[k].value()];
    if (v.type != ValueType::kReal) {
      throw ModelError(flat->instances[v.instance.value()].loc,
                       "the input " + names[k] + " is not connected; only a Real input can be an input of a "
                       "linearisation (connect it to a source)");
    }
    const auto given = options.input_values.find(names[k]);
    const double value = given == options.input_values.end() ? 0.0 : given->second;
    EquationDecl held, initial;
    held.text = "der(" + names[k] + ") = 0";
    initial.text = names[k] + " = " + NumberText(value);
    held.loc = initial.loc = spec->loc;
    held.ast = ParseEquation(held.text, held.loc);
    initial.ast = ParseEquation(initial.text, initial.loc);
    spec->equations.push_back(std::move(held));
    spec->initial_equations.push_back(std::move(initial));
  }
  report->inputs = names;
  return std::make_shared<FlatSystem>(Flatten(*spec, library, overrides, /*defer_equations=*/true));
}

/// The flatten step: `spec` flattened once (BuildOptions), then released when `release` is given.
StepOutcome FlattenModel(const ModelSpec& spec, ModelSpec* release, const Library& library,
                         const BuildOptions& options, BuildState* state) {
  state->overrides = options.overrides;
  state->flat = FlattenWithOverrides(spec, library, options.override_units, &state->overrides);
  // Held inputs and added outputs go on a spec of the build's own unless the caller gave the spec up.
  std::optional<ModelSpec> copy;
  auto extended = [&]() -> ModelSpec* { return release != nullptr ? release : copy ? &*copy : &copy.emplace(spec); };
  if (options.hold_free_inputs || !options.input_values.empty()) {
    state->flat = FlattenWithHeldInputs(std::move(state->flat), extended(), library, options, state->overrides,
                                        state->report);
  }
  if (options.add_outputs) {
    state->flat = FlattenWithAddedOutputs(std::move(state->flat), extended(), library, options,
                                          state->overrides);
  }
  state->deferred = std::move(state->flat->deferred);
  if (release != nullptr) *release = ModelSpec();
  const FlatSystem& flat = *state->flat;
  state->report->num_components = flat.instances.size();
  state->report->num_parameters = flat.parameters.size();
  state->report->overrides = state->overrides;
  return StepResult{flat.variables.size(), flat.equations.size(), FlattenNote(flat)};
}

/// BuildModel; `release`, when given, is `spec` itself, emptied once flattened.
std::shared_ptr<const CompiledModel> Build(const ModelSpec& spec, ModelSpec* release, const Library& library,
                                           const BuildOptions& options, BuildReport* report) {
  PassLog log(report);
  BuildState state;
  state.report = report;
  log.RunPass("flatten", [&] { return FlattenModel(spec, release, library, options, &state); });
  for (const Step& step : kSteps) log.RunPass(step.name, [&] { return step.run(&state); });
  return state.model;
}

}  // namespace

std::shared_ptr<const CompiledModel> BuildModel(const ModelSpec& spec, const Library& library,
                                                const BuildOptions& options, BuildReport* report) {
  return Build(spec, nullptr, library, options, report);
}

std::shared_ptr<const CompiledModel> BuildModel(ModelSpec&& spec, const Library& library,
                                                const BuildOptions& options, BuildReport* report) {
  return Build(spec, &spec, library, options, report);
}

}  // namespace momenta
