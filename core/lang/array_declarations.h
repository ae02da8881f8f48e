#pragma once
/// The declarations of one scope — a component type or the model — rewritten element by element
/// (core/lang/arrays.h): a parameter or variable of shape [2] becomes two scalar declarations, an
/// equation between arrays one equation per element, a when-statement on an array one statement
/// per element. Each expression is evaluated by core/lang/array_expression.h.

#include <string>
#include <vector>

#include "core/lang/array_expression.h"
#include "core/lang/arrays.h"

namespace momenta {

class DeclarationScalariser {
 public:
  /// `scope` resolves the names of the expressions; `table` receives the shapes of the scope's
  /// arrays as they are declared (null for modifiers, which declare none); `who` prefixes the
  /// names in messages ("Body" → "Body.r"; empty in the model).
  DeclarationScalariser(ArrayScope scope, ArrayShapes* table, std::string who)
      : scope_(std::move(scope)), table_(table), who_(std::move(who)) {}

  const ArrayScope& scope() const { return scope_; }

  /// The value of `a` (written at `loc`, text `text`) with the shape `shape` must have: a scalar
  /// fills every element; an array must have that shape.
  std::vector<AstPtr> Fill(const AstPtr& a, const std::string& text, const SourceLoc& loc,
                           const Shape& shape, const std::string& what);

  /// Parameters: shapes first (declared, or of a literal value), so that values may use later
  /// arrays; a parameter without shape whose value is an array takes the value's shape.
  std::vector<ParameterDecl> Parameters(const std::vector<ParameterDecl>& params);

  /// Variables. `signals`: shaped signal connectors, whose attributes `variables:` may give
  /// under their name.
  std::vector<VariableDecl> Variables(const std::vector<VariableDecl>& vars,
                                      const ArrayShapes& signals);

  /// Equations: both sides of one shape, one equation per element.
  std::vector<EquationDecl> Equations(const std::vector<EquationDecl>& eqs);

  /// When-clauses: a scalar condition; a statement on an array runs on each element.
  std::vector<WhenDecl> Whens(const std::vector<WhenDecl>& whens);

  /// "Body.r", or "r" in the model.
  std::string Who(const std::string& name) const { return who_.empty() ? name : who_ + "." + name; }

 private:
  /// A record equation (`frame_b.R = absoluteRotation(frame_a.R, R_rel)`): one equation per
  /// field element, of which an overdetermined record's first `residues` are counted.
  void RecordEquation(ArrayEvaluator* ev, const EquationDecl& e, std::vector<EquationDecl>* out);

  ArrayScope scope_;
  ArrayShapes* table_;
  std::string who_;
};

}  // namespace momenta
