// The operations of operators and functions, read alike in both lowering scopes.

#include "core/flatten/lower.h"

#include <unordered_map>

#include "core/expr/expr_chain.h"

namespace momenta::flatten_internal {

Op ChainOp(const Ast& a, bool inverse) {
  if (a.kind == Ast::Kind::kSum) return inverse ? Op::kSub : Op::kAdd;
  if (a.kind == Ast::Kind::kProduct) return inverse ? Op::kDiv : Op::kMul;
  return BinaryOp(a.op);
}

std::vector<bool> ChainInverse(const Ast& a) {
  if (a.kind == Ast::Kind::kBinary) return std::vector<bool>(a.args.size(), false);
  return InverseFlags(a.op);
}

Op BinaryOp(const std::string& s) {
  static const std::unordered_map<std::string, Op> kOps = {
      {"+", Op::kAdd}, {"-", Op::kSub}, {"*", Op::kMul}, {"/", Op::kDiv}, {"^", Op::kPow},
      {"<", Op::kLt},  {"<=", Op::kLe}, {">", Op::kGt},  {">=", Op::kGe}, {"==", Op::kEq},
      {"<>", Op::kNe}, {"and", Op::kAnd}, {"or", Op::kOr}};
  return kOps.at(s);
}

bool FunctionOp(const std::string& s, Op* op) {
  static const std::unordered_map<std::string, Op> kFns = {
      {"sin", Op::kSin},   {"cos", Op::kCos},   {"tan", Op::kTan},     {"asin", Op::kAsin},
      {"acos", Op::kAcos}, {"atan", Op::kAtan}, {"sinh", Op::kSinh},   {"cosh", Op::kCosh},
      {"tanh", Op::kTanh}, {"exp", Op::kExp},   {"log", Op::kLog},     {"log10", Op::kLog10},
      {"sqrt", Op::kSqrt}, {"abs", Op::kAbs},   {"sign", Op::kSign},   {"atan2", Op::kAtan2},
      {"min", Op::kMin},   {"max", Op::kMax},   {"floor", Op::kFloor}};
  auto it = kFns.find(s);
  if (it == kFns.end()) return false;
  *op = it->second;
  return true;
}

}  // namespace momenta::flatten_internal
