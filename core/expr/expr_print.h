#pragma once
/// Expressions as infix text, for `momenta check` and for messages.

#include <cstdint>
#include <functional>
#include <string>

#include "core/expr/expr.h"

namespace momenta {

/// Names for printing leaves.
struct ExprNamer {
  std::function<std::string(uint32_t)> var;
  std::function<std::string(uint32_t)> param;
};

/// Infix text of an expression (for `momenta check` and messages); deep trees are elided.
std::string ToString(const ExprPool& pool, ExprId e, const ExprNamer& names);

}  // namespace momenta
