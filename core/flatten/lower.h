#pragma once
/// Lowering: an expression's syntax tree (core/lang/ast.h) to an expression of the flat system,
/// in the model scope (model_scope.h: nodes of the expression pool) or in a type scope
/// (type_scope.h: template nodes over the type's local indices). What both scopes read the
/// same way is here.

#include <string>
#include <utility>
#include <vector>

#include "core/expr/expr.h"
#include "core/lang/ast.h"

namespace momenta::flatten_internal {

/// The index in scope while an expression is lowered: a `for:` connection's loop variable, or
/// the element index `i` in the modifiers of a `count:` array; its name and value.
using LoopIndex = std::pair<std::string, double>;

/// The operation of a kBinary, kSum or kProduct node; `inverse` for '-' and '/' operands.
Op ChainOp(const Ast& a, bool inverse);

/// Which operands of a kBinary, kSum or kProduct node enter through the inverse operator.
std::vector<bool> ChainInverse(const Ast& a);

/// The operation of a binary operator's text ("+", "<=", "and").
Op BinaryOp(const std::string& s);

/// The operation of a function the expression pool computes (sin, atan2, max); false for any
/// other name.
bool FunctionOp(const std::string& s, Op* op);

}  // namespace momenta::flatten_internal
