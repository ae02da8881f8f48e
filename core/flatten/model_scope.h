#pragma once
/// The model scope: the names a model's own expressions use (its parameters and variables, its
/// components' variables and parameters by path, time, pi, a loop index), the model's parameters
/// and variables themselves, and the values the model's structure is built with (a `count:`, a
/// subscript, a `for:` range), which may use the model's parameters only.

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/flatten/flatten_context.h"
#include "core/flatten/lower.h"
#include "core/lang/unit_check.h"

namespace momenta::flatten_internal {

class ModelScope {
 public:
  explicit ModelScope(FlattenContext* context) : context_(*context) {}

  /// Makes the model's parameters (the first flat parameters), bound to their values.
  void DeclareParameters();
  /// Makes the model's own variables (the first flat variables), with their start values.
  void DeclareVariables();
  /// Whether `name` is a model parameter or a model variable.
  bool Declares(const std::string& name) const { return parameters_.count(name) || variables_.count(name); }

  /// `a`, written as `text` at `loc`, as an expression of the flat system. `loop`: the index in
  /// scope, or null. With `allow_variables` (an equation, a when-clause, an output) it may use
  /// variables, time and the operators on variables; else only parameters and constants.
  ExprId Expr(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop,
              bool allow_variables);
  /// A start value of the model scope (a variable's or a modifier's): its text, which only
  /// messages quote, is made for an expression, not for a number (a start per written-out mass).
  ExprId StartExpr(const Ast& a, const SourceLoc& loc, const LoopIndex* loop);
  /// A structural value that must be a whole number (a count, an index, a range bound; `what`
  /// names it). It stays a double: callers compare it with their limits before converting it to
  /// an integer.
  double StructuralWhole(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop,
                         const std::string& what);
  /// The instance that `seg` (a component's name, with a subscript for an element of an array)
  /// names of component `arr`.
  uint32_t ElementOf(const ComponentArray& arr, const NameSegment& seg, const SourceLoc& loc, const LoopIndex* loop,
                     const std::string& text);
  /// The dimension check of the model's own equations and outputs: names are resolved as the
  /// model's expressions resolve them (a variable's or parameter's unit; "" for anything else).
  UnitChecker& Units();

 private:
  /// The numeric value of a model-scope expression at build time (count:, indices, ranges). Only
  /// model parameters may appear; their values (with overrides) are computed once.
  double StructuralValue(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop);
  /// A model parameter's value, following its binding through other model parameters (each
  /// evaluated once; a binding that reaches itself is a cycle).
  double ParameterValue(ParamId id);
  /// Resolves a name (a kName node) to a leaf expression.
  ExprId Name(const Ast& a, const SourceLoc& base, const LoopIndex* loop, bool allow_variables, const std::string& text);
  /// The value of a subscript. A whole number, the loop index, or a sum of these is added up
  /// here, exactly (whole numbers below 2^52); anything else is built and evaluated as a
  /// structural value, whose text only a message needs (a for: connection resolves two
  /// subscripts per iteration).
  double SubscriptValue(const Ast& a, const SourceLoc& loc, const LoopIndex* loop);
  static std::optional<double> WholeSum(const Ast& a, const LoopIndex* loop);

  /// One expression of the model scope as a LoweringScope (lower.h), made in the pool.
  class Lowering;

  FlattenContext& context_;
  std::unordered_map<std::string, ParamId> parameters_;  ///< the model's, by name
  std::unordered_map<std::string, VarId> variables_;     ///< the model's own, by name
  std::vector<double> structural_values_;  ///< model parameters' values for structural expressions
  std::vector<uint8_t> param_state_;  ///< ParameterValue: 0 new, 1 being evaluated, 2 done
  std::vector<double> param_value_;
  std::optional<UnitChecker> units_;
};

}  // namespace momenta::flatten_internal
