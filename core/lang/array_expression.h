#pragma once
/// One expression on arrays evaluated into the scalar syntax trees of its elements
/// (core/lang/arrays.h): array literals, elementwise `+ -`, scalar `* /`, matrix products, the
/// array functions, element access with constant subscripts, elementwise functions and
/// if-expressions. A scalar subtree that contains no array is returned as it is (the same node),
/// so scalar equations stay untouched. Names are looked up through the ArrayScope alone
/// (ArrayEvaluator::Name), so that one scope abstraction can take its place.

#include <cstddef>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/lang/arrays.h"

namespace momenta {

/// A shape and the scalar tree of each element, row by row.
struct ArrayValue {
  Shape shape;
  std::vector<AstPtr> elements;
  bool scalar() const { return shape.empty(); }
};

/// "1" or "1,2": the subscripts of element `flat` (0-based, row-major).
std::string SubscriptText(const Shape& shape, size_t flat);

/// Whether a tree uses array syntax: a literal, an array function, a matrix subscript, or (when
/// `any_subscript`) any subscript on a name's last segment. False for a null tree.
bool UsesArraySyntax(const AstPtr& a, bool any_subscript);

/// Counts the nodes one scalar form makes (matrix products and long chains of array operations
/// multiply nodes), from the outermost call (ScalarForm, ScalarModifiers, ScalarModel) on;
/// ArrayEvaluator stops past kMaxArrayNodes, about 150 MB of trees.
class ArrayNodeBudget {
 public:
  ArrayNodeBudget();
  ~ArrayNodeBudget();
  ArrayNodeBudget(const ArrayNodeBudget&) = delete;
  ArrayNodeBudget& operator=(const ArrayNodeBudget&) = delete;
};

/// Evaluates the expressions of one statement, whose text `text` at `loc` its messages quote.
class ArrayEvaluator {
 public:
  ArrayEvaluator(const ArrayScope& scope, const std::string& text, const SourceLoc& loc);

  /// The value of tree `p`: its shape and its elements' scalar trees.
  ArrayValue Eval(const AstPtr& p);

  /// The scalar value of a tree that must not be an array (`what` names it in the message).
  AstPtr Scalar(const AstPtr& p, const std::string& what);

  /// Throws ModelError at column `column` of the statement, quoting it and the scope's owner.
  [[noreturn]] void Fail(int column, const std::string& what) const;

 private:
  /// Stops when the nodes made so far exceed kMaxArrayNodes.
  void CheckBudget(int column) const;
  void CheckSize(const Shape& shape, int column) const;

  ArrayValue EvalNode(const AstPtr& p);
  std::vector<ArrayValue> Operands(const Ast& a);
  ArrayValue Elementwise(const AstPtr& p, std::vector<ArrayValue> ops, const std::string& op,
                         bool broadcast);
  ArrayValue Name(const AstPtr& p);
  size_t Subscript(const Ast& name, const Ast& index, int size);
  ArrayValue Literal(const Ast& a);
  ArrayValue Multiply(const AstPtr& p);
  ArrayValue Times(const ArrayValue& x, const ArrayValue& y, int column);
  ArrayValue ArrayFunction(const Ast& a);
  int Size(const Ast& x, const std::string& f);

  const ArrayScope& scope_;
  std::string text_;
  SourceLoc loc_;
};

}  // namespace momenta
