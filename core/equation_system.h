#pragma once
/// The working form of a model between flattening and compilation. Each pass takes an
/// EquationSystem and returns a smaller one: eliminated variables leave the unknowns and are
/// replaced, in every remaining equation, initial equation and output, by an expression of the
/// variables that stay (`eliminated`).

#include <memory>
#include <string>
#include <vector>

#include "core/flat_system.h"

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

}  // namespace momenta
