// Reading model and library files with yaml-cpp. Every error names the file, line and column
// (yaml-cpp marks are 0-based; we add 1), the user's path, what was expected, and the valid keys.

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "core/lang/arrays.h"
#include "core/lang/model_spec.h"
#include "core/lang/parser.h"
#include "core/lang/unit_check.h"
#include "core/lang/yaml_document.h"
#include "core/lang/yaml_loader.h"

namespace momenta {

namespace {

/// Larger model files are refused before they are read whole (a model is a few kilobytes; the
/// largest benchmark model is under 2 KiB).
constexpr size_t kMaxModelFileBytes = size_t{256} << 20;

/// Whose value a message is about ("start of mass1.s"): its pieces, put together only when a
/// message is made. A file of 100 000 components has a few such descriptions per component and,
/// usually, no error. The pieces are views: a What lives no longer than the call it is passed to.
class What {
 public:
  What(const char* text) : parts_{text}, size_(1) {}         // NOLINT: as a string
  What(const std::string& text) : parts_{text}, size_(1) {}  // NOLINT: as a string
  What(std::initializer_list<std::string_view> parts) : size_(0) {
    for (std::string_view p : parts) Add(p);
  }
  /// This description with `more` appended ("mass1.s" + ".fixed").
  What Plus(std::string_view a, std::string_view b = {}) const {
    What w = *this;
    w.Add(a);
    w.Add(b);
    return w;
  }
  std::string str() const {
    std::string s;
    for (size_t k = 0; k < size_; ++k) s += parts_[k];
    return s;
  }

 private:
  void Add(std::string_view p) {
    if (p.empty()) return;
    MOMENTA_CHECK(size_ < parts_.size());
    parts_[size_++] = p;
  }
  std::array<std::string_view, 6> parts_;
  size_t size_;
};

std::string operator+(const What& a, const char* b) { return a.str() + b; }
std::string operator+(const std::string& a, const What& b) { return a + b.str(); }
std::string operator+(const char* a, const What& b) { return a + b.str(); }

/// The text of a mapping's key as yaml-cpp's as<std::string>() gives it ("null" for a null key;
/// YAML::TypedBadConversion for a list or mapping), without a copy.
std::string_view KeyText(const YamlNode& key) { return key.AsText(); }

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) { file_loc_.set_file(file_); }

  SourceLoc Loc(const YamlNode& n) const {
    SourceLoc l = file_loc_;  // the file name interned once, not at every place
    YamlMark m = n.Mark();
    if (m.line >= 0) {
      l.line = m.line + 1;
      l.column = m.column + 1;
    }
    return l;
  }

  /// Where the text of a scalar starts (after the opening quote of a quoted scalar).
  SourceLoc TextLoc(const YamlNode& n) const {
    SourceLoc l = Loc(n);
    if (n.Tag() == "!") l.column += 1;
    return l;
  }

  [[noreturn]] void Fail(const YamlNode& n, const std::string& msg) const {
    throw ModelError(Loc(n), msg);
  }

  void ExpectMap(const YamlNode& n, const What& what) const {
    if (!n.IsMap()) Fail(n, what + " must be a mapping of keys to values");
  }

  void CheckKeys(const YamlNode& n, const What& what,
                 std::initializer_list<std::string_view> allowed) const {
    CheckKeys(n, what, allowed.begin(), allowed.end());
  }
  void CheckKeys(const YamlNode& n, const What& what,
                 const std::vector<std::string>& allowed) const {
    CheckKeys(n, what, allowed.begin(), allowed.end());
  }
  template <typename It>
  void CheckKeys(const YamlNode& n, const What& what, It begin, It end) const {
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string_view key = KeyText(it->first);
      bool ok = false;
      for (It a = begin; a != end && !ok; ++a) ok = *a == key;
      if (!ok) {
        Fail(it->first, "unknown key '" + std::string(key) + "' in " + what + " (valid keys: " +
                            JoinNames(std::vector<std::string>(begin, end)) + ")");
      }
    }
  }

  /// The text of a scalar, a view into the document.
  std::string_view ScalarText(const YamlNode& n, const What& what) const {
    if (!n.IsScalar()) Fail(n, what + " must be a single value, not a list or mapping");
    return n.Scalar();
  }
  std::string Scalar(const YamlNode& n, const What& what) const {
    return std::string(ScalarText(n, what));
  }

  double Number(const YamlNode& n, const What& what) const {
    std::string s = Scalar(n, what);
    CheckFinite(n, s, what);
    try {
      size_t used = 0;
      double v = std::stod(s, &used);
      if (used != s.size()) throw std::invalid_argument(s);
      return v;
    } catch (const std::exception&) {
      Fail(n, what + " must be a number, found '" + s + "'");
    }
  }

  void CheckFinite(const YamlNode& n, std::string_view s, const What& what) const {
    static const std::string_view kNonFinite[] = {".nan", ".NaN",  ".NAN", ".inf", "-.inf",
                                                  ".Inf", "-.Inf", "nan",  "NaN",  "inf",
                                                  "-inf", "Inf",   "-Inf"};
    if (s.size() < 3 || s.size() > 5) return;  // none of them: the common case, decided at once
    for (std::string_view x : kNonFinite) {
      if (s == x) Fail(n, what + " must be a finite number, found '" + std::string(s) + "'");
    }
  }

  bool Bool(const YamlNode& n, const What& what) const {
    std::string_view s = ScalarText(n, what);
    if (s == "true") return true;
    if (s == "false") return false;
    Fail(n, what + " must be true or false, found '" + std::string(s) + "'");
  }

  /// The text of a value: a scalar as written, a list (`[0.5, 4]`, a matrix as a list of rows)
  /// as the array literal it stands for.
  std::string ValueText(const YamlNode& n, const What& what) const {
    if (!n.IsSequence()) return Scalar(n, what);
    if (n.size() == 0) Fail(n, what + " is an empty list; an array has at least one element");
    std::string s = "[";
    for (size_t k = 0; k < n.size(); ++k) s += (k ? ", " : "") + ValueText(n[k], what);
    return s + "]";
  }

  /// `shape: [2]` or `shape: [3, 3]`: one or two whole numbers of at least 1. With `open`, a
  /// size may be ":" (kOpenSize): the parameter's value gives it (`shape: [":", 2]`).
  Shape ReadShape(const YamlNode& n, const What& what, bool open = false) const {
    if (!n.IsSequence() || n.size() < 1 || n.size() > 2) {
      Fail(n, "the shape of " + what + " is a list of one or two sizes, e.g. shape: [2] or shape: [3, 3]");
    }
    Shape shape;
    double elements = 1;
    for (const auto& d : n) {
      if (d.IsScalar() && d.Scalar() == ":") {
        if (!open) Fail(d, "the shape of " + what + " has ':', which only a parameter of a component type may have");
        shape.push_back(kOpenSize);
        continue;
      }
      double v = Number(d, "a size in the shape of " + what);
      if (v != std::floor(v) || v < 1) Fail(d, "a size in the shape of " + what + " must be a whole number of at least 1");
      elements *= v;
      if (elements > static_cast<double>(kMaxArrayElements)) {
        Fail(n, "the shape of " + what + " has more than " + std::to_string(kMaxArrayElements) + " elements");
      }
      shape.push_back(static_cast<int>(v));
    }
    return shape;
  }

  AstPtr Expression(const YamlNode& n, const What& what) const {
    return Expression(n, ValueText(n, what), what);
  }

  /// The expression of a value whose text (ValueText) is `s`.
  AstPtr Expression(const YamlNode& n, const std::string& s, const What& what) const {
    CheckFinite(n, s, what);
    if (s.empty()) Fail(n, what + " is empty");
    // (Sharing one tree among the values written the same way, "1e4" in every spring, was
    // tried twice on the written-out chain: first 20-45 MB more peak RSS; then, with the flat
    // records reserved at their size, 26 MB less, but load and flatten took 15-30 % more CPU.)
    try {
      return ParseExpression(s, TextLoc(n));
    } catch (const ModelError& e) {
      // The parser names the place and the text; add whose value it is (spring.c).
      const std::string whose = what.str();
      bool phrase = whose.find(" of ") != std::string::npos;
      throw ModelError(std::string(e.what()) + " (in " + (phrase ? "the " : "") + whose + ")");
    }
  }

  /// A `unit:` string, checked to parse (an error at its place otherwise).
  std::string UnitString(const YamlNode& n, const std::string& what) const {
    std::string unit = Scalar(n, what);
    CheckUnitString(unit, TextLoc(n), "the unit of " + what);
    return unit;
  }

  /// A value as an expression, from its text (ValueText); a number written with a unit ("40 kg",
  /// "10kN/m") is the number, and `*unit` receives the unit for the caller to convert
  /// (core/lang/units.h).
  AstPtr ValueExpression(const YamlNode& n, const std::string& text, const What& what,
                         std::string* unit) const {
    if (n.IsScalar()) {
      std::optional<Quantity> q;
      try {
        q = SplitQuantity(text);
      } catch (const UnitError& e) {
        Fail(n, std::string(e.what()) + ", in the value of " + what);
      }
      if (q) {
        *unit = q->unit;
        auto number = std::make_shared<Ast>();
        number->number = q->value;
        return number;
      }
    }
    return Expression(n, text, what);
  }

  /// The key of a component, parameter or variable the model's expressions refer to: a name as
  /// the expression parser reads it (ASCII letters, digits and '_', not starting with a digit).
  std::string Name(const YamlNode& key, const What& what) const {
    std::string s = Scalar(key, what);
    bool ok = !s.empty() && !std::isdigit(static_cast<unsigned char>(s[0]));
    for (char c : s) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
    if (!ok) {
      Fail(key, what + " '" + s + "' is not a name: use ASCII letters, digits and '_', " +
                    "not starting with a digit");
    }
    return s;
  }

  std::optional<double> OptionalNumber(const YamlNode& map, const char* key,
                                       const What& what) const {
    const YamlNode value = map[key];
    if (!value) return std::nullopt;
    return Number(value, what.Plus(".", key));
  }

  ValueType Type(const YamlNode& n, const What& what) const {
    std::string_view s = ScalarText(n, what);
    if (s == "Real") return ValueType::kReal;
    if (s == "Integer") return ValueType::kInteger;
    if (s == "Boolean") return ValueType::kBoolean;
    Fail(n, "unknown type '" + std::string(s) + "' for " + what +
                " (valid types: Real, Integer, Boolean)");
  }

  ParameterDecl Parameter(const std::string& name, const YamlNode& n,
                          const std::string& owner) const {
    ParameterDecl p;
    p.name = name;
    p.loc = Loc(n);
    std::string what = owner + "." + name;
    std::string value_unit;
    if (n.IsMap()) {
      CheckKeys(n, "parameter " + what, {"value", "unit", "doc", "min", "max", "type", "shape"});
      if (!n["value"]) Fail(n, "parameter " + what + " needs a value");
      p.value_text = ValueText(n["value"], "value of " + what);
      p.value = ValueExpression(n["value"], p.value_text, "value of " + what, &value_unit);
      if (n["shape"]) p.shape = ReadShape(n["shape"], what, true);
      p.loc = TextLoc(n["value"]);
      if (n["unit"]) p.unit = UnitString(n["unit"], what);
      if (n["doc"]) p.doc = Scalar(n["doc"], what + ".doc");
      p.min = OptionalNumber(n, "min", what);
      p.max = OptionalNumber(n, "max", what);
      if (n["type"]) p.type = Type(n["type"], what);
    } else {
      p.value_text = ValueText(n, "value of " + what);
      p.value = ValueExpression(n, p.value_text, "value of " + what, &value_unit);
      p.loc = TextLoc(n);
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

  /// `stateSelect:` (MSL's StateSelect) as a priority: never -2, avoid -1, default 0, prefer 1,
  /// always 2.
  int StateSelect(const YamlNode& n, const What& what) const {
    static const char* const kChoices[] = {"never", "avoid", "default", "prefer", "always"};
    std::string_view s = ScalarText(n, what.Plus(".stateSelect"));
    for (int k = 0; k < 5; ++k) {
      if (s == kChoices[k]) return k - 2;
    }
    Fail(n, "unknown stateSelect '" + std::string(s) + "' for " + what +
                " (valid choices: never, avoid, default, prefer, always)");
  }

  VariableDecl Variable(const std::string& name, const YamlNode& n,
                        const std::string& owner) const {
    VariableDecl v;
    v.name = name;
    v.loc = Loc(n);
    std::string what = owner + "." + name;
    if (n.IsNull()) return v;
    ExpectMap(n, "variable " + what);
    CheckKeys(n, "variable " + what,
              {"unit", "doc", "start", "fixed", "nominal", "min", "max", "stateSelect", "type", "shape"});
    if (n["shape"]) v.shape = ReadShape(n["shape"], what);
    if (n["unit"]) v.unit = UnitString(n["unit"], what);
    if (n["doc"]) v.doc = Scalar(n["doc"], what + ".doc");
    if (n["start"]) v.start = Expression(n["start"], "start of " + what);
    if (n["fixed"]) v.fixed = Bool(n["fixed"], what + ".fixed");
    if (n["nominal"]) {
      v.nominal = Number(n["nominal"], what + ".nominal");
      if (!(v.nominal > 0)) Fail(n["nominal"], what + ".nominal must be positive");
    }
    v.min = OptionalNumber(n, "min", what);
    v.max = OptionalNumber(n, "max", what);
    if (n["type"]) v.type = Type(n["type"], what);
    if (n["stateSelect"]) v.state_priority = StateSelect(n["stateSelect"], what);
    return v;
  }

  std::vector<EquationDecl> Equations(const YamlNode& n, const std::string& what) const {
    std::vector<EquationDecl> out;
    if (n.IsNull()) return out;
    if (!n.IsSequence()) Fail(n, what + " must be a list of equations such as '- v = der(s)'");
    for (const auto& e : n) {
      EquationDecl d;
      d.text = Scalar(e, "an equation of " + what);
      d.loc = TextLoc(e);
      d.ast = ParseEquation(d.text, d.loc);
      out.push_back(std::move(d));
    }
    return out;
  }

  std::vector<WhenDecl> Whens(const YamlNode& n, const std::string& what) const {
    std::vector<WhenDecl> out;
    if (n.IsNull()) return out;
    if (!n.IsSequence()) Fail(n, what + " must be a list of {when: condition, then: [statements]}");
    for (const auto& w : n) {
      ExpectMap(w, "a when-clause of " + what);
      CheckKeys(w, "a when-clause of " + what, {"when", "then"});
      if (!w["when"] || !w["then"]) Fail(w, "a when-clause needs 'when: condition' and 'then: [statements]'");
      WhenDecl d;
      d.loc = Loc(w);
      d.text = Scalar(w["when"], "a when condition");
      d.condition = ParseExpression(d.text, TextLoc(w["when"]));
      const YamlNode& body = w["then"];
      if (!body.IsSequence()) Fail(body, "'then' must be a list such as [\"reinit(v, -e*pre(v))\", \"n = pre(n) + 1\"]");
      for (const auto& st : body) {
        StatementDecl sd;
        sd.text = Scalar(st, "a when statement");
        sd.loc = TextLoc(st);
        if (sd.text.rfind("reinit", 0) == 0) {
          AstPtr call = ParseExpression(sd.text, sd.loc);
          if (call->kind != Ast::Kind::kCall || call->op != "reinit" || call->args[0]->kind != Ast::Kind::kName) {
            Fail(st, "expected reinit(variable, expression), found '" + sd.text + "'");
          }
          sd.is_reinit = true;
          sd.target = call->args[0]->PathText();
          sd.value = call->args[1];
        } else {
          AstEquation eq = ParseEquation(sd.text, sd.loc);
          if (eq.lhs->kind != Ast::Kind::kName) {
            Fail(st, "a when statement is reinit(x, expr) or an assignment 'x = expr'; found '" + sd.text + "'");
          }
          sd.target = eq.lhs->PathText();
          sd.value = eq.rhs;
        }
        d.statements.push_back(std::move(sd));
      }
      out.push_back(std::move(d));
    }
    return out;
  }

  ImpactDecl Impact(const YamlNode& n, const std::string& what) const {
    ImpactDecl d;
    d.loc = Loc(n);
    ExpectMap(n, "impact of " + what);
    CheckKeys(n, "impact of " + what,
              {"gap", "velocity", "force", "restitution", "contact", "release", "v_small"});
    for (const char* key : {"gap", "velocity", "force", "restitution", "contact", "release", "v_small"}) {
      if (!n[key]) Fail(n, "impact of " + what + " needs '" + key + "'");
    }
    auto expr = [&](const char* key, AstPtr* ast, std::string* text) {
      *text = Scalar(n[key], std::string("impact ") + key);
      *ast = ParseExpression(*text, TextLoc(n[key]));
    };
    expr("gap", &d.gap, &d.gap_text);
    expr("velocity", &d.velocity, &d.velocity_text);
    expr("restitution", &d.restitution, &d.restitution_text);
    expr("v_small", &d.v_small, &d.v_small_text);
    expr("release", &d.release, &d.release_text);
    d.force = Scalar(n["force"], "impact force");
    d.contact = Scalar(n["contact"], "impact contact");
    return d;
  }

  /// `animation:`: a list of shapes, each a mapping with `shape:` and that kind's fields.
  std::vector<ShapeDecl> Animation(const YamlNode& n, const std::string& what) const {
    static const std::map<std::string, std::pair<std::vector<std::string>, std::vector<std::string>>> kKinds = {
        // kind -> (required fields, optional fields)
        {"circle", {{"at", "radius"}, {"angle"}}},
        {"line", {{"from", "to"}, {}}},
        {"spring", {{"from", "to"}, {}}},
        {"pin", {{"at"}, {}}},
        {"ground", {{"at"}, {}}},
        {"wall", {{"at", "normal"}, {"start", "end"}}},
    };
    if (!n.IsSequence()) Fail(n, "animation of " + what + " must be a list of shapes such as {shape: circle, at: [frame_a.x, frame_a.y], radius: r}");
    std::vector<ShapeDecl> out;
    for (const auto& item : n) {
      ExpectMap(item, "a shape in the animation of " + what);
      if (!item["shape"]) Fail(item, "a shape in the animation of " + what + " needs 'shape' (circle, ground, line, pin, spring or wall)");
      ShapeDecl d;
      d.loc = Loc(item);
      d.kind = Scalar(item["shape"], "shape");
      auto kind = kKinds.find(d.kind);
      if (kind == kKinds.end()) {
        Fail(item["shape"], "unknown shape '" + d.kind + "' in the animation of " + what + " (valid shapes: circle, ground, line, pin, spring, wall)");
      }
      std::vector<std::string> keys = {"shape"};
      keys.insert(keys.end(), kind->second.first.begin(), kind->second.first.end());
      keys.insert(keys.end(), kind->second.second.begin(), kind->second.second.end());
      CheckKeys(item, d.kind + " in the animation of " + what, keys);
      for (const auto& key : kind->second.first) {
        if (!item[key]) Fail(item, d.kind + " in the animation of " + what + " needs '" + key + "'");
      }
      for (size_t k = 1; k < keys.size(); ++k) {
        if (!item[keys[k]]) continue;
        ShapeField f;
        f.key = keys[k];
        f.text = ValueText(item[keys[k]], d.kind + " " + f.key);
        f.loc = TextLoc(item[keys[k]]);
        f.expr = ParseExpression(f.text, f.loc);
        d.fields.push_back(std::move(f));
      }
      out.push_back(std::move(d));
    }
    return out;
  }

  ConnectorType Connector(const std::string& name, const YamlNode& n) const {
    ConnectorType c;
    c.name = name;
    c.loc = Loc(n);
    CheckKeys(n, "connector type " + name,
              {"kind", "doc", "potential", "flow", "causality", "type"});
    if (n["doc"]) c.doc = Scalar(n["doc"], name + ".doc");
    if (n["causality"]) {
      std::string s = Scalar(n["causality"], name + ".causality");
      if (s != "input" && s != "output") {
        Fail(n["causality"], "causality of " + name + " must be input or output, found '" + s + "'");
      }
      c.is_signal = true;
      c.is_input = s == "input";
      c.signal_type = n["type"] ? Type(n["type"], name) : ValueType::kReal;
      if (n["potential"] || n["flow"]) {
        Fail(n, "signal connector " + name + " cannot have potential or flow variables");
      }
      return c;
    }
    auto vars = [&](const char* key, std::vector<ConnectorVariable>* out) {
      if (!n[key]) return;
      ExpectMap(n[key], std::string(key) + " of " + name);
      for (auto it = n[key].begin(); it != n[key].end(); ++it) {
        ConnectorVariable v;
        v.name = it->first.as<std::string>();
        if (it->second.IsMap()) {
          CheckKeys(it->second, name + "." + v.name, {"unit", "doc", "shape"});
          if (it->second["shape"]) v.shape = ReadShape(it->second["shape"], name + "." + v.name);
          if (it->second["unit"]) v.unit = UnitString(it->second["unit"], name + "." + v.name);
          if (it->second["doc"]) v.doc = it->second["doc"].Scalar();
        }
        out->push_back(v);
      }
    };
    vars("potential", &c.potentials);
    vars("flow", &c.flows);
    if (c.potentials.size() != c.flows.size()) {
      Fail(n, "connector type " + name + " must have as many flow as potential variables");
    }
    return c;
  }

  ComponentType Component(const std::string& name, const YamlNode& n, bool user) const {
    ComponentType t;
    t.name = name;
    t.loc = Loc(n);
    t.user_defined = user;
    ExpectMap(n, "component type " + name);
    CheckKeys(n, "component type " + name,
              {"kind", "doc", "parameters", "connectors", "variables", "equations",
               "initial_equations", "when", "impact", "animation", "components", "connections"});
    if (n["doc"]) t.doc = Scalar(n["doc"], name + ".doc");
    if (n["parameters"] && !n["parameters"].IsNull()) {
      ExpectMap(n["parameters"], "parameters of " + name);
      for (auto it = n["parameters"].begin(); it != n["parameters"].end(); ++it) {
        ParameterDecl p = Parameter(Name(it->first, "parameter of " + name), it->second, name);
        // A size from the value (shape: [":", 2]) makes a table (docs/FORMAT.md, "Tables").
        (IsOpen(p.shape) ? t.tables : t.parameters).push_back(std::move(p));
      }
    }
    if (n["connectors"] && !n["connectors"].IsNull()) {
      ExpectMap(n["connectors"], "connectors of " + name);
      for (auto it = n["connectors"].begin(); it != n["connectors"].end(); ++it) {
        ConnectorDecl c;
        c.name = it->first.as<std::string>();
        c.loc = Loc(it->second);
        if (it->second.IsMap()) {
          CheckKeys(it->second, "connector " + name + "." + c.name, {"type", "doc", "shape", "condition"});
          if (it->second["shape"]) c.shape = ReadShape(it->second["shape"], name + "." + c.name);
          if (!it->second["type"]) Fail(it->second, "connector " + name + "." + c.name + " needs a type");
          c.type = Scalar(it->second["type"], "type");
          if (it->second["doc"]) c.doc = it->second["doc"].Scalar();
          if (it->second["condition"]) c.condition = Name(it->second["condition"], "condition of connector " + name + "." + c.name);
        } else {
          c.type = Scalar(it->second, "type of connector " + name + "." + c.name);
        }
        t.connectors.push_back(c);
      }
    }
    if (n["variables"] && !n["variables"].IsNull()) {
      ExpectMap(n["variables"], "variables of " + name);
      for (auto it = n["variables"].begin(); it != n["variables"].end(); ++it) {
        t.variables.push_back(Variable(Name(it->first, "variable of " + name), it->second, name));
      }
    }
    if (n["equations"]) t.equations = Equations(n["equations"], "equations of " + name);
    if (n["initial_equations"]) {
      t.initial_equations = Equations(n["initial_equations"], "initial equations of " + name);
    }
    if (n["when"]) t.whens = Whens(n["when"], name);
    if (n["impact"]) t.impacts.push_back(Impact(n["impact"], name));
    if (n["animation"]) t.animation = Animation(n["animation"], name);
    Parts(n, &t.components, &t.connections);
    return t;
  }

  /// `components:` and `connections:` of a model or a composite type.
  void Parts(const YamlNode& n, std::vector<ComponentSpec>* components,
             std::vector<ConnectionSpec>* connections) const {
    // (Reserved: a written-out model has 100 000 entries, which would be moved as the lists grow.)
    if (const YamlNode parts = n["components"]; parts && !parts.IsNull()) {
      ExpectMap(parts, "components");
      components->reserve(components->size() + parts.size());
      for (auto it = parts.begin(); it != parts.end(); ++it) {
        components->push_back(ComponentEntry(Name(it->first, "component"), it->second));
      }
    }
    if (const YamlNode list = n["connections"]; list && !list.IsNull()) {
      if (!list.IsSequence()) Fail(list, "connections must be a list");
      connections->reserve(connections->size() + list.size());
      for (const auto& c : list) connections->push_back(Connection(c));
    }
  }

  void LibraryEntries(const YamlNode& root, Library* lib, std::vector<ComponentType>* defines,
                      bool user, const char* what = nullptr) const {
    ExpectMap(root, what ? what : user ? "define" : "a library file");
    for (auto it = root.begin(); it != root.end(); ++it) {
      std::string name = it->first.as<std::string>();
      const YamlNode n = it->second;  // a copy: it->second is a temporary
      ExpectMap(n, "type " + name);
      std::string kind = n["kind"] ? Scalar(n["kind"], name + ".kind") : "component";
      if (kind == "connector") {
        if (user) Fail(n["kind"], "a model's define: section and a uses: file hold component types only; connector types come from the library");
        lib->AddConnector(ScalarForm(Connector(name, n)));
      } else if (kind == "component") {
        ComponentType t = Component(name, n, user);
        if (defines) {
          defines->push_back(std::move(t));
        } else {
          lib->AddComponent(std::move(t));
        }
      } else {
        Fail(n["kind"], "unknown kind '" + kind + "' of " + name + " (valid kinds: component, connector)");
      }
    }
  }

  ComponentSpec ComponentEntry(const std::string& name, const YamlNode& n) const {
    ComponentSpec c;
    c.name = name;
    c.loc = Loc(n);
    ExpectMap(n, What{"component ", name});
    const YamlNode type = n["type"];
    if (!type) Fail(n, "component " + name + " needs a type, e.g. {type: Mass}");
    c.type = Scalar(type, What{"type of ", name});
    c.type_loc = Loc(type);
    c.modifiers.reserve(n.size() - 1);
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string_view key = KeyText(it->first);
      if (key == "type") continue;
      if (key == "doc") {
        c.doc = Scalar(it->second, What{name, ".doc"});
        continue;
      }
      if (key == "count") {
        c.count = Expression(it->second, What{"count of ", name});
        continue;
      }
      // Descriptions for messages, made only when there is one.
      const What what{name, ".", key};
      Modifier m;
      m.key = key;
      m.loc = Loc(it->first);
      m.key_loc = m.loc;
      const YamlNode value = it->second;
      if (value.IsMap()) {
        CheckKeys(value, what, {"start", "fixed", "stateSelect"});
        if (const YamlNode start = value["start"]) {
          m.start = Expression(start, What{"start of ", name, ".", key});
        }
        if (const YamlNode fixed = value["fixed"]) m.fixed = Bool(fixed, what.Plus(".fixed"));
        if (const YamlNode choice = value["stateSelect"]) {
          m.state_priority = StateSelect(choice, what);
        }
      } else {
        m.value_text = ValueText(value, what);
        m.value = ValueExpression(value, m.value_text, what, &m.value_unit);
        m.loc = TextLoc(value);
      }
      c.modifiers.push_back(std::move(m));
    }
    return c;
  }

  /// A connection end's text and place, and its tree unless it is a plain dotted name, which
  /// reads without an error (ConnectionSpec::EndA makes its tree when it is needed).
  AstPtr End(const YamlNode& n, std::string* text, SourceLoc* loc) const {
    *text = ScalarText(n, "a connection end");
    *loc = TextLoc(n);
    return IsPlainName(*text) ? nullptr : ParseName(*text, *loc);
  }

  ConnectionSpec Connection(const YamlNode& n) const {
    ConnectionSpec c;
    c.loc = Loc(n);
    if (n.IsMap()) {
      CheckKeys(n, "a connection", {"for", "connect"});
      if (!n["connect"]) Fail(n, "a connection mapping needs 'connect: [a, b]'");
      if (n["for"]) {
        // for: i in 1:n-1
        std::string spec = Scalar(n["for"], "for");
        SourceLoc loc = TextLoc(n["for"]);
        c.loop_text = spec;
        c.loop_loc = loc;
        size_t in = spec.find(" in ");
        size_t colon = spec.find(':', in == std::string::npos ? 0 : in);
        if (in == std::string::npos || colon == std::string::npos) {
          Fail(n["for"], "'for' must read like 'i in 1:n-1', found '" + spec + "'");
        }
        c.loop_var = spec.substr(0, in);
        while (!c.loop_var.empty() && c.loop_var.back() == ' ') c.loop_var.pop_back();
        while (!c.loop_var.empty() && c.loop_var.front() == ' ') c.loop_var.erase(0, 1);
        c.loop_from = ParseExpression(spec.substr(in + 4, colon - in - 4),
                                      loc.Shifted(static_cast<int>(in + 4)));
        c.loop_to = ParseExpression(spec.substr(colon + 1), loc.Shifted(static_cast<int>(colon + 1)));
      }
    }
    // (yaml-cpp's Node::operator= writes through to the node, so the pair is bound once.)
    const YamlNode pair = n.IsMap() ? n["connect"] : n;
    if (!pair.IsSequence() || pair.size() != 2) {
      Fail(pair, "a connection is a list of two connectors, e.g. [A.flange_b, B.flange_a]");
    }
    c.a = End(pair[0], &c.a_text, &c.a_loc);
    c.b = End(pair[1], &c.b_text, &c.b_loc);
    return c;
  }

  ModelSpec Model(const YamlNode& root) const {
    ModelSpec m;
    m.file = file_;
    m.loc = Loc(root);
    if (!root.IsMap()) {
      throw ModelError(Loc(root), "a model file must be a mapping with keys such as model, components, connections");
    }
    CheckKeys(root, "the model",
              {"model", "doc", "uses", "parameters", "define", "components", "connections", "variables",
               "equations", "initial_equations", "when", "experiment", "outputs"});
    if (!root["model"]) Fail(root, "the model needs a name: 'model: MyModel'");
    m.name = Scalar(root["model"], "model");
    if (root["doc"]) m.doc = Scalar(root["doc"], "doc");
    if (root["uses"] && !root["uses"].IsNull()) {
      const YamlNode& u = root["uses"];
      if (!u.IsSequence()) Fail(u, "uses must be a list of YAML files, e.g. uses: [mylib.yaml]");
      for (const auto& f : u) m.uses.push_back({Scalar(f, "a uses: file"), TextLoc(f)});
    }
    if (root["parameters"] && !root["parameters"].IsNull()) {
      ExpectMap(root["parameters"], "parameters");
      for (auto it = root["parameters"].begin(); it != root["parameters"].end(); ++it) {
        m.parameters.push_back(Parameter(Name(it->first, "parameter"), it->second, m.name));
        if (IsOpen(m.parameters.back().shape)) {
          Fail(it->second["shape"], "the model parameter " + m.parameters.back().name +
                                        " has a size ':'; only a component type's parameter (a table) may");
        }
      }
    }
    if (root["define"] && !root["define"].IsNull()) {
      Library scratch;
      LibraryEntries(root["define"], &scratch, &m.defines, true);
    }
    Parts(root, &m.components, &m.connections);
    if (root["variables"] && !root["variables"].IsNull()) {
      ExpectMap(root["variables"], "variables");
      for (auto it = root["variables"].begin(); it != root["variables"].end(); ++it) {
        m.variables.push_back(Variable(Name(it->first, "variable"), it->second, m.name));
      }
    }
    if (root["equations"]) m.equations = Equations(root["equations"], "the model's equations");
    if (root["initial_equations"]) {
      m.initial_equations = Equations(root["initial_equations"], "the model's initial equations");
    }
    if (root["when"]) m.whens = Whens(root["when"], "the model");
    if (root["experiment"]) {
      const YamlNode& e = root["experiment"];
      ExpectMap(e, "experiment");
      CheckKeys(e, "experiment", {"start", "stop", "tolerance", "interval", "linear_solver", "max_order"});
      m.experiment.loc = Loc(e);
      if (e["start"]) m.experiment.start = Number(e["start"], "experiment.start");
      if (e["stop"]) m.experiment.stop = Number(e["stop"], "experiment.stop");
      if (e["tolerance"]) m.experiment.tolerance = Number(e["tolerance"], "experiment.tolerance");
      if (e["interval"]) m.experiment.interval = Number(e["interval"], "experiment.interval");
      if (e["max_order"]) {
        const double k = Number(e["max_order"], "experiment.max_order");
        if (!(k >= 1 && k <= 5 && k == std::floor(k))) {
          Fail(e["max_order"],
               "experiment.max_order must be a whole number from 1 to 5 (IDA's maximum BDF order; "
               "the default is 5), found '" +
                   std::string(e["max_order"].Scalar()) + "'");
        }
        m.experiment.max_order = static_cast<int>(k);
      }
      if (e["linear_solver"]) {
        m.experiment.linear_solver = Scalar(e["linear_solver"], "experiment.linear_solver");
        const std::string& s = m.experiment.linear_solver;
        if (s != "auto" && s != "dense" && s != "klu") {
          Fail(e["linear_solver"], "unknown linear_solver '" + s + "' (valid: auto, dense, klu)");
        }
      }
      // Each value is checked where it is written (the section itself when it is missing).
      const ExperimentSpec& x = m.experiment;
      auto at = [&](const char* key) { return e[key] ? e[key] : e; };
      auto shown = [&](const char* key, double v) {
        if (e[key]) return "'" + std::string(e[key].Scalar()) + "'";
        std::ostringstream text;
        text << v << " (the default)";
        return text.str();
      };
      if (!(x.stop > x.start)) {
        Fail(at("stop"), "experiment.stop must be after experiment.start (" + shown("start", x.start) + "), found " +
                             shown("stop", x.stop));
      }
      if (!(x.tolerance >= kMinRelTolerance && x.tolerance < 1)) {
        Fail(at("tolerance"), "experiment.tolerance must lie between 1e-15 and 1 (double precision resolves about "
                              "2.2e-16), found " + shown("tolerance", x.tolerance));
      }
      if (e["interval"]) {
        if (!(x.interval > 0)) {
          Fail(e["interval"], "experiment.interval must be positive, found " + shown("interval", x.interval));
        }
        if (std::string grid = OutputGridProblem(x.start, x.stop, x.interval); !grid.empty()) {
          Fail(e["interval"], "experiment.interval " + shown("interval", x.interval) + ": " + grid);
        }
      }
    }
    if (root["outputs"] && !root["outputs"].IsNull()) {
      if (!root["outputs"].IsSequence()) Fail(root["outputs"], "outputs must be a list of paths such as A.v");
      for (const auto& o : root["outputs"]) {
        OutputSpec out;
        out.text = Scalar(o, "an output");
        out.loc = TextLoc(o);
        out.expr = ParseExpression(out.text, out.loc);
        m.outputs.push_back(std::move(out));
      }
    }
    return m;
  }

 private:
  std::string file_;
  SourceLoc file_loc_;  ///< no place yet: the file
};

/// The place of a 0-based line and column (a node's YamlMark or a yaml-cpp exception's mark;
/// none when the line is negative: yaml-cpp's null mark).
SourceLoc MarkLoc(const std::string& file, int line, int column) {
  SourceLoc loc;
  loc.set_file(file);
  if (line >= 0) {
    loc.line = line + 1;
    loc.column = column + 1;
  }
  return loc;
}
SourceLoc MarkLoc(const std::string& file, const YamlMark& mark) {
  return MarkLoc(file, mark.line, mark.column);
}
SourceLoc MarkLoc(const std::string& file, const YAML::Mark& mark) {
  return MarkLoc(file, mark.line, mark.column);
}

/// Where a mapping's key `k` was first given before (its index), or -1 when it is new. Small
/// mappings compare their keys pairwise; large ones (a model's 100 000 components) use a table.
class FirstKeys {
 public:
  explicit FirstKeys(size_t pairs) : hashed_(pairs > kPairwise) {
    if (hashed_) first_.reserve(pairs);
  }
  long Add(std::string_view key, size_t k) {
    if (hashed_) {
      auto [at, inserted] = first_.emplace(key, k);
      return inserted ? -1 : static_cast<long>(at->second);
    }
    for (size_t j = 0; j < keys_.size(); ++j) {
      if (keys_[j].first == key) return static_cast<long>(keys_[j].second);
    }
    keys_.emplace_back(key, k);
    return -1;
  }

 private:
  static constexpr size_t kPairwise = 16;
  bool hashed_;
  std::vector<std::pair<std::string_view, size_t>> keys_;
  std::unordered_map<std::string_view, size_t> first_;
};

/// A YAML mapping keeps every pair and looks a key up by its first occurrence, so a key
/// given twice would silently lose its second value: report it, with both places. The walk is
/// iterative and visits a node reached through several aliases once (alias bombs stay linear).
void CheckDuplicateKeys(const YamlDoc& doc, const std::string& file, const std::string& what) {
  // A node to walk: the collection it was reached from (an index into `walked`, kTop for the
  // root) and the key or element number it is there. Paths are spelled out for a message only.
  constexpr uint32_t kTop = ~0u;
  struct Step {
    YamlNode node;
    uint32_t parent;
    std::string_view key;  ///< under a mapping
    size_t element;        ///< under a sequence: 1-based
  };
  std::vector<Step> walked;  // the collections walked, in order
  std::vector<bool> seen(doc.num_nodes());
  auto path_of = [&](uint32_t at) {
    std::vector<const Step*> up;
    for (; at != kTop; at = walked[at].parent) up.push_back(&walked[at]);
    std::string path;
    for (auto s = up.rbegin(); s != up.rend(); ++s) {
      if ((*s)->parent == kTop) continue;
      if ((*s)->element > 0) {
        path += "[" + std::to_string((*s)->element) + "]";
      } else {
        path += path.empty() ? std::string((*s)->key) : "." + std::string((*s)->key);
      }
    }
    return path;
  };
  std::vector<Step> stack{{doc.root(), kTop, {}, 0}};
  while (!stack.empty()) {
    const Step step = stack.back();
    stack.pop_back();
    const YamlNode node = step.node;
    if (!node.IsMap() && !node.IsSequence()) continue;
    if (seen[node.id()]) continue;
    seen[node.id()] = true;
    const auto here = static_cast<uint32_t>(walked.size());
    walked.push_back(step);
    const size_t n = node.size();
    // The children, walked in the order of the file (pushed last to first).
    const size_t bottom = stack.size();
    if (node.IsSequence()) {
      for (size_t k = n; k-- > 0;) stack.push_back({node[k], here, {}, k + 1});
      continue;
    }
    FirstKeys first(n);
    size_t k = 0;
    for (auto it = node.begin(); it != node.end(); ++it, ++k) {
      if (!it->first.IsScalar()) continue;
      const std::string_view key = it->first.Scalar();
      const long before = first.Add(key, k);
      if (before >= 0) {
        const YamlMark at = (*YamlNode::Iterator(node, static_cast<size_t>(before))).first.Mark();
        const std::string path = path_of(here);
        throw ModelError(MarkLoc(file, it->first.Mark()),
                         "'" + std::string(key) + "' is given twice in " +
                             (path.empty() ? "the " + what : path) + " (first at line " +
                             std::to_string(at.line + 1) + ", column " +
                             std::to_string(at.column + 1) + "); remove one of them");
      }
      stack.push_back({it->second, here, key, 0});
    }
    std::reverse(stack.begin() + static_cast<std::ptrdiff_t>(bottom), stack.end());
  }
}

/// Reads the single YAML document of a file (core/lang/yaml_tree.h: the subset reader, else libyaml's
/// event parser for a large file, else yaml-cpp's). An empty file, a second document (`---`), YAML
/// nested deeper than yaml-cpp reads, and a key given twice in one mapping are errors.
std::unique_ptr<YamlDoc> ParseYaml(const std::string& text, const std::string& file, const std::string& what) {
  ParsedYaml parsed;
  try {
    parsed = ParseYamlDocument(text);
  } catch (const YAML::DeepRecursion& e) {
    throw ModelError(MarkLoc(file, e.mark),
                     "YAML nested too deeply: lists and mappings nested hundreds of levels deep are "
                     "not read (a " + what + " needs a few levels)");
  } catch (const YAML::Exception& e) {
    throw ModelError(MarkLoc(file, e.mark), "YAML syntax error: " + e.msg);
  }
  if (parsed.documents == 2) {
    // yaml-cpp's parser does not consume a ',' where a document should start (0.7: the input ",").
    if (parsed.stuck) {
      throw ModelError(MarkLoc(file, parsed.second_mark),
                       "YAML syntax error: unexpected '" + text.substr(parsed.second_offset, 1) + "'");
    }
    throw ModelError(MarkLoc(file, parsed.second_mark),
                     "a second YAML document starts here; a " + what + " holds one document");
  }
  if (parsed.documents == 0 || !parsed.doc || parsed.doc->empty()) {
    bool blank = text.find_first_not_of(" \t\r\n") == std::string::npos;
    throw ModelError(SourceLoc(file), "the " + what + " is empty" +
                                          (blank ? "" : " (it holds only comments)"));
  }
  if (parsed.doc->has_repeated_key()) CheckDuplicateKeys(*parsed.doc, file, what);
  return std::move(parsed.doc);
}

/// The text of a model or library file, refused when it is a directory or larger than a model
/// can sensibly be.
std::string ReadModelText(const std::string& path, const char* what) {
  // A directory opens as a stream on Linux and reads as nothing; a device may never end.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw ModelError(path + ": is a directory, not a " + what);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path + ": cannot open the " + what);
  std::string text;
  // A regular file's size is known: the text is allocated once (a model of 100 000 components
  // is 12 MB).
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size <= kMaxModelFileBytes) text.reserve(size);
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
    if (text.size() > kMaxModelFileBytes) {
      throw ModelError(path + ": the " + what + " is larger than " +
                       std::to_string(kMaxModelFileBytes >> 20) + " MiB; a model is a short text");
    }
  }
  if (in.bad()) throw ModelError(path + ": cannot read the " + what);
  return text;
}

ModelSpec ParseModel(const std::string& yaml, const std::string& file_name) {
  Reader reader(file_name);
  std::unique_ptr<YamlDoc> doc = ParseYaml(yaml, file_name, "model file");
  try {
    return reader.Model(doc->root());
  } catch (const YAML::Exception& e) {
    SourceLoc loc;
    loc.set_file(file_name);
    if (e.mark.line >= 0) {
      loc.line = e.mark.line + 1;
      loc.column = e.mark.column + 1;
    }
    throw ModelError(loc, "malformed model: " + e.msg);
  }
}

/// Appends to spec->defines the types of every file spec->uses names (paths relative to the
/// directory of spec->file), and of the files those use, each file once: a model file becomes a
/// type of its model's name (with its own define: types), a library file gives its component types.
void LoadUses(ModelSpec* spec, std::set<std::string>* loaded) {
  namespace fs = std::filesystem;
  for (const UsesSpec& u : spec->uses) {
    fs::path path = fs::path(u.path).is_absolute() ? fs::path(u.path) : fs::path(spec->file).parent_path() / u.path;
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      throw ModelError(u.loc, "uses: no file '" + u.path + "' (looked for " + path.lexically_normal().string() + ")");
    }
    std::string key = fs::weakly_canonical(path, ec).string();
    if (!loaded->insert(key).second) continue;
    std::string file = path.lexically_normal().string();
    std::string text;
    try {
      text = ReadModelText(file, "file in uses:");
    } catch (const ModelError& e) {
      throw ModelError(u.loc, std::string("uses: ") + e.what());
    }
    std::unique_ptr<YamlDoc> doc = ParseYaml(text, file, "file in uses:");
    const YamlNode root = doc->root();
    if (root.IsMap() && root["model"]) {
      ModelSpec used = ParseModel(text, file);
      LoadUses(&used, loaded);
      for (auto& d : used.defines) spec->defines.push_back(std::move(d));
      spec->defines.push_back(ModelAsType(used));
    } else {
      Library scratch;
      try {
        Reader(file).LibraryEntries(root, &scratch, &spec->defines, true, "a library file in uses:");
      } catch (const YAML::Exception& e) {
        throw ModelError(MarkLoc(file, e.mark), "malformed library file: " + e.msg);
      }
    }
  }
}

}  // namespace

ComponentType ModelAsType(const ModelSpec& m) {
  ComponentType t;
  t.name = m.name;
  t.doc = m.doc;
  t.parameters = m.parameters;
  t.variables = m.variables;
  t.equations = m.equations;
  t.initial_equations = m.initial_equations;
  t.whens = m.whens;
  t.components = m.components;
  t.connections = m.connections;
  t.loc = m.loc;
  t.user_defined = true;
  return t;
}

ModelSpec LoadModelString(const std::string& yaml, const std::string& file_name) {
  ModelSpec spec = ParseModel(yaml, file_name);
  if (!spec.uses.empty()) {
    std::set<std::string> loaded;
    std::error_code ec;
    loaded.insert(std::filesystem::weakly_canonical(file_name, ec).string());
    // The used types first, so that a clash is reported at the model's own definition.
    std::vector<ComponentType> own = std::move(spec.defines);
    spec.defines.clear();
    LoadUses(&spec, &loaded);
    for (auto& d : own) spec.defines.push_back(std::move(d));
  }
  return spec;
}

ModelSpec LoadModelFile(const std::string& path) {
  return LoadModelString(ReadModelText(path, "model file"), path);
}

void LoadLibraryString(const std::string& yaml, const std::string& file_name, Library* library) {
  Reader reader(file_name);
  std::unique_ptr<YamlDoc> doc = ParseYaml(yaml, file_name, "library file");
  reader.LibraryEntries(doc->root(), library, nullptr, false);
  ScalariseLibrary(library);  // vectors and matrices become scalars (core/lang/arrays.h)
}

}  // namespace momenta
