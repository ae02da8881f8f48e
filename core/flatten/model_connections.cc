// The model's connections: ends resolved to slots, slots joined, and each set's equations made in
// the pool, or deferred when they are aliases.

#include "core/flatten/model_connections.h"

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/flatten/deferred_aliases.h"
#include "core/flatten/type_layout.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

void ModelConnections::Run() {
  for (const auto& c : context_.spec.connections) {
    if (c.loop_var.empty()) {
      const std::optional<EndRef> a = PlainEnd(c.a, c.a_text, c.a_loc), b = PlainEnd(c.b, c.b_text, c.b_loc);
      Join(a ? *a : ResolveEnd(*c.EndA(), c.a_text, c.a_loc, nullptr),
           b ? *b : ResolveEnd(*c.EndB(), c.b_text, c.b_loc, nullptr));
      continue;
    }
    double from = 0;
    size_t iterations = LoopLength(c, &from);
    for (size_t k = 0; k < iterations; ++k) {
      LoopIndex loop{c.loop_var, from + static_cast<double>(k)};
      Join(ResolveEnd(*c.EndA(), c.a_text, c.a_loc, &loop), ResolveEnd(*c.EndB(), c.b_text, c.b_loc, &loop));
    }
  }
  const std::vector<std::vector<uint32_t>> sets = sets_.Sets();
  context_.flat.equations.reserve(context_.flat.equations.size() + ConnectionEquationCount(sets));
  sets_.WriteEquations(sets, this);
}

std::string ModelConnections::EndText(const EndRef& e) const {
  return context_.flat.InstancePath(InstanceId(e.instance)) + "." +
         context_.instance_data[e.instance].layout->connectors[e.connector].decl->name;
}

ModelConnections::EndRef ModelConnections::ResolveEnd(const Ast& a, const std::string& text, const SourceLoc& loc,
                                                      const LoopIndex* loop) {
  const ComponentIndex& components = context_.components;
  if (a.path.size() > 2 && components.Find(a.path[0].name)) {
    throw ModelError(loc, "'" + text + "' reaches into " + a.path[0].name + "; a model connects to a component's " +
                              "own connectors only (a composite type exposes a part's connector by connecting it " +
                              "to one of its own)");
  }
  if (a.path.size() != 2) {
    throw ModelError(loc, "a connection end names a component and one of its connectors, e.g. A.flange_a; found '" + text + "'");
  }
  const ComponentArray* arr = components.Find(a.path[0].name);
  if (!arr) {
    std::vector<std::string> names;
    for (const auto& c : context_.spec.components) names.push_back(c.name);
    auto close = ClosestNames(a.path[0].name, names);
    throw ModelError(loc, "unknown component '" + a.path[0].name + "' in connection end '" + text + "'" +
                              (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                              " (valid components: " + JoinNames(names) + ")");
  }
  uint32_t inst = scope_.ElementOf(*arr, a.path[0], loc, loop, text);
  const TypeLayout& layout = *context_.instance_data[inst].layout;
  if (a.path[1].index) throw ModelError(loc, "connectors cannot be indexed, in '" + text + "'");
  auto c = layout.connector_index.find(a.path[1].name);
  if (c == layout.connector_index.end()) {
    std::vector<std::string> names;
    for (const auto& s : layout.connectors) names.push_back(s.decl->name);
    throw ModelError(loc, context_.flat.InstancePath(InstanceId(inst)) + " (" + layout.type->name + ") has no connector '" +
                              a.path[1].name + "' (valid connectors: " +
                              (names.empty() ? std::string("none") : JoinNames(names)) + ")");
  }
  return {inst, c->second, loc};
}

std::optional<ModelConnections::EndRef> ModelConnections::PlainEnd(const AstPtr& tree, const std::string& text,
                                                                   const SourceLoc& loc) const {
  const size_t dot = text.find('.');
  if (tree || dot == std::string::npos || text.find('.', dot + 1) != std::string::npos) return std::nullopt;
  const ComponentArray* arr = context_.components.Find(std::string_view(text).substr(0, dot));
  if (!arr || arr->is_array) return std::nullopt;
  const TypeLayout& layout = *context_.instance_data[arr->first_instance].layout;
  auto connector = layout.connector_index.find(text.substr(dot + 1));
  if (connector == layout.connector_index.end()) return std::nullopt;
  return EndRef{arr->first_instance, connector->second, loc};
}

size_t ModelConnections::LoopLength(const ConnectionSpec& c, double* from) {
  const SourceLoc& loc = c.loop_loc.known() ? c.loop_loc : c.loc;
  std::string range = "the range of 'for: " +
                      (c.loop_text.empty() ? c.loop_var + " in " + AstToString(*c.loop_from) + ":" +
                                                 AstToString(*c.loop_to)
                                           : c.loop_text) +
                      "'";
  *from = scope_.StructuralWhole(*c.loop_from, AstToString(*c.loop_from), loc, nullptr, "the start of " + range);
  double to = scope_.StructuralWhole(*c.loop_to, AstToString(*c.loop_to), loc, nullptr, "the end of " + range);
  double n = to - *from + 1;
  if (n <= 0) return 0;
  const size_t connectors = context_.slot_instance.size();
  if (n > static_cast<double>(connectors)) {
    throw ModelError(loc, range + " makes " + NumberText(n) + " connections, more than the model's " +
                              std::to_string(connectors) + " connectors can need; a range runs over " +
                              "the elements of an array, e.g. i in 1:n");
  }
  return static_cast<size_t>(n);
}

void ModelConnections::Join(const EndRef& x, const EndRef& y) {
  const std::vector<InstanceData>& instance_data = context_.instance_data;
  const ConnectorSlot& cx = instance_data[x.instance].layout->connectors[x.connector];
  const ConnectorSlot& cy = instance_data[y.instance].layout->connectors[y.connector];
  if (!Compatible(cx.type, cy.type)) CheckCompatible(cx.type, EndText(x), cy.type, EndText(y), x.loc);
  uint32_t sx = instance_data[x.instance].first_slot + x.connector;
  uint32_t sy = instance_data[y.instance].first_slot + y.connector;
  if (sx == sy) throw ModelError(x.loc, "connection of " + EndText(x) + " to itself");
  for (auto [s, e] : {std::pair{sx, &x}, std::pair{sy, &y}}) {
    if (!sets_.Locate(s, e->loc)) continue;
    auto cc = context_.conditional_slot.find(s);
    if (cc != context_.conditional_slot.end()) context_.flat.conditional_connectors[cc->second].connected_at = e->loc;
  }
  sets_.Join(sx, sy);
}

size_t ModelConnections::ConnectionEquationCount(const std::vector<std::vector<uint32_t>>& sets) const {
  size_t n = 0;
  for (const auto& set : sets) {
    const ConnectorType& ct = TypeOf(set[0]);
    if (set.size() == 1 && DecidedAbsent(set[0])) continue;
    if (ct.is_signal) {
      n += set.size() - 1;
    } else {
      n += ct.potentials.size() * (set.size() - 1) + ct.flows.size();
    }
  }
  return n;
}

void ModelConnections::CheckConnectedUnits(VarId a, const std::string& a_name, VarId b, const std::string& b_name,
                                           const SourceLoc& loc) {
  const std::string& ua = context_.flat.VariableUnit(a);
  const std::string& ub = context_.flat.VariableUnit(b);
  if (ua.empty() || ub.empty() || ua == ub) return;
  std::optional<Dimension> da = scope_.Units().DimensionOf(ua), db = scope_.Units().DimensionOf(ub);
  if (da && db && *da != *db) {
    throw ModelError(loc, "dimension mismatch in the connection of " + a_name + " [" + ua + "] to " + b_name +
                              " [" + ub + "]: " + DimensionText(*da) + " against " + DimensionText(*db));
  }
}

bool ModelConnections::DecidedAbsent(uint32_t slot) const {
  auto cc = context_.conditional_slot.find(slot);
  return cc != context_.conditional_slot.end() && context_.flat.conditional_connectors[cc->second].decided == 0;
}

VarId ModelConnections::VarOf(uint32_t slot, uint32_t k) const {
  const InstanceData& data = context_.instance_data[context_.slot_instance[slot]];
  const ConnectorSlot& cs = data.layout->connectors[slot - data.first_slot];
  return VarId(data.first_var.value() + cs.first_local_var + k);
}

std::string ModelConnections::NameOf(uint32_t slot) const {
  const InstanceData& data = context_.instance_data[context_.slot_instance[slot]];
  return context_.flat.InstancePath(InstanceId(context_.slot_instance[slot])) + "." +
         data.layout->connectors[slot - data.first_slot].decl->name;
}

const ConnectorType& ModelConnections::TypeOf(uint32_t slot) const {
  const InstanceData& data = context_.instance_data[context_.slot_instance[slot]];
  return *data.layout->connectors[slot - data.first_slot].type;
}

void ModelConnections::Add(ExprId residual, TextRef text, const SourceLoc& loc) {
  FlatEquation eq;
  eq.residual = residual;  // invalid: deferred
  eq.origin = EquationOrigin::kConnection;
  eq.text = text;
  eq.loc = loc;
  context_.flat.equations.push_back(std::move(eq));
}

bool ModelConnections::Continuous(VarId a, VarId b) const {
  const std::vector<FlatVariable>& variables = context_.flat.variables;
  return a != b && !variables[a.value()].discrete && !variables[b.value()].discrete;
}

void ModelConnections::Unconnected(uint32_t slot) {
  // An unconnected physical connector: its flows are zero. An unconnected signal input is
  // recorded: a linearisation takes it as an input, anything else refuses it.
  const ConnectorType& type = TypeOf(slot);
  if (type.is_signal) {
    if (type.is_input && !context_.conditional_slot.count(slot)) context_.flat.free_inputs.push_back(VarOf(slot, 0));
    return;
  }
  FlatSystem& flat = context_.flat;
  if (DecidedAbsent(slot)) return;  // its flows' equations go with it
  ExprPool& pool = context_.pool();
  const uint32_t instance = context_.slot_instance[slot];
  for (size_t k = 0; k < type.flows.size(); ++k) {
    VarId f = VarOf(slot, static_cast<uint32_t>(type.potentials.size() + k));
    FlatEquation eq;
    // f = 0 is an alias to a constant, unless the connector is conditional (an absent
    // one's equation goes: ResolveConditionalConnectors).
    if (context_.deferred && !flat.variables[f.value()].discrete && !context_.conditional_slot.count(slot)) {
      pool.Var(f);  // the leaf, in its place (InstanceBuilder::MakeBelowRoot)
      context_.deferred->AddZero(flat.equations.size(), f);
    } else {
      eq.residual = pool.Var(f);
    }
    eq.origin = EquationOrigin::kUnconnectedFlow;
    eq.instance = InstanceId(instance);
    eq.text = {TextRef::kUnconnected, f.value(), 0};  // "<connector>.<flow> = 0 (unconnected)"
    eq.loc = flat.instances[instance].loc;
    flat.equations.push_back(std::move(eq));
  }
}

uint32_t ModelConnections::Driver(const std::vector<uint32_t>& set, const SourceLoc& loc) {
  // Exactly one output drives the set; every input equals it.
  std::vector<uint32_t> outputs;
  for (uint32_t s : set) {
    if (!TypeOf(s).is_input) outputs.push_back(s);
  }
  if (outputs.empty()) {
    std::string members;
    for (uint32_t s : set) members += (members.empty() ? "" : ", ") + NameOf(s);
    throw ModelError(loc, "the signals " + members + " are joined but no output drives them; connect an output (e.g. a Constant block's y)");
  }
  if (outputs.size() > 1) {
    throw ModelError(loc, "the outputs " + NameOf(outputs[0]) + " and " + NameOf(outputs[1]) +
                              " are connected to each other; a signal has exactly one output");
  }
  return outputs[0];
}

void ModelConnections::Equal(uint32_t slot, uint32_t to, uint32_t k, const SourceLoc& loc) {
  // "<a> = <b> (connection)": the connectors' variables are named <connector>.<potential>.
  const VarId a = VarOf(slot, k), b = VarOf(to, k);
  if (TypeOf(to).is_signal) CheckConnectedUnits(a, NameOf(slot), b, NameOf(to), loc);
  ExprPool& pool = context_.pool();
  const TextRef text{TextRef::kEqual, a.value(), b.value()};
  if (context_.deferred && Continuous(a, b)) {
    // The leaves, in the order the made branch below makes them.
    pool.Var(b);
    pool.Var(a);
    context_.deferred->AddEqual(context_.flat.equations.size(), a, b);
    Add(ExprId(), text, loc);
  } else {
    const ExprId vb = pool.Var(b);
    const ExprId va = pool.Var(a);
    Add(pool.Sub(va, vb), text, loc);
  }
}

void ModelConnections::FlowSum(const std::vector<uint32_t>& set, uint32_t flow, const SourceLoc& loc) {
  ExprPool& pool = context_.pool();
  FlatSystem& flat = context_.flat;
  const uint32_t s0 = set[0];
  const auto local = static_cast<uint32_t>(TypeOf(s0).potentials.size() + flow);
  ExprId sum = pool.Var(VarOf(s0, local));
  if (context_.deferred && set.size() == 2 && Continuous(VarOf(s0, local), VarOf(set[1], local))) {
    pool.Var(VarOf(set[1], local));
    context_.deferred->AddSum(flat.equations.size(), VarOf(s0, local), VarOf(set[1], local));
    sum = ExprId();
  } else {
    for (size_t j = 1; j < set.size(); ++j) sum = pool.Add(sum, pool.Var(VarOf(set[j], local)));
  }
  // "sum of <flow> over {<connectors>} = 0 (connection)", named from the flow variables.
  const TextRef text{TextRef::kFlowSum, static_cast<uint32_t>(flat.connection_vars.size()),
                     static_cast<uint32_t>(set.size())};
  for (uint32_t s : set) flat.connection_vars.push_back(VarOf(s, local));
  Add(sum, text, loc);
}

}  // namespace momenta::flatten_internal
