#pragma once
/// Infix parser for momenta's equation language (docs/FORMAT.md). Precedence, lowest first:
/// if-then-else, or, and, not, relations, + -, * /, unary minus, ^ (right-associative).

#include <string>

#include "core/ast.h"
#include "core/error.h"

namespace momenta {

/// Parses one expression. `loc` is where the text starts in the user's file; errors are
/// ModelErrors at the offending column.
AstPtr ParseExpression(const std::string& text, const SourceLoc& loc);

/// Parses `lhs = rhs`.
AstEquation ParseEquation(const std::string& text, const SourceLoc& loc);

/// Parses a dotted, possibly subscripted name such as `R[i+1].p` (connection ends, outputs).
AstPtr ParseName(const std::string& text, const SourceLoc& loc);

/// The built-in functions and their argument counts, for messages.
bool IsKnownFunction(const std::string& name, int* arity);
std::string KnownFunctionList();

}  // namespace momenta
