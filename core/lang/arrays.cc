// The scalar form of arrays (core/lang/arrays.h): which types and models need it, the names their
// expressions see, and the scalar form of a type, a connector, a component's modifiers and a
// model. An expression is evaluated by core/lang/array_expression.h; the declarations of a type or
// the model are rewritten element by element by core/lang/array_declarations.h.

#include "core/lang/arrays.h"

#include <algorithm>
#include <functional>
#include <unordered_map>

#include "core/lang/array_declarations.h"
#include "core/lang/array_expression.h"
#include "core/lang/records.h"

namespace momenta {

std::string ShapeText(const Shape& shape) {
  if (shape.empty()) return "scalar";
  std::string s = "[";
  for (size_t k = 0; k < shape.size(); ++k) {
    s += (k ? ", " : "") + (shape[k] == kOpenSize ? std::string(":") : std::to_string(shape[k]));
  }
  return s + "]";
}

size_t ElementCount(const Shape& shape) {
  size_t n = 1;
  for (int d : shape) n *= static_cast<size_t>(d);
  return n;
}

std::string ElementName(const std::string& name, const Shape& shape, size_t flat) {
  return name + "[" + SubscriptText(shape, flat) + "]";
}

namespace {

// ---- The names an expression sees: every lookup of an array's shape is here ---------------------

/// The local name a kName refers to: its segments' names joined by '.', subscripts left out.
std::string JoinedName(const Ast& a, size_t from) {
  std::string s;
  for (size_t k = from; k < a.path.size(); ++k) {
    if (k > from) s += '.';
    s += a.path[k].name;
  }
  return s;
}

/// A type's names: its own arrays (`table`), `owner` naming it in messages.
ArrayScope TypeScope(const ArrayShapes* table, const std::string& owner) {
  ArrayScope scope;
  scope.owner = owner;
  scope.shape_of = [table](const Ast& name) -> const Shape* {
    if (table->empty()) return nullptr;
    auto it = table->find(JoinedName(name, 0));
    return it == table->end() ? nullptr : &it->second;
  };
  return scope;
}

/// The components of the model by name, with their types (null for an unknown type).
using ComponentTypes = std::unordered_map<std::string, const ComponentType*>;

/// The model's names: its parameters and variables (`table`), and `component.name` in a
/// component's type, down through the parts of composite types (`pair.body.r`). The scope refers
/// to `table` and `component_type`, which must outlive it.
ArrayScope ModelScope(const ArrayShapes* table, const ComponentTypes* component_type,
                      std::function<const ComponentType*(const std::string&)> type_of) {
  ArrayScope scope;
  scope.component_arrays = true;
  scope.shape_of = [table, component_type, type_of](const Ast& name) -> const Shape* {
    if (name.path.size() == 1) {
      auto it = table->find(name.path[0].name);
      return it == table->end() ? nullptr : &it->second;
    }
    // A field of the model's own record variable (`R.T`).
    if (auto own = table->find(JoinedName(name, 0)); own != table->end()) return &own->second;
    auto c = component_type->find(name.path[0].name);
    if (c == component_type->end() || !c->second) return nullptr;
    // Down through the parts of composite types, then the type's own arrays.
    const ComponentType* t = c->second;
    size_t k = 1;
    for (bool deeper = true; deeper && k + 1 < name.path.size();) {
      deeper = false;
      for (const auto& part : t->components) {
        if (part.name != name.path[k].name) continue;
        const ComponentType* pt = type_of(part.type);
        if (!pt) return nullptr;
        t = pt;
        ++k;
        deeper = true;
        break;
      }
    }
    if (t->arrays.empty()) return nullptr;
    auto it = t->arrays.find(JoinedName(name, k));
    return it == t->arrays.end() ? nullptr : &it->second;
  };
  return scope;
}

// ---- Which types need a scalar form -----------------------------------------------------------

bool ConnectorHasArrays(const ComponentType& type, const Library& library) {
  for (const auto& c : type.connectors) {
    if (!c.shape.empty()) return true;
    const ConnectorType* ct = library.FindConnector(c.type);
    if (ct && !ct->arrays.empty()) return true;
  }
  return false;
}

}  // namespace

ArrayScope ScopeOf(const ComponentType& type) { return TypeScope(&type.arrays, type.name); }

bool NeedsScalarForm(const ComponentType& type, const Library& library) {
  if (type.scalar_form) return false;
  if (ConnectorHasArrays(type, library)) return true;
  if (UsesRecordsOrBlocks(type, library)) return true;
  for (const auto& p : type.parameters) {
    if (!p.shape.empty() || UsesArraySyntax(p.value, true)) return true;
  }
  for (const auto& v : type.variables) {
    if (!v.shape.empty() || UsesArraySyntax(v.start, true)) return true;
  }
  for (const auto* list : {&type.equations, &type.initial_equations}) {
    for (const auto& e : *list) {
      if (UsesArraySyntax(e.ast.lhs, true) || UsesArraySyntax(e.ast.rhs, true)) return true;
    }
  }
  for (const auto& w : type.whens) {
    if (UsesArraySyntax(w.condition, true)) return true;
    for (const auto& st : w.statements) {
      if (UsesArraySyntax(st.value, true) || st.target.find('[') != std::string::npos) return true;
    }
  }
  return false;
}

ComponentType ScalarForm(const ComponentType& source, const Library& library) {
  ArrayNodeBudget budget;
  // Records and the graph's predicates first (core/lang/records.h): their fields are arrays.
  const bool records = UsesRecordsOrBlocks(source, library);
  const ComponentType expanded = records ? ExpandRecordDeclarations(source, library) : ComponentType();
  const ComponentType& type = records ? expanded : source;
  ComponentType out = type;
  out.arrays = records ? expanded.arrays : ArrayShapes();  // an outer's arrays (core/lang/records.h)
  ArrayShapes& table = out.arrays;
  // Shaped signal connectors become one connector per element; the arrays of a connector type
  // are seen as `c.r`.
  ArrayShapes signals;
  out.connectors.clear();
  for (const auto& c : type.connectors) {
    const ConnectorType* ct = library.FindConnector(c.type);
    if (ct) {
      for (const auto& [name, shape] : ct->arrays) table[c.name + "." + name] = shape;
    }
    if (c.shape.empty()) {
      out.connectors.push_back(c);
      continue;
    }
    if (ct && !ct->is_signal) {
      throw ModelError(c.loc, type.name + "." + c.name + ": only signal connectors take a shape; " + c.type +
                                  " is a physical connector (give its type's variables a shape instead)");
    }
    table[c.name] = signals[c.name] = c.shape;
    for (size_t i = 0; i < ElementCount(c.shape); ++i) {
      ConnectorDecl e = c;
      e.name = ElementName(c.name, c.shape, i);
      e.shape.clear();
      out.connectors.push_back(std::move(e));
    }
  }
  ArrayScope scope = TypeScope(&table, type.name);
  scope.library = &library;
  scope.records = &type.records;
  DeclarationScalariser s(scope, &table, type.name);
  out.parameters = s.Parameters(type.parameters);
  out.variables = s.Variables(type.variables, signals);
  out.equations = s.Equations(type.equations);
  out.initial_equations = s.Equations(type.initial_equations);
  out.whens = s.Whens(type.whens);
  for (auto& im : out.impacts) {
    auto scalar = [&](AstPtr* a, const std::string& text) {
      *a = ArrayEvaluator(s.scope(), text, im.loc).Scalar(*a, "an impact's expression");
    };
    scalar(&im.gap, im.gap_text);
    scalar(&im.velocity, im.velocity_text);
    scalar(&im.restitution, im.restitution_text);
    scalar(&im.v_small, im.v_small_text);
    scalar(&im.release, im.release_text);
  }
  if (records) FinishRecordsAndBlocks(&out, library);
  out.scalar_form = true;
  return out;
}

ConnectorType ScalarForm(ConnectorType connector) {
  for (auto* list : {&connector.potentials, &connector.flows}) {
    std::vector<ConnectorVariable> out;
    for (const auto& v : *list) {
      if (v.shape.empty()) {
        out.push_back(v);
        continue;
      }
      connector.arrays[v.name] = v.shape;
      for (size_t i = 0; i < ElementCount(v.shape); ++i) {
        ConnectorVariable e = v;
        e.name = ElementName(v.name, v.shape, i);
        e.shape.clear();
        out.push_back(std::move(e));
      }
    }
    *list = std::move(out);
  }
  return connector;
}

void ScalariseLibrary(Library* library) {
  for (const std::string& name : library->ComponentNames()) {
    const ComponentType* t = library->FindComponent(name);
    if (NeedsScalarForm(*t, *library)) library->AddComponent(ScalarForm(*t, *library));
  }
}

std::vector<Modifier> ScalarModifiers(const ComponentSpec& component, const ComponentType& type,
                                      const ArrayScope& scope) {
  ArrayNodeBudget budget;
  std::vector<Modifier> out;
  DeclarationScalariser s(scope, nullptr, "");
  for (const Modifier& m : component.modifiers) {
    // A table's value (shape: [":", 2]) is sized by the flattener.
    if (std::any_of(type.tables.begin(), type.tables.end(), [&](const ParameterDecl& t) { return t.name == m.key; })) {
      out.push_back(m);
      continue;
    }
    Modifier base = m;
    // `R[1, 2]` and `R[1,2]` name the same element.
    if (base.key.find('[') != std::string::npos) base.key.erase(std::remove(base.key.begin(), base.key.end(), ' '), base.key.end());
    auto found = type.arrays.find(base.key);
    const Shape shape = found == type.arrays.end() ? Shape{} : found->second;
    const std::string who = component.name + "." + base.key;
    std::vector<AstPtr> values, starts;
    if (m.value) values = s.Fill(m.value, m.value_text, m.loc, shape, "the value of " + who);
    if (m.start) starts = s.Fill(m.start, AstToString(*m.start), m.loc, shape, "the start value of " + who);
    for (size_t i = 0; i < ElementCount(shape); ++i) {
      Modifier e = base;
      if (!shape.empty()) e.key = ElementName(base.key, shape, i);
      if (m.value) {
        e.value = values[i];
        if (!shape.empty()) e.value_text = AstToString(*values[i]);
      }
      if (m.start) e.start = starts[i];
      out.push_back(std::move(e));
    }
  }
  return out;
}

namespace {

bool ModelNeedsScalarForm(const ModelSpec& spec, const Library& library,
                          const std::function<const ComponentType*(const std::string&)>& type_of) {
  for (const auto& d : spec.defines) {
    if (NeedsScalarForm(d, library)) return true;
  }
  for (const auto& c : spec.components) {
    const ComponentType* t = type_of(c.type);
    if (t && !t->arrays.empty()) return true;
    for (const auto& m : c.modifiers) {
      if (UsesArraySyntax(m.value, false) || UsesArraySyntax(m.start, false)) return true;
    }
  }
  for (const auto& p : spec.parameters) {
    if (!p.shape.empty() || UsesArraySyntax(p.value, false)) return true;
  }
  for (const auto& v : spec.variables) {
    if (!v.shape.empty() || !v.record.empty() || UsesArraySyntax(v.start, false)) return true;
  }
  for (const auto* list : {&spec.equations, &spec.initial_equations}) {
    for (const auto& e : *list) {
      if (UsesArraySyntax(e.ast.lhs, false) || UsesArraySyntax(e.ast.rhs, false)) return true;
      if (CallsLibraryFunction(e.ast.lhs) || CallsLibraryFunction(e.ast.rhs)) return true;
    }
  }
  for (const auto& w : spec.whens) {
    if (UsesArraySyntax(w.condition, false)) return true;
    for (const auto& st : w.statements) {
      if (UsesArraySyntax(st.value, false)) return true;
    }
  }
  for (const auto& o : spec.outputs) {
    if (UsesArraySyntax(o.expr, false)) return true;
  }
  return false;
}

/// A connection end `c.u` or `c.u[2]` as the element ends it stands for (one when it names a
/// scalar connector or one element).
struct EndElements {
  Shape shape;
  std::vector<AstPtr> ends;
  std::vector<std::string> texts;
};

EndElements ConnectionEnd(const AstPtr& end, const std::string& text, const SourceLoc& loc,
                          const ArrayScope& scope) {
  ArrayEvaluator ev(scope, text, loc);
  ArrayValue v = ev.Eval(end);
  EndElements out{v.shape, {}, {}};
  for (size_t i = 0; i < v.elements.size(); ++i) {
    out.ends.push_back(v.elements[i]);
    out.texts.push_back(v.scalar() ? (v.elements[0] == end ? text : v.elements[0]->PathText())
                                   : ElementName(text, v.shape, i));
  }
  return out;
}

/// The model's connections, those between shaped signal connectors element by element.
std::vector<ConnectionSpec> ScalarConnections(const std::vector<ConnectionSpec>& connections,
                                              const ArrayScope& scope) {
  std::vector<ConnectionSpec> out;
  for (const auto& c : connections) {
    EndElements a = ConnectionEnd(c.EndA(), c.a_text, c.a_loc, scope);
    EndElements b = ConnectionEnd(c.EndB(), c.b_text, c.b_loc, scope);
    if (a.shape != b.shape) {
      throw ModelError(c.a_loc, "cannot connect " + c.a_text + " (shape " + ShapeText(a.shape) + ") to " + c.b_text +
                                    " (shape " + ShapeText(b.shape) + "): connected signals must have the same shape");
    }
    for (size_t i = 0; i < a.ends.size(); ++i) {
      ConnectionSpec e = c;
      e.a = a.ends[i];
      e.b = b.ends[i];
      e.a_text = a.texts[i];
      e.b_text = b.texts[i];
      out.push_back(std::move(e));
    }
  }
  return out;
}

/// The model's outputs, a whole array as one column per element.
std::vector<OutputSpec> ScalarOutputs(const std::vector<OutputSpec>& outputs, const ArrayScope& scope) {
  std::vector<OutputSpec> out;
  for (const auto& o : outputs) {
    ArrayValue v = ArrayEvaluator(scope, o.text, o.loc).Eval(o.expr);
    const bool name = o.expr->kind == Ast::Kind::kName;
    for (size_t i = 0; i < v.elements.size(); ++i) {
      OutputSpec e = o;
      e.expr = v.elements[i];
      if (!v.scalar()) e.text = ElementName(name ? o.text : "(" + o.text + ")", v.shape, i);
      out.push_back(std::move(e));
    }
  }
  return out;
}

}  // namespace

std::optional<ModelSpec> ScalarModel(const ModelSpec& spec, const Library& library) {
  std::unordered_map<std::string, const ComponentType*> defined;
  for (const auto& d : spec.defines) defined[d.name] = &d;
  auto type_of = [&](const std::string& name) -> const ComponentType* {
    auto it = defined.find(name);
    return it != defined.end() ? it->second : library.FindComponent(name);
  };
  if (!ModelNeedsScalarForm(spec, library, type_of)) return std::nullopt;
  ArrayNodeBudget budget;

  ModelSpec out = spec;
  // The types first: the model's names see their arrays.
  defined.clear();
  for (auto& d : out.defines) {
    if (NeedsScalarForm(d, library)) d = ScalarForm(d, library);
    defined[d.name] = &d;
  }
  ComponentTypes component_type;
  for (const auto& c : spec.components) component_type[c.name] = type_of(c.type);
  // The parts of composite types: their modifiers in the scope of the type that holds them.
  for (auto& d : out.defines) {
    for (auto& c : d.components) {
      if (const ComponentType* t = type_of(c.type)) c.modifiers = ScalarModifiers(c, *t, ScopeOf(d));
    }
  }

  // The model's own declarations and its components' modifiers.
  ArrayShapes table;
  ArrayScope scope = ModelScope(&table, &component_type, type_of);
  scope.library = &library;
  // Record names the model's expressions may use whole: its own record variables (`R`) and its
  // components' record potentials and variables (`body.frame_a.R`).
  std::map<std::string, std::string> records;
  const std::vector<VariableDecl> variables = ExpandRecordVariables(spec.variables, library, "", &records);
  for (const auto& [name, type] : component_type) {
    if (!type) continue;
    for (const auto& [local, record] : type->records) records.emplace(name + "." + local, record);
  }
  scope.records = &records;
  DeclarationScalariser s(scope, &table, "");
  out.parameters = s.Parameters(spec.parameters);
  out.variables = s.Variables(variables, {});
  out.equations = s.Equations(spec.equations);
  out.initial_equations = s.Equations(spec.initial_equations);
  out.whens = s.Whens(spec.whens);
  for (auto& c : out.components) {
    if (const ComponentType* t = component_type[c.name]) c.modifiers = ScalarModifiers(c, *t, scope);
  }
  out.connections = ScalarConnections(spec.connections, scope);
  out.outputs = ScalarOutputs(spec.outputs, scope);
  return out;
}

}  // namespace momenta
