// A variable is needed when an output uses it, or when a needed equation uses it; an equation is
// needed when it determines a needed variable (for a state x, the equation matched to der(x)).
// An initial equation is kept when it touches a needed variable, or a variable that needed ones
// determine (it then constrains them), and then all its variables are needed too. The closure is
// a breadth-first walk over the matching.

#include "core/passes/pruning.h"

namespace momenta {

namespace {

/// What the outputs need: variables, equations and initial equations, marked by a closure over
/// the matching from the outputs and the event machinery.
class NeededParts {
 public:
  NeededParts(const EquationSystem& sys, const Structure& structure)
      : need_var(sys.role.size(), false), need_eq(sys.equations.size(), false),
        need_init(sys.initial.size(), false), sys_(sys), pool_(*sys.pool), structure_(structure) {
    // The variables of each initial equation, collected once for the repeated scans below: those
    // of initial equation k are init_vars_[init_start_[k] .. init_start_[k+1]).
    init_start_.reserve(sys.initial.size() + 1);
    for (const SystemEquation& eq : sys.initial) {
      CollectLeaves(pool_, eq.residual, kHasVar | kHasDer | kHasPre, &leaves_);
      for (ExprId leaf : leaves_) init_vars_.push_back(pool_.node(leaf).a);
      init_start_.push_back(static_cast<uint32_t>(init_vars_.size()));
    }
  }

  /// Marks what the outputs and the event machinery read, then everything that determines it.
  void Mark() {
    for (ExprId o : sys_.outputs) MarkLeaves(o);
    // Event machinery is kept whole: what it reads and what it sets.
    for (const auto& w : sys_.whens) {
      MarkLeaves(w.condition);
      for (const auto& a : w.assigns) MarkLeaves(a.second);
      for (const auto& r : w.reinits) {
        MarkLeaves(r.second);
        MarkLeaves(sys_.pool->Var(r.first));
      }
    }
    for (const auto& im : sys_.impacts) {
      for (ExprId e : {im.gap, im.velocity, im.release}) MarkLeaves(e);
      MarkLeaves(sys_.pool->Var(im.force));
    }
    for (const auto& d : sys_.discrete) MarkLeaves(d.value);
    do {
      while (!queue_.empty()) {
        uint32_t v = queue_.back();
        queue_.pop_back();
        int32_t e = structure_.equation_of_var[v];
        if (e >= 0 && !need_eq[e]) {
          need_eq[e] = true;
          MarkLeaves(sys_.equations[e].residual);
        }
      }
    } while (MarkInitialEquations() || !queue_.empty());
  }

  std::vector<bool> need_var, need_eq, need_init;  ///< by variable, equation, initial equation

 private:
  void MarkVariable(uint32_t v) {
    // Cheapest test first: a variable is marked once per leaf that names it, and its flat record
    // is a cache miss each time.
    if (!need_var[v] && sys_.role[v] == VarRole::kUnknown && !sys_.flat->variables[v].discrete) {
      need_var[v] = true;
      queue_.push_back(v);
    }
  }

  void MarkLeaves(ExprId e) {
    CollectLeaves(pool_, e, kHasVar | kHasDer | kHasPre, &leaves_);
    for (ExprId leaf : leaves_) MarkVariable(pool_.node(leaf).a);
  }

  /// Initial equations that touch what is kept, and their variables; returns whether any was
  /// added.
  bool MarkInitialEquations() {
    bool added = false;
    dead_.assign(need_var.size(), false);
    for (size_t k = 0; k < sys_.initial.size(); ++k) {
      if (need_init[k]) continue;
      bool touches = false;
      for (uint32_t j = init_start_[k]; j < init_start_[k + 1] && !touches; ++j) {
        const uint32_t v = init_vars_[j];
        // Discrete variables are always kept (events may need them), so are their initial values.
        touches =
            need_var[v] || (sys_.role[v] == VarRole::kUnknown && sys_.flat->variables[v].discrete);
      }
      if (!touches) touches = ConstrainsNeeded(k);
      if (touches) {
        need_init[k] = true;
        for (uint32_t j = init_start_[k]; j < init_start_[k + 1]; ++j) MarkVariable(init_vars_[j]);
        added = true;
      }
    }
    return added;
  }

  /// Whether initial equation k, which names no needed variable, still constrains one: a variable
  /// it names is determined (through equations that are not a state's) by a needed one. The tip
  /// position of a double pendulum fixed by a sensor-like joint that no output reads settles the
  /// needed joint angles. The variables a failed walk visited are dead for the rest of the pass
  /// (MarkInitialEquations clears them: what is needed grows between passes), so the walks of
  /// one pass cost about one walk over the model.
  bool ConstrainsNeeded(size_t k) {
    std::vector<uint32_t> stack(init_vars_.begin() + init_start_[k], init_vars_.begin() + init_start_[k + 1]);
    std::vector<uint32_t> visited;
    while (!stack.empty()) {
      const uint32_t v = stack.back();
      stack.pop_back();
      if (dead_[v]) continue;
      if (need_var[v]) {
        for (uint32_t u : visited) dead_[u] = false;
        return true;
      }
      dead_[v] = true;
      visited.push_back(v);
      // A state's value at the start is an unknown of the initial system itself, not a function
      // of what its derivative's equation reads.
      const int32_t e = structure_.equation_of_var[v];
      if (e < 0 || structure_.is_state[v] || sys_.role[v] != VarRole::kUnknown) continue;
      CollectLeaves(pool_, sys_.equations[e].residual, kHasVar | kHasDer | kHasPre, &walk_leaves_);
      for (ExprId leaf : walk_leaves_) stack.push_back(pool_.node(leaf).a);
    }
    return false;
  }

  const EquationSystem& sys_;
  const ExprPool& pool_;
  const Structure& structure_;
  std::vector<uint32_t> queue_;
  std::vector<uint32_t> init_start_{0}, init_vars_;
  std::vector<ExprId> leaves_, walk_leaves_;  // scratch
  std::vector<bool> dead_;  ///< by variable: no needed variable determines it (this pass)
};

}  // namespace

EquationSystem Prune(EquationSystem sys, Structure* structure, PruneStats* stats) {
  NeededParts needed(sys, *structure);
  needed.Mark();
  // Drop the rest and renumber the matching.
  stats->equations += KeepMatchedEquations(&sys, structure, needed.need_eq);
  std::vector<SystemEquation> init;
  for (size_t k = 0; k < sys.initial.size(); ++k) {
    if (needed.need_init[k]) {
      init.push_back(sys.initial[k]);
    } else {
      ++stats->initial_equations;
    }
  }
  sys.initial.swap(init);
  structure->num_states = 0;
  for (uint32_t v = 0; v < sys.role.size(); ++v) {
    if (sys.role[v] != VarRole::kUnknown || sys.flat->variables[v].discrete) continue;
    if (!needed.need_var[v]) {
      sys.role[v] = VarRole::kPruned;
      structure->is_state[v] = false;
      ++stats->variables;
    } else {
      structure->num_states += structure->is_state[v];
    }
  }
  return sys;
}

}  // namespace momenta
