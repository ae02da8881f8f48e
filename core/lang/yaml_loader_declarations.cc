// Reading the declarations of a type or a model (core/lang/yaml_loader_declarations.h).

#include "core/lang/yaml_loader_declarations.h"

#include <map>
#include <utility>

#include "core/lang/parser.h"
#include "core/lang/units.h"

namespace momenta {

ParameterDecl ReadParameter(const ValueReader& reader, const std::string& name, const YamlNode& n,
                            const std::string& owner) {
  ParameterDecl p;
  p.name = name;
  p.loc = reader.Loc(n);
  std::string what = owner + "." + name;
  std::string value_unit;
  if (n.IsMap()) {
    reader.CheckKeys(n, "parameter " + what,
                     {"value", "unit", "doc", "min", "max", "type", "shape", "evaluate"});
    if (!n["value"]) reader.Fail(n, "parameter " + what + " needs a value");
    p.value_text = reader.ValueText(n["value"], "value of " + what);
    p.value = reader.ValueExpression(n["value"], p.value_text, "value of " + what, &value_unit);
    if (n["shape"]) p.shape = reader.ReadShape(n["shape"], what, true);
    p.loc = reader.TextLoc(n["value"]);
    if (n["unit"]) p.unit = reader.UnitString(n["unit"], what);
    if (n["doc"]) p.doc = reader.Scalar(n["doc"], what + ".doc");
    p.min = reader.OptionalNumber(n, "min", what);
    p.max = reader.OptionalNumber(n, "max", what);
    if (n["type"]) p.type = reader.Type(n["type"], what);
    if (n["evaluate"]) p.evaluate = reader.Bool(n["evaluate"], what + ".evaluate");
  } else {
    p.value_text = reader.ValueText(n, "value of " + what);
    p.value = reader.ValueExpression(n, p.value_text, "value of " + what, &value_unit);
    p.loc = reader.TextLoc(n);
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

VariableDecl ReadVariable(const ValueReader& reader, const std::string& name, const YamlNode& n,
                          const std::string& owner) {
  VariableDecl v;
  v.name = name;
  v.loc = reader.Loc(n);
  std::string what = owner + "." + name;
  if (n.IsNull()) return v;
  reader.ExpectMap(n, "variable " + what);
  reader.CheckKeys(
      n, "variable " + what,
      {"unit", "doc", "start", "fixed", "nominal", "min", "max", "stateSelect", "type", "shape"});
  if (n["shape"]) v.shape = reader.ReadShape(n["shape"], what);
  if (n["unit"]) v.unit = reader.UnitString(n["unit"], what);
  if (n["doc"]) v.doc = reader.Scalar(n["doc"], what + ".doc");
  if (n["start"]) v.start = reader.Expression(n["start"], "start of " + what);
  if (n["fixed"]) v.fixed = reader.Bool(n["fixed"], what + ".fixed");
  if (n["nominal"]) {
    v.nominal = reader.Number(n["nominal"], what + ".nominal");
    if (!(v.nominal > 0)) reader.Fail(n["nominal"], what + ".nominal must be positive");
  }
  v.min = reader.OptionalNumber(n, "min", what);
  v.max = reader.OptionalNumber(n, "max", what);
  if (n["type"]) {
    // A record type (docs/FORMAT.md, "Records") is checked by the record expansion, which knows
    // the library's records; Real, Integer and Boolean here.
    const std::string t = reader.Scalar(n["type"], what + ".type");
    if (t == "Real" || t == "Integer" || t == "Boolean") {
      v.type = reader.Type(n["type"], what);
    } else {
      v.record = t;
    }
  }
  if (n["stateSelect"]) v.state_priority = reader.StateSelect(n["stateSelect"], what);
  return v;
}

namespace {

/// The equations of list `n` into `out`, inside the blocks `blocks` under the condition `guard`;
/// a conditional block (`- if: c` with `then:` and `else:` lists) adds its branches, each under
/// its condition, and records where it is written in `block_locs`.
void ReadEquationList(const ValueReader& reader, const YamlNode& n, const std::string& what,
                      const std::vector<BlockBranch>& blocks, const AstPtr& guard,
                      std::vector<SourceLoc>* block_locs, std::vector<EquationDecl>* out) {
  if (n.IsNull()) return;
  if (!n.IsSequence()) reader.Fail(n, what + " must be a list of equations such as '- v = der(s)'");
  for (const auto& e : n) {
    if (e.IsMap()) {
      if (!block_locs) reader.Fail(e, "a conditional block (- if: …) belongs in a component type's equations");
      reader.CheckKeys(e, "a conditional block of " + what, {"if", "then", "else"});
      if (!e["if"] || !e["then"]) reader.Fail(e, "a conditional block of " + what + " needs 'if:' and 'then:'");
      const std::string text = reader.Scalar(e["if"], "the condition of a block of " + what);
      AstPtr condition = ParseExpression(text, reader.TextLoc(e["if"]));
      const uint32_t id = static_cast<uint32_t>(block_locs->size());
      block_locs->push_back(reader.Loc(e));
      for (uint32_t branch = 0; branch < 2; ++branch) {
        const YamlNode list = e[branch == 0 ? "then" : "else"];
        AstPtr c = branch == 0 ? condition : MakeAst(Ast::Kind::kUnary, condition->column, "not", {condition});
        AstPtr g = guard ? MakeAst(Ast::Kind::kBinary, c->column, "and", {guard, c}) : c;
        std::vector<BlockBranch> inner = blocks;
        inner.push_back({id, branch});
        if (list) ReadEquationList(reader, list, what, inner, g, block_locs, out);
      }
      continue;
    }
    EquationDecl d;
    d.text = reader.Scalar(e, "an equation of " + what);
    d.loc = reader.TextLoc(e);
    d.ast = ParseEquation(d.text, d.loc);
    d.guard = guard;
    d.blocks = blocks;
    out->push_back(std::move(d));
  }
}

}  // namespace

std::vector<EquationDecl> ReadEquations(const ValueReader& reader, const YamlNode& n,
                                        const std::string& what, std::vector<SourceLoc>* block_locs) {
  std::vector<EquationDecl> out;
  ReadEquationList(reader, n, what, {}, nullptr, block_locs, &out);
  return out;
}

namespace {

/// A statement of a when-clause: reinit(x, expr) or an assignment `x = expr`.
StatementDecl ReadWhenStatement(const ValueReader& reader, const YamlNode& statement) {
  StatementDecl sd;
  sd.text = reader.Scalar(statement, "a when statement");
  sd.loc = reader.TextLoc(statement);
  if (sd.text.rfind("reinit", 0) == 0) {
    AstPtr call = ParseExpression(sd.text, sd.loc);
    if (call->kind != Ast::Kind::kCall || call->op != "reinit" ||
        call->args[0]->kind != Ast::Kind::kName) {
      reader.Fail(statement, "expected reinit(variable, expression), found '" + sd.text + "'");
    }
    sd.is_reinit = true;
    sd.target = call->args[0]->PathText();
    sd.value = call->args[1];
  } else {
    AstEquation eq = ParseEquation(sd.text, sd.loc);
    if (eq.lhs->kind != Ast::Kind::kName) {
      reader.Fail(statement,
                  "a when statement is reinit(x, expr) or an assignment 'x = expr'; found '" +
                      sd.text + "'");
    }
    sd.target = eq.lhs->PathText();
    sd.value = eq.rhs;
  }
  return sd;
}

}  // namespace

std::vector<WhenDecl> ReadWhens(const ValueReader& reader, const YamlNode& n,
                                const std::string& what) {
  std::vector<WhenDecl> out;
  if (n.IsNull()) return out;
  if (!n.IsSequence())
    reader.Fail(n, what + " must be a list of {when: condition, then: [statements]}");
  for (const auto& w : n) {
    reader.ExpectMap(w, "a when-clause of " + what);
    reader.CheckKeys(w, "a when-clause of " + what, {"when", "then"});
    if (!w["when"] || !w["then"])
      reader.Fail(w, "a when-clause needs 'when: condition' and 'then: [statements]'");
    WhenDecl d;
    d.loc = reader.Loc(w);
    d.text = reader.Scalar(w["when"], "a when condition");
    d.condition = ParseExpression(d.text, reader.TextLoc(w["when"]));
    const YamlNode& body = w["then"];
    if (!body.IsSequence())
      reader.Fail(body,
                  "'then' must be a list such as [\"reinit(v, -e*pre(v))\", \"n = pre(n) + 1\"]");
    for (const auto& statement : body) d.statements.push_back(ReadWhenStatement(reader, statement));
    out.push_back(std::move(d));
  }
  return out;
}

ImpactDecl ReadImpact(const ValueReader& reader, const YamlNode& n, const std::string& what) {
  ImpactDecl d;
  d.loc = reader.Loc(n);
  reader.ExpectMap(n, "impact of " + what);
  reader.CheckKeys(n, "impact of " + what,
                   {"gap", "velocity", "force", "restitution", "contact", "release", "v_small"});
  for (const char* key :
       {"gap", "velocity", "force", "restitution", "contact", "release", "v_small"}) {
    if (!n[key]) reader.Fail(n, "impact of " + what + " needs '" + key + "'");
  }
  auto expr = [&](const char* key, AstPtr* ast, std::string* text) {
    *text = reader.Scalar(n[key], std::string("impact ") + key);
    *ast = ParseExpression(*text, reader.TextLoc(n[key]));
  };
  expr("gap", &d.gap, &d.gap_text);
  expr("velocity", &d.velocity, &d.velocity_text);
  expr("restitution", &d.restitution, &d.restitution_text);
  expr("v_small", &d.v_small, &d.v_small_text);
  expr("release", &d.release, &d.release_text);
  d.force = reader.Scalar(n["force"], "impact force");
  d.contact = reader.Scalar(n["contact"], "impact contact");
  return d;
}

namespace {

/// A kind of shape: its fields, each with the shape of its value; the required ones first.
struct ShapeKind {
  bool space;
  std::vector<std::pair<std::string, Shape>> required, optional;
};

const ShapeKind* FindShapeKind(const std::string& kind, bool space) {
  static const Shape kScalar, kPoint = {2}, kVector = {3}, kMatrix = {3, 3};
  // The MSL's Shape (Visualizers.Advanced.Shape): a frame (r, T) and the shape in it.
  static const ShapeKind kSolid = {true,
                                   {{"r", kVector}, {"length", kScalar}},
                                   {{"T", kMatrix},
                                    {"r_shape", kVector},
                                    {"length_direction", kVector},
                                    {"width_direction", kVector},
                                    {"width", kScalar},
                                    {"height", kScalar},
                                    {"color", kVector},
                                    {"extra", kScalar}}};
  static const std::map<std::string, ShapeKind> kPlanar = {
      {"circle", {false, {{"at", kPoint}, {"radius", kScalar}}, {{"angle", kScalar}}}},
      {"line", {false, {{"from", kPoint}, {"to", kPoint}}, {}}},
      {"spring", {false, {{"from", kPoint}, {"to", kPoint}}, {}}},
      {"pin", {false, {{"at", kPoint}}, {}}},
      {"ground", {false, {{"at", kPoint}}, {}}},
      {"wall", {false, {{"at", kPoint}, {"normal", kPoint}}, {{"start", kScalar}, {"end", kScalar}}}},
  };
  static const std::map<std::string, ShapeKind> kSpace = {
      {"sphere", kSolid},
      {"box", kSolid},
      {"cylinder", kSolid},
      {"cone", kSolid},
      {"pipe", kSolid},
      {"beam", kSolid},
      {"gearwheel", kSolid},
      {"spring", kSolid},
      {"frame", {true, {{"r", kVector}, {"length", kScalar}}, {{"T", kMatrix}, {"color", kVector}}}},
      {"line3d", {true, {{"from", kVector}, {"to", kVector}}, {{"color", kVector}}}},
  };
  const auto& kinds = space ? kSpace : kPlanar;
  auto it = kinds.find(kind);
  return it == kinds.end() ? nullptr : &it->second;
}

}  // namespace

std::vector<ShapeDecl> ReadAnimation(const ValueReader& reader, const YamlNode& n,
                                     const std::string& what) {
  static const char* kValid =
      "box, beam, circle, cone, cylinder, frame, gearwheel, ground, line, line3d, pin, pipe, "
      "sphere, spring, wall";
  if (!n.IsSequence())
    reader.Fail(n, "animation of " + what +
                       " must be a list of shapes such as {shape: circle, at: [frame_a.x, "
                       "frame_a.y], radius: r}");
  std::vector<ShapeDecl> out;
  for (const auto& item : n) {
    reader.ExpectMap(item, "a shape in the animation of " + what);
    if (!item["shape"])
      reader.Fail(item, "a shape in the animation of " + what + " needs 'shape' (" + kValid + ")");
    ShapeDecl d;
    d.loc = reader.Loc(item);
    d.kind = reader.Scalar(item["shape"], "shape");
    // A planar kind, or a 3-D one (spring is either: with `r` it is the MSL's coil).
    const ShapeKind* kind = FindShapeKind(d.kind, false);
    if (!kind || (d.kind == "spring" && item["r"])) kind = FindShapeKind(d.kind, true);
    if (!kind) {
      reader.Fail(item["shape"], "unknown shape '" + d.kind + "' in the animation of " + what +
                                     " (valid shapes: " + kValid + ")");
    }
    d.space = kind->space;
    std::vector<std::string> keys = {"shape", "if"};
    for (const auto* list : {&kind->required, &kind->optional}) {
      for (const auto& field : *list) keys.push_back(field.first);
    }
    reader.CheckKeys(item, d.kind + " in the animation of " + what, keys);
    for (const auto& [key, shape] : kind->required) {
      if (!item[key])
        reader.Fail(item, d.kind + " in the animation of " + what + " needs '" + key + "'");
    }
    auto read_field = [&](const std::string& key, const Shape& shape) {
      ShapeField f;
      f.key = key;
      f.shape = shape;
      f.text = reader.ValueText(item[key], d.kind + " " + f.key);
      f.loc = reader.TextLoc(item[key]);
      f.expr = ParseExpression(f.text, f.loc);
      d.fields.push_back(std::move(f));
    };
    for (const auto* list : {&kind->required, &kind->optional}) {
      for (const auto& [key, shape] : *list) {
        if (item[key]) read_field(key, shape);
      }
    }
    // `if:` (any kind): a Boolean expression; the report draws the shape only where it holds at
    // the start (app/report.cc).
    if (item["if"]) read_field("if", Shape{});
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace momenta
