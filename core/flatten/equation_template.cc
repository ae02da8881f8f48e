// Equation templates (core/flatten/equation_template.h).

#include "core/flatten/equation_template.h"

#include <algorithm>
#include <cmath>

#include "core/base/error.h"

namespace momenta {

ExprId NoTable(const TNode&, const std::vector<ExprId>&) {
  MOMENTA_CHECK_MSG(false, "a template copied without its instance's tables reads none");
  return ExprId();
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
