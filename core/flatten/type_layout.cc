// Type layouts: a type's own names and templates, its parts' (composite_parts.cc) and inner
// connections (inner_connections.cc), and what is checked once per type (units, local balance).

#include "core/flatten/type_layout.h"

#include <algorithm>
#include <cmath>

#include "core/base/error.h"
#include "core/base/memory_budget.h"
#include "core/base/messages.h"
#include "core/flatten/composite_parts.h"
#include "core/flatten/inner_connections.h"
#include "core/flatten/type_scope.h"
#include "core/lang/arrays.h"
#include "core/lang/parser.h"
#include "core/lang/unit_check.h"

namespace momenta::flatten_internal {

namespace {

/// Composite types nest at most this deep (a model of a hundred levels is a mistake, and each
/// level copies the names below it).
constexpr size_t kMaxTypeDepth = 64;

/// The type's own variables: its connectors' first (a physical connector's potentials, then its
/// flows; a signal connector's one variable, which a declared variable of its name describes),
/// then its declared variables.
void LayoutOwnVariables(const Library& library, TypeLayout* layout) {
  const ComponentType* type = layout->type;
  std::unordered_map<std::string, const VariableDecl*> declared;
  for (const auto& v : type->variables) {
    if (declared.count(v.name)) throw ModelError(v.loc, type->name + "." + v.name + " is declared twice");
    declared[v.name] = &v;
  }
  for (const auto& c : type->connectors) {
    const ConnectorType* ct = library.FindConnector(c.type);
    if (!ct) {
      throw ModelError(c.loc, "unknown connector type '" + c.type + "' for " + type->name + "." +
                                  c.name + " (valid connector types: " +
                                  JoinNames(library.ConnectorNames()) + ")");
    }
    if (layout->connector_index.count(c.name)) throw ModelError(c.loc, type->name + "." + c.name + " is declared twice");
    layout->connector_index[c.name] = static_cast<uint32_t>(layout->connectors.size());
    layout->connectors.push_back({&c, ct, static_cast<uint32_t>(layout->vars.size())});
    if (ct->is_signal) {
      LocalVar lv;
      lv.name = c.name;
      lv.type = ct->signal_type;
      lv.is_input = ct->is_input;
      auto declaration = declared.find(c.name);
      if (declaration != declared.end()) {
        lv.decl = declaration->second;
        lv.unit = declaration->second->unit;
        declared.erase(declaration);
      }
      layout->vars.push_back(lv);
    } else {
      for (const auto& pv : ct->potentials) {
        LocalVar lv;
        lv.name = c.name + "." + pv.name;
        lv.unit = pv.unit;
        lv.counted = pv.counted;
        layout->vars.push_back(lv);
      }
      for (const auto& fv : ct->flows) {
        LocalVar lv;
        lv.name = c.name + "." + fv.name;
        lv.unit = fv.unit;
        lv.is_flow = true;
        layout->vars.push_back(lv);
      }
    }
  }
  for (const auto& v : type->variables) {
    if (!declared.count(v.name)) continue;  // attributes of a signal connector
    if (layout->connector_index.count(v.name)) {
      throw ModelError(v.loc, type->name + "." + v.name + " is both a connector and a variable");
    }
    LocalVar lv;
    lv.name = v.name;
    lv.decl = &v;
    lv.type = v.type;
    lv.unit = v.unit;
    lv.counted = v.counted;
    layout->vars.push_back(lv);
  }
}

/// The type's parameters and tables after its variables, and the index of every own name, each
/// declared once.
void LayoutOwnParameters(TypeLayout* layout) {
  const ComponentType* type = layout->type;
  for (const auto& p : type->parameters) layout->params.push_back({p.name, &p, -1, SourceLoc()});
  for (uint32_t k = 0; k < layout->vars.size(); ++k) layout->var_index[layout->vars[k].name] = k;
  for (uint32_t k = 0; k < layout->params.size(); ++k) {
    const auto& p = type->parameters[k];
    if (layout->param_index.count(p.name) || layout->var_index.count(p.name)) {
      throw ModelError(p.loc, type->name + "." + p.name + " is declared twice");
    }
    layout->param_index[p.name] = k;
  }
  for (const auto& table : type->tables) {
    if (layout->param_index.count(table.name) || layout->var_index.count(table.name) || layout->table_index.count(table.name)) {
      throw ModelError(table.loc, type->name + "." + table.name + " is declared twice");
    }
    layout->table_index[table.name] = static_cast<uint32_t>(layout->tables.size());
    layout->tables.push_back({&table, 0, 0, {}});
  }
}

/// A conditional connector's `condition:` names a Boolean parameter of its type.
void CheckCondition(const TypeLayout& layout, const ConnectorDecl& c) {
  if (c.condition.empty()) return;
  const ComponentType* type = layout.type;
  auto p = layout.param_index.find(c.condition);
  if (p == layout.param_index.end() || type->parameters[p->second].type != ValueType::kBoolean) {
    std::vector<std::string> booleans;
    for (const auto& q : type->parameters) {
      if (q.type == ValueType::kBoolean) booleans.push_back(q.name);
    }
    throw ModelError(c.loc, "the condition of connector " + type->name + "." + c.name + " must be a Boolean " +
                                "parameter of " + type->name + ", found '" + c.condition + "'" +
                                (p == layout.param_index.end() ? "" : " (a " + std::string(ValueTypeName(type->parameters[p->second].type)) + " parameter)") +
                                " (Boolean parameters: " + (booleans.empty() ? std::string("none") : JoinNames(booleans)) + ")");
  }
}

/// The templates of the type's own parameter defaults, table defaults, start values (of its
/// first `own_vars` variables, its own), equations and initial equations.
void LayoutOwnTemplates(TypeLayout* layout, size_t own_vars) {
  const ComponentType* type = layout->type;
  for (const auto& p : type->parameters) {
    layout->param_defaults.push_back(MakeTemplate(*layout, *p.value, p.value_text, p.loc, true));
  }
  for (TypeLayout::TableSlot& slot : layout->tables) {
    const ParameterDecl& decl = *slot.decl;
    for (const AstPtr& e : TableElements(decl.value, decl, decl.loc, type->name + "." + decl.name, &slot.rows, &slot.cols)) {
      slot.defaults.push_back(MakeTemplate(*layout, *e, decl.value_text, decl.loc, true));
    }
  }
  for (size_t k = 0; k < own_vars; ++k) {
    const LocalVar& v = layout->vars[k];
    layout->starts.push_back(v.decl && v.decl->start
                                 ? MakeTemplate(*layout, *v.decl->start, AstToString(*v.decl->start), v.decl->loc, true)
                                 : Template());
  }
  for (const auto& e : type->equations) {
    layout->equations.push_back(EquationTemplate(*layout, e));
    layout->equation_info.push_back({e.text, e.loc, -1, EquationOrigin::kComponent, e.guard != nullptr});
  }
  for (const auto& e : type->initial_equations) {
    layout->initial_equations.push_back(EquationTemplate(*layout, e));
    layout->initial_info.push_back({e.text, e.loc, -1, EquationOrigin::kInitial});
  }
}

/// The local index of variable `name`, which `what` of the type assigns.
uint32_t LocalVariable(const TypeLayout& layout, const std::string& name, const SourceLoc& loc,
                       const std::string& what) {
  auto found = layout.var_index.find(name);
  if (found == layout.var_index.end()) {
    throw ModelError(loc, "unknown variable '" + name + "' in " + what + " of " + layout.type->name +
                              " (valid variables: " + JoinNames([&] {
                                std::vector<std::string> v;
                                for (const auto& x : layout.vars) v.push_back(x.name);
                                return v;
                              }()) + ")");
  }
  return found->second;
}

/// The type's discrete variables (Boolean and Integer ones, its parts', and those its
/// when-clauses and impacts assign), and the templates of its when-clauses and impacts.
void LayoutEvents(TypeLayout* layout, const std::vector<PartPlan>& parts) {
  const ComponentType* type = layout->type;
  layout->discrete.assign(layout->vars.size(), false);
  for (size_t k = 0; k < layout->vars.size(); ++k) layout->discrete[k] = layout->vars[k].type != ValueType::kReal;
  for (const PartPlan& plan : parts) {  // a part's own discrete variables
    const uint32_t var_off = layout->subs[plan.sub].first_var;
    for (size_t k = 0; k < plan.layout->vars.size(); ++k) layout->discrete[var_off + k] = plan.layout->discrete[k];
  }
  for (const auto& w : type->whens) {
    TypeLayout::WhenTemplate wt;
    wt.condition = MakeTemplate(*layout, *w.condition, w.text, w.loc, false);
    for (const auto& statement : w.statements) {
      uint32_t target = LocalVariable(*layout, statement.target, statement.loc, "'" + statement.text + "'");
      Template value = MakeTemplate(*layout, *statement.value, statement.text, statement.loc, false);
      if (statement.is_reinit) {
        wt.reinits.emplace_back(target, std::move(value));
      } else {
        wt.assigns.emplace_back(target, std::move(value));
        layout->discrete[target] = true;
      }
    }
    layout->whens.push_back(std::move(wt));
    layout->when_info.push_back({w.text, w.loc, -1, EquationOrigin::kComponent});
  }
  for (const auto& im : type->impacts) {
    TypeLayout::ImpactTemplate tmpl;
    tmpl.gap = MakeTemplate(*layout, *im.gap, im.gap_text, im.loc, false);
    tmpl.velocity = MakeTemplate(*layout, *im.velocity, im.velocity_text, im.loc, false);
    tmpl.restitution = MakeTemplate(*layout, *im.restitution, im.restitution_text, im.loc, true);
    tmpl.v_small = MakeTemplate(*layout, *im.v_small, im.v_small_text, im.loc, true);
    tmpl.release = MakeTemplate(*layout, *im.release, im.release_text, im.loc, false);
    tmpl.force = LocalVariable(*layout, im.force, im.loc, "impact");
    tmpl.contact = LocalVariable(*layout, im.contact, im.loc, "impact");
    tmpl.decl = &im;
    if (layout->vars[tmpl.contact].type != ValueType::kBoolean) {
      throw ModelError(im.loc, "the impact contact of " + type->name + " must be a Boolean variable (type: Boolean)");
    }
    layout->discrete[tmpl.contact] = true;
    layout->impacts.push_back(std::move(tmpl));
  }
}

/// The dimension check of a type's own equations (core/lang/unit_check.h), once per type.
void CheckTypeUnits(const TypeLayout& layout) {
  CheckComponentUnits(*layout.type, [&layout](const std::string& name) -> std::string {
    if (auto v = layout.var_index.find(name); v != layout.var_index.end()) return layout.vars[v->second].unit;
    if (auto p = layout.param_index.find(name); p != layout.param_index.end()) {
      return layout.params[p->second].decl ? layout.params[p->second].decl->unit : std::string();
    }
    return std::string();
  });
}

/// Modelica's local balance: a component determines its own unknowns except the flow
/// variables of its connectors (the connections determine those) and its signal inputs; the
/// variables set by when-clauses and impacts need no equation.
void CheckLocalBalance(const TypeLayout& layout, const ComponentSpec* user) {
  const ComponentType* type = layout.type;
  // Only the type's own connectors' flows and own inputs are left to the outside; a part's
  // flows and inputs are the type's unknowns, which its connections determine.
  auto outside = [&](const LocalVar& v) { return v.sub < 0 && (v.is_flow || v.is_input); };
  size_t unknowns = 0;
  for (const LocalVar& v : layout.vars) unknowns += !outside(v) && v.counted;
  std::vector<bool> assigned(layout.vars.size(), false);
  for (const auto& w : layout.whens) {
    for (const auto& a : w.assigns) assigned[a.first] = true;
  }
  for (const auto& im : layout.impacts) assigned[im.contact] = true;
  for (size_t k = 0; k < layout.vars.size(); ++k) {
    if (assigned[k] && !outside(layout.vars[k])) --unknowns;
  }
  size_t equations = layout.equations.size() + layout.impacts.size() - layout.uncounted_equations;
  size_t flows = 0, inputs = 0, set = 0;
  for (size_t k = 0; k < layout.vars.size(); ++k) {
    flows += layout.vars[k].sub < 0 && layout.vars[k].is_flow;
    inputs += layout.vars[k].sub < 0 && layout.vars[k].is_input;
    set += assigned[k] && !outside(layout.vars[k]);
  }
  if (equations == unknowns) return;
  std::string who = user ? user->name + " (" + type->name + ")" : type->name;
  throw ModelError(user ? user->loc : type->loc,
                   who + " is not balanced: it has " + Counted(equations, "equation") + " for " +
                       Counted(unknowns, "unknown") + " (" + Counted(layout.vars.size(), "variable") +
                       ", less " + Counted(flows, "flow variable") + " of its connectors, " +
                       Counted(inputs, "signal input") + " and " + Counted(set, "variable") +
                       " set by when-clauses or impacts" +
                       (layout.subs.empty() ? "" : "; its parts' equations and its connections included") + "); " +
                       (equations > unknowns ? "remove the extra equation or add the variable it determines"
                                             : "add an equation for each variable nothing determines") +
                       " (type defined at " + type->loc.ToString() + ")");
}

}  // namespace

const TypeLayout& TypeLayoutBuilder::Layout(const ComponentType* type, const ComponentSpec* user) {
  auto it = layouts_.find(type);
  if (it != layouts_.end()) return *it->second;
  CheckNesting(type, user);
  laying_out_.push_back(type);
  // Popped however the layout ends: a layout that fails leaves no trace of its nesting.
  struct Nested {
    std::vector<const ComponentType*>& types;
    ~Nested() { types.pop_back(); }
  } nested{laying_out_};
  auto layout = std::make_unique<TypeLayout>();
  layout->type = type;
  // Its own names, its parts' after them (so that every expression of the type can use them:
  // mass.s, spring.c); then the templates, its own before its parts'.
  LayoutOwnVariables(context_.library, layout.get());
  const size_t own_vars = layout->vars.size();
  LayoutOwnParameters(layout.get());
  for (const ConnectorSlot& cs : layout->connectors) CheckCondition(*layout, *cs.decl);
  std::vector<PartPlan> parts = LayoutPartNames(layout.get(), this, &context_);
  LayoutOwnTemplates(layout.get(), own_vars);
  layout->uncounted_equations = type->uncounted_equations;
  LayoutEvents(layout.get(), parts);
  // A built-in type's dimensions are checked once for the whole library, by the test suite
  // (UnitCheckTest.EveryLibraryTypeAndModelPasses), not at every run that uses it: the check was
  // 2 % of a small model's whole run (bench/RESULTS.md, "Read this first").
  if (type->user_defined) CheckTypeUnits(*layout);
  LayoutPartTemplates(layout.get(), parts);
  InnerConnections(layout.get(), &parts);
  CheckLocalBalance(*layout, user);
  const TypeLayout& ref = *layout;
  layouts_[type] = std::move(layout);
  return ref;
}

void TypeLayoutBuilder::CheckNesting(const ComponentType* type, const ComponentSpec* user) const {
  for (size_t k = 0; k < laying_out_.size(); ++k) {
    if (laying_out_[k] != type) continue;
    std::string cycle;
    for (size_t j = k; j < laying_out_.size(); ++j) cycle += laying_out_[j]->name + " -> ";
    cycle += type->name;
    throw ModelError(user ? user->type_loc : type->loc,
                     "type " + type->name + " contains itself: " + cycle + "; a type cannot be a part of itself");
  }
  if (laying_out_.size() >= kMaxTypeDepth) {
    std::string chain;
    for (const ComponentType* t : laying_out_) chain += t->name + " -> ";
    throw ModelError(user ? user->type_loc : type->loc,
                     "types nested deeper than " + std::to_string(kMaxTypeDepth) + " levels: " + Excerpt(chain + type->name, 0) +
                         "; flatten the hierarchy");
  }
}

double EstimatedBytes(const TypeLayout& layout) {
  size_t nodes = 0;
  for (const auto* list : {&layout.equations, &layout.initial_equations, &layout.param_defaults, &layout.starts}) {
    for (const Template& t : *list) nodes += t.nodes.size();
  }
  // A composite's names carry its parts' paths: their text, in the layout and in every
  // instance's flat names, counts too.
  double names = 0;
  if (!layout.subs.empty()) {
    for (const auto& v : layout.vars) names += static_cast<double>(v.name.size());
    for (const auto& p : layout.params) names += static_cast<double>(p.name.size());
    for (const auto& sub : layout.subs) names += static_cast<double>(sub.path.size());
  }
  return EstimatedComponentBytes(layout.vars.size(), layout.params.size(), nodes) + 4 * names;
}

uint32_t CheckedCount(FlattenContext* context, const ComponentSpec& c, const TypeLayout& layout, double n,
                      std::string what, const std::string& text) {
  std::string value = NumberText(n);
  if (!std::isfinite(n) || n != std::floor(n)) throw ModelError(c.loc, what + " must be a whole number, found " + value);
  if (value != text) what += " ('" + text + "')";
  if (n < 1) throw ModelError(c.loc, what + " must be at least 1, found " + value);
  double bytes = context->planned_bytes + n * EstimatedBytes(layout);
  const MemoryBudget& budget = context->Budget();
  if (bytes > budget.bytes) {
    throw ModelError(c.loc, what + " is " + value + ": " + value + " " + layout.type->name + " components (" +
                                Counted(layout.vars.size(), "variable") + ", " +
                                Counted(layout.params.size(), "parameter") + " each) need about " +
                                ByteText(bytes) + " of memory to build, more than the budget of " +
                                ByteText(budget.bytes) + " (" + budget.source + ")");
  }
  NotePlannedBuild(bytes, budget);
  // Instances, variables and parameters are numbered with 32-bit indices.
  const FlatSystem& flat = context->flat;
  double ids = std::max({static_cast<double>(flat.instances.size()), static_cast<double>(flat.variables.size()),
                         static_cast<double>(flat.parameters.size())}) +
               n * static_cast<double>(std::max({layout.vars.size(), layout.params.size(), layout.subs.size() + 1}));
  if (ids >= 2147483648.0) {
    throw ModelError(c.loc, what + " is " + value + ": more components, variables or parameters than " +
                                "momenta numbers (2^31)");
  }
  return static_cast<uint32_t>(n);
}

std::vector<AstPtr> TableElements(const AstPtr& value, const ParameterDecl& decl, const SourceLoc& loc,
                                  const std::string& who, uint32_t* rows, uint32_t* cols) {
  const std::string example = decl.shape.size() == 1 ? "[0, 1, 2]" : "[[0, 1], [1, 2]]";
  const std::string expected = "the value of " + who + " (shape " + ShapeText(decl.shape) + ") must be a list of " +
                               (decl.shape.size() == 1 ? "numbers" : "rows of one length") + ", e.g. " + example;
  std::vector<AstPtr> elements;
  const bool list = value->kind == Ast::Kind::kArray;
  if (decl.shape.size() == 1) {
    if (!list) throw ModelError(loc, expected);
    for (const AstPtr& e : value->args) {
      if (e->kind == Ast::Kind::kArray) throw ModelError(loc, expected + "; found a nested list");
      elements.push_back(e);
    }
    *rows = static_cast<uint32_t>(elements.size());
    *cols = 1;
  } else {
    if (!list || value->args[0]->kind != Ast::Kind::kArray) throw ModelError(loc, expected);
    *rows = static_cast<uint32_t>(value->args.size());
    *cols = static_cast<uint32_t>(value->args[0]->args.size());
    for (size_t r = 0; r < value->args.size(); ++r) {
      const Ast& row = *value->args[r];
      if (row.kind != Ast::Kind::kArray || row.args.size() != *cols) {
        throw ModelError(loc, expected + "; row " + std::to_string(r + 1) + " has " +
                                  std::to_string(row.kind == Ast::Kind::kArray ? row.args.size() : 1) +
                                  " elements, row 1 has " + std::to_string(*cols));
      }
      for (const AstPtr& e : row.args) {
        if (e->kind == Ast::Kind::kArray) throw ModelError(loc, expected + "; found a list nested deeper");
        elements.push_back(e);
      }
    }
  }
  const Shape found = decl.shape.size() == 1 ? Shape{static_cast<int>(*rows)}
                                          : Shape{static_cast<int>(*rows), static_cast<int>(*cols)};
  for (size_t k = 0; k < decl.shape.size(); ++k) {
    if (decl.shape[k] != kOpenSize && decl.shape[k] != found[k]) {
      throw ModelError(loc, "the value of " + who + " has shape " + ShapeText(found) + ", but it is declared with shape " +
                                ShapeText(decl.shape));
    }
  }
  if (elements.size() > kMaxArrayElements) {
    throw ModelError(loc, "the value of " + who + " has " + std::to_string(elements.size()) + " elements, more than " +
                              std::to_string(kMaxArrayElements));
  }
  return elements;
}

bool IsFreeParameter(const Modifier& m) { return !m.value && m.fixed && !*m.fixed; }

std::pair<bool, uint32_t> ModifierTarget(const ComponentSpec& c, const TypeLayout& layout, const Modifier& m) {
  auto p = layout.param_index.find(m.key);
  if (p != layout.param_index.end()) {
    if (!m.value && !IsFreeParameter(m)) {
      throw ModelError(m.loc, c.name + "." + m.key + " is a parameter: give it a value, e.g. " + m.key + ": 2, " +
                                  "or {fixed: false, start: 2} to have the initial conditions determine it");
    }
    if (!m.value && (m.nominal || m.min || m.max || m.state_priority)) {
      throw ModelError(m.loc, c.name + "." + m.key + " is a parameter with fixed: false: it takes start and fixed only");
    }
    return {true, p->second};
  }
  auto v = layout.var_index.find(m.key);
  if (v != layout.var_index.end()) {
    if (m.value) {
      throw ModelError(m.loc, c.name + "." + m.key + " is a variable: give its start value as " + m.key +
                                  ": {start: " + m.value_text + ", fixed: true}");
    }
    return {false, v->second};
  }
  std::vector<std::string> names;
  for (const auto& p2 : layout.params) names.push_back(p2.name);
  for (const auto& v2 : layout.vars) names.push_back(v2.name);
  auto close = ClosestNames(m.key, names);
  throw ModelError(m.key_loc, "unknown key '" + m.key + "' for " + c.name + " (" + layout.type->name + ")" +
                                  (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                  " (valid parameters and variables: " + JoinNames(names) +
                                  "; reserved keys: type, count, condition, doc)");
}

AstPtr ModifierValue(const Modifier& m, const ParameterDecl& target, const std::string& component) {
  if (m.value_unit.empty()) return m.value;
  return ValueInUnit(m.value->number, m.value_unit, target.unit, component + "." + target.name, m.loc);
}

}  // namespace momenta::flatten_internal
