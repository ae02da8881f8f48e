// The model's components as instances: their records reserved first (the sizes are known from
// the layouts), then each instance made one kind of record at a time, in the order of the flat
// system's arrays and of the expression pool's nodes.

#include "core/flatten/instances.h"

#include <algorithm>
#include <unordered_set>

#include "core/base/error.h"
#include "core/flatten/deferred_aliases.h"
#include "core/flatten/type_scope.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

namespace {

/// About how many connection equations an instance of a layout adds: a connection set of s
/// physical connectors makes s times their potentials' count of equations (s - 1 equal potentials
/// and one flow sum each, as many flows as potentials); a signal set fewer than its connectors.
size_t Joins(const TypeLayout& layout, const DecidedConditions* decided = nullptr) {
  size_t joins = 0;
  for (size_t k = 0; k < layout.connectors.size(); ++k) {
    if (decided && decided->connector[k] == 0) continue;  // absent: no connection, no unconnected flow
    const ConnectorSlot& c = layout.connectors[k];
    joins += c.type->is_signal ? 1 : c.type->potentials.size();
  }
  return joins;
}

/// How many of a layout's equations (or initial equations) each instance makes.
size_t Made(const std::vector<Template>& templates, const std::vector<DecidedConditions::Use>* use) {
  if (!use) return templates.size();
  return static_cast<size_t>(std::count_if(use->begin(), use->end(),
                                            [](DecidedConditions::Use u) { return u != DecidedConditions::kLeftOut; }));
}

/// About how many new nodes of the expression pool an instance of a layout makes: its
/// templates' operations and distinct leaves (constants and time are shared by all instances).
size_t InstanceNodes(const TypeLayout& layout) {
  std::unordered_set<uint64_t> leaves;
  size_t ops = 0;
  for (const auto* list : {&layout.equations, &layout.initial_equations, &layout.param_defaults, &layout.starts}) {
    for (const Template& t : *list) {
      for (const TNode& n : t.nodes) {
        if (n.kind == TNode::kLocalVar || n.kind == TNode::kLocalParam || n.kind == TNode::kPre) {
          leaves.insert(uint64_t{n.kind} << 32 | n.local);
        } else if (n.kind != TNode::kConst && n.kind != TNode::kTime && n.kind != TNode::kInitial) {
          ++ops;
        }
      }
    }
  }
  return ops + leaves.size();
}

/// About how many nodes an element of an array's modifiers makes: each element's values are
/// expressions of its own (`R: "1/i"`: its index's number and the quotient).
size_t ModifierNodes(const ComponentSpec& c) {
  size_t nodes = 0;
  std::vector<const Ast*> todo;
  for (const Modifier& m : c.modifiers) {
    for (const AstPtr& a : {m.value, m.start}) {
      if (a) todo.push_back(a.get());
    }
  }
  while (!todo.empty()) {
    const Ast* a = todo.back();
    todo.pop_back();
    ++nodes;
    for (const AstPtr& arg : a->args) todo.push_back(arg.get());
  }
  return nodes;
}

/// `a` with the names that start with component `own`'s name (`bodyCylinder.diameter` in
/// bodyCylinder's own entry: Modelica reads a modifier in the enclosing scope, where that name is
/// the component's own parameter) written as its type's local names (`diameter`). Null when it
/// names none of them; `*other` is set when it names anything else (then the model's scope reads
/// the whole expression).
AstPtr OwnNamesAsLocal(const AstPtr& a, const std::string& own, bool* other) {
  if (a->kind == Ast::Kind::kName) {
    if (a->path.size() < 2 || a->path[0].name != own || a->path[0].index) {
      *other = true;
      return nullptr;
    }
    auto local = std::make_shared<Ast>(*a);
    local->path.erase(local->path.begin());
    return local;
  }
  std::shared_ptr<Ast> copy;
  for (size_t k = 0; k < a->args.size(); ++k) {
    AstPtr changed = OwnNamesAsLocal(a->args[k], own, other);
    if (!changed) continue;
    if (!copy) copy = std::make_shared<Ast>(*a);
    copy->args[k] = std::move(changed);
  }
  return copy;
}

}  // namespace

void InstanceBuilder::Components() {
  ReserveComponents();
  const ModelSpec& spec = context_.spec;
  FlatSystem& flat = context_.flat;
  for (size_t s = 0; s < spec.components.size(); ++s) {
    const ComponentSpec& c = spec.components[s];
    if (context_.components.Find(c.name) || scope_.Declares(c.name)) {
      throw ModelError(c.loc, "the name " + c.name + " is used twice");
    }
    if (c.condition) {
      throw ModelError(c.condition_loc, "component " + c.name + " of the model has a condition; condition: is taken " +
                                            "by the parts of a component type (the model's parameters are set for " +
                                            "each run), not by a model's components");
    }
    const ComponentType* type = context_.FindType(c.type);
    if (!type) context_.UnknownType(c);
    const TypeLayout& layout = layouts_.Layout(type, &c);
    ComponentArray arr{s, static_cast<uint32_t>(flat.instances.size()), 1, c.count != nullptr,
                       static_cast<uint32_t>(1 + layout.subs.size())};
    if (c.count) arr.count = ArrayCount(c, layout);
    context_.planned_bytes += arr.count * EstimatedBytes(layout);  // every element, as CheckedCount planned
    if (arr.is_array) ReserveElements(layout, arr.count, ModifierNodes(c));
    const Modifiers modifiers = SortModifiers(c, layout);
    const int32_t block = arr.is_array ? BeginBlock(c, layout) : -1;
    const int32_t names = NamesOf(layout);
    const DecidedConditions* decided = Decided(layout, modifiers);
    for (uint32_t k = 0; k < arr.count; ++k) {
      LoopIndex index{"i", static_cast<double>(k + 1)};
      AddInstance(c, layout, block, names, modifiers, arr.is_array ? &index : nullptr, decided);
    }
    if (block >= 0) EndBlock(&flat.blocks[block]);
    context_.components.Add(c.name, arr);
  }
}

InstanceBuilder::Modifiers InstanceBuilder::SortModifiers(const ComponentSpec& c, const TypeLayout& layout) const {
  Modifiers sorted;
  sorted.params.assign(layout.params.size(), nullptr);
  sorted.vars.assign(layout.vars.size(), nullptr);
  sorted.tables.assign(layout.tables.size(), nullptr);
  for (const auto& m : c.modifiers) {
    if (auto t = layout.table_index.find(m.key); t != layout.table_index.end()) {
      if (!m.value) throw ModelError(m.loc, c.name + "." + m.key + " is a table: give its value, e.g. " + m.key + ": [[0, 1], [1, 2]]");
      sorted.tables[t->second] = &m;
      continue;
    }
    auto [is_param, k] = ModifierTarget(c, layout, m);
    (is_param ? sorted.params : sorted.vars)[k] = &m;
  }
  return sorted;
}

/// Room for the components written one by one (a count: array reserves its own, from its
/// count): the flat system's records, the expression pool's table and the names of the
/// components take their memory once, at their size, instead of doubling as 100 000
/// components fill them (which copies the records and leaves up to half of them unused). A
/// type that cannot be laid out is left to the loop in Components, which reports it in the
/// model's order; nothing is reserved then. Composite types are not counted.
void InstanceBuilder::ReserveComponents() {
  const ModelSpec& spec = context_.spec;
  FlatSystem& flat = context_.flat;
  context_.components.Reserve(spec.components.size());
  struct Use {
    const ComponentSpec* first;
    size_t count;
  };
  std::unordered_map<std::string_view, size_t> use_of;  // type name -> uses[]
  std::vector<Use> uses;
  for (const ComponentSpec& c : spec.components) {
    if (c.count) continue;
    auto [at, added] = use_of.emplace(c.type, uses.size());
    if (added) uses.push_back({&c, 0});
    ++uses[at->second].count;
  }
  size_t instances = 0, slots = 0, vars = 0, params = 0, equations = 0, initials = 0, nodes = 0;
  for (const Use& u : uses) {
    const ComponentType* type = context_.FindType(u.first->type);
    // A composite's layout is checked against the memory budget with the components before
    // it: it is laid out in the loop, in its place.
    if (!type || !type->components.empty()) continue;
    const TypeLayout* layout = nullptr;
    try {
      layout = &layouts_.Layout(type, u.first);
    } catch (const ModelError&) {
      return;
    }
    // As an entry without modifiers decides its conditional connectors (nearly every entry).
    Modifiers none;
    none.params.assign(layout->params.size(), nullptr);
    const DecidedConditions* d = Decided(*layout, none);
    instances += u.count * (1 + layout->subs.size());
    slots += u.count * layout->connectors.size();
    vars += u.count * layout->vars.size();
    params += u.count * layout->params.size();
    equations += u.count * (Made(layout->equations, d ? &d->equation_use : nullptr) + layout->impacts.size() +
                            Joins(*layout, d));
    initials += u.count * Made(layout->initial_equations, d ? &d->initial_use : nullptr);
    nodes += u.count * (InstanceNodes(*layout) + Joins(*layout));
  }
  equations += spec.equations.size();
  initials += spec.initial_equations.size();
  auto room = [](auto* records, size_t more) { records->reserve(records->size() + more); };
  room(&flat.instances, instances);
  room(&context_.instance_data, instances);
  room(&context_.slot_instance, slots);
  room(&flat.variables, vars);
  room(&flat.parameters, params);
  room(&flat.equations, equations);
  room(&flat.initial_equations, initials);
  // The build reserves twice the flattened pool for the passes after flattening (core/build.cc):
  // the table is made at that size at once, not grown through the sizes on the way.
  context_.pool().Reserve(2 * (context_.pool().size() + nodes));
}

/// A large array then takes its memory once, at its size, instead of doubling (which copies the
/// records at every step and leaves up to half of the last block unused). It still grows
/// geometrically over many small arrays.
void InstanceBuilder::ReserveElements(const TypeLayout& layout, uint32_t count, size_t modifier_nodes) {
  auto room = [count](auto* records, size_t per_element) {
    const size_t needed = records->size() + size_t{count} * per_element;
    if (needed > records->capacity()) records->reserve(std::max(needed, records->capacity() + records->capacity() / 2));
  };
  FlatSystem& flat = context_.flat;
  room(&flat.instances, 1 + layout.subs.size());
  room(&context_.instance_data, 1 + layout.subs.size());
  room(&context_.slot_instance, layout.connectors.size());
  room(&flat.variables, layout.vars.size());
  room(&flat.parameters, layout.params.size());  // tables' elements come on top
  room(&flat.equations, layout.equations.size() + layout.impacts.size());
  room(&flat.initial_equations, layout.initial_equations.size());
  // The pool's table at the size the build reserves after flattening (twice the flattened
  // pool, core/build.cc), so that it is made once per array instead of grown through the sizes
  // on the way (the RC ladder: a rehash every half again).
  context_.pool().Reserve(2 * (context_.pool().size() +
                                size_t{count} * (InstanceNodes(layout) + Joins(layout) + modifier_nodes)));
}

uint32_t InstanceBuilder::ArrayCount(const ComponentSpec& c, const TypeLayout& layout) {
  std::string text = AstToString(*c.count);
  std::string what = "count of " + c.name;
  double n = scope_.StructuralWhole(*c.count, text, c.loc, nullptr, what);
  return CheckedCount(&context_, c, layout, n, what, text);
}

int32_t InstanceBuilder::BeginBlock(const ComponentSpec& c, const TypeLayout& layout) {
  FlatSystem& flat = context_.flat;
  FlatBlock b;
  b.name = c.name;
  b.type = layout.type;
  b.loc = c.loc;
  b.first_instance = InstanceId(flat.instances.size());
  b.first_var = VarId(flat.variables.size());
  b.first_param = ParamId(flat.parameters.size());
  b.first_equation = static_cast<uint32_t>(flat.equations.size());
  b.first_initial = static_cast<uint32_t>(flat.initial_equations.size());
  b.stride = static_cast<uint32_t>(1 + layout.subs.size());
  for (const SubInstance& sub : layout.subs) b.part_paths.push_back(sub.path);
  flat.blocks.push_back(std::move(b));
  return static_cast<int32_t>(flat.blocks.size() - 1);
}

void InstanceBuilder::EndBlock(FlatBlock* b) {
  const FlatSystem& flat = context_.flat;
  b->count = (static_cast<uint32_t>(flat.instances.size()) - b->first_instance.value()) / b->stride;
  b->vars_per = (static_cast<uint32_t>(flat.variables.size()) - b->first_var.value()) / b->count;
  b->params_per = (static_cast<uint32_t>(flat.parameters.size()) - b->first_param.value()) / b->count;
  b->equations_per = (static_cast<uint32_t>(flat.equations.size()) - b->first_equation) / b->count;
  b->initials_per = (static_cast<uint32_t>(flat.initial_equations.size()) - b->first_initial) / b->count;
}

uint32_t InstanceBuilder::HeldText(std::string text) {
  FlatSystem& flat = context_.flat;
  flat.texts.push_back(std::move(text));
  return static_cast<uint32_t>(flat.texts.size() - 1);
}

int32_t InstanceBuilder::NamesOf(const TypeLayout& layout) {
  FlatSystem& flat = context_.flat;
  auto [at, added] = names_of_.emplace(&layout, static_cast<int32_t>(flat.type_names.size()));
  if (!added) return at->second;
  auto n = std::make_shared<TypeNames>();
  for (const LocalVar& v : layout.vars) {
    n->vars.push_back(v.name);
    n->var_units.push_back(v.unit);
  }
  for (const LocalParam& p : layout.params) {
    n->params.push_back(p.name);
    n->param_units.push_back(p.decl->unit);
    n->param_docs.push_back(p.decl->doc);
  }
  for (const auto* infos : {&layout.equation_info, &layout.initial_info}) {  // the equations, then the initial ones
    for (const PartInfo& info : *infos) n->equations.push_back(info.text);
  }
  for (const PartInfo& info : layout.when_info) n->whens.push_back(info.text);
  flat.type_names.push_back(std::move(n));
  return at->second;
}

/// A local variable of a conditional connector (the layout's or a part's) or of a conditional
/// part makes its equations made: they may go when it is absent (ResolveConditionalConnectors).
const std::vector<uint32_t>& InstanceBuilder::SureAliasShapes(const TypeLayout& layout) {
  auto [at, added] = sure_shapes_.emplace(&layout, std::vector<uint32_t>());
  if (!added) return at->second;
  std::vector<bool> conditional(layout.vars.size(), false);
  auto mark = [&](const TypeLayout& connectors_of, uint32_t var_off) {
    for (const ConnectorSlot& cs : connectors_of.connectors) {
      if (cs.decl->condition.empty()) continue;
      const size_t count = cs.type->is_signal ? 1 : cs.type->potentials.size() + cs.type->flows.size();
      for (size_t j = 0; j < count; ++j) conditional[var_off + cs.first_local_var + j] = true;
    }
  };
  mark(layout, 0);
  for (const SubInstance& sub : layout.subs) mark(*sub.layout, sub.first_var);
  // A conditional part's variables: all its equations and connections may go.
  for (const SubInstance& sub : layout.subs) {
    if (sub.condition.root < 0) continue;
    std::fill_n(conditional.begin() + sub.first_var, sub.layout->vars.size(), true);
  }
  std::vector<uint32_t>& shapes = at->second;
  for (const Template& t : layout.equations) {
    const SureAlias form = ReadSureAlias(t, layout.discrete, conditional);
    shapes.push_back(form.sure ? context_.deferred->AddShape(t, form) : kNotSure);
  }
  return shapes;
}

/// The nodes below the root, in their order: one may be shared with another equation, and the
/// pool orders the operands of a commutative operation by node id, so every node that is made
/// keeps the place it has when all equations are made (and the build makes the same programs).
/// The root is the template's last node; a root that is a leaf (f = 0) is made too, as
/// ModelConnections makes an unconnected flow's.
void InstanceBuilder::MakeBelowRoot(const Template& t, VarId first_var, ParamId first_param) {
  MOMENTA_CHECK_MSG(static_cast<size_t>(t.root) + 1 == t.nodes.size(), "a template's root is its last node");
  const bool leaf_root = t.nodes.back().kind != TNode::kOp;
  CopyTemplate(&context_.pool(), t, first_var, first_param, &scratch_, NoTable, /*cached_constants=*/true,
               leaf_root ? t.nodes.size() : t.nodes.size() - 1);
}

const DecidedConditions* InstanceBuilder::Decided(const TypeLayout& layout, const Modifiers& modifiers) {
  if (std::all_of(layout.connectors.begin(), layout.connectors.end(),
                  [](const ConnectorSlot& cs) { return cs.decl->condition.empty(); })) {
    return nullptr;
  }
  std::vector<int8_t> decidable = DecidableConnectors(layout, modifiers.params, context_.overrides);
  if (std::all_of(decidable.begin(), decidable.end(), [](int8_t d) { return d < 0; })) return nullptr;
  auto& made = decided_[&layout];
  for (const auto& [key, d] : made) {
    if (key == decidable) return d->Any() ? d.get() : nullptr;
  }
  auto d = std::make_unique<DecidedConditions>(DecideConditions(layout, decidable));
  made.emplace_back(std::move(decidable), std::move(d));
  return made.back().second->Any() ? made.back().second.get() : nullptr;
}

void InstanceBuilder::AddInstance(const ComponentSpec& c, const TypeLayout& layout, int32_t block, int32_t names,
                                  const Modifiers& modifiers, const LoopIndex* index,
                                  const DecidedConditions* decided) {
  const NewInstance instance = AddRecords(c, layout, block, names, index, decided);
  AddConditionalConnectors(instance);
  AddParameters(instance, modifiers.params);
  tables_.Add(c, layout, instance.data, instance.id, modifiers.tables, index);
  AddVariables(instance, modifiers.vars);
  // Equations that alias elimination surely removes are not made (DeferredAliases).
  const std::vector<uint32_t>* sure_shapes = context_.deferred ? &SureAliasShapes(layout) : nullptr;
  AddEquations(instance, layout.equations, layout.equation_info, 0, sure_shapes,
               decided ? &decided->equation_use : nullptr, decided ? &decided->equations : nullptr,
               &context_.flat.equations);
  AddWhens(instance);
  AddImpacts(instance);
  AddEquations(instance, layout.initial_equations, layout.initial_info, static_cast<uint32_t>(layout.equations.size()),
               nullptr, decided ? &decided->initial_use : nullptr, decided ? &decided->initial_equations : nullptr,
               &context_.flat.initial_equations);
  if (decided) context_.flat.conditions_decided += decided->conditions;
}

InstanceBuilder::NewInstance InstanceBuilder::AddRecords(const ComponentSpec& c, const TypeLayout& layout,
                                                         int32_t block, int32_t names, const LoopIndex* index,
                                                         const DecidedConditions* decided) {
  FlatSystem& flat = context_.flat;
  InstanceId inst(flat.instances.size());
  // An element of a block is named by the block; a component alone holds its path.
  auto instance = [&](const ComponentType* t, const SourceLoc& loc, int32_t type_names, const std::string* part) {
    FlatInstance fi;
    fi.type = t;
    fi.loc = loc;
    fi.names = type_names;
    fi.block = block;
    if (block < 0) fi.path_text = HeldText(part ? c.name + "." + *part : c.name);
    flat.instances.push_back(fi);
  };
  instance(layout.type, c.loc, names, nullptr);
  InstanceData data{&layout, VarId(flat.variables.size()), ParamId(flat.parameters.size()),
                    static_cast<uint32_t>(context_.slot_instance.size())};
  context_.instance_data.push_back(data);
  for (size_t k = 0; k < layout.connectors.size(); ++k) context_.slot_instance.push_back(inst.value());
  // A composite's parts, at every depth, are instances of their own (for messages).
  for (const SubInstance& sub : layout.subs) {
    instance(sub.layout->type, sub.loc, -1, &sub.path);
    context_.instance_data.push_back({sub.layout, VarId(data.first_var.value() + sub.first_var),
                                      ParamId(data.first_param.value() + sub.first_param), kNoSlot});
  }
  return {c, layout, inst, data, index, decided};
}

/// The instance's own conditional connectors (its connections come later), its parts', and its
/// conditional parts.
void InstanceBuilder::AddConditionalConnectors(const NewInstance& instance) {
  const InstanceData& data = instance.data;
  auto conditional = [&](const TypeLayout& connectors_of, int32_t sub, uint32_t var_off, uint32_t param_off) {
    for (uint32_t k = 0; k < connectors_of.connectors.size(); ++k) {
      const ConnectorSlot& cs = connectors_of.connectors[k];
      if (cs.decl->condition.empty()) continue;
      FlatConditionalConnector cc;
      cc.instance = instance.InstanceOf(sub);
      cc.name = cs.decl->name;
      cc.condition = ParamId(data.first_param.value() + param_off + connectors_of.param_index.at(cs.decl->condition));
      cc.first_var = VarId(data.first_var.value() + var_off + cs.first_local_var);
      // A signal connector's one variable counts as a potential: absent, it is set to zero.
      cc.num_potentials = cs.type->is_signal ? 1 : static_cast<uint32_t>(cs.type->potentials.size());
      cc.num_flows = cs.type->is_signal ? 0 : static_cast<uint32_t>(cs.type->flows.size());
      if (sub >= 0) {
        auto at = instance.layout.connected.find(var_off + cs.first_local_var);
        if (at != instance.layout.connected.end()) cc.connected_at = at->second;
      } else {
        context_.conditional_slot[data.first_slot + k] = context_.flat.conditional_connectors.size();
        if (instance.decided) cc.decided = instance.decided->connector[k];
      }
      context_.flat.conditional_connectors.push_back(std::move(cc));
    }
  };
  const TypeLayout& layout = instance.layout;
  conditional(layout, -1, 0, 0);
  for (size_t k = 0; k < layout.subs.size(); ++k) {
    conditional(*layout.subs[k].layout, static_cast<int32_t>(k), layout.subs[k].first_var, layout.subs[k].first_param);
  }
  // Conditional parts, at every depth (a part's own parts follow it among the subs).
  for (size_t k = 0; k < layout.subs.size(); ++k) {
    const SubInstance& sub = layout.subs[k];
    if (sub.condition.root < 0) continue;
    FlatConditionalPart cp;
    cp.instance = instance.InstanceOf(static_cast<int32_t>(k));
    cp.num_instances = static_cast<uint32_t>(1 + sub.layout->subs.size());
    // The composite it is a part of: the nearest sub whose path its own path extends.
    cp.owner = instance.id;
    for (size_t j = k; j-- > 0;) {
      const std::string& p = layout.subs[j].path;
      if (sub.path.size() > p.size() && sub.path.compare(0, p.size(), p) == 0 && sub.path[p.size()] == '.') {
        cp.owner = instance.InstanceOf(static_cast<int32_t>(j));
        break;
      }
    }
    cp.condition = Instantiate(instance, sub.condition, sub.condition_text, sub.condition_loc);
    cp.condition_text = sub.condition_text;
    cp.first_var = VarId(data.first_var.value() + sub.first_var);
    cp.num_vars = static_cast<uint32_t>(sub.layout->vars.size());
    cp.loc = sub.condition_loc;
    context_.flat.conditional_parts.push_back(std::move(cp));
  }
}

void InstanceBuilder::AddParameters(const NewInstance& instance, const std::vector<const Modifier*>& modifiers) {
  const TypeLayout& layout = instance.layout;
  FlatSystem& flat = context_.flat;
  for (size_t k = 0; k < layout.params.size(); ++k) {
    const LocalParam& lp = layout.params[k];
    const ParameterDecl& decl = *lp.decl;
    FlatParameter fp;
    const TextRef local{TextRef::kType, instance.id.value(), static_cast<uint32_t>(k)};
    fp.name = local;
    fp.type = decl.type;
    fp.evaluate = decl.evaluate;
    if (decl.min) fp.min = *decl.min;
    if (decl.max) fp.max = *decl.max;
    if (!decl.unit.empty()) fp.unit = local;
    if (!decl.doc.empty()) fp.doc = local;
    fp.instance = instance.InstanceOf(lp.sub);
    if (const Modifier* m = modifiers[k]; m != nullptr && !m->value) {  // fixed: false (free_parameters.h)
      fp.binding = m->start ? scope_.Expr(*m->start, AstToString(*m->start), m->loc, instance.index, false)
                            : Instantiate(instance, layout.param_defaults[k], decl.value_text, decl.loc);
      fp.loc = m->loc;
      context_.free_parameters.push_back(ParamId(static_cast<uint32_t>(flat.parameters.size())));
    } else if (m != nullptr) {
      const AstPtr value = m->value_unit.empty() ? m->value : ModifierValue(*m, decl, flat.InstancePath(instance.id));
      bool other = false;
      const AstPtr local = instance.index ? nullptr : OwnNamesAsLocal(value, instance.component.name, &other);
      if (local && !other) {  // its own parameters only: read in its type's scope
        fp.binding = Instantiate(instance, MakeTemplate(layout, *local, m->value_text, m->loc, true), m->value_text, m->loc);
      } else {
        fp.binding = scope_.Expr(*value, m->value_text, m->loc, instance.index, false);
      }
      fp.loc = m->loc;
    } else {
      fp.binding = Instantiate(instance, layout.param_defaults[k], decl.value_text, decl.loc);
      fp.loc = lp.loc.known() ? lp.loc : instance.LocOf(lp.sub);
    }
    flat.parameters.push_back(std::move(fp));
  }
}

void InstanceBuilder::AddVariables(const NewInstance& instance, const std::vector<const Modifier*>& modifiers) {
  const TypeLayout& layout = instance.layout;
  for (size_t k = 0; k < layout.vars.size(); ++k) {
    const LocalVar& lv = layout.vars[k];
    FlatVariable fv;
    fv.name = {TextRef::kType, instance.id.value(), static_cast<uint32_t>(k)};
    fv.type = lv.type;
    fv.is_flow = lv.is_flow;
    fv.is_input = lv.is_input;
    fv.instance = instance.InstanceOf(lv.sub);
    fv.loc = lv.loc.known() ? lv.loc : instance.LocOf(lv.sub);
    if (lv.decl) {
      fv.fixed = lv.decl->fixed;
      fv.nominal = lv.decl->nominal;
      fv.state_priority = lv.decl->state_priority;
    }
    if (lv.fixed) fv.fixed = *lv.fixed;
    if (lv.state_priority) fv.state_priority = *lv.state_priority;
    if (lv.nominal) fv.nominal = *lv.nominal;
    if (layout.starts[k].root >= 0) fv.start = Instantiate(instance, layout.starts[k], "", fv.loc);
    fv.discrete = layout.discrete[k];
    if (const Modifier* m = modifiers[k]) {
      if (m->start) fv.start = scope_.StartExpr(*m->start, m->loc, instance.index);
      if (m->fixed) fv.fixed = *m->fixed;
      if (m->state_priority) fv.state_priority = *m->state_priority;
      if (m->nominal) fv.nominal = *m->nominal;
      fv.loc = m->loc;
    }
    context_.flat.variables.push_back(std::move(fv));
  }
}

void InstanceBuilder::AddEquations(const NewInstance& instance, const std::vector<Template>& templates,
                                   const std::vector<PartInfo>& info, uint32_t first_text,
                                   const std::vector<uint32_t>* shapes,
                                   const std::vector<DecidedConditions::Use>* use, const std::vector<Template>* fixed,
                                   std::vector<FlatEquation>* out) {
  const InstanceData& data = instance.data;
  for (size_t k = 0; k < templates.size(); ++k) {
    const PartInfo& part_info = info[k];
    const DecidedConditions::Use how = use ? (*use)[k] : DecidedConditions::kAsLayout;
    if (how == DecidedConditions::kLeftOut) continue;
    FlatEquation eq;
    if (how == DecidedConditions::kFixed) {
      eq.residual = Instantiate(instance, (*fixed)[k], part_info.text, instance.component.loc);
    } else if (shapes != nullptr && (*shapes)[k] != kNotSure) {
      MakeBelowRoot(templates[k], data.first_var, data.first_param);
      context_.deferred->AddCopy(out->size(), (*shapes)[k], data.first_var, data.first_param);
    } else {
      eq.residual = Instantiate(instance, templates[k], part_info.text, instance.component.loc);
    }
    eq.origin = part_info.origin;
    eq.guarded = part_info.guarded;
    eq.instance = part_info.origin == EquationOrigin::kConnection ? InstanceId() : instance.InstanceOf(part_info.sub);
    eq.text = {TextRef::kType, instance.id.value(), first_text + static_cast<uint32_t>(k)};
    eq.loc = part_info.loc;
    out->push_back(std::move(eq));
  }
}

void InstanceBuilder::AddWhens(const NewInstance& instance) {
  const TypeLayout& layout = instance.layout;
  auto inst_expr = [&](const Template& t, const std::string& text) {
    return Instantiate(instance, t, text, instance.component.loc);
  };
  auto var_of = [&](uint32_t local) { return VarId(instance.data.first_var.value() + local); };
  for (size_t k = 0; k < layout.whens.size(); ++k) {
    const auto& wt = layout.whens[k];
    const PartInfo& info = layout.when_info[k];
    FlatWhen w;
    w.condition = inst_expr(wt.condition, info.text);
    for (const auto& [target, value] : wt.assigns) w.assigns.emplace_back(var_of(target), inst_expr(value, ""));
    for (const auto& [target, value] : wt.reinits) w.reinits.emplace_back(var_of(target), inst_expr(value, ""));
    w.instance = instance.InstanceOf(info.sub);
    w.text = {TextRef::kType, instance.id.value(), static_cast<uint32_t>(k)};
    w.loc = info.loc;
    context_.flat.whens.push_back(std::move(w));
  }
}

void InstanceBuilder::AddImpacts(const NewInstance& instance) {
  FlatSystem& flat = context_.flat;
  auto inst_expr = [&](const Template& t, const std::string& text) {
    return Instantiate(instance, t, text, instance.component.loc);
  };
  auto var_of = [&](uint32_t local) { return VarId(instance.data.first_var.value() + local); };
  for (const auto& it : instance.layout.impacts) {
    const ImpactDecl& decl = *it.decl;
    FlatImpact im;
    im.gap = inst_expr(it.gap, decl.gap_text);
    im.velocity = inst_expr(it.velocity, decl.velocity_text);
    im.restitution = inst_expr(it.restitution, decl.restitution_text);
    im.v_small = inst_expr(it.v_small, decl.v_small_text);
    im.release = inst_expr(it.release, decl.release_text);
    im.force = var_of(it.force);
    im.contact = var_of(it.contact);
    im.instance = instance.InstanceOf(it.sub);
    im.loc = decl.loc;
    // The contact law: no force while open, no relative acceleration while closed.
    ExprPool& pool = context_.pool();
    if (pool.mask(im.velocity) & kHasDer) {
      throw ModelError(decl.loc, "the impact velocity of " + flat.instances[im.instance.value()].type->name +
                                  " may not contain der()");
    }
    ExprId dvel = TimeDerivative(&pool, im.velocity);
    FlatEquation eq;
    eq.residual = pool.If(pool.Var(im.contact), dvel, pool.Var(im.force));
    eq.origin = EquationOrigin::kComponent;
    eq.instance = im.instance;
    eq.text = flat.Own("0 = if " + decl.contact + " then der(" + decl.velocity_text + ") else " + decl.force + " (impact)");
    eq.loc = decl.loc;
    im.mode_equation = static_cast<uint32_t>(flat.equations.size());
    flat.equations.push_back(std::move(eq));
    flat.impacts.push_back(std::move(im));
  }
}

}  // namespace momenta::flatten_internal
