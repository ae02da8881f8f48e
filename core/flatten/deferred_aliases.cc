// Deferred alias equations: each one's form, read from its template or its two variables, and
// the equation made on demand with the leaves in the order flattening would have made them.

#include "core/flatten/deferred_aliases.h"

#include <algorithm>

namespace momenta::flatten_internal {

bool DeferredAliases::Form(uint32_t k, std::vector<std::pair<VarId, double>>* terms, double* offset) const {
  if (k >= entries_.size() || entries_[k].kind == kMade) return false;
  const Entry& e = entries_[k];
  terms->clear();
  *offset = 0;
  switch (e.kind) {
    case kCopy: {
      const SureAlias& a = shapes_[e.shape].form;
      for (const auto& [local, c] : a.terms) terms->emplace_back(VarId(e.x + local), c);
      *offset = a.offset;
      break;
    }
    case kZero: terms->emplace_back(VarId(e.x), 1.0); break;
    case kEqual:
      terms->emplace_back(VarId(e.x), 1.0);
      terms->emplace_back(VarId(e.y), -1.0);
      break;
    case kSum:
      terms->emplace_back(VarId(e.x), 1.0);
      terms->emplace_back(VarId(e.y), 1.0);
      break;
    case kMade: break;
  }
  return true;
}

ExprId DeferredAliases::Make(uint32_t k) const {
  ExprPool& pool = *pool_;
  const Entry& e = entries_[k];
  if (e.kind == kCopy) {
    return CopyTemplate(&pool, *shapes_[e.shape].tmpl, VarId(e.x), ParamId(e.y), &scratch_, NoTable);
  }
  // The leaves in the order ModelConnections makes them.
  if (e.kind == kZero) return pool.Var(VarId(e.x));
  if (e.kind == kEqual) {
    const ExprId y = pool.Var(VarId(e.y));
    return pool.Sub(pool.Var(VarId(e.x)), y);
  }
  const ExprId x = pool.Var(VarId(e.x));
  return pool.Add(x, pool.Var(VarId(e.y)));
}

uint32_t DeferredAliases::AddShape(const Template& t, const SureAlias& form) {
  shapes_.push_back({&t, form});
  return static_cast<uint32_t>(shapes_.size() - 1);
}

void DeferredAliases::MakeDiscrete(FlatSystem* flat) {
  std::vector<std::pair<VarId, double>> terms;
  double offset = 0;
  for (uint32_t k = 0; k < entries_.size(); ++k) {
    if (!Form(k, &terms, &offset)) continue;
    const bool discrete = std::any_of(terms.begin(), terms.end(),
                                      [&](const auto& t) { return flat->variables[t.first.value()].discrete; });
    if (!discrete) continue;
    flat->equations[k].residual = Make(k);
    entries_[k].kind = kMade;
  }
}

}  // namespace momenta::flatten_internal
