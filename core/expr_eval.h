#pragma once
/// Numeric meaning of each operation, shared by constant folding, the build-time evaluator and the
/// compiled programs, so that all three agree to the bit.

#include <cmath>
#include <vector>

#include "core/expr.h"

namespace momenta {

inline double ApplyUnary(Op op, double x) {
  switch (op) {
    case Op::kNeg: return -x;
    case Op::kSin: return std::sin(x);
    case Op::kCos: return std::cos(x);
    case Op::kTan: return std::tan(x);
    case Op::kAsin: return std::asin(x);
    case Op::kAcos: return std::acos(x);
    case Op::kAtan: return std::atan(x);
    case Op::kSinh: return std::sinh(x);
    case Op::kCosh: return std::cosh(x);
    case Op::kTanh: return std::tanh(x);
    case Op::kExp: return std::exp(x);
    case Op::kLog: return std::log(x);
    case Op::kLog10: return std::log10(x);
    case Op::kSqrt: return std::sqrt(x);
    case Op::kAbs: return std::fabs(x);
    case Op::kSign: return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
    case Op::kNot: return x != 0 ? 0.0 : 1.0;
    default: return std::nan("");
  }
}

/// x^y with the integer cases done by multiplication (exact and fast for x^2, x^3).
inline double PowValue(double x, double y) {
  if (y == 2.0) return x * x;
  if (y == 3.0) return x * x * x;
  if (y == 0.5) return std::sqrt(x);
  return std::pow(x, y);
}

inline double ApplyBinary(Op op, double x, double y) {
  switch (op) {
    case Op::kAdd: return x + y;
    case Op::kSub: return x - y;
    case Op::kMul: return x * y;
    case Op::kDiv: return x / y;
    case Op::kPow: return PowValue(x, y);
    case Op::kAtan2: return std::atan2(x, y);
    case Op::kMin: return x < y ? x : y;
    case Op::kMax: return x > y ? x : y;
    case Op::kLt: return x < y ? 1.0 : 0.0;
    case Op::kLe: return x <= y ? 1.0 : 0.0;
    case Op::kGt: return x > y ? 1.0 : 0.0;
    case Op::kGe: return x >= y ? 1.0 : 0.0;
    case Op::kEq: return x == y ? 1.0 : 0.0;
    case Op::kNe: return x != y ? 1.0 : 0.0;
    case Op::kAnd: return (x != 0 && y != 0) ? 1.0 : 0.0;
    case Op::kOr: return (x != 0 || y != 0) ? 1.0 : 0.0;
    default: return std::nan("");
  }
}

/// Values for the leaves of an expression, for evaluation outside the compiled programs (parameter
/// bindings at build time, tests). Missing vectors read as zero.
struct LeafValues {
  const double* params = nullptr;
  const double* vars = nullptr;
  const double* ders = nullptr;
  const double* pres = nullptr;
  const double* conds = nullptr;
  double time = 0;
  bool initial = false;
};

/// Evaluates `e` by walking the tree with an explicit stack, each node once: for build time and
/// tests, not hot paths.
double Evaluate(const ExprPool& pool, ExprId e, const LeafValues& leaves);

}  // namespace momenta
