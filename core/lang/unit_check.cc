// The dimension check: a bottom-up walk of each expression tree giving every node a dimension that
// is known, unknown (a name without a unit: it matches anything), or flexible (a number: 1 in a
// product, anything in a sum or a relation). Terms that must agree are unified; the first pair of
// known, different dimensions is the error.

#include "core/lang/unit_check.h"

#include <cmath>
#include <set>
#include <utility>

namespace momenta {

struct UnitChecker::Term {
  enum Kind { kUnknown, kFlexible, kKnown };
  Kind kind = kUnknown;
  Dimension dim;
  std::string text;  ///< the unit as the user wrote it (a name's unit:) or DimensionText(dim)

  static Term Known(const Dimension& d, std::string t = "") {
    Term x;
    x.kind = kKnown;
    x.dim = d;
    x.text = t.empty() ? DimensionText(d) : std::move(t);
    return x;
  }
  static Term Flexible() {
    Term x;
    x.kind = kFlexible;
    return x;
  }
  static Term Unknown() { return Term(); }
};

namespace {

/// Functions whose argument is a pure number and whose value is dimensionless.
const std::set<std::string> kTranscendental = {"sin",  "cos",  "tan",  "asin", "acos", "atan",
                                               "sinh", "cosh", "tanh", "exp",  "log",  "log10"};

/// The number an exponent is, when it is a literal (`2`, `-1`, `0.5`).
std::optional<double> LiteralNumber(const Ast& a) {
  if (a.kind == Ast::Kind::kNumber) return a.number;
  if (a.kind == Ast::Kind::kUnary && a.op == "-" && a.args[0]->kind == Ast::Kind::kNumber) {
    return -a.args[0]->number;
  }
  return std::nullopt;
}

}  // namespace

UnitChecker::UnitChecker(std::string owner, UnitOfName unit_of)
    : owner_(std::move(owner)), unit_of_(std::move(unit_of)) {}

std::optional<Dimension> UnitChecker::DimensionOf(const std::string& unit) {
  if (unit.empty()) return std::nullopt;
  auto it = cache_.find(unit);
  if (it != cache_.end()) return it->second;
  std::optional<Dimension> d;
  try {
    d = ParseUnit(unit).dimension;
  } catch (const UnitError&) {
    // The loader reports unparsable units at their place; here they are unknown.
  }
  cache_[unit] = d;
  return d;
}

void UnitChecker::Fail(const Ast& at, const std::string& why) const {
  throw ModelError(loc_.Shifted(at.column),
                   "dimension mismatch in '" + *text_ + "' of " + owner_ + ": " + why);
}

UnitChecker::Term UnitChecker::NameTerm(const Ast& a) {
  std::string path = a.PathText();
  std::string unit = unit_of_(path);
  if (!unit.empty()) {
    if (auto d = DimensionOf(unit)) return Term::Known(*d, unit);
    return Term::Unknown();
  }
  auto inf = inferred_.find(path);
  if (inf != inferred_.end()) return Term::Known(inf->second);
  if (path == "pi") return Term::Flexible();
  return Term::Unknown();
}

UnitChecker::Term UnitChecker::Unify(const Term& x, const Term& y, const Ast& at,
                                     const std::function<std::string()>& what) {
  // Unknown matches anything; a number takes the other's dimension.
  if (x.kind == Term::kKnown && y.kind == Term::kKnown) {
    if (x.dim != y.dim)
      Fail(at, what() + " have different dimensions: " + x.text + " against " + y.text);
    return x;
  }
  if (x.kind == Term::kKnown) return x;
  if (y.kind == Term::kKnown) return y;
  return x.kind == Term::kUnknown ? x : y;
}

UnitChecker::Term UnitChecker::Eval(const Ast& a) {
  using K = Ast::Kind;
  switch (a.kind) {
    case K::kNumber:
    case K::kBool:
      return Term::Flexible();
    case K::kName:
      return NameTerm(a);
    case K::kUnary: {
      Term t = Eval(*a.args[0]);
      return a.op == "not" ? Term::Flexible() : t;
    }
    case K::kSum:
      return SumTerm(a);
    case K::kProduct:
      return ProductTerm(a);
    case K::kBinary:
      return BinaryTerm(a);
    case K::kIf:
      return IfTerm(a);
    case K::kArray: {
      Term t = Term::Flexible();
      for (const auto& x : a.args)
        t = Unify(t, Eval(*x), *x, [] { return std::string("the elements of the array"); });
      return t;
    }
    case K::kCall:
      break;
  }
  return CallTerm(a);
}

UnitChecker::Term UnitChecker::SumTerm(const Ast& a) {
  Term t = Eval(*a.args[0]);
  for (size_t k = 1; k < a.args.size(); ++k) {
    t = Unify(t, Eval(*a.args[k]), *a.args[k], [&] {
      return "the terms '" + AstToString(*a.args[k - 1]) + "' and '" + AstToString(*a.args[k]) +
             "'";
    });
  }
  return t;
}

UnitChecker::Term UnitChecker::ProductTerm(const Ast& a) {
  Term t = Term::Flexible();
  bool unknown = false;
  for (size_t k = 0; k < a.args.size(); ++k) {
    Term f = Eval(*a.args[k]);
    if (f.kind == Term::kUnknown) unknown = true;
    if (f.kind != Term::kKnown) continue;
    Dimension d = a.op[k] == '/' ? Dimension() / f.dim : f.dim;
    t = Term::Known(t.kind == Term::kKnown ? t.dim * d : d);
  }
  return unknown ? Term::Unknown() : t;
}

UnitChecker::Term UnitChecker::BinaryTerm(const Ast& a) {
  if (a.op == "and" || a.op == "or") {
    for (const auto& x : a.args) Eval(*x);
    return Term::Flexible();
  }
  if (a.op == "^") {
    Term base = Eval(*a.args[0]);
    Term exponent = Eval(*a.args[1]);
    if (exponent.kind == Term::kKnown && !exponent.dim.dimensionless()) {
      Fail(*a.args[1], "the exponent '" + AstToString(*a.args[1]) +
                           "' must be dimensionless, found " + exponent.text);
    }
    if (base.kind != Term::kKnown || base.dim.dimensionless()) return base;
    std::optional<double> p = LiteralNumber(*a.args[1]);
    return p ? Term::Known(base.dim.Power(*p)) : Term::Unknown();
  }
  // A relation: both sides agree; the value is a Boolean.
  Unify(Eval(*a.args[0]), Eval(*a.args[1]), a,
        [&] { return "the two sides of '" + AstToString(a) + "'"; });
  return Term::Flexible();
}

UnitChecker::Term UnitChecker::IfTerm(const Ast& a) {
  Term t = Term::Flexible();
  bool first = true;
  for (size_t k = 0; k < a.args.size(); ++k) {
    bool is_value = k % 2 == 1 || k + 1 == a.args.size();
    Term x = Eval(*a.args[k]);
    if (!is_value) continue;
    t = first ? x : Unify(t, x, *a.args[k], [] {
      return std::string("the branches of the if-expression");
    });
    first = false;
  }
  return t;
}

UnitChecker::Term UnitChecker::CallTerm(const Ast& a) {
  const std::string& f = a.op;
  std::vector<Term> args;
  for (const auto& x : a.args) args.push_back(Eval(*x));
  if (f == "der") {
    if (args.size() != 1 || args[0].kind != Term::kKnown)
      return args.empty() ? Term::Unknown() : args[0];
    return Term::Known(args[0].dim / ParseUnit("s").dimension);
  }
  if (f == "pre" || f == "noEvent" || f == "abs" || f == "floor" || f == "smooth")
    return args.empty() ? Term::Unknown() : args.back();
  if (f == "edge" || f == "change" || f == "initial" || f == "sign") return Term::Flexible();
  if (kTranscendental.count(f) && args.size() == 1) {
    if (args[0].kind == Term::kKnown && !args[0].dim.dimensionless()) {
      Fail(*a.args[0], "the argument of " + f + "() must be dimensionless, found " + args[0].text);
    }
    return Term::Flexible();
  }
  if (f == "sqrt" && args.size() == 1) {
    return args[0].kind == Term::kKnown ? Term::Known(args[0].dim.Power(0.5)) : args[0];
  }
  if ((f == "min" || f == "max" || f == "atan2") && args.size() == 2) {
    Term t = Unify(args[0], args[1], a, [&] { return "the arguments of " + f + "()"; });
    return f == "atan2" ? Term::Flexible() : t;
  }
  // Anything else (array functions, table look-ups): not known here.
  return Term::Unknown();
}

void UnitChecker::CheckEquation(const Ast& lhs, const Ast& rhs, const std::string& text,
                                const SourceLoc& loc) {
  text_ = &text;
  loc_ = loc;
  // `0 = if c then r1 else r2` is the residual form of alternative equations (a structural if,
  // docs/FORMAT.md): each branch is an equation of its own, checked on its own.
  for (auto [zero, alt] : {std::pair{&lhs, &rhs}, std::pair{&rhs, &lhs}}) {
    if (zero->kind == Ast::Kind::kNumber && alt->kind == Ast::Kind::kIf) {
      for (const auto& branch : alt->args) Eval(*branch);
      return;
    }
  }
  static const Ast kStart;  // column 0: the message points at the equation
  Unify(Eval(lhs), Eval(rhs), kStart, [] { return std::string("the two sides"); });
}

void UnitChecker::CheckExpression(const Ast& e, const std::string& text, const SourceLoc& loc) {
  text_ = &text;
  loc_ = loc;
  Eval(e);
}

std::string UnitChecker::UnitText(const Ast& e, const std::string& text, const SourceLoc& loc) {
  text_ = &text;
  loc_ = loc;
  Term t = Eval(e);
  return t.kind == Term::kKnown ? t.text : std::string();
}

void UnitChecker::CheckAssignment(const std::string& target, const std::string& target_unit,
                                  const Ast& value, const std::string& text, const SourceLoc& loc) {
  text_ = &text;
  loc_ = loc;
  Term t = Term::Unknown();
  if (auto d = DimensionOf(target_unit)) t = Term::Known(*d, target_unit);
  Unify(t, Eval(value), value, [&] { return "the value and " + target; });
}

void UnitChecker::Infer(const std::vector<std::pair<const Ast*, const Ast*>>& equations) {
  static const std::string kNoText;
  text_ = &kNoText;
  // A bare name (or der of one) of unknown dimension on one side takes the other side's.
  auto bare = [](const Ast& a, bool* is_der) -> const Ast* {
    *is_der = a.kind == Ast::Kind::kCall && a.op == "der" && a.args.size() == 1;
    const Ast& n = *is_der ? *a.args[0] : a;
    return n.kind == Ast::Kind::kName ? &n : nullptr;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (auto [lhs, rhs] : equations) {
      for (auto [side, other] : {std::pair{lhs, rhs}, std::pair{rhs, lhs}}) {
        bool is_der = false;
        const Ast* name = bare(*side, &is_der);
        if (!name || NameTerm(*name).kind != Term::kUnknown || !unit_of_(name->PathText()).empty())
          continue;
        Term t;
        try {
          t = Eval(*other);
        } catch (const ModelError&) {
          continue;  // reported by the check proper
        }
        if (t.kind != Term::kKnown) continue;
        inferred_[name->PathText()] = is_der ? t.dim * ParseUnit("s").dimension : t.dim;
        changed = true;
      }
    }
  }
}

void CheckComponentUnits(const ComponentType& type, const UnitOfName& unit_of) {
  UnitChecker check(type.name, unit_of);
  // Names without a unit learn one from the equations that define them.
  std::vector<std::pair<const Ast*, const Ast*>> pairs;
  for (const auto& e : type.equations) pairs.emplace_back(e.ast.lhs.get(), e.ast.rhs.get());
  check.Infer(pairs);
  for (const auto* list : {&type.equations, &type.initial_equations}) {
    for (const auto& e : *list) check.CheckEquation(*e.ast.lhs, *e.ast.rhs, e.text, e.loc);
  }
  for (const auto& p : type.parameters) {
    if (p.value) check.CheckAssignment(p.name, p.unit, *p.value, p.value_text, p.loc);
  }
  for (const auto& v : type.variables) {
    if (v.start)
      check.CheckAssignment(v.name, unit_of(v.name), *v.start, AstToString(*v.start), v.loc);
  }
  for (const auto& w : type.whens) {
    check.CheckExpression(*w.condition, w.text, w.loc);
    for (const auto& st : w.statements) {
      check.CheckAssignment(st.target, unit_of(st.target), *st.value, st.text, st.loc);
    }
  }
  for (const auto& im : type.impacts) {
    check.CheckExpression(*im.gap, im.gap_text, im.loc);
    check.CheckExpression(*im.velocity, im.velocity_text, im.loc);
    check.CheckExpression(*im.release, im.release_text, im.loc);
  }
}

}  // namespace momenta
