#pragma once
/// The syntax tree of one equation or expression as the user wrote it, before names are resolved.
/// Parsed once per component type and shared by every instance.
///
/// A chain of one kind of operator is one node however long it is — the terms of `a - b + c`, the
/// factors of `a * b / c`, the operands of `a and b and c`, the branches of an elseif chain — so
/// the tree's height grows with nesting only, which the parser bounds (kMaxExpressionDepth), and
/// every recursive walk over a tree stays shallow.

#include <memory>
#include <string>
#include <vector>

namespace momenta {

struct Ast;
using AstPtr = std::shared_ptr<const Ast>;

/// One segment of a dotted name: `R[i+1]` in `R[i+1].p.v`, `R[1, 2]` in `body.R[1, 2]`.
struct NameSegment {
  std::string name;
  AstPtr index;   ///< null when the segment has no subscript
  AstPtr index2;  ///< the second subscript of a matrix element `R[i, j]`, else null
};

struct Ast {
  enum class Kind { kNumber, kBool, kName, kCall, kUnary, kBinary, kSum, kProduct, kIf, kArray };
  Kind kind = Kind::kNumber;
  double number = 0;                ///< kNumber, kBool (0/1)
  std::vector<NameSegment> path;    ///< kName
  /// kCall: function name; kUnary: "-" or "not"; kBinary: the operator ("and" and "or" take any
  /// number of operands, the others two); kSum, kProduct: the operator before each operand, one
  /// character each ('+' or '-', '*' or '/'; the first is '+' or '*').
  std::string op;
  /// Operands. kIf: cond1, value1, cond2, value2, …, else-value (an elseif chain is one node).
  /// kArray: the elements of an array literal `[a, b]` (a matrix `[[1, 0], [0, 1]]` has rows).
  std::vector<AstPtr> args;
  int column = 0;                   ///< 0-based offset of the construct in its source text
  int height = 1;                   ///< levels of nesting, this node included (a leaf is 1)

  /// The dotted name as written, e.g. "R[i].p" (subscripts re-printed from the tree).
  std::string PathText() const;
};

/// An equation `lhs = rhs` as written.
struct AstEquation {
  AstPtr lhs, rhs;
};

/// Fully parenthesised text of the tree: chains print left-associated, "((a - b) + c)".
std::string AstToString(const Ast& a);

/// A node over `args`, one level above the highest of them (no depth check: for trees built from
/// parsed ones, such as the elements of array expressions in core/lang/array_expression.cc).
AstPtr MakeAst(Ast::Kind kind, int column, std::string op, std::vector<AstPtr> args);

}  // namespace momenta
