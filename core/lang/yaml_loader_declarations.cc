// Reading the declarations of a type or a model (core/lang/yaml_loader_declarations.h).

#include "core/lang/yaml_loader_declarations.h"

#include <map>
#include <utility>

#include "core/lang/parser.h"
#include "core/lang/units.h"

namespace momenta {

ParameterDecl ReadParameter(const ValueReader& in, const std::string& name, const YamlNode& n,
                            const std::string& owner) {
  ParameterDecl p;
  p.name = name;
  p.loc = in.Loc(n);
  std::string what = owner + "." + name;
  std::string value_unit;
  if (n.IsMap()) {
    in.CheckKeys(n, "parameter " + what, {"value", "unit", "doc", "min", "max", "type", "shape"});
    if (!n["value"]) in.Fail(n, "parameter " + what + " needs a value");
    p.value_text = in.ValueText(n["value"], "value of " + what);
    p.value = in.ValueExpression(n["value"], p.value_text, "value of " + what, &value_unit);
    if (n["shape"]) p.shape = in.ReadShape(n["shape"], what, true);
    p.loc = in.TextLoc(n["value"]);
    if (n["unit"]) p.unit = in.UnitString(n["unit"], what);
    if (n["doc"]) p.doc = in.Scalar(n["doc"], what + ".doc");
    p.min = in.OptionalNumber(n, "min", what);
    p.max = in.OptionalNumber(n, "max", what);
    if (n["type"]) p.type = in.Type(n["type"], what);
  } else {
    p.value_text = in.ValueText(n, "value of " + what);
    p.value = in.ValueExpression(n, p.value_text, "value of " + what, &value_unit);
    p.loc = in.TextLoc(n);
  }
  // `m: 40 kg`: a parameter without a declared unit takes the value's; one with a unit gets the
  // value converted to it.
  if (!value_unit.empty() && p.unit.empty()) p.unit = value_unit;
  if (!value_unit.empty()) p.value = ValueInUnit(p.value->number, value_unit, p.unit, what, p.loc);
  if (p.value->kind == Ast::Kind::kBool && !(n.IsMap() && n["type"])) {
    p.type = ValueType::kBoolean;
  }
  return p;
}

VariableDecl ReadVariable(const ValueReader& in, const std::string& name, const YamlNode& n,
                          const std::string& owner) {
  VariableDecl v;
  v.name = name;
  v.loc = in.Loc(n);
  std::string what = owner + "." + name;
  if (n.IsNull()) return v;
  in.ExpectMap(n, "variable " + what);
  in.CheckKeys(n, "variable " + what,
               {"unit", "doc", "start", "fixed", "nominal", "min", "max", "stateSelect", "type", "shape"});
  if (n["shape"]) v.shape = in.ReadShape(n["shape"], what);
  if (n["unit"]) v.unit = in.UnitString(n["unit"], what);
  if (n["doc"]) v.doc = in.Scalar(n["doc"], what + ".doc");
  if (n["start"]) v.start = in.Expression(n["start"], "start of " + what);
  if (n["fixed"]) v.fixed = in.Bool(n["fixed"], what + ".fixed");
  if (n["nominal"]) {
    v.nominal = in.Number(n["nominal"], what + ".nominal");
    if (!(v.nominal > 0)) in.Fail(n["nominal"], what + ".nominal must be positive");
  }
  v.min = in.OptionalNumber(n, "min", what);
  v.max = in.OptionalNumber(n, "max", what);
  if (n["type"]) v.type = in.Type(n["type"], what);
  if (n["stateSelect"]) v.state_priority = in.StateSelect(n["stateSelect"], what);
  return v;
}

std::vector<EquationDecl> ReadEquations(const ValueReader& in, const YamlNode& n,
                                        const std::string& what) {
  std::vector<EquationDecl> out;
  if (n.IsNull()) return out;
  if (!n.IsSequence()) in.Fail(n, what + " must be a list of equations such as '- v = der(s)'");
  for (const auto& e : n) {
    EquationDecl d;
    d.text = in.Scalar(e, "an equation of " + what);
    d.loc = in.TextLoc(e);
    d.ast = ParseEquation(d.text, d.loc);
    out.push_back(std::move(d));
  }
  return out;
}

namespace {

/// A statement of a when-clause: reinit(x, expr) or an assignment `x = expr`.
StatementDecl ReadWhenStatement(const ValueReader& in, const YamlNode& statement) {
  StatementDecl sd;
  sd.text = in.Scalar(statement, "a when statement");
  sd.loc = in.TextLoc(statement);
  if (sd.text.rfind("reinit", 0) == 0) {
    AstPtr call = ParseExpression(sd.text, sd.loc);
    if (call->kind != Ast::Kind::kCall || call->op != "reinit" || call->args[0]->kind != Ast::Kind::kName) {
      in.Fail(statement, "expected reinit(variable, expression), found '" + sd.text + "'");
    }
    sd.is_reinit = true;
    sd.target = call->args[0]->PathText();
    sd.value = call->args[1];
  } else {
    AstEquation eq = ParseEquation(sd.text, sd.loc);
    if (eq.lhs->kind != Ast::Kind::kName) {
      in.Fail(statement, "a when statement is reinit(x, expr) or an assignment 'x = expr'; found '" + sd.text + "'");
    }
    sd.target = eq.lhs->PathText();
    sd.value = eq.rhs;
  }
  return sd;
}

}  // namespace

std::vector<WhenDecl> ReadWhens(const ValueReader& in, const YamlNode& n, const std::string& what) {
  std::vector<WhenDecl> out;
  if (n.IsNull()) return out;
  if (!n.IsSequence()) in.Fail(n, what + " must be a list of {when: condition, then: [statements]}");
  for (const auto& w : n) {
    in.ExpectMap(w, "a when-clause of " + what);
    in.CheckKeys(w, "a when-clause of " + what, {"when", "then"});
    if (!w["when"] || !w["then"]) in.Fail(w, "a when-clause needs 'when: condition' and 'then: [statements]'");
    WhenDecl d;
    d.loc = in.Loc(w);
    d.text = in.Scalar(w["when"], "a when condition");
    d.condition = ParseExpression(d.text, in.TextLoc(w["when"]));
    const YamlNode& body = w["then"];
    if (!body.IsSequence()) in.Fail(body, "'then' must be a list such as [\"reinit(v, -e*pre(v))\", \"n = pre(n) + 1\"]");
    for (const auto& statement : body) d.statements.push_back(ReadWhenStatement(in, statement));
    out.push_back(std::move(d));
  }
  return out;
}

ImpactDecl ReadImpact(const ValueReader& in, const YamlNode& n, const std::string& what) {
  ImpactDecl d;
  d.loc = in.Loc(n);
  in.ExpectMap(n, "impact of " + what);
  in.CheckKeys(n, "impact of " + what,
               {"gap", "velocity", "force", "restitution", "contact", "release", "v_small"});
  for (const char* key : {"gap", "velocity", "force", "restitution", "contact", "release", "v_small"}) {
    if (!n[key]) in.Fail(n, "impact of " + what + " needs '" + key + "'");
  }
  auto expr = [&](const char* key, AstPtr* ast, std::string* text) {
    *text = in.Scalar(n[key], std::string("impact ") + key);
    *ast = ParseExpression(*text, in.TextLoc(n[key]));
  };
  expr("gap", &d.gap, &d.gap_text);
  expr("velocity", &d.velocity, &d.velocity_text);
  expr("restitution", &d.restitution, &d.restitution_text);
  expr("v_small", &d.v_small, &d.v_small_text);
  expr("release", &d.release, &d.release_text);
  d.force = in.Scalar(n["force"], "impact force");
  d.contact = in.Scalar(n["contact"], "impact contact");
  return d;
}

std::vector<ShapeDecl> ReadAnimation(const ValueReader& in, const YamlNode& n,
                                     const std::string& what) {
  static const std::map<std::string, std::pair<std::vector<std::string>, std::vector<std::string>>> kKinds = {
      // kind -> (required fields, optional fields)
      {"circle", {{"at", "radius"}, {"angle"}}},
      {"line", {{"from", "to"}, {}}},
      {"spring", {{"from", "to"}, {}}},
      {"pin", {{"at"}, {}}},
      {"ground", {{"at"}, {}}},
      {"wall", {{"at", "normal"}, {"start", "end"}}},
  };
  if (!n.IsSequence()) in.Fail(n, "animation of " + what + " must be a list of shapes such as {shape: circle, at: [frame_a.x, frame_a.y], radius: r}");
  std::vector<ShapeDecl> out;
  for (const auto& item : n) {
    in.ExpectMap(item, "a shape in the animation of " + what);
    if (!item["shape"]) in.Fail(item, "a shape in the animation of " + what + " needs 'shape' (circle, ground, line, pin, spring or wall)");
    ShapeDecl d;
    d.loc = in.Loc(item);
    d.kind = in.Scalar(item["shape"], "shape");
    auto kind = kKinds.find(d.kind);
    if (kind == kKinds.end()) {
      in.Fail(item["shape"], "unknown shape '" + d.kind + "' in the animation of " + what + " (valid shapes: circle, ground, line, pin, spring, wall)");
    }
    std::vector<std::string> keys = {"shape"};
    keys.insert(keys.end(), kind->second.first.begin(), kind->second.first.end());
    keys.insert(keys.end(), kind->second.second.begin(), kind->second.second.end());
    in.CheckKeys(item, d.kind + " in the animation of " + what, keys);
    for (const auto& key : kind->second.first) {
      if (!item[key]) in.Fail(item, d.kind + " in the animation of " + what + " needs '" + key + "'");
    }
    for (size_t k = 1; k < keys.size(); ++k) {
      if (!item[keys[k]]) continue;
      ShapeField f;
      f.key = keys[k];
      f.text = in.ValueText(item[keys[k]], d.kind + " " + f.key);
      f.loc = in.TextLoc(item[keys[k]]);
      f.expr = ParseExpression(f.text, f.loc);
      d.fields.push_back(std::move(f));
    }
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace momenta
