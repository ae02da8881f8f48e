#include "core/expr/expr_eval.h"

#include <unordered_map>

namespace momenta {

namespace {

double LeafValue(const Node& n, const LeafValues& lv) {
  switch (n.op) {
    case Op::kConst: return n.value();
    case Op::kVar: return lv.vars ? lv.vars[n.a] : 0.0;
    case Op::kDer: return lv.ders ? lv.ders[n.a] : 0.0;
    case Op::kPre: return lv.pres ? lv.pres[n.a] : (lv.vars ? lv.vars[n.a] : 0.0);
    case Op::kParam: return lv.params ? lv.params[n.a] : 0.0;
    case Op::kTime: return lv.time;
    case Op::kInitial: return lv.initial ? 1.0 : 0.0;
    case Op::kCond: return lv.conds ? lv.conds[n.a] : 0.0;
    default: return 0.0;  // kCj
  }
}

}  // namespace

double Evaluate(const ExprPool& pool, ExprId root, const LeafValues& leaves) {
  // Children first with an explicit stack (an expression may be a deep chain), each node once.
  std::unordered_map<uint32_t, double> value;
  std::vector<uint32_t> stack{root.value()};
  while (!stack.empty()) {
    const uint32_t id = stack.back();
    const Node& n = pool.node(ExprId(id));
    if (value.count(id)) {
      stack.pop_back();
      continue;
    }
    const int arity = Arity(n.op);
    if (arity == 0) {
      value.emplace(id, LeafValue(n, leaves));
      stack.pop_back();
      continue;
    }
    const uint32_t kids[3] = {n.a, n.b, n.c};
    bool ready = true;
    for (int k = 0; k < arity; ++k) {
      if (!value.count(kids[k])) {
        stack.push_back(kids[k]);
        ready = false;
      }
    }
    if (!ready) continue;
    stack.pop_back();
    double r;
    if (n.op == Op::kInterp || n.op == Op::kInterpSlope) {
      // The table's elements are parameters: read them from the parameter values.
      const Node& t = pool.node(ExprId(n.b));
      r = leaves.params ? InterpolateTable(leaves.params + t.a, t.b, t.TableColumns(), t.TableColumn(),
                                           value.at(n.a), n.op == Op::kInterpSlope)
                        : 0.0;
    } else if (arity == 1) {
      r = ApplyUnary(n.op, value.at(n.a));
    } else if (arity == 2) {
      r = ApplyBinary(n.op, value.at(n.a), value.at(n.b));
    } else {
      r = value.at(n.a) != 0 ? value.at(n.b) : value.at(n.c);
    }
    value.emplace(id, r);
  }
  return value.at(root.value());
}

}  // namespace momenta
