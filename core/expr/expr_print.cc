// Infix text of an expression (core/expr/expr_print.h): precedence decides the parentheses;
// deep or long expressions are elided.

#include "core/expr/expr_print.h"

#include <sstream>

namespace momenta {

namespace {

int Precedence(Op op);

int Precedence(const ExprPool& pool, ExprId e) {
  // A negative number prints with a leading minus: it binds like unary minus.
  if (pool.IsConst(e) && pool.ConstValue(e) < 0) return 8;
  return Precedence(pool.op(e));
}

int Precedence(Op op) {
  switch (op) {
    case Op::kIf: return 1;
    case Op::kOr: return 2;
    case Op::kAnd: return 3;
    case Op::kNot: return 4;
    case Op::kLt: case Op::kLe: case Op::kGt: case Op::kGe: case Op::kEq: case Op::kNe:
      return 5;
    case Op::kAdd: case Op::kSub: return 6;
    case Op::kMul: case Op::kDiv: return 7;
    case Op::kNeg: return 8;
    case Op::kPow: return 9;
    default: return 10;
  }
}

/// A constant as expression text shows it: 15 significant digits, not the shortest text that
/// reads back (NumberText, core/base/messages.h). The constants of an equation are often folded
/// (2*pi), and their last binary digits are the folding's noise: 6.28318530717959 says what the
/// model says, 6.283185307179586 says more (`check -v` prints every equation this way).
std::string FormatNumber(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

void Print(const ExprPool& pool, ExprId e, const ExprNamer& names, int depth, std::string* out) {
  if (depth > 60 || out->size() > 4000) {
    *out += "…";
    return;
  }
  const Node& n = pool.node(e);
  auto child = [&](uint32_t c, int min_prec) {
    bool paren = Precedence(pool, ExprId(c)) < min_prec;
    if (paren) *out += "(";
    Print(pool, ExprId(c), names, depth + 1, out);
    if (paren) *out += ")";
  };
  switch (n.op) {
    case Op::kConst:
      *out += FormatNumber(n.value());
      return;
    case Op::kVar: *out += names.var ? names.var(n.a) : "x" + std::to_string(n.a); return;
    case Op::kDer:
      for (uint32_t k = 0; k <= n.b; ++k) *out += "der(";
      *out += names.var ? names.var(n.a) : "x" + std::to_string(n.a);
      for (uint32_t k = 0; k <= n.b; ++k) *out += ")";
      return;
    case Op::kPre:
      *out += "pre(" + (names.var ? names.var(n.a) : "x" + std::to_string(n.a)) + ")";
      return;
    case Op::kParam: *out += names.param ? names.param(n.a) : "p" + std::to_string(n.a); return;
    case Op::kTime: *out += "time"; return;
    case Op::kInitial: *out += "initial()"; return;
    case Op::kCj: *out += "cj"; return;
    case Op::kCond: *out += "c" + std::to_string(n.a); return;
    case Op::kTable: {
      // The table's name: its element [1,1]'s name without the subscript.
      std::string first = names.param ? names.param(n.a) : "p" + std::to_string(n.a);
      *out += first.substr(0, first.rfind('['));
      return;
    }
    case Op::kInterp:
    case Op::kInterpSlope:
      *out += n.op == Op::kInterp ? "interpolate(" : "interpolate_slope(";
      Print(pool, ExprId(n.b), names, depth + 1, out);
      *out += ", ";
      Print(pool, ExprId(n.a), names, depth + 1, out);
      *out += ", " + std::to_string(pool.node(ExprId(n.b)).TableColumn()) + ")";
      return;
    case Op::kNeg: *out += "-"; child(n.a, Precedence(Op::kNeg) + 1); return;
    case Op::kNot: *out += "not "; child(n.a, Precedence(Op::kNot)); return;
    case Op::kIf:
      *out += "if ";
      Print(pool, ExprId(n.a), names, depth + 1, out);
      *out += " then ";
      Print(pool, ExprId(n.b), names, depth + 1, out);
      *out += " else ";
      Print(pool, ExprId(n.c), names, depth + 1, out);
      return;
    default:
      break;
  }
  int arity = Arity(n.op);
  int prec = Precedence(n.op);
  if (prec == 10) {  // function call
    *out += OpName(n.op);
    *out += "(";
    Print(pool, ExprId(n.a), names, depth + 1, out);
    if (arity == 2) {
      *out += ", ";
      Print(pool, ExprId(n.b), names, depth + 1, out);
    }
    *out += ")";
    return;
  }
  bool right_assoc = n.op == Op::kPow;
  // Relations do not chain: both operands of one are parenthesised if they are relations.
  bool relation = IsRelation(n.op);
  child(n.a, right_assoc || relation ? prec + 1 : prec);
  *out += " ";
  *out += OpName(n.op);
  *out += " ";
  child(n.b, right_assoc ? prec : prec + 1);
}

}  // namespace

std::string ToString(const ExprPool& pool, ExprId e, const ExprNamer& names) {
  std::string out;
  Print(pool, e, names, 0, &out);
  return out;
}

}  // namespace momenta
