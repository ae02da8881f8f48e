#pragma once
/// Infix parser for momenta's equation language (docs/FORMAT.md). Precedence, lowest first:
/// if-then-else, or, and, not, relations, + -, * /, unary minus, ^ (right-associative).
///
/// The parser recurses only into nested constructs (parentheses, call arguments, subscripts,
/// if-expressions); chains of one operator are collected by loops into one node (see ast.h).

#include <string>
#include <string_view>

#include "core/lang/ast.h"
#include "core/base/error.h"
#include "core/base/limits.h"

namespace momenta {

/// The deepest nesting an expression may have (kMaxNestingDepth): parentheses, function calls,
/// subscripts, if-expressions, unary minus, `not` and the exponents of a power chain each add one
/// level; the operands of one chain (`a + b - c`, `a * b`, `a and b`, `elseif` branches) do not.
/// Deeper input is a ModelError "expression nested deeper than 256 levels" at the offending
/// column, instead of a stack overflow in the parser or in a pass that walks the tree. der()
/// around anything but a variable may nest kMaxDifferentiations deep (a ModelError at the
/// innermost der() beyond), so that no derivative is built that index reduction would refuse.
constexpr int kMaxExpressionDepth = kMaxNestingDepth;

/// Parses one expression. `loc` is where the text starts in the user's file; errors are
/// ModelErrors at the offending column.
AstPtr ParseExpression(const std::string& text, const SourceLoc& loc);

/// Parses `lhs = rhs`.
AstEquation ParseEquation(const std::string& text, const SourceLoc& loc);

/// Parses a dotted, possibly subscripted name such as `R[i+1].p` (connection ends, outputs).
AstPtr ParseName(const std::string& text, const SourceLoc& loc);

/// Whether `text` is a dotted name and nothing else (`mass1.flange_b`: no subscripts, spaces or
/// keyword first), which ParseName reads without an error.
bool IsPlainName(std::string_view text);

/// The text to quote in a message: all of it when short, otherwise about 120 characters around
/// `column` (0-based), elided with "…", so a 100 000-term expression does not flood the message.
std::string Excerpt(const std::string& text, int column);

/// The built-in functions and their argument counts (-2: one or two), for messages.
bool IsKnownFunction(const std::string& name, int* arity);
std::string KnownFunctionList();

/// Makes a library's expression function known to the parser by its full name and each dotted
/// tail of it (`MultiBody.Frames.resolve2`, `Frames.resolve2`, `resolve2`), taking `arity`
/// arguments; the library resolves which function a call means.
void RegisterFunction(const std::string& name, int arity);

/// What reads the library's functions when a text calls one that is registered but not yet read
/// (the built-in library reads its functions on first use); called once, then the call's argument
/// count is checked against the function's.
void SetLibraryFunctionReader(void (*read)());

/// Whether `name` is one of momenta's own functions (not a library's).
bool IsBuiltinFunction(const std::string& name);

}  // namespace momenta
