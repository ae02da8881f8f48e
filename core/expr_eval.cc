#include "core/expr_eval.h"

#include <unordered_map>

namespace momenta {

namespace {

double EvalRec(const ExprPool& pool, ExprId e, const LeafValues& lv,
               std::unordered_map<uint32_t, double>& memo) {
  const Node& n = pool.node(e);
  switch (n.op) {
    case Op::kConst: return n.value;
    case Op::kVar: return lv.vars ? lv.vars[n.a] : 0.0;
    case Op::kDer: return lv.ders ? lv.ders[n.a] : 0.0;
    case Op::kPre: return lv.pres ? lv.pres[n.a] : (lv.vars ? lv.vars[n.a] : 0.0);
    case Op::kParam: return lv.params ? lv.params[n.a] : 0.0;
    case Op::kTime: return lv.time;
    case Op::kInitial: return lv.initial ? 1.0 : 0.0;
    case Op::kCj: return 0.0;
    case Op::kCond: return lv.conds ? lv.conds[n.a] : 0.0;
    default: break;
  }
  auto it = memo.find(e.value());
  if (it != memo.end()) return it->second;
  double r;
  switch (Arity(n.op)) {
    case 1:
      r = ApplyUnary(n.op, EvalRec(pool, ExprId(n.a), lv, memo));
      break;
    case 2:
      r = ApplyBinary(n.op, EvalRec(pool, ExprId(n.a), lv, memo),
                      EvalRec(pool, ExprId(n.b), lv, memo));
      break;
    default:
      r = EvalRec(pool, ExprId(n.a), lv, memo) != 0 ? EvalRec(pool, ExprId(n.b), lv, memo)
                                                     : EvalRec(pool, ExprId(n.c), lv, memo);
  }
  memo.emplace(e.value(), r);
  return r;
}

}  // namespace

double Evaluate(const ExprPool& pool, ExprId e, const LeafValues& leaves) {
  std::unordered_map<uint32_t, double> memo;
  return EvalRec(pool, e, leaves, memo);
}

}  // namespace momenta
