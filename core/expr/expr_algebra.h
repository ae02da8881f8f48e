#pragma once
/// Symbolic algebra on the expression pool, for callers that use several of its parts: leaf
/// collection (expr_leaves.h), substitution (expr_substitution.h), partial and time derivatives
/// (expr_derivatives.h), affine decomposition and solving an equation for one leaf
/// (expr_affine.h), and printing (expr_print.h). Every traversal is iterative (explicit stack),
/// so a 100 000-deep expression — a chain of rods whose offsets add up — cannot overflow the call
/// stack.

#include "core/expr/expr_affine.h"
#include "core/expr/expr_derivatives.h"
#include "core/expr/expr_leaves.h"
#include "core/expr/expr_print.h"
#include "core/expr/expr_substitution.h"
