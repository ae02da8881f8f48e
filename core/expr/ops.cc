// The operations' arity and names (core/expr/ops.h); their arithmetic is inline in the header,
// where constant folding, the evaluator and the program interpreter inline it.

#include "core/expr/ops.h"

namespace momenta {

int Arity(Op op) {
  switch (op) {
    case Op::kConst:
    case Op::kVar:
    case Op::kDer:
    case Op::kPre:
    case Op::kParam:
    case Op::kTime:
    case Op::kInitial:
    case Op::kCj:
    case Op::kCond:
    case Op::kTable:
      return 0;
    case Op::kNeg:
    case Op::kSin:
    case Op::kCos:
    case Op::kTan:
    case Op::kAsin:
    case Op::kAcos:
    case Op::kAtan:
    case Op::kSinh:
    case Op::kCosh:
    case Op::kTanh:
    case Op::kExp:
    case Op::kLog:
    case Op::kLog10:
    case Op::kSqrt:
    case Op::kAbs:
    case Op::kSign:
    case Op::kFloor:
    case Op::kNot:
      return 1;
    case Op::kIf:
      return 3;
    default:
      return 2;
  }
}

bool IsLeaf(Op op) { return Arity(op) == 0; }

bool IsRelation(Op op) {
  return op == Op::kLt || op == Op::kLe || op == Op::kGt || op == Op::kGe || op == Op::kEq ||
         op == Op::kNe;
}

bool IsBooleanOp(Op op) {
  return IsRelation(op) || op == Op::kAnd || op == Op::kOr || op == Op::kNot;
}

const char* OpName(Op op) {
  switch (op) {
    case Op::kConst: return "const";
    case Op::kVar: return "var";
    case Op::kDer: return "der";
    case Op::kPre: return "pre";
    case Op::kParam: return "param";
    case Op::kTime: return "time";
    case Op::kInitial: return "initial";
    case Op::kCj: return "cj";
    case Op::kCond: return "cond";
    case Op::kTable: return "table";
    case Op::kAdd: return "+";
    case Op::kSub: return "-";
    case Op::kMul: return "*";
    case Op::kDiv: return "/";
    case Op::kPow: return "^";
    case Op::kNeg: return "-";
    case Op::kSin: return "sin";
    case Op::kCos: return "cos";
    case Op::kTan: return "tan";
    case Op::kAsin: return "asin";
    case Op::kAcos: return "acos";
    case Op::kAtan: return "atan";
    case Op::kSinh: return "sinh";
    case Op::kCosh: return "cosh";
    case Op::kTanh: return "tanh";
    case Op::kExp: return "exp";
    case Op::kLog: return "log";
    case Op::kLog10: return "log10";
    case Op::kSqrt: return "sqrt";
    case Op::kAbs: return "abs";
    case Op::kSign: return "sign";
    case Op::kFloor: return "floor";
    case Op::kAtan2: return "atan2";
    case Op::kMin: return "min";
    case Op::kMax: return "max";
    case Op::kLt: return "<";
    case Op::kLe: return "<=";
    case Op::kGt: return ">";
    case Op::kGe: return ">=";
    case Op::kEq: return "==";
    case Op::kNe: return "<>";
    case Op::kAnd: return "and";
    case Op::kOr: return "or";
    case Op::kNot: return "not";
    case Op::kIf: return "if";
    case Op::kInterp: return "interpolate";
    case Op::kInterpSlope: return "interpolate_slope";
  }
  return "?";
}

}  // namespace momenta
