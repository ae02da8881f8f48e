// Alias elimination by union-find with signs and offsets: every variable x points to a root r
// with x = sign*r + offset (sign = ±1, offset a parameter expression), or to "constant" with
// x = offset. An alias equation c1*x + c2*y + d = 0 (|c1| = |c2|) joins the roots of x and y.

#include "core/passes/alias_elimination.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace momenta {

namespace {

constexpr uint32_t kConstantRoot = 0xfffffffeu;
/// An alias equation, resolved, leaves two variables; one with more terms than this is not looked
/// at (a longer equation rarely shrinks to two).
constexpr size_t kMaxAliasTerms = 6;

struct Link {
  uint32_t parent;
  double sign;
  ExprId offset;
};

class AliasForest {
 public:
  AliasForest(ExprPool* pool, size_t n) : pool_(pool), links_(n) {
    for (uint32_t k = 0; k < n; ++k) links_[k] = {k, 1.0, pool->Zero()};
  }

  /// x = sign*root + offset, with path compression.
  Link Find(uint32_t x) {
    ExprPool& p = *pool_;
    // Walk to the root, then compress.
    std::vector<uint32_t>& path = path_;
    path.clear();
    uint32_t r = x;
    while (r != kConstantRoot && links_[r].parent != r) {
      path.push_back(r);
      r = links_[r].parent;
    }
    // Compose from the node nearest the root outwards.
    for (size_t k = path.size(); k-- > 0;) {
      uint32_t node = path[k];
      Link& l = links_[node];
      if (l.parent == r) continue;
      const Link& up = links_[l.parent];  // already points at r
      l.offset = p.Add(p.Mul(p.Const(l.sign), up.offset), l.offset);
      l.sign *= up.sign;
      l.parent = r;
    }
    if (x == r) return {r, 1.0, p.Zero()};
    return links_[x];
  }

  void Attach(uint32_t child_root, uint32_t parent, double sign, ExprId offset) {
    links_[child_root] = {parent, sign, offset};
  }

 private:
  ExprPool* pool_;
  std::vector<Link> links_;
  std::vector<uint32_t> path_;  ///< Find's scratch
};

/// Whether `e` is an alias candidate: affine in at most `max_terms` variables, with numeric
/// coefficients; sets the terms (variable, coefficient) and the offset.
bool IsAffine(ExprPool* p, ExprId e, size_t max_terms, AffineForm* form,
              std::vector<std::pair<VarId, double>>* terms, ExprId* offset) {
  if (p->mask(e) & kNeverAliasLeaves) return false;
  if (!DecomposeAffine(p, e, max_terms, form) || form->terms.empty()) return false;
  terms->clear();
  for (const auto& [leaf, c] : form->terms) terms->emplace_back(VarId(p->node(leaf).a), c);
  *offset = form->offset;
  return true;
}

/// The form of flat equation k, which flattening did not make (DeferredEquations), as IsAffine
/// gives a made one's.
bool DeferredForm(ExprPool* p, const DeferredEquations* deferred, uint32_t k,
                  std::vector<std::pair<VarId, double>>* terms, ExprId* offset) {
  MOMENTA_CHECK_MSG(deferred != nullptr, "a flat system with deferred equations goes with its DeferredEquations");
  double c = 0;
  if (!deferred->Form(k, terms, &c)) return false;
  *offset = p->Const(c);
  return true;
}

/// What one alias equation does when its terms are resolved through the forest.
enum class AliasOutcome {
  kJoined,     ///< two roots joined, or one made constant: the equation is consumed
  kMayAlias,   ///< kept; more roots now, but later joins may leave two
  kCancelled,  ///< every term cancelled: kept as 0 = d (`cancelled` holds d)
  kKept,       ///< kept for good: not affine with a few terms, or of discrete variables
};

/// Joins alias sets in the forest, one equation at a time: an equation is an alias once its
/// terms, resolved through the forest, leave at most two roots with coefficients of equal size.
class AliasJoiner {
 public:
  AliasJoiner(const EquationSystem& sys, const DeferredEquations* deferred,
              const std::vector<bool>& differentiated)
      : pool_(*sys.pool),
        flat_(*sys.flat),
        deferred_(deferred),
        differentiated_(differentiated),
        forest_(sys.pool.get(), sys.flat->variables.size()),
        keep_(sys.flat->variables.size(), false) {
    // Impact forces stay (their equation gives way to Newton's law at an impact).
    for (const auto& im : sys.impacts) keep_[im.force.value()] = true;
  }

  /// Resolves `eq` and joins what it makes aliases; `*cancelled` is set with kCancelled.
  AliasOutcome Join(const SystemEquation& eq, ExprId* cancelled) {
    ExprPool& p = pool_;
    ExprId d;  // the form's offset
    if (!(eq.residual.valid() ? IsAffine(&p, eq.residual, kMaxAliasTerms, &form_, &terms_, &d)
                              : DeferredForm(&p, deferred_, eq.origin, &terms_, &d))) {
      return AliasOutcome::kKept;
    }
    // The terms by variable index, not in the order the form's walk met them (which follows node
    // ids): the roots, and the sum their offsets make, come in that order.
    std::sort(terms_.begin(), terms_.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    // Discrete variables are never aliased: their equations are evaluated at events.
    bool discrete = false;
    for (const auto& t : terms_) discrete = discrete || flat_.variables[t.first.value()].discrete;
    ResolveRoots(&d);
    if (roots_.empty() && !discrete) {
      // Every term cancels: 0 = d. Redundant or contradictory; kept in that plain form, so the
      // structural check reports it as an equation without unknowns.
      *cancelled = d;
      return AliasOutcome::kCancelled;
    }
    if (discrete) return AliasOutcome::kKept;
    if (roots_.size() == 1) {
      // a*r + d = 0: r is constant.
      forest_.Attach(roots_[0].first, kConstantRoot, 1.0,
                     p.Neg(p.Div(d, p.Const(roots_[0].second))));
      return AliasOutcome::kJoined;
    }
    if (roots_.size() == 2 && std::fabs(roots_[0].second) == std::fabs(roots_[1].second)) {
      // a1*r1 + a2*r2 + d = 0  =>  r1 = -(a2/a1) r2 - d/a1, r1 the one that gives way.
      auto [r1, a1] = roots_[0];
      auto [r2, a2] = roots_[1];
      if (Rank(r1) > Rank(r2) || (Rank(r1) == Rank(r2) && r1 < r2)) {
        std::swap(r1, r2);
        std::swap(a1, a2);
      }
      forest_.Attach(r1, r2, -a2 / a1, p.Neg(p.Div(d, p.Const(a1))));
      return AliasOutcome::kJoined;
    }
    return AliasOutcome::kMayAlias;
  }

  AliasForest& forest() { return forest_; }

 private:
  /// Which root survives: impact forces, `stateSelect: always`, states, `stateSelect: prefer`, a
  /// fixed start, then order. An `always` variable stays even when an alias of it appears
  /// differentiated and it does not (a spherical joint's w_rel, the body's w_a after it): its
  /// derivative then appears in the alias's place, and the state is the one the user chose.
  std::tuple<int, int, int, int, int, int> Rank(uint32_t v) const {
    const FlatVariable& fv = flat_.variables[v];
    return std::make_tuple(keep_[v] ? 1 : 0, fv.state_priority == kStateAlways ? 1 : 0,
                           differentiated_[v] ? 1 : 0, fv.state_priority, fv.fixed ? 1 : 0,
                           fv.is_flow ? 0 : 1);
  }

  /// sum c_k x_k + d with x_k = s_k r_k + o_k: a_r per root (those left nonzero) in `roots_`, the
  /// offsets added to `*d`.
  void ResolveRoots(ExprId* d) {
    ExprPool& p = pool_;
    roots_.clear();
    for (const auto& [var, c] : terms_) {
      Link l = forest_.Find(var.value());
      if (!p.IsConst(l.offset, 0)) *d = p.Add(*d, p.Mul(p.Const(c), l.offset));
      if (l.parent == kConstantRoot) continue;
      auto it = std::find_if(roots_.begin(), roots_.end(),
                             [&](const auto& r) { return r.first == l.parent; });
      if (it == roots_.end()) {
        roots_.emplace_back(l.parent, c * l.sign);
      } else {
        it->second += c * l.sign;
      }
    }
    roots_.erase(
        std::remove_if(roots_.begin(), roots_.end(), [](const auto& r) { return r.second == 0.0; }),
        roots_.end());
  }

  ExprPool& pool_;
  const FlatSystem& flat_;
  const DeferredEquations* deferred_;
  const std::vector<bool>& differentiated_;
  AliasForest forest_;
  std::vector<bool> keep_;  ///< by variable: an impact force, which stays
  AffineForm form_;                                 // scratch
  std::vector<std::pair<VarId, double>> terms_;     // scratch: c_k per variable of one equation
  std::vector<std::pair<uint32_t, double>> roots_;  // scratch: a_r per root of one equation
};

/// Scans the equations for aliases until a pass finds none: resolving can turn a longer equation
/// into one (a term whose root became constant drops out), so the scan repeats. Leaves the
/// equations that stay in sys->equations (and `leaves`, when valid, current).
void JoinAliasSets(EquationSystem* sys, AliasJoiner* joiner, EquationLeaves* leaves) {
  const bool have_leaves = leaves != nullptr && leaves->valid();
  std::vector<SystemEquation> pending = std::move(sys->equations), kept;
  // Whether each pending equation may still become an alias: one that is not affine with a few
  // terms, holds a discrete variable or reduced to 0 = d never will (its residual stays as it
  // is during this scan), so later passes skip it instead of decomposing it again.
  std::vector<uint8_t> candidate(pending.size(), 1), kept_candidate;
  // With `leaves`, each pending equation's index in sys->equations as it came (its leaves).
  std::vector<uint32_t> index, kept_index;
  if (have_leaves) {
    index.resize(pending.size());
    for (uint32_t k = 0; k < index.size(); ++k) index[k] = k;
  }
  for (int pass = 0; pass < 10; ++pass) {
    kept.clear();
    kept.reserve(pending.size());
    kept_candidate.clear();
    kept_candidate.reserve(pending.size());
    kept_index.clear();
    size_t joined = 0;
    for (size_t k = 0; k < pending.size(); ++k) {
      ExprId cancelled;
      const AliasOutcome outcome =
          candidate[k] ? joiner->Join(pending[k], &cancelled) : AliasOutcome::kKept;
      if (outcome == AliasOutcome::kJoined) {
        ++joined;
        continue;
      }
      if (have_leaves) kept_index.push_back(index[k]);
      kept.push_back(pending[k]);
      kept_candidate.push_back(outcome == AliasOutcome::kMayAlias ? 1 : 0);
      if (outcome == AliasOutcome::kCancelled) {
        kept.back().residual = cancelled;
        if (have_leaves) leaves->Update(*sys->pool, index[k], cancelled);
      }
    }
    pending.swap(kept);
    candidate.swap(kept_candidate);
    index.swap(kept_index);
    if (joined == 0) break;
  }
  sys->equations = std::move(pending);
  if (have_leaves) leaves->Keep(index);
}

/// Records the forest's eliminations in sys->eliminated (x -> sign*root + offset, or a constant;
/// der(x) and pre(x) with it) and carries start values over to the roots that stay; returns
/// whether any is new.
bool RecordEliminations(AliasForest* forest, EquationSystem* sys, AliasStats* stats) {
  ExprPool& p = *sys->pool;
  const FlatSystem& flat = *sys->flat;
  Substitution& s = *sys->eliminated;
  const size_t eliminated_before = stats->aliases + stats->constants;
  for (uint32_t v = 0; v < flat.variables.size(); ++v) {
    Link l = forest->Find(v);
    if (l.parent == v) continue;
    // der(x) and pre(x) are rewritten only where some equation holds them.
    ExprId der = p.FindLeaf(Op::kDer, v), pre = p.FindLeaf(Op::kPre, v);
    if (l.parent == kConstantRoot) {
      s.Set(p.Var(VarId(v)), l.offset);
      if (der.valid()) s.Set(der, p.Zero());
      if (pre.valid()) s.Set(pre, l.offset);
      sys->role[v] = VarRole::kConstant;
      ++stats->constants;
      continue;
    }
    ExprId root = p.Var(VarId(l.parent));
    ExprId sign = p.Const(l.sign);
    s.Set(p.Var(VarId(v)), p.Add(p.Mul(sign, root), l.offset));
    if (der.valid()) s.Set(der, p.Mul(sign, p.Der(VarId(l.parent))));
    if (pre.valid()) s.Set(pre, p.Add(p.Mul(sign, p.Pre(VarId(l.parent))), l.offset));
    sys->role[v] = VarRole::kAlias;
    ++stats->aliases;
    const FlatVariable& fv = flat.variables[v];
    if (fv.start.valid() && !flat.variables[l.parent].start.valid()) {
      // root = (x - offset)/sign
      sys->guess[l.parent] = p.Mul(sign, p.Sub(fv.start, l.offset));
    }
  }
  return stats->aliases + stats->constants != eliminated_before;
}

/// Applies the eliminations to the system, and makes the deferred equations still in it.
void ApplyToSystem(EquationSystem* sys, bool eliminated_new, const DeferredEquations* deferred,
                   EquationLeaves* leaves) {
  // Every part of the system has had the earlier eliminations applied: with none new (a later
  // round that found nothing), rewriting it would change nothing. Deferred equations are skipped.
  // With `leaves`, the leaves tell which equations hold an eliminated one (collected first, in
  // the build's first round: the walk that collects an equation's leaves replaces the one that
  // looked for eliminated leaves in it).
  if (leaves != nullptr) {
    if (!leaves->valid()) leaves->Collect(*sys);
    if (eliminated_new) ApplyEliminations(sys, leaves);
  } else if (eliminated_new) {
    sys->ApplyEliminations();
  }
  // A deferred equation is consumed or found redundant (0 = c). Should one stay (flattening
  // checks discreteness, the one reason it could), it is made here.
  for (size_t k = 0; k < sys->equations.size(); ++k) {
    SystemEquation& eq = sys->equations[k];
    if (eq.residual.valid()) continue;
    eq.residual = sys->eliminated->Apply(deferred->Make(eq.origin));
    if (leaves != nullptr) leaves->Update(*sys->pool, k, eq.residual);
  }
}

}  // namespace

EquationSystem EliminateAliases(EquationSystem sys, AliasStats* stats, const DeferredEquations* deferred,
                                EquationLeaves* leaves) {
  const bool have_leaves = leaves != nullptr && leaves->valid();
  const std::vector<bool> differentiated =
      have_leaves ? leaves->Differentiated(*sys.pool, sys.role.size())
                  : DifferentiatedVariables(sys);  // deferred ones hold no der()
  AliasJoiner joiner(sys, deferred, differentiated);
  JoinAliasSets(&sys, &joiner, leaves);
  const bool eliminated_new = RecordEliminations(&joiner.forest(), &sys, stats);
  ApplyToSystem(&sys, eliminated_new, deferred, leaves);
  return sys;
}

}  // namespace momenta
