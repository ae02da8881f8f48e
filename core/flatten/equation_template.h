#pragma once
/// Equation templates: a component type's equations, start values and parameter bindings as
/// expressions over its local variables and parameters, prepared once per type
/// (core/flatten/type_layout.h's TypeLayout) and copied into the expression pool for each instance with its
/// own first variable and parameter. What is known of every copy from the template alone is read
/// here once (ReadSureAlias), not from each copy.

#include <cstdint>
#include <utility>
#include <vector>

#include "core/expr/expr.h"
#include "core/expr/expr_algebra.h"

namespace momenta {

/// A node of an equation template: an expression over a component's local names.
struct TNode {
  /// kTable: column `value` of the layout's table `local` (the second operand of an interpolation).
  /// kTimeTable: timeTable(table, x, column, smoothness, extrapolation) with a = x, b = the kTable
  /// node, c = smoothness, local = extrapolation; kBooleanTable: booleanTable(table, x), a = x,
  /// b = the kTable node. Both expand per instance (TableExpansion).
  enum Kind : uint8_t { kOp, kConst, kLocalVar, kLocalParam, kPre, kDerOf, kNoEvent, kTime, kInitial, kTable,
                        kTimeTable, kBooleanTable };
  Kind kind = kConst;
  Op op = Op::kConst;
  int32_t a = -1, b = -1, c = -1;  ///< children (template node indices)
  double value = 0;
  uint32_t local = 0;
};

struct Template {
  std::vector<TNode> nodes;
  int32_t root = -1;
  /// Pool ids of the instance-independent nodes (constants, time), filled on first use.
  mutable std::vector<ExprId> fixed;
};

/// Copies template `t` into the pool for the instance whose local variable j is first_var + j
/// (parameters likewise). A node that reads a table is made by `table_node(node, made)`; a
/// template without one never calls it. Constants come from the template's cache (`t.fixed`, made
/// in this pool) unless `cached_constants` is false (another pool). Only the template's first
/// `end` nodes are made when given (its root, the last node, is then not made: invalid result).
template <class TableNode>
ExprId CopyTemplate(ExprPool* pool, const Template& t, VarId first_var, ParamId first_param,
                    std::vector<ExprId>* scratch, TableNode&& table_node, bool cached_constants = true,
                    size_t end = SIZE_MAX) {
  ExprPool& p = *pool;
  std::vector<ExprId>& made = *scratch;
  made.assign(t.nodes.size(), ExprId());
  end = std::min(end, t.nodes.size());
  if (cached_constants && t.fixed.size() != t.nodes.size()) {
    t.fixed.assign(t.nodes.size(), ExprId());
    for (size_t k = 0; k < t.nodes.size(); ++k) {
      if (t.nodes[k].kind == TNode::kConst) t.fixed[k] = p.Const(t.nodes[k].value);
    }
  }
  for (size_t k = 0; k < end; ++k) {
    const TNode& n = t.nodes[k];
    ExprId r;
    switch (n.kind) {
      case TNode::kConst: r = cached_constants ? t.fixed[k] : p.Const(n.value); break;
      case TNode::kLocalVar: r = p.Var(VarId(first_var.value() + n.local)); break;
      case TNode::kLocalParam: r = p.Param(ParamId(first_param.value() + n.local)); break;
      case TNode::kPre: r = p.Pre(VarId(first_var.value() + n.local)); break;
      case TNode::kTime: r = p.Time(); break;
      case TNode::kInitial: r = p.Initial(); break;
      case TNode::kTable:
      case TNode::kTimeTable:
      case TNode::kBooleanTable: r = table_node(n, made); break;
      case TNode::kNoEvent: r = p.NoEvent(made[n.a]); break;
      case TNode::kDerOf: r = TimeDerivative(&p, made[n.a]); break;
      case TNode::kOp: {
        int arity = Arity(n.op);
        if (arity == 1) {
          r = p.Unary(n.op, made[n.a]);
        } else if (arity == 2) {
          r = p.Binary(n.op, made[n.a], made[n.b]);
        } else {
          r = p.If(made[n.a], made[n.b], made[n.c]);
        }
        break;
      }
    }
    made[k] = r;
  }
  return made[t.root];
}

/// For copies of templates that read no table (CopyTemplate's table_node).
ExprId NoTable(const TNode& node, const std::vector<ExprId>& made);

/// `t` with some local parameters fixed (`values[local]`; NaN: not fixed) and what that decides
/// folded as the pool would fold its copies: an operation on numbers is their number when it is
/// finite, an if-expression on a number is its branch, noEvent of a number the number. Only the
/// nodes its root still reaches are kept, in their order (the root stays the last node). Each
/// if-expression folded because its condition read a fixed parameter adds its condition's node
/// index in `t` to `folded` (when given). `outside` (when given) is set when a fixed parameter is
/// still read after folding (anywhere but in a condition it decides, as in `b and x` or `b*x`).
/// A template that reads a table is returned unchanged: the caller leaves those alone.
Template FixLocalParameters(const Template& t, const std::vector<double>& values, std::vector<int32_t>* folded,
                            bool* outside = nullptr);

/// Whether template `t` reads a table (its copies need the instance's tables).
bool ReadsTable(const Template& t);
/// Whether template `t` reads a local parameter that `values` fixes (not NaN there).
bool ReadsFixedParameter(const Template& t, const std::vector<double>& values);

/// Whether template `t` names one of the local variables [first, first + count) (its value, a
/// derivative or a left limit).
bool NamesLocalVariables(const Template& t, uint32_t first, uint32_t count);

/// The form of an equation template that alias elimination always removes: x = ±y + c or x = c,
/// over continuous variables, with c a number. Whatever aliases come before it, it is consumed or
/// found redundant (0 = c): it is never needed as an expression.
struct SureAlias {
  bool sure = false;
  std::vector<std::pair<uint32_t, double>> terms;  ///< local variable, coefficient ±1
  double offset = 0;
};

/// Whether template `t` is a sure alias (±x ± y = c or ±x = c), read from a copy in a pool of its
/// own (the model's pool is not touched). `discrete` and `conditional` mark the local variables
/// that are discrete (never aliased) or of a conditional connector (whose equations may go before
/// alias elimination); a template that names one of them, reads a table or has an if-expression
/// is not a sure alias. Nor is one with two constants or a variable named twice: its form is
/// folded in an order that follows node ids, which differ between the two pools, so its offset or
/// coefficient could differ in the last bit from the form of a made copy.
SureAlias ReadSureAlias(const Template& t, const std::vector<bool>& discrete, const std::vector<bool>& conditional);

}  // namespace momenta
