#pragma once
/// The dimension check of equations (docs/FORMAT.md, "Units"): both sides of an equation, every
/// term of a sum, both operands of a relation and every branch of an if-expression have one
/// dimension; `der(x)` has x's dimension per second; the arguments of exp, log, sin, … are
/// dimensionless. Run once per component type (and once for the model's own equations), so its
/// cost does not grow with the number of instances.
///
/// What is known and what is not:
/// - a variable or parameter with a `unit:` has that unit's dimension; one without is *unknown*
///   and matches anything (no false errors), though an equation `x = <known>` infers x's
///   dimension for the type's other equations;
/// - a number is *dimensionless but flexible*, as Modelica tools treat literals: it is 1 in a
///   product (`2*x` has x's dimension) and takes the dimension of what it is added to or compared
///   with (`x + 1`, `x > 0`, `m*a = 0`);
/// - the value of exp, log, sin, atan2, sign … is dimensionless and flexible like a number;
/// - `time` and `pi` have no dimension of their own (models without units use time freely, as in
///   `sin(time)`); `der(x)` is x's dimension per second all the same.

#include <functional>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/lang/ast.h"
#include "core/lang/component_type.h"
#include "core/base/error.h"
#include "core/lang/units.h"

namespace momenta {

/// The unit string of a name as an expression writes it ("flange_a.f", "R[3].v"), or "" when the
/// name has no unit (unknown dimension) or is not a variable or parameter.
using UnitOfName = std::function<std::string(const std::string& path)>;

/// Checks the dimensions of expressions and equations of one scope (a component type or the
/// model). Unit strings are parsed once each and cached.
class UnitChecker {
 public:
  /// `owner` names the scope in messages ("Mass", "model CarrierCollision").
  UnitChecker(std::string owner, UnitOfName unit_of);

  /// `lhs = rhs`: throws ModelError at `loc` (shifted to the offending term) naming the equation,
  /// the owner and the two dimensions, e.g. "… in 'm*a = f + v' of Mass: the terms 'f' and 'v'
  /// have different dimensions: N against m/s".
  void CheckEquation(const Ast& lhs, const Ast& rhs, const std::string& text, const SourceLoc& loc);
  /// An expression on its own (a when-condition, an output): its inner consistency.
  void CheckExpression(const Ast& e, const std::string& text, const SourceLoc& loc);
  /// The unit of an expression, checked as CheckExpression does: a name's declared unit as
  /// written, a known dimension in the words of DimensionText, or "" when not known.
  std::string UnitText(const Ast& e, const std::string& text, const SourceLoc& loc);
  /// `target := value` (a parameter binding, a start value, a when-statement): value has the
  /// dimension of the unit `target_unit` ("" = unknown).
  void CheckAssignment(const std::string& target, const std::string& target_unit, const Ast& value,
                       const std::string& text, const SourceLoc& loc);
  /// Infers the dimensions of names without a unit from equations `x = <known>` (either side a
  /// bare name or der(name)), repeated until nothing changes; call before checking.
  void Infer(const std::vector<std::pair<const Ast*, const Ast*>>& equations);

  /// The dimension of a unit string (cached); nullopt for "".
  std::optional<Dimension> DimensionOf(const std::string& unit);

 private:
  struct Term;
  /// The dimension of a tree, bottom-up; each kind of node has its rule.
  Term Eval(const Ast& a);
  Term SumTerm(const Ast& a);      ///< every term one dimension
  Term ProductTerm(const Ast& a);  ///< the product of the known factors' dimensions
  Term BinaryTerm(const Ast& a);   ///< `and`/`or`, a power, a relation
  Term IfTerm(const Ast& a);       ///< every branch one dimension
  Term CallTerm(const Ast& a);     ///< der, pre, the transcendental functions, sqrt, min, max …
  /// The common dimension of x and y; throws naming `what()` (e.g. "the two sides") when both
  /// are known and differ.
  Term Unify(const Term& x, const Term& y, const Ast& at, const std::function<std::string()>& what);
  Term NameTerm(const Ast& a);
  [[noreturn]] void Fail(const Ast& at, const std::string& why) const;

  std::string owner_;
  UnitOfName unit_of_;
  std::unordered_map<std::string, std::optional<Dimension>> cache_;
  std::unordered_map<std::string, Dimension> inferred_;
  // The statement being checked, for messages.
  const std::string* text_ = nullptr;
  SourceLoc loc_;
};

/// Checks every equation, initial equation, when-clause, parameter binding and start value of a
/// component type (its own declarations; a composite's parts are checked as their own types).
/// `unit_of` gives the units of the type's local names (its variables, connector variables,
/// parameters and its parts' names).
void CheckComponentUnits(const ComponentType& type, const UnitOfName& unit_of);

}  // namespace momenta
