// The connection sets inside a composite type, as templates of its layout: the composite's own
// connectors stand outside (their flows count negative), its parts' inside.

#include "core/flatten/inner_connections.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/flatten/connection_sets.h"
#include "core/flatten/type_scope.h"

namespace momenta::flatten_internal {

namespace {

/// sum of ±local variables, as a template.
Template SignedSum(const std::vector<std::pair<uint32_t, bool>>& terms) {
  Template t;
  for (const auto& [local, negative] : terms) {
    TNode v;
    v.kind = TNode::kLocalVar;
    v.local = local;
    t.nodes.push_back(v);
    int32_t id = static_cast<int32_t>(t.nodes.size() - 1);
    if (t.root < 0) {
      if (negative) {
        TNode neg;
        neg.kind = TNode::kOp;
        neg.op = Op::kNeg;
        neg.a = id;
        t.nodes.push_back(neg);
        id = static_cast<int32_t>(t.nodes.size() - 1);
      }
      t.root = id;
      continue;
    }
    TNode op;
    op.kind = TNode::kOp;
    op.op = negative ? Op::kSub : Op::kAdd;
    op.a = t.root;
    op.b = id;
    t.nodes.push_back(op);
    t.root = static_cast<int32_t>(t.nodes.size() - 1);
  }
  return t;
}

/// The connectors of one composite type and its parts as slots of its connection sets.
/// A ConnectionWriter (connection_sets.h) of templates over the type's local variables.
class InnerConnectionSets {
 public:
  InnerConnectionSets(TypeLayout* layout, std::vector<PartPlan>* plans);
  /// Joins the slots that the type's connections name.
  void JoinConnections();
  /// Appends the sets' equations to the layout.
  void Write();

  const ConnectorType& TypeOf(uint32_t slot) const { return *slots_[slot].cs->type; }
  void Unconnected(uint32_t slot);
  uint32_t Driver(const std::vector<uint32_t>& set, const SourceLoc& loc);
  void Equal(uint32_t slot, uint32_t to, uint32_t k, const SourceLoc& loc);
  void FlowSum(const std::vector<uint32_t>& set, uint32_t flow, const SourceLoc& loc);

 private:
  struct Slot {
    const ConnectorSlot* cs;
    uint32_t first_var;
    bool outside;
    std::string name;  ///< relative to the composite
    SourceLoc loc;     ///< the part's entry, or the connector's declaration
    /// Of a conditional part, or a conditional connector of the type's own: its connections
    /// vanish when it is absent (core/passes/conditional_connectors.h).
    bool conditional = false;
  };
  /// Refuses a set whose members that always exist are joined only through conditional ones:
  /// absent, those would leave them joined here but not in Modelica, where their connections vanish.
  void CheckJoinedWithout(const std::vector<uint32_t>& set) const;
  /// The slot a connection end names: one of the type's own connectors (alone), or a part's
  /// (mass.flange_a, links[2].frame_b).
  uint32_t Resolve(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop);
  void Join(uint32_t x, uint32_t y, const std::string& xt, const std::string& yt, const SourceLoc& loc);
  /// The connections of a `for:` range, whose bounds are whole numbers written in the type.
  void JoinRange(const ConnectionSpec& c);
  /// "\x01mass.flange_a": a slot as an equation's text names it (the instance's path goes first).
  std::string Named(uint32_t slot) const { return "\x01" + slots_[slot].name; }
  void Add(std::vector<std::pair<uint32_t, bool>> terms, std::string text, const SourceLoc& loc,
           EquationOrigin origin);

  TypeLayout& layout_;
  std::vector<PartPlan>& plans_;
  std::vector<Slot> slots_;
  std::unordered_map<std::string, std::vector<size_t>> plans_of_;  ///< part name -> its elements
  ConnectionSets sets_{0};
  std::vector<std::pair<uint32_t, uint32_t>> edges_;  ///< the connections, as pairs of slots
  std::vector<SourceLoc> edge_locs_;
};

InnerConnectionSets::InnerConnectionSets(TypeLayout* layout, std::vector<PartPlan>* plans)
    : layout_(*layout), plans_(*plans) {
  for (const ConnectorSlot& cs : layout_.connectors) {
    slots_.push_back({&cs, cs.first_local_var, true, cs.decl->name, cs.decl->loc, !cs.decl->condition.empty()});
  }
  for (size_t k = 0; k < plans_.size(); ++k) {
    PartPlan& plan = plans_[k];
    plans_of_[plan.spec->name].push_back(k);
    plan.first_slot = static_cast<uint32_t>(slots_.size());
    const uint32_t var_off = layout_.subs[plan.sub].first_var;
    for (const ConnectorSlot& cs : plan.layout->connectors) {
      slots_.push_back({&cs, var_off + cs.first_local_var, false, plan.path + "." + cs.decl->name, plan.spec->loc,
                        plan.spec->condition != nullptr});
    }
  }
  sets_ = ConnectionSets(slots_.size());
}

uint32_t InnerConnectionSets::Resolve(const Ast& a, const std::string& text, const SourceLoc& loc,
                                      const LoopIndex* loop) {
  if (a.path.size() == 1 && !a.path[0].index) {
    auto c = layout_.connector_index.find(a.path[0].name);
    if (c != layout_.connector_index.end()) return c->second;
  }
  if (a.path.size() == 2 && !a.path[1].index) {
    auto part = plans_of_.find(a.path[0].name);
    if (part != plans_of_.end()) {
      const std::vector<size_t>& elems = part->second;
      const PartPlan& first = plans_[elems[0]];
      size_t e = 0;
      if (first.spec->count) {
        if (!a.path[0].index) {
          throw ModelError(loc, a.path[0].name + " is an array of " + std::to_string(elems.size()) +
                                    " parts; name one element, e.g. " + a.path[0].name + "[1], in '" + text + "'");
        }
        std::optional<double> i = ConstantValue(*a.path[0].index, loop);
        if (!i || *i != std::floor(*i) || *i < 1 || *i > static_cast<double>(elems.size())) {
          throw ModelError(loc, "'" + text + "': the index must be a whole number in 1.." + std::to_string(elems.size()));
        }
        e = static_cast<size_t>(*i - 1);
      } else if (a.path[0].index) {
        throw ModelError(loc, a.path[0].name + " is not an array (it has no count:), in '" + text + "'");
      }
      const PartPlan& plan = plans_[elems[e]];
      auto c = plan.layout->connector_index.find(a.path[1].name);
      if (c != plan.layout->connector_index.end()) return plan.first_slot + c->second;
    }
  }
  std::vector<std::string> names;
  for (const Slot& s : slots_) names.push_back(s.name);
  auto close = ClosestNames(a.PathText(), names);
  throw ModelError(loc, "unknown connector '" + a.PathText() + "' in connection end '" + text + "' of " +
                            layout_.type->name + (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                            " (its own connectors are named alone, its parts' like mass.flange_a; valid: " +
                            JoinNames(names) + ")");
}

void InnerConnectionSets::Join(uint32_t x, uint32_t y, const std::string& xt, const std::string& yt,
                               const SourceLoc& loc) {
  CheckCompatible(slots_[x].cs->type, xt, slots_[y].cs->type, yt, loc, " in " + layout_.type->name);
  if (x == y) throw ModelError(loc, "connection of " + xt + " to itself");
  sets_.Locate(x, loc);
  sets_.Locate(y, loc);
  for (uint32_t s : {x, y}) {
    if (!slots_[s].outside) layout_.connected.emplace(slots_[s].first_var, loc);
  }
  sets_.Join(x, y);
  edges_.emplace_back(x, y);
  edge_locs_.push_back(loc);
}

void InnerConnectionSets::Write() {
  std::vector<std::vector<uint32_t>> sets = sets_.Sets();
  for (std::vector<uint32_t>& set : sets) {
    if (set.size() < 2) continue;
    CheckJoinedWithout(set);
    // A member that always exists first: the others' potentials equal its own, so that an
    // absent member takes only its own equations with it.
    auto always = std::find_if(set.begin(), set.end(), [&](uint32_t s) { return !slots_[s].conditional; });
    if (always != set.end()) std::rotate(set.begin(), always, always + 1);
  }
  sets_.WriteEquations(sets, this);
}

void InnerConnectionSets::CheckJoinedWithout(const std::vector<uint32_t>& set) const {
  // (`set` is in slot order.)
  std::vector<uint32_t> always;
  for (uint32_t s : set) {
    if (!slots_[s].conditional) always.push_back(s);
  }
  if (always.size() == set.size() || always.size() < 2) return;
  DisjointSets joined(slots_.size());
  for (const auto& [x, y] : edges_) {
    if (!slots_[x].conditional && !slots_[y].conditional) joined.Join(x, y);
  }
  for (uint32_t s : always) {
    if (joined.Find(s) == joined.Find(always[0])) continue;
    // A connection of the set's between a conditional member and another, for the message.
    SourceLoc at;
    std::string through;
    for (size_t k = 0; k < edges_.size(); ++k) {
      const auto [x, y] = edges_[k];
      if (slots_[x].conditional != slots_[y].conditional && std::binary_search(set.begin(), set.end(), x)) {
        at = edge_locs_[k];
        through = slots_[x].conditional ? slots_[x].name : slots_[y].name;
        break;
      }
    }
    throw ModelError(at, slots_[always[0]].name + " and " + slots_[s].name + " in " + layout_.type->name +
                             " are connected only through " + through + ", which is conditional: absent, its " +
                             "connections vanish and would leave them apart; connect them directly");
  }
}

void InnerConnectionSets::JoinConnections() {
  for (const auto& c : layout_.type->connections) {
    if (c.loop_var.empty()) {
      Join(Resolve(*c.EndA(), c.a_text, c.a_loc, nullptr), Resolve(*c.EndB(), c.b_text, c.b_loc, nullptr), c.a_text,
           c.b_text, c.a_loc);
    } else {
      JoinRange(c);
    }
  }
}

void InnerConnectionSets::JoinRange(const ConnectionSpec& c) {
  std::optional<double> from = ConstantValue(*c.loop_from, nullptr), to = ConstantValue(*c.loop_to, nullptr);
  const SourceLoc& loc = c.loop_loc.known() ? c.loop_loc : c.loc;
  const std::string& type_name = layout_.type->name;
  // Whole numbers that doubles count exactly (beyond 2^53, i + 1 == i).
  constexpr double kExact = 9007199254740992.0;
  if (!from || !to || *from != std::floor(*from) || *to != std::floor(*to) || std::fabs(*from) > kExact ||
      std::fabs(*to) > kExact) {
    throw ModelError(loc, "the range of 'for: " + c.loop_text + "' inside " + type_name +
                              " must have whole-number bounds below 2^53 (a type's structure is fixed)");
  }
  const double n = *to - *from + 1;
  if (n > static_cast<double>(slots_.size())) {
    throw ModelError(loc, "the range of 'for: " + c.loop_text + "' makes more connections than " + type_name +
                              " has connectors");
  }
  for (size_t k = 0; n > 0 && k < static_cast<size_t>(n); ++k) {
    LoopIndex loop{c.loop_var, *from + static_cast<double>(k)};
    Join(Resolve(*c.EndA(), c.a_text, c.a_loc, &loop), Resolve(*c.EndB(), c.b_text, c.b_loc, &loop), c.a_text,
         c.b_text, c.a_loc);
  }
}

void InnerConnectionSets::Add(std::vector<std::pair<uint32_t, bool>> terms, std::string text, const SourceLoc& loc,
                              EquationOrigin origin) {
  layout_.equations.push_back(SignedSum(terms));
  layout_.equation_info.push_back({std::move(text), loc, -1, origin});
}

void InnerConnectionSets::Unconnected(uint32_t slot) {
  const Slot& s0 = slots_[slot];
  const ConnectorType* ct = s0.cs->type;
  const std::string& type_name = layout_.type->name;
  if (ct->is_signal) {
    if (!s0.outside && ct->is_input && s0.cs->decl->condition.empty()) {
      throw ModelError(s0.loc, "the signal input " + s0.name + " inside " + type_name +
                                   " is connected to nothing; connect it to an output or to an input of " + type_name);
    }
    return;
  }
  if (s0.outside) return;  // the type's own equations determine its own connector's flows
  const auto np = static_cast<uint32_t>(ct->potentials.size());
  for (uint32_t k = 0; k < ct->flows.size(); ++k) {
    Add({{s0.first_var + np + k, false}}, Named(slot) + "." + ct->flows[k].name + " = 0 (unconnected)", s0.loc,
        EquationOrigin::kUnconnectedFlow);
  }
}

uint32_t InnerConnectionSets::Driver(const std::vector<uint32_t>& set, const SourceLoc& loc) {
  // An output of a part drives the set from inside, an input of the type from outside.
  std::vector<uint32_t> drivers;
  for (uint32_t s : set) {
    if (slots_[s].cs->type->is_input == slots_[s].outside) drivers.push_back(s);
  }
  if (drivers.size() == 1) return drivers[0];
  // Without either, an output of the type that its own equations determine drives its parts'
  // inputs (MSL's FreeMotionScalarInit: [angle_1, derd[1].u]).
  if (drivers.empty()) {
    for (uint32_t s : set) {
      if (slots_[s].outside && !slots_[s].cs->type->is_input) drivers.push_back(s);
    }
    if (drivers.size() == 1) return drivers[0];
  }
  std::string members;
  for (uint32_t s : set) members += (members.empty() ? "" : ", ") + slots_[s].name;
  const std::string& type_name = layout_.type->name;
  throw ModelError(loc, "the signals " + members + " inside " + type_name + " have " +
                            std::to_string(drivers.size()) + " drivers; a signal set has exactly one " +
                            "(an output of a part, or an input of " + type_name + ")");
}

void InnerConnectionSets::Equal(uint32_t slot, uint32_t to, uint32_t k, const SourceLoc& loc) {
  const ConnectorType& ct = TypeOf(to);
  std::string text = ct.is_signal ? Named(slot) + " = " + Named(to) + " (connection)"
                                  : Named(slot) + "." + ct.potentials[k].name + " = " + Named(to) + "." +
                                        ct.potentials[k].name + " (connection)";
  Add({{slots_[slot].first_var + k, false}, {slots_[to].first_var + k, true}}, std::move(text), loc,
      EquationOrigin::kConnection);
  // An overdetermined record's elements beyond its residues: the equality is not counted.
  if (!ct.is_signal && !ct.potentials[k].counted) ++layout_.uncounted_equations;
}

void InnerConnectionSets::FlowSum(const std::vector<uint32_t>& set, uint32_t flow, const SourceLoc& loc) {
  const ConnectorType& ct = TypeOf(set[0]);
  const auto np = static_cast<uint32_t>(ct.potentials.size());
  std::string members;
  for (uint32_t s : set) members += (members.empty() ? "" : ", ") + Named(s);
  std::vector<std::pair<uint32_t, bool>> terms;
  for (uint32_t s : set) terms.push_back({slots_[s].first_var + np + flow, slots_[s].outside});
  bool any_outside = false;
  for (uint32_t s : set) any_outside = any_outside || slots_[s].outside;
  Add(terms, "sum of " + ct.flows[flow].name + " over {" + members + "} = 0 (connection" +
                 (any_outside ? "; " + layout_.type->name + "'s own connectors count negative)" : ")"),
      loc, EquationOrigin::kConnection);
}

}  // namespace

void InnerConnections(TypeLayout* layout, std::vector<PartPlan>* plans) {
  if (plans->empty() && layout->type->connections.empty()) return;
  InnerConnectionSets sets(layout, plans);
  sets.JoinConnections();
  sets.Write();
}

}  // namespace momenta::flatten_internal
