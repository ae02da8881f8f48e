// Alias elimination by union-find with signs and offsets: every variable x points to a root r
// with x = sign*r + offset (sign = ±1, offset a parameter expression), or to "constant" with
// x = offset. An alias equation c1*x + c2*y + d = 0 (|c1| = |c2|) joins the roots of x and y.

#include "core/alias_elimination.h"

#include <cmath>

namespace momenta {

namespace {

constexpr uint32_t kConstantRoot = 0xfffffffeu;

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
    std::vector<uint32_t> path;
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
};

}  // namespace

EquationSystem EliminateAliases(EquationSystem sys, AliasStats* stats) {
  ExprPool& p = *sys.pool;
  const FlatSystem& flat = *sys.flat;
  const size_t n = flat.variables.size();
  std::vector<bool> diff = DifferentiatedVariables(sys);
  AliasForest forest(&p, n);

  // Which root survives: impact forces, states, `state: prefer`, a fixed start, then order.
  // Impact forces stay (their equation gives way to Newton's law at an impact).
  std::vector<bool> keep(n, false);
  for (const auto& im : sys.impacts) keep[im.force.value()] = true;
  auto rank = [&](uint32_t v) {
    const FlatVariable& fv = flat.variables[v];
    return std::make_tuple(keep[v] ? 1 : 0, diff[v] ? 1 : 0, fv.state_priority, fv.fixed ? 1 : 0,
                           fv.is_flow ? 0 : 1);
  };

  std::vector<SystemEquation> kept;
  kept.reserve(sys.equations.size());
  AffineForm form;
  for (const SystemEquation& eq : sys.equations) {
    const uint8_t m = p.mask(eq.residual);
    bool consumed = false;
    if (!(m & (kHasDer | kHasPre | kHasTime | kHasInitial)) &&
        DecomposeAffine(&p, eq.residual, 2, &form) && !form.terms.empty()) {
      // Discrete variables are never aliased: their equations are evaluated at events.
      bool discrete = false;
      for (const auto& t : form.terms) discrete = discrete || flat.variables[p.node(t.first).a].discrete;
      if (discrete) {
        kept.push_back(eq);
        continue;
      }
      // Resolve each term through the forest: c*x = c*(s*r + o).
      double c1 = form.terms[0].second;
      Link l1 = forest.Find(p.node(form.terms[0].first).a);
      double c2 = form.terms.size() == 2 ? form.terms[1].second : 0.0;
      Link l2 = form.terms.size() == 2 ? forest.Find(p.node(form.terms[1].first).a)
                                       : Link{kConstantRoot, 1.0, p.Zero()};
      // With x_k = s_k*r_k + o_k: a1*r1 + a2*r2 + d = 0, where a constant root contributes
      // only its offset (its a_k is zero).
      double a1 = l1.parent == kConstantRoot ? 0.0 : c1 * l1.sign;
      double a2 = l2.parent == kConstantRoot ? 0.0 : c2 * l2.sign;
      ExprId d = p.Add(form.offset, p.Add(p.Mul(p.Const(c1), l1.offset), p.Mul(p.Const(c2), l2.offset)));
      if (l1.parent == kConstantRoot) {
        std::swap(l1, l2);
        std::swap(a1, a2);
      }
      if (l1.parent == kConstantRoot) {
        // Both sides already constant: the equation is redundant or contradictory; keep it so
        // the structural check reports it.
      } else if (l2.parent == kConstantRoot || l1.parent == l2.parent) {
        // a*r1 + d = 0: r1 is constant.
        double a = (l1.parent == l2.parent) ? a1 + a2 : a1;
        if (a != 0.0) {
          forest.Attach(l1.parent, kConstantRoot, 1.0, p.Neg(p.Div(d, p.Const(a))));
          consumed = true;
        }
      } else if (std::fabs(std::fabs(a1) - std::fabs(a2)) == 0.0) {
        // r1 = -(a2/a1) r2 - d/a1 or the other way round.
        uint32_t r1 = l1.parent, r2 = l2.parent;
        if (rank(r1) > rank(r2) || (rank(r1) == rank(r2) && r1 < r2)) {
          std::swap(r1, r2);
          std::swap(a1, a2);
        }
        forest.Attach(r1, r2, -a2 / a1, p.Neg(p.Div(d, p.Const(a1))));
        consumed = true;
      }
    }
    if (!consumed) kept.push_back(eq);
  }
  sys.equations.swap(kept);

  // Record the eliminations and carry start values over to the roots that stay.
  Substitution& s = *sys.eliminated;
  for (uint32_t v = 0; v < n; ++v) {
    Link l = forest.Find(v);
    if (l.parent == v) continue;
    // der(x) and pre(x) are rewritten only where some equation holds them.
    ExprId der = p.FindLeaf(Op::kDer, v), pre = p.FindLeaf(Op::kPre, v);
    if (l.parent == kConstantRoot) {
      s.Set(p.Var(VarId(v)), l.offset);
      if (der.valid()) s.Set(der, p.Zero());
      if (pre.valid()) s.Set(pre, l.offset);
      sys.role[v] = VarRole::kConstant;
      ++stats->constants;
      continue;
    }
    ExprId root = p.Var(VarId(l.parent));
    ExprId sign = p.Const(l.sign);
    s.Set(p.Var(VarId(v)), p.Add(p.Mul(sign, root), l.offset));
    if (der.valid()) s.Set(der, p.Mul(sign, p.Der(VarId(l.parent))));
    if (pre.valid()) s.Set(pre, p.Add(p.Mul(sign, p.Pre(VarId(l.parent))), l.offset));
    sys.role[v] = VarRole::kAlias;
    ++stats->aliases;
    const FlatVariable& fv = flat.variables[v];
    if (fv.start.valid() && !flat.variables[l.parent].start.valid()) {
      // root = (x - offset)/sign
      sys.guess[l.parent] = p.Mul(sign, p.Sub(fv.start, l.offset));
    }
  }
  sys.ApplyEliminations();
  return sys;
}

}  // namespace momenta
