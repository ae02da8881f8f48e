// A composite type's parts inside its layout: their names first, so that every expression of the
// type can name them, their templates after, rebased, with the composite's modifiers in place.

#include "core/flatten/composite_parts.h"

#include <unordered_set>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/flatten/type_scope.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

namespace {

/// One composite type holds at most this many variables with all its parts (a type is laid out
/// whole; twenty levels of two parts each would be a million components in one type; use count:
/// in the model for big arrays).
constexpr double kMaxTypeVariables = 250000;

/// The count of an array part: a whole number written in the type (its structure is fixed;
/// the type's parameters cannot size it), checked against the memory budget.
uint32_t PartCount(FlattenContext* context, const ComponentSpec& c, const TypeLayout& layout,
                   const TypeLayout& part) {
  std::string text = AstToString(*c.count);
  std::string what = "count of " + c.name + " in " + layout.type->name;
  std::optional<double> n = ConstantValue(*c.count, nullptr);
  if (!n) {
    throw ModelError(c.loc, what + " must be a number: a type's structure is fixed, so its parameters cannot size its parts, found '" + text + "'");
  }
  return CheckedCount(context, c, part, *n, what, text);
}

void CheckLayoutBudget(FlattenContext* context, const ComponentSpec& c, const TypeLayout& layout, double bytes) {
  const MemoryBudget& budget = context->Budget();
  if (context->planned_bytes + bytes <= budget.bytes) return;
  throw ModelError(c.loc, layout.type->name + " with its parts up to " + c.name + " (" + c.type + ") needs about " +
                              ByteText(context->planned_bytes + bytes) + " of memory to build, more than the budget of " +
                              ByteText(budget.bytes) + " (" + budget.source + "); parts of parts multiply");
}

/// A template with its local variables and parameters moved by the given offsets.
Template Rebased(const Template& t, uint32_t var_offset, uint32_t param_offset) {
  Template r;
  r.nodes = t.nodes;
  r.root = t.root;
  for (TNode& n : r.nodes) {
    if (n.kind == TNode::kLocalVar || n.kind == TNode::kPre) n.local += var_offset;
    if (n.kind == TNode::kLocalParam) n.local += param_offset;
  }
  return r;
}

/// Element `k` of part `c` (whose type is laid out as `part`), appended to `layout`: its record
/// in the composite's subs, its parts' records after it, and its variables and parameters under
/// its path.
PartPlan AddPart(TypeLayout* layout, const ComponentSpec& c, const TypeLayout& part, uint32_t k) {
  PartPlan plan;
  plan.spec = &c;
  plan.layout = &part;
  plan.path = c.count ? c.name + "[" + std::to_string(k + 1) + "]" : c.name;
  plan.index = c.count ? k + 1.0 : 0.0;
  plan.first_slot = 0;
  const auto var_off = static_cast<uint32_t>(layout->vars.size());
  const auto param_off = static_cast<uint32_t>(layout->params.size());
  plan.sub = static_cast<int32_t>(layout->subs.size());
  layout->subs.push_back({plan.path, &part, c.loc, var_off, param_off, Template(), c.condition_text, c.condition_loc});
  plan.sub_base = static_cast<int32_t>(layout->subs.size());
  for (const SubInstance& ss : part.subs) {
    layout->subs.push_back({plan.path + "." + ss.path, ss.layout, ss.loc, var_off + ss.first_var, param_off + ss.first_param,
                            ss.condition.root >= 0 ? Rebased(ss.condition, var_off, param_off) : Template(),
                            ss.condition_text, ss.condition_loc});
  }
  auto remap = [&](int32_t sub) { return sub < 0 ? plan.sub : plan.sub_base + sub; };
  // The part's variables and parameters under their paths in the composite.
  auto adopt = [&](const auto& items, auto* out, auto* index) {
    for (const auto& item : items) {
      auto local = item;
      local.name = plan.path + "." + item.name;
      local.sub = remap(item.sub);
      if (layout->var_index.count(local.name) || layout->param_index.count(local.name)) {
        throw ModelError(c.loc, "the name " + local.name + " in " + layout->type->name + " is used twice");
      }
      (*index)[local.name] = static_cast<uint32_t>(out->size());
      out->push_back(std::move(local));
    }
  };
  adopt(part.vars, &layout->vars, &layout->var_index);
  adopt(part.params, &layout->params, &layout->param_index);
  for (const auto& [var, at] : part.connected) layout->connected.emplace(var_off + var, at);
  return plan;
}

/// Part `plan`'s own templates (its parameters' defaults, start values, equations, when-clauses
/// and impacts), rebased into `layout`.
void AdoptPartTemplates(TypeLayout* layout, const PartPlan& plan) {
  const TypeLayout& part = *plan.layout;
  const uint32_t var_off = layout->subs[plan.sub].first_var, param_off = layout->subs[plan.sub].first_param;
  auto rebase = [&](const Template& t) { return Rebased(t, var_off, param_off); };
  auto remap = [&](const PartInfo& info) {
    PartInfo r = info;
    r.sub = info.sub < 0 ? plan.sub : plan.sub_base + info.sub;
    // Connection texts name connectors relative to the part: insert the part's path.
    for (size_t at = r.text.find('\x01'); at != std::string::npos; at = r.text.find('\x01', at + 1)) {
      r.text.insert(at + 1, plan.path + ".");
    }
    return r;
  };
  for (const Template& t : part.param_defaults) layout->param_defaults.push_back(rebase(t));
  for (const Template& t : part.starts) layout->starts.push_back(t.root >= 0 ? rebase(t) : Template());
  layout->uncounted_equations += part.uncounted_equations;
  for (size_t k = 0; k < part.equations.size(); ++k) {
    layout->equations.push_back(rebase(part.equations[k]));
    layout->equation_info.push_back(remap(part.equation_info[k]));
  }
  for (size_t k = 0; k < part.initial_equations.size(); ++k) {
    layout->initial_equations.push_back(rebase(part.initial_equations[k]));
    layout->initial_info.push_back(remap(part.initial_info[k]));
  }
  for (size_t k = 0; k < part.whens.size(); ++k) {
    const auto& w = part.whens[k];
    TypeLayout::WhenTemplate wt;
    wt.condition = rebase(w.condition);
    for (const auto& [target, value] : w.assigns) wt.assigns.emplace_back(target + var_off, rebase(value));
    for (const auto& [target, value] : w.reinits) wt.reinits.emplace_back(target + var_off, rebase(value));
    layout->whens.push_back(std::move(wt));
    layout->when_info.push_back(remap(part.when_info[k]));
  }
  for (const auto& im : part.impacts) {
    TypeLayout::ImpactTemplate t;
    t.gap = rebase(im.gap);
    t.velocity = rebase(im.velocity);
    t.restitution = rebase(im.restitution);
    t.v_small = rebase(im.v_small);
    t.release = rebase(im.release);
    t.force = im.force + var_off;
    t.contact = im.contact + var_off;
    t.decl = im.decl;
    t.sub = im.sub < 0 ? plan.sub : plan.sub_base + im.sub;
    layout->impacts.push_back(std::move(t));
  }
}

/// The composite's modifiers of part `plan`, in place of the part's defaults: a parameter's value,
/// or a variable's start, fixed, nominal and stateSelect.
void ApplyModifiers(TypeLayout* layout, const PartPlan& plan) {
  const TypeLayout& part = *plan.layout;
  const uint32_t var_off = layout->subs[plan.sub].first_var, param_off = layout->subs[plan.sub].first_param;
  LoopIndex index{"i", plan.index};
  const LoopIndex* loop = plan.index > 0 ? &index : nullptr;
  for (const Modifier& m : plan.spec->modifiers) {
    auto [is_param, k] = ModifierTarget(*plan.spec, part, m);
    if (is_param) {
      if (!m.value) {
        throw ModelError(m.loc, plan.spec->name + "." + m.key + ": fixed: false on a parameter is taken in a model's " +
                                    "component entries, not inside a composite type");
      }
      const AstPtr value = ModifierValue(m, *part.params[k].decl, plan.spec->name);
      layout->param_defaults[param_off + k] = MakeTemplate(*layout, *value, m.value_text, m.loc, true, loop);
      layout->params[param_off + k].loc = m.loc;
    } else {
      if (m.start) layout->starts[var_off + k] = MakeTemplate(*layout, *m.start, AstToString(*m.start), m.loc, true, loop);
      if (m.fixed) layout->vars[var_off + k].fixed = *m.fixed;
      if (m.state_priority) layout->vars[var_off + k].state_priority = *m.state_priority;
      if (m.nominal) layout->vars[var_off + k].nominal = *m.nominal;
      layout->vars[var_off + k].loc = m.loc;
    }
  }
}

/// Whether `a` is a truth value: a Boolean parameter of `layout`, true or false, a comparison,
/// and/or/not, or an if-expression of truth values.
bool IsTruth(const TypeLayout& layout, const Ast& a) {
  switch (a.kind) {
    case Ast::Kind::kBool:
      return true;
    case Ast::Kind::kName: {
      auto p = layout.param_index.find(a.PathText());
      return p != layout.param_index.end() && layout.params[p->second].decl->type == ValueType::kBoolean;
    }
    case Ast::Kind::kUnary:
      return a.op == "not";
    case Ast::Kind::kBinary:
      return a.op == "and" || a.op == "or" || a.op == "<" || a.op == "<=" || a.op == ">" || a.op == ">=" ||
             a.op == "==" || a.op == "<>";
    case Ast::Kind::kIf:
      for (size_t k = 1; k < a.args.size(); k += 2) {
        if (!IsTruth(layout, *a.args[k])) return false;
      }
      return IsTruth(layout, *a.args.back());
    default:
      return false;
  }
}

/// The first name `a` reads that is a variable of `layout` (a condition may read parameters
/// only), or null.
const Ast* VariableNamed(const TypeLayout& layout, const Ast& a) {
  if (a.kind == Ast::Kind::kName && layout.var_index.count(a.PathText())) return &a;
  for (const AstPtr& arg : a.args) {
    if (const Ast* v = VariableNamed(layout, *arg)) return v;
  }
  return nullptr;
}

/// The template of part `c`'s condition in `layout`: a truth value of parameters, fixed when the
/// model is built (core/passes/conditional_connectors.h).
Template PartCondition(const TypeLayout& layout, const ComponentSpec& c) {
  const std::string what = "the condition of part " + c.name + " in " + layout.type->name;
  if (const Ast* v = VariableNamed(layout, *c.condition)) {
    throw ModelError(c.condition_loc, what + " reads the variable " + v->PathText() + ", in '" + c.condition_text +
                                          "'; a part's condition may read parameters only (it is decided when the " +
                                          "model is built)");
  }
  // Unknown names are reported by the template, with the valid ones.
  Template t = MakeTemplate(layout, *c.condition, c.condition_text, c.condition_loc, true);
  if (!IsTruth(layout, *c.condition)) {
    std::string found = "'" + c.condition_text + "'";
    if (c.condition->kind == Ast::Kind::kName) {
      auto p = layout.param_index.find(c.condition->PathText());
      if (p != layout.param_index.end()) {
        found += " (a " + std::string(ValueTypeName(layout.params[p->second].decl->type)) + " parameter)";
      }
    }
    throw ModelError(c.condition_loc, what + " must be a Boolean: a Boolean parameter, a comparison or and/or/not " +
                                          "of them (e.g. use_v, m > 0), found " + found);
  }
  return t;
}

}  // namespace

std::vector<PartPlan> LayoutPartNames(TypeLayout* layout, TypeLayoutBuilder* builder, FlattenContext* context) {
  const ComponentType* type = layout->type;
  std::vector<PartPlan> plans;
  std::unordered_set<std::string> names;
  double layout_bytes = 0;
  for (const auto& c : type->components) {
    if (!names.insert(c.name).second || layout->var_index.count(c.name) || layout->param_index.count(c.name) ||
        layout->connector_index.count(c.name)) {
      throw ModelError(c.loc, "the name " + c.name + " is used twice in " + type->name);
    }
    const ComponentType* part_type = context->FindType(c.type);
    if (!part_type) context->UnknownType(c);
    const TypeLayout& part = builder->Layout(part_type, &c);
    if (!part.tables.empty()) {
      throw ModelError(c.loc, c.name + " (" + c.type + ") in " + type->name + " has the table " +
                                  part.tables[0].decl->name + "; a part of a composite type cannot have a table yet " +
                                  "(use the component in the model)");
    }
    uint32_t n = c.count ? PartCount(context, c, *layout, part) : 1;
    // The type's parts so far, and these, must fit in the memory budget before they are laid out
    // (parts of parts multiply: twenty levels of two parts each are a million components).
    layout_bytes += n * EstimatedBytes(part);
    CheckLayoutBudget(context, c, *layout, layout_bytes);
    if (static_cast<double>(layout->vars.size()) + n * static_cast<double>(part.vars.size()) > kMaxTypeVariables) {
      throw ModelError(c.loc, type->name + " with its parts up to " + c.name + " (" + c.type + ") has more than " +
                                  std::to_string(static_cast<long>(kMaxTypeVariables)) + " variables; parts of parts multiply: " +
                                  "make large arrays with count: in the model");
    }
    for (uint32_t k = 0; k < n; ++k) plans.push_back(AddPart(layout, c, part, k));
  }
  return plans;
}

void LayoutPartTemplates(TypeLayout* layout, const std::vector<PartPlan>& plans) {
  for (const PartPlan& plan : plans) {
    AdoptPartTemplates(layout, plan);
    ApplyModifiers(layout, plan);
    if (plan.spec->condition) layout->subs[plan.sub].condition = PartCondition(*layout, *plan.spec);
  }
}

}  // namespace momenta::flatten_internal
