#pragma once
/// One expression on arrays evaluated into the scalar syntax trees of its elements
/// (core/lang/arrays.h): array literals, elementwise `+ -`, scalar `* /`, matrix products, the
/// array functions, element access with constant subscripts, elementwise functions and
/// if-expressions. A scalar subtree that contains no array is returned as it is (the same node),
/// so scalar equations stay untouched. Names are looked up through the ArrayScope alone
/// (ArrayEvaluator::Name), so that one scope abstraction can take its place.

#include <cstddef>
#include <map>
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

  /// A record's value: its type and each field's value, in the type's field order.
  struct RecordValue {
    const RecordType* type = nullptr;
    std::vector<ArrayValue> fields;
  };
  /// Whether `p` is record-valued: a record name of the scope (`frame_a.R`, `R_rel`), a record
  /// input of the function being inlined, or a call of a function that returns a record.
  bool IsRecord(const AstPtr& p) const;
  /// The value of a record-valued tree (IsRecord).
  RecordValue EvalRecord(const AstPtr& p);

 private:
  /// A library function inlined (docs/FORMAT.md, "Functions"): its inputs bound to the
  /// arguments' values, its body evaluated in a nested evaluator.
  ArrayValue CallFunction(const Ast& a, const FunctionDecl& f);
  RecordValue CallRecordFunction(const Ast& a, const FunctionDecl& f);
  void BindInputs(const Ast& a, const FunctionDecl& f, ArrayEvaluator* inner);
  /// The element, row or whole of value `v` that name `a`'s last subscripts pick.
  ArrayValue Pick(const ArrayValue& v, const Ast& a);
  /// The function `a` calls, if it is a library's.
  const FunctionDecl* LibraryFunction(const Ast& a) const;

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
  std::map<std::string, ArrayValue> bound_;            ///< a function's inputs (`v`, `R.T`)
  std::map<std::string, RecordValue> bound_records_;  ///< its record inputs
  int depth_ = 0;                                      ///< nesting of inlined functions
};

}  // namespace momenta
