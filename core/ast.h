#pragma once
/// The syntax tree of one equation or expression as the user wrote it, before names are resolved.
/// Parsed once per component type and shared by every instance.

#include <memory>
#include <string>
#include <vector>

namespace momenta {

struct Ast;
using AstPtr = std::shared_ptr<const Ast>;

/// One segment of a dotted name: `R[i+1]` in `R[i+1].p.v`.
struct NameSegment {
  std::string name;
  AstPtr index;  ///< null when the segment has no subscript
};

struct Ast {
  enum class Kind { kNumber, kBool, kName, kCall, kUnary, kBinary, kIf };
  Kind kind = Kind::kNumber;
  double number = 0;                ///< kNumber, kBool (0/1)
  std::vector<NameSegment> path;    ///< kName
  std::string op;                   ///< kCall: function name; kUnary/kBinary: operator text
  std::vector<AstPtr> args;         ///< operands; kIf: cond, then, else
  int column = 0;                   ///< 0-based offset of the construct in its source text

  /// The dotted name as written, e.g. "R[i].p" (subscripts re-printed from the tree).
  std::string PathText() const;
};

/// An equation `lhs = rhs` as written.
struct AstEquation {
  AstPtr lhs, rhs;
};

std::string AstToString(const Ast& a);

}  // namespace momenta
