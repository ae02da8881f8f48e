#include "core/passes/equation_system.h"

#include <algorithm>

namespace momenta {

const char* VarRoleName(VarRole r) {
  switch (r) {
    case VarRole::kUnknown: return "unknown";
    case VarRole::kAlias: return "alias";
    case VarRole::kConstant: return "constant";
    case VarRole::kConstrained: return "constrained state";
    case VarRole::kInlined: return "inlined";
    case VarRole::kPruned: return "pruned";
  }
  return "?";
}

size_t EquationSystem::num_unknowns() const {
  size_t n = 0;
  for (VarRole r : role) n += r == VarRole::kUnknown;
  for (uint32_t v : DiscreteVariables()) n -= v < role.size() && role[v] == VarRole::kUnknown;
  return n;
}

const std::vector<uint32_t>& EquationSystem::DiscreteVariables() const {
  if (discrete_vars_of_ != flat.get() || discrete_vars_count_ != flat->variables.size()) {
    discrete_vars_.clear();
    for (uint32_t v = 0; v < flat->variables.size(); ++v) {
      if (flat->variables[v].discrete) discrete_vars_.push_back(v);
    }
    discrete_vars_of_ = flat.get();
    discrete_vars_count_ = flat->variables.size();
  }
  return discrete_vars_;
}

FlatSystem& EquationSystem::MutableFlat() {
  if (!owns_flat) {
    // Nobody else holds the flat system (the build hands it over): it is this system's already.
    // Otherwise copy it, so what the other holders see stays as it was.
    if (flat.use_count() != 1) flat = std::make_shared<FlatSystem>(*flat);
    owns_flat = true;
  }
  // The flat system is this system's alone: handing it out for modification is safe.
  return const_cast<FlatSystem&>(*flat);
}

VarId EquationSystem::AddVariable(FlatVariable v, ExprId start_guess) {
  FlatSystem& f = MutableFlat();
  VarId id(static_cast<uint32_t>(f.variables.size()));
  f.variables.push_back(std::move(v));
  role.push_back(VarRole::kUnknown);
  guess.push_back(start_guess);
  return id;
}

uint32_t EquationSystem::AddEquation(FlatEquation eq) {
  FlatSystem& f = MutableFlat();
  ExprId residual = eq.residual;
  f.equations.push_back(std::move(eq));
  equations.push_back({residual, static_cast<uint32_t>(f.equations.size() - 1), SystemEquation::Kind::kDynamic});
  return static_cast<uint32_t>(equations.size() - 1);
}

std::string EquationSystem::Describe(const SystemEquation& eq) const { return DescribeSystemEquation(*flat, eq); }

std::string DescribeSystemEquation(const FlatSystem& flat, const SystemEquation& eq) {
  switch (eq.kind) {
    case SystemEquation::Kind::kDynamic:
      return flat.DescribeEquation(flat.equations[eq.origin]);
    case SystemEquation::Kind::kInitial:
      return "initial equation " + flat.DescribeEquation(flat.initial_equations[eq.origin]);
    case SystemEquation::Kind::kFixedStart: {
      const FlatVariable& v = flat.variables[eq.origin];
      return "fixed start value of " + flat.VariableName(VarId(eq.origin)) + " (" + v.loc.ToString() + ")";
    }
  }
  return "";
}

void EquationSystem::ApplyEliminations() { ApplySubstitution(eliminated.get()); }

void EquationSystem::ApplySubstitution(Substitution* subst) {
  Substitution& s = *subst;
  // Most equations hold no replaced leaf when a later round or pass adds a few replacements to
  // many: checking first spares those the rewrite's memo writes (the result is the same). So
  // for the initial equations and outputs (the fixed start values, x - start, are mostly of
  // states, which stay).
  for (auto& e : equations) {
    if (e.residual.valid() && s.Touches(e.residual)) e.residual = s.Apply(e.residual);  // invalid: deferred
  }
  ApplySubstitutionButEquations(subst);
}

void EquationSystem::ApplySubstitutionButEquations(Substitution* subst) {
  Substitution& s = *subst;
  for (auto& e : initial) {
    if (s.Touches(e.residual)) e.residual = s.Apply(e.residual);
  }
  for (auto& o : outputs) {
    if (s.Touches(o)) o = s.Apply(o);
  }
  ApplySubstitutionToEvents(subst);
}

void EquationSystem::ApplySubstitutionToEvents(Substitution* subst) {
  Substitution& s = *subst;
  for (auto& w : whens) {
    w.condition = s.Apply(w.condition);
    for (auto& a : w.assigns) a.second = s.Apply(a.second);
    for (auto& r : w.reinits) r.second = s.Apply(r.second);
  }
  for (auto& im : impacts) {
    for (ExprId* e : {&im.gap, &im.velocity, &im.restitution, &im.v_small, &im.release}) *e = s.Apply(*e);
  }
  for (auto& d : discrete) d.value = s.Apply(d.value);
}

EquationSystem MakeEquationSystem(std::shared_ptr<const FlatSystem> flat) {
  EquationSystem sys;
  sys.flat = flat;
  sys.pool = flat->pool;
  sys.eliminated = std::make_shared<Substitution>(sys.pool.get());
  sys.role.assign(flat->variables.size(), VarRole::kUnknown);
  sys.guess.resize(flat->variables.size());
  ExprPool& p = *sys.pool;
  sys.equations.reserve(flat->equations.size());
  for (uint32_t k = 0; k < flat->equations.size(); ++k) {
    sys.equations.push_back({flat->equations[k].residual, k, SystemEquation::Kind::kDynamic});
  }
  for (uint32_t k = 0; k < flat->initial_equations.size(); ++k) {
    sys.initial.push_back({flat->initial_equations[k].residual, k, SystemEquation::Kind::kInitial});
  }
  for (uint32_t k = 0; k < flat->variables.size(); ++k) {
    const FlatVariable& v = flat->variables[k];
    sys.guess[k] = v.start.valid() ? v.start : p.Zero();
    if (v.fixed) {
      sys.initial.push_back({p.Sub(p.Var(VarId(k)), sys.guess[k]), k, SystemEquation::Kind::kFixedStart});
    }
  }
  for (const auto& o : flat->outputs) sys.outputs.push_back(o.expr);
  for (uint32_t k = 0; k < flat->whens.size(); ++k) {
    const FlatWhen& w = flat->whens[k];
    sys.whens.push_back({w.condition, w.assigns, w.reinits, k});
  }
  for (uint32_t k = 0; k < flat->impacts.size(); ++k) {
    const FlatImpact& im = flat->impacts[k];
    sys.impacts.push_back({im.gap, im.velocity, im.restitution, im.v_small, im.release, im.force, im.contact, k});
  }
  return sys;
}

std::vector<bool> DifferentiatedVariables(const EquationSystem& sys) {
  std::vector<bool> diff(sys.role.size(), false);
  std::vector<ExprId> ders;
  for (const auto& e : sys.equations) {
    if (!e.residual.valid() || !(sys.pool->mask(e.residual) & kHasDer)) continue;  // invalid: deferred
    CollectLeaves(*sys.pool, e.residual, kHasDer, &ders);
    for (ExprId leaf : ders) {
      diff[sys.pool->node(leaf).a] = true;
    }
  }
  return diff;
}

void EquationLeaves::Invalidate() {
  valid_ = false;
  begin_.clear();
  end_.clear();
  leaves_.clear();
}

void EquationLeaves::Collect(const EquationSystem& sys) {
  const ExprPool& p = *sys.pool;
  const size_t n = sys.equations.size();
  begin_.resize(n);
  end_.resize(n);
  leaves_.clear();
  for (size_t k = 0; k < n; ++k) {
    const ExprId r = sys.equations[k].residual;
    if (r.valid()) {
      CollectLeaves(p, r, kKinds, &scratch_);
    } else {
      scratch_.clear();  // deferred: none until made (Update)
    }
    begin_[k] = static_cast<uint32_t>(leaves_.size());
    leaves_.insert(leaves_.end(), scratch_.begin(), scratch_.end());
    end_[k] = static_cast<uint32_t>(leaves_.size());
  }
  valid_ = true;
}

void EquationLeaves::Update(const ExprPool& pool, size_t k, ExprId residual) {
  CollectLeaves(pool, residual, kKinds, &scratch_);
  if (scratch_.size() <= end_[k] - begin_[k]) {
    // Fewer or as many leaves (a substitution most often replaces one by one): in place.
    std::copy(scratch_.begin(), scratch_.end(), leaves_.begin() + begin_[k]);
    end_[k] = begin_[k] + static_cast<uint32_t>(scratch_.size());
    return;
  }
  begin_[k] = static_cast<uint32_t>(leaves_.size());
  leaves_.insert(leaves_.end(), scratch_.begin(), scratch_.end());
  end_[k] = static_cast<uint32_t>(leaves_.size());
}

void EquationLeaves::Keep(const std::vector<uint32_t>& kept) {
  for (size_t j = 0; j < kept.size(); ++j) {
    begin_[j] = begin_[kept[j]];
    end_[j] = end_[kept[j]];
  }
  begin_.resize(kept.size());
  end_.resize(kept.size());
}

void EquationLeaves::Drop(const std::vector<bool>& drop) {
  size_t j = 0;
  for (size_t k = 0; k < begin_.size(); ++k) {
    if (drop[k]) continue;
    begin_[j] = begin_[k];
    end_[j] = end_[k];
    ++j;
  }
  begin_.resize(j);
  end_.resize(j);
}

bool EquationLeaves::Touches(const Substitution& s, size_t k) const {
  for (const ExprId* l = begin(k); l != end(k); ++l) {
    if (s.Has(*l)) return true;
  }
  return false;
}

std::vector<bool> EquationLeaves::Differentiated(const ExprPool& pool, size_t num_variables) const {
  std::vector<bool> diff(num_variables, false);
  for (size_t k = 0; k < begin_.size(); ++k) {
    for (const ExprId* l = begin(k); l != end(k); ++l) {
      const Node& n = pool.node(*l);
      if (n.op == Op::kDer) diff[n.a] = true;
    }
  }
  return diff;
}

void ApplyEliminations(EquationSystem* sys, EquationLeaves* leaves) {
  Substitution& s = *sys->eliminated;
  const ExprPool& p = *sys->pool;
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    if (!leaves->Touches(s, k)) continue;  // also a deferred equation's (none)
    ExprId& r = sys->equations[k].residual;
    r = s.Apply(r);
    leaves->Update(p, k, r);
  }
  sys->ApplySubstitutionButEquations(&s);
}

}  // namespace momenta
