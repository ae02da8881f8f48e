#pragma once
/// Lowering: an expression's syntax tree (core/lang/ast.h) to nodes of the flat system's
/// expressions. One walk (Lower) serves both scopes an expression can be written in, as marco's
/// expression lowerer serves every construct over one LoweringContext: the model scope
/// (model_scope.h), which makes nodes of the expression pool, and a type scope (type_scope.h),
/// which makes template nodes over the type's local indices. The scope resolves names, says what
/// may appear (parameters only? time? tables?) and makes the nodes (LoweringScope); the walk
/// gives every construct one meaning: chains of + - * / and/or as balanced trees, if-elseif
/// chains nested from the last branch, functions, der, noEvent, initial, pre, edge and change.

#include <concepts>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/error.h"
#include "core/expr/expr.h"
#include "core/expr/expr_chain.h"
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

/// The scope an expression is lowered in: how its names resolve, what it may use, and where its
/// nodes go (`Node` identifies a node made).
template <class Scope>
concept LoweringScope = requires(Scope scope, const Scope& const_scope, const Ast& a,
                                 typename Scope::Node x, Op op, double value) {
  /// Whether a function's second operand is lowered before its first (node ids keep the order).
  { Scope::kSecondOperandFirst } -> std::convertible_to<bool>;
  { scope.Constant(value) } -> std::same_as<typename Scope::Node>;
  /// A kName node: a leaf of the scope, or an error naming the valid names.
  { scope.Name(a) } -> std::same_as<typename Scope::Node>;
  { scope.Unary(op, x) } -> std::same_as<typename Scope::Node>;
  { scope.Negate(x) } -> std::same_as<typename Scope::Node>;
  { scope.Binary(op, x, x) } -> std::same_as<typename Scope::Node>;
  { scope.If(x, x, x) } -> std::same_as<typename Scope::Node>;
  { scope.NoEvent(x) } -> std::same_as<typename Scope::Node>;
  { scope.Der(x) } -> std::same_as<typename Scope::Node>;
  { scope.Initial() } -> std::same_as<typename Scope::Node>;
  /// pre() of a node for which IsVariable holds.
  { scope.Pre(x) } -> std::same_as<typename Scope::Node>;
  { const_scope.IsVariable(x) } -> std::same_as<bool>;
  /// Throws for a call (not a function the pool computes) that may not appear here.
  scope.CheckCall(a);
  /// A call that reads a table of the scope (interpolate, timeTable, booleanTable), lowered;
  /// nothing for any other call.
  { scope.TableCall(a) } -> std::same_as<std::optional<typename Scope::Node>>;
  /// The expression's text as messages quote it, and what follows the quote in a message about
  /// the expression's form (" of Mass" in a type, nothing in the model).
  { const_scope.text() } -> std::convertible_to<std::string>;
  { const_scope.OfOwner() } -> std::convertible_to<std::string>;
  /// Throws ModelError with `message` at the column of `at`.
  const_scope.Fail(a, std::string());
};

template <LoweringScope Scope>
typename Scope::Node Lower(const Ast& a, Scope* scope);

/// A call's meaning: a function the pool computes, or an operator the scope allows.
template <LoweringScope Scope>
typename Scope::Node LowerCall(const Ast& a, Scope* scope) {
  using Node = typename Scope::Node;
  auto operand = [&](size_t k) { return Lower(*a.args[k], scope); };
  Op op;
  if (FunctionOp(a.op, &op)) {
    if (Arity(op) == 1) return scope->Unary(op, operand(0));
    if constexpr (Scope::kSecondOperandFirst) {
      const Node y = operand(1);
      return scope->Binary(op, operand(0), y);
    } else {
      const Node x = operand(0);
      return scope->Binary(op, x, operand(1));
    }
  }
  scope->CheckCall(a);
  if (a.op == "noEvent") return scope->NoEvent(operand(0));
  if (std::optional<Node> table = scope->TableCall(a)) return *table;
  if (a.op == "der") return scope->Der(operand(0));
  if (a.op == "initial") return scope->Initial();
  // pre(), edge() and change() take a variable.
  const Node x = operand(0);
  if (!scope->IsVariable(x)) scope->Fail(a, a.op + "() takes a variable, in '" + scope->text() + "'");
  const Node pre = scope->Pre(x);
  if (a.op == "pre") return pre;
  if (a.op == "edge") {
    const Node not_pre = scope->Unary(Op::kNot, pre);
    return scope->Binary(Op::kAnd, x, not_pre);
  }
  if (a.op == "change") return scope->Binary(Op::kNe, x, pre);
  scope->Fail(a, a.op + "() is not allowed in '" + scope->text() + "'");
}

/// `a` lowered in `scope`: its nodes made, operands before the operation that takes them.
template <LoweringScope Scope>
typename Scope::Node Lower(const Ast& a, Scope* scope) {
  using Node = typename Scope::Node;
  auto operands = [&] {
    std::vector<Node> made;
    for (size_t k = 0; k < a.args.size(); ++k) made.push_back(Lower(*a.args[k], scope));
    return made;
  };
  switch (a.kind) {
    case Ast::Kind::kNumber:
    case Ast::Kind::kBool:
      return scope->Constant(a.number);
    case Ast::Kind::kName:
      return scope->Name(a);
    case Ast::Kind::kArray:
      scope->Fail(a, "an array where a number is expected, in '" + scope->text() + "'" + scope->OfOwner());
    case Ast::Kind::kUnary:
      if (a.op == "not") return scope->Unary(Op::kNot, Lower(*a.args[0], scope));
      return scope->Negate(Lower(*a.args[0], scope));
    case Ast::Kind::kBinary:
    case Ast::Kind::kSum:
    case Ast::Kind::kProduct:
      // A chain (a + b - c, a * b / c, a and b and c) as a balanced tree; relations and ^ have
      // two operands.
      return BuildChain(operands(), ChainInverse(a), [&](Node x, bool inverse, Node y) {
        return scope->Binary(ChainOp(a, inverse), x, y);
      });
    case Ast::Kind::kIf:
      // if c1 then v1 elseif c2 then v2 … else e, nested from the last branch.
      return BuildIfChain(operands(), [&](Node c, Node x, Node y) { return scope->If(c, x, y); });
    case Ast::Kind::kCall:
      return LowerCall(a, scope);
  }
  MOMENTA_CHECK_MSG(false, "every kind of syntax node is lowered");
  return scope->Constant(0);
}

}  // namespace momenta::flatten_internal
