// Equation templates (core/flatten/equation_template.h).

#include "core/flatten/equation_template.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/base/error.h"

namespace momenta {

ExprId NoTable(const TNode&, const std::vector<ExprId>&) {
  MOMENTA_CHECK_MSG(false, "a template copied without its instance's tables reads none");
  return ExprId();
}

namespace {

/// The children of a template node (-1: none).
std::array<int32_t, 3> Children(const TNode& n) {
  switch (n.kind) {
    case TNode::kOp: {
      const int arity = Arity(n.op);
      return {arity >= 1 ? n.a : -1, arity >= 2 ? n.b : -1, arity >= 3 ? n.c : -1};
    }
    case TNode::kNoEvent:
    case TNode::kDerOf: return {n.a, -1, -1};
    default: return {-1, -1, -1};
  }
}

}  // namespace

bool ReadsTable(const Template& t) {
  return std::any_of(t.nodes.begin(), t.nodes.end(), [](const TNode& n) {
    return n.kind == TNode::kTable || n.kind == TNode::kTimeTable || n.kind == TNode::kBooleanTable;
  });
}

Template FixLocalParameters(const Template& t, const std::vector<double>& values, std::vector<int32_t>* folded,
                            bool* outside) {
  if (outside != nullptr) *outside = false;
  if (t.root < 0 || ReadsTable(t)) return t;
  const size_t size = t.nodes.size();
  // Each node stands for itself, for an earlier node (a folded if-expression: its branch), or
  // for a number; `fixed` marks the subtrees that read a fixed parameter.
  std::vector<int32_t> same(size);
  std::vector<double> number(size, 0.0);
  std::vector<uint8_t> is_number(size, 0), fixed(size, 0);
  for (size_t k = 0; k < size; ++k) {
    const TNode& n = t.nodes[k];
    same[k] = static_cast<int32_t>(k);
    const std::array<int32_t, 3> c = Children(n);
    auto num = [&](int j) { return c[j] >= 0 && is_number[same[c[j]]]; };
    auto value = [&](int j) { return number[same[c[j]]]; };
    for (int32_t child : c) fixed[k] |= child >= 0 && fixed[same[child]];
    double v = std::nan("");
    if (n.kind == TNode::kConst) {
      v = n.value;
    } else if (n.kind == TNode::kLocalParam) {
      if (n.local < values.size() && !std::isnan(values[n.local])) {
        v = values[n.local];
        fixed[k] = 1;
      }
    } else if (n.kind == TNode::kNoEvent && num(0)) {
      v = value(0);
    } else if (n.kind == TNode::kOp && n.op == Op::kIf) {
      if (num(0)) {
        same[k] = same[value(0) != 0 ? c[1] : c[2]];
        if (fixed[same[c[0]]] && folded != nullptr) folded->push_back(c[0]);
        continue;
      }
    } else if (n.kind == TNode::kOp && Arity(n.op) == 1 && num(0)) {
      v = ApplyUnary(n.op, value(0));
    } else if (n.kind == TNode::kOp && Arity(n.op) == 2 && num(0) && num(1)) {
      v = ApplyBinary(n.op, value(0), value(1));
    }
    if (std::isfinite(v)) {
      is_number[k] = 1;
      number[k] = v;
    }
  }
  // The nodes the root reaches, in their order.
  const int32_t root = same[t.root];
  std::vector<uint8_t> reached(size, 0);
  reached[root] = 1;
  for (int32_t k = root; k >= 0; --k) {
    if (!reached[k]) continue;
    if (fixed[k] && outside != nullptr) *outside = true;  // read where no condition decides it
    if (is_number[k]) continue;
    for (int32_t child : Children(t.nodes[k])) {
      if (child >= 0) reached[same[child]] = 1;
    }
  }
  Template out;
  std::vector<int32_t> at(size, -1);
  for (int32_t k = 0; k <= root; ++k) {
    if (!reached[k]) continue;
    TNode n = t.nodes[k];
    if (is_number[k]) {
      n = TNode();
      n.value = number[k];
    } else {
      int32_t* fields[3] = {&n.a, &n.b, &n.c};
      const std::array<int32_t, 3> c = Children(t.nodes[k]);
      for (int j = 0; j < 3; ++j) {
        if (c[j] >= 0) *fields[j] = at[same[c[j]]];
      }
    }
    at[k] = static_cast<int32_t>(out.nodes.size());
    out.nodes.push_back(n);
  }
  out.root = at[root];
  return out;
}

bool NamesLocalVariables(const Template& t, uint32_t first, uint32_t count) {
  return std::any_of(t.nodes.begin(), t.nodes.end(), [&](const TNode& n) {
    return (n.kind == TNode::kLocalVar || n.kind == TNode::kPre) && n.local >= first && n.local < first + count;
  });
}

bool ReadsFixedParameter(const Template& t, const std::vector<double>& values) {
  return std::any_of(t.nodes.begin(), t.nodes.end(), [&](const TNode& n) {
    return n.kind == TNode::kLocalParam && n.local < values.size() && !std::isnan(values[n.local]);
  });
}

SureAlias ReadSureAlias(const Template& t, const std::vector<bool>& discrete, const std::vector<bool>& conditional) {
  SureAlias out;
  size_t constants = 0;
  std::vector<uint32_t> locals;
  for (const TNode& n : t.nodes) {
    switch (n.kind) {
      case TNode::kConst:
        if (++constants > 1) return out;
        break;
      case TNode::kLocalParam: break;
      case TNode::kLocalVar:
        if ((n.local < discrete.size() && discrete[n.local]) || (n.local < conditional.size() && conditional[n.local])) {
          return out;
        }
        if (std::find(locals.begin(), locals.end(), n.local) != locals.end()) return out;
        locals.push_back(n.local);
        break;
      case TNode::kOp:
        if (n.op == Op::kIf) return out;
        break;
      default: return out;  // derivatives, pre-values, time, tables: never an alias
    }
  }
  if (t.root < 0) return out;
  ExprPool pool;
  std::vector<ExprId> made;
  const ExprId r = CopyTemplate(&pool, t, VarId(0), ParamId(0), &made, NoTable, /*cached_constants=*/false);
  AffineForm form;
  if ((pool.mask(r) & kNeverAliasLeaves) ||
      !DecomposeAffine(&pool, r, 2, &form) || form.terms.empty() || !pool.IsConst(form.offset)) {
    return out;
  }
  for (const auto& [leaf, c] : form.terms) {
    if (std::fabs(c) != 1.0) return out;
    out.terms.emplace_back(pool.node(leaf).a, c);
  }
  out.offset = pool.ConstValue(form.offset);
  out.sure = true;
  return out;
}

}  // namespace momenta
