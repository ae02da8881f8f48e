#pragma once
/// The operations of an expression node and their numeric meaning, below everything else in
/// core/expr: the pool folds constants with ApplyUnary/ApplyBinary, the build-time evaluator
/// (expr_eval.h) and the compiled programs (core/compile/program.h) compute with the same
/// functions, so that all three agree to the bit.

#include <cmath>
#include <cstdint>

namespace momenta {

enum class Op : uint8_t {
  // Leaves.
  kConst,    ///< value
  kVar,      ///< a = VarId: the value of a variable
  kDer,      ///< a = VarId, b = order - 1: a time derivative of a variable (order 1, 2, …)
  kPre,      ///< a = VarId: the left limit of a discrete variable at an event
  kParam,    ///< a = ParamId
  kTime,     ///< the independent variable
  kInitial,  ///< true during initialisation only
  kCj,       ///< IDA's coefficient cj in dF/dy + cj dF/dy' (Jacobians only)
  kCond,     ///< a = condition index: an event relation's value, frozen between events
  /// A column of a table parameter (docs/FORMAT.md, "Tables"): a = ParamId of its element [1,1],
  /// b = rows, c = the columns (elements row by row in consecutive parameters) and the column
  /// read (1-based; Node::TableColumns, Node::TableColumn). Read only as the second operand of
  /// kInterp and kInterpSlope.
  kTable,
  // Arithmetic.
  kAdd, kSub, kMul, kDiv, kPow, kNeg,
  // Functions of one argument.
  kSin, kCos, kTan, kAsin, kAcos, kAtan, kSinh, kCosh, kTanh, kExp, kLog, kLog10, kSqrt, kAbs,
  kSign,
  // Functions of two arguments.
  kAtan2, kMin, kMax,
  // Relations and logic; values are 1.0 (true) and 0.0 (false).
  kLt, kLe, kGt, kGe, kEq, kNe, kAnd, kOr, kNot,
  // if a then b else c.
  kIf,
  // interpolate(table, x): a = x, b = a kTable leaf; linear between rows, linear extrapolation
  // through the first or last two rows, constant for a one-row table. kInterpSlope is its
  // derivative with respect to x (the slope of the segment x lies in).
  kInterp, kInterpSlope,
  // floor(x), a function of one argument, last: the values above stay those that compiled code's
  // cache keys (core/compile/native_code.cc) hash.
  kFloor,
};

int Arity(Op op);
bool IsLeaf(Op op);
bool IsRelation(Op op);
bool IsBooleanOp(Op op);  ///< relations, and/or/not: the value is 0 or 1
const char* OpName(Op op);

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
    case Op::kFloor: return std::floor(x);
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

}  // namespace momenta
