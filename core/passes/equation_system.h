#pragma once
/// The working form of a model between flattening and compilation. Each pass takes an
/// EquationSystem and returns a smaller one: eliminated variables leave the unknowns and are
/// replaced, in every remaining equation, initial equation and output, by an expression of the
/// variables that stay (`eliminated`).

#include <memory>
#include <string>
#include <vector>

#include "core/flatten/flat_system.h"

namespace momenta {

/// What became of a variable of the flat system.
enum class VarRole : uint8_t {
  kUnknown,      ///< still solved for
  kAlias,        ///< = ±other + offset (alias elimination)
  kConstant,     ///< = a parameter expression (alias elimination)
  kConstrained,  ///< a state fixed by a constraint on other states (index reduction)
  kInlined,      ///< computed explicitly from its equation (causalisation)
  kPruned,       ///< nothing requested needs it
};
const char* VarRoleName(VarRole r);

struct SystemEquation {
  ExprId residual;
  uint32_t origin;  ///< index into flat->equations, or into flat->initial_equations (initial), or the variable (fixed start)
  enum class Kind : uint8_t { kDynamic, kInitial, kFixedStart } kind = Kind::kDynamic;
};

/// A parameter expression that divides in an eliminated variable's formula: zero would make the
/// model singular, so it is checked whenever parameters are set.
struct DivisorGuard {
  ExprId divisor;
  uint32_t equation;  ///< index into flat->equations
  VarId variable;
};

/// A when-clause as it stands after eliminations (targets are flat variables).
struct SystemWhen {
  ExprId condition;
  std::vector<std::pair<VarId, ExprId>> assigns, reinits;
  uint32_t origin;  ///< index into flat->whens
};

struct SystemImpact {
  ExprId gap, velocity, restitution, v_small, release;
  VarId force, contact;
  uint32_t origin;  ///< index into flat->impacts
};

/// A discrete variable's defining equation, solved: var = value (evaluated at events only).
struct DiscreteEquation {
  VarId var;
  ExprId value;
  uint32_t origin;  ///< index into flat->equations
};

struct EquationSystem {
  std::shared_ptr<const FlatSystem> flat;
  std::shared_ptr<ExprPool> pool;
  std::vector<SystemEquation> equations;  ///< continuous-time equations
  std::vector<SystemEquation> initial;    ///< initial equations and fixed start values
  std::vector<VarRole> role;              ///< by flat variable
  std::vector<ExprId> guess;              ///< start value (guess) by flat variable, parameter-only
  std::vector<ExprId> outputs;            ///< by flat output
  std::shared_ptr<Substitution> eliminated;
  std::vector<DivisorGuard> guards;
  std::vector<SystemWhen> whens;
  std::vector<SystemImpact> impacts;
  std::vector<DiscreteEquation> discrete;  ///< in evaluation order
  bool owns_flat = false;  ///< `flat` is this system's alone (see MutableFlat)

  /// The continuous unknowns: variables still solved for, less the discrete ones.
  size_t num_unknowns() const;
  /// The flat system for passes that add to it (index reduction): copied on first use, so the
  /// flat system others hold stays as flattened.
  FlatSystem& MutableFlat();
  /// Adds a variable (unknown, with a parameter-only start guess) and returns it.
  VarId AddVariable(FlatVariable v, ExprId guess);
  /// Adds a continuous equation with its flat description; returns its index in `equations`.
  uint32_t AddEquation(FlatEquation eq);
  /// The flat equation an equation came from, described in the user's names.
  std::string Describe(const SystemEquation& eq) const;
  /// Applies `eliminated` to every equation, initial equation, output and guess.
  void ApplyEliminations();
  /// Applies `s` to every initial equation, output, when-clause, impact and discrete equation:
  /// ApplySubstitution but for the equations (see ApplyEliminations(sys, leaves)).
  void ApplySubstitutionButEquations(Substitution* s);
  /// Applies `s` to every equation, initial equation, output, when-clause, impact and discrete
  /// equation.
  void ApplySubstitution(Substitution* s);
  /// Applies `s` to the when-clauses, impacts and discrete equations only (for a substitution
  /// whose leaves the equations and outputs are known not to hold).
  void ApplySubstitutionToEvents(Substitution* s);

 private:
  /// The discrete variables of the flat system (num_unknowns' list: the build counts unknowns
  /// after every round, and reading each unknown's record from the flat system was a cache miss
  /// each), taken again when the flat system is replaced or extended.
  const std::vector<uint32_t>& DiscreteVariables() const;
  mutable std::vector<uint32_t> discrete_vars_;
  mutable const FlatSystem* discrete_vars_of_ = nullptr;
  mutable size_t discrete_vars_count_ = 0;
};

/// The flat equation `eq` came from, described in the user's names (EquationSystem::Describe, for
/// holders of the flat system alone: a compiled model describes its rows on demand).
std::string DescribeSystemEquation(const FlatSystem& flat, const SystemEquation& eq);

/// Sets up the working form: every flat variable unknown, every equation present, fixed start
/// values as initial equations `x = start`.
EquationSystem MakeEquationSystem(std::shared_ptr<const FlatSystem> flat);

/// Variables whose derivative appears in the equations (the candidate states), by flat variable.
std::vector<bool> DifferentiatedVariables(const EquationSystem& sys);

/// The variable, derivative and pre-value leaves of each equation of a system, collected once and
/// kept current by the passes that rewrite or drop equations: the rounds of alias elimination and
/// index reduction ask several questions of every equation (is it touched by a substitution? are
/// all its variables states? which derivatives does it hold?), and reading a few leaves is cheaper
/// than walking the equation's tree for each.
class EquationLeaves {
 public:
  /// The kinds of leaf held (a substitution of the passes maps only these).
  static constexpr uint8_t kKinds = kHasVar | kHasDer | kHasPre;

  /// Whether the lists are collected (Collect) and current.
  bool valid() const { return valid_; }
  /// Forgets the lists (a pass rewrote the equations without keeping them current).
  void Invalidate();
  /// Collects the leaves of every equation of `sys` (all made).
  void Collect(const EquationSystem& sys);
  /// Equation k's residual is now `residual`: collects its leaves again.
  void Update(const ExprPool& pool, size_t k, ExprId residual);
  /// Keeps the lists of the equations `kept` (indices, increasing), renumbered 0, 1, ...: the
  /// system's equations were filtered the same way.
  void Keep(const std::vector<uint32_t>& kept);
  /// Keeps the lists of the equations whose `drop` flag is false.
  void Drop(const std::vector<bool>& drop);

  size_t size() const { return begin_.size(); }
  const ExprId* begin(size_t k) const { return leaves_.data() + begin_[k]; }
  const ExprId* end(size_t k) const { return leaves_.data() + end_[k]; }
  /// Whether `s` maps a leaf of equation k: s.Touches(residual), for a substitution that maps
  /// variables, derivatives and pre-values only.
  bool Touches(const Substitution& s, size_t k) const;
  /// Variables whose derivative appears in the equations: DifferentiatedVariables(sys).
  std::vector<bool> Differentiated(const ExprPool& pool, size_t num_variables) const;

 private:
  std::vector<uint32_t> begin_, end_;  ///< by equation, into leaves_
  std::vector<ExprId> leaves_;         ///< an updated equation's list is appended anew
  std::vector<ExprId> scratch_;
  bool valid_ = false;
};

/// Applies `sys.eliminated` to the system's equations that `leaves` says it touches, keeping the
/// lists current, and to everything else as EquationSystem::ApplyEliminations does.
void ApplyEliminations(EquationSystem* sys, EquationLeaves* leaves);

}  // namespace momenta
