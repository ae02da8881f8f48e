// The connection graph of overdetermined connectors (core/flatten/connection_graph.h).

#include "core/flatten/connection_graph.h"

#include <algorithm>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>

#include "core/base/error.h"
#include "core/base/graph.h"
#include "core/expr/expr_leaves.h"
#include "core/flatten/deferred_aliases.h"
#include "core/flatten/flatten.h"
#include "core/lang/records.h"

namespace momenta::flatten_internal {

namespace {

/// One record potential of one instance's connector: `frame_a.R` of `rev`.
struct RecordNode {
  InstanceId instance;
  std::string local;  ///< "frame_a.R"
};

/// A branch, root or potential root of an instance, resolved to nodes.
struct Role {
  uint32_t a = 0, b = 0;
  int priority = 0;
  InstanceId instance;
  const GraphDecl* decl = nullptr;
};

class Graph {
 public:
  explicit Graph(FlattenContext* context) : context_(*context), flat_(context->flat) {}

  void Run() {
    if (!Declared()) return;
    for (uint32_t q = 0; q < flat_.parameters.size(); ++q) param_of_.emplace(flat_.ParameterName(ParamId(q)), ParamId(q));
    const std::vector<double> params = EvaluateParameters(flat_, context_.overrides);
    CollectNodes(params);
    CollectRoles(params);
    JoinConnections();
    ChooseRootsAndTree();
    SetPredicates();
  }

 private:
  /// Whether any type declares roots or branches.
  bool Declared() const {
    for (const FlatInstance& inst : flat_.instances) {
      const ComponentType* t = inst.type;
      if (!t->roots.empty() || !t->potential_roots.empty() || !t->branches.empty()) return true;
    }
    return false;
  }

  /// Whether connector `connector` of instance `i` exists (a conditional connector's parameter).
  bool Present(InstanceId i, const ComponentType& type, const std::string& connector, const std::vector<double>& params) const {
    for (const ConnectorDecl& c : type.connectors) {
      if (c.name != connector || c.condition.empty()) continue;
      auto p = FindParameter(i, c.condition);
      return !p || params[p->value()] != 0;
    }
    return true;
  }

  /// The first element of each record potential of each instance whose type has one, less those
  /// of absent conditional connectors.
  void CollectNodes(const std::vector<double>& params) {
    // local name of a record's first element → the record ("frame_a.R.T[1,1]" → "frame_a.R"), per type
    std::unordered_map<const ComponentType*, std::unordered_map<std::string, std::string>> firsts;
    for (const FlatInstance& inst : flat_.instances) {
      auto [it, fresh] = firsts.try_emplace(inst.type);
      if (!fresh) continue;
      for (const auto& [record_name, record] : inst.type->records) {
        const std::string name = record_name;  // a copy: a lambda cannot capture a structured binding in C++20
        // Connectors' record potentials only (`frame_a.R`), not record variables (`R_rel`).
        const size_t dot = name.find('.');
        const auto& cs = inst.type->connectors;
        if (dot == std::string::npos ||
            std::none_of(cs.begin(), cs.end(), [&](const ConnectorDecl& c) { return c.name == name.substr(0, dot); })) {
          continue;
        }
        const RecordType* r = context_.library.FindRecord(record);
        if (!r || r->residues == 0 || r->fields.empty()) continue;
        const ConnectorVariable& f = r->fields[0];
        it->second[name + "." + f.name + (f.shape.empty() ? "" : f.shape.size() == 1 ? "[1]" : "[1,1]")] = name;
      }
    }
    for (uint32_t v = 0; v < flat_.variables.size(); ++v) {
      const InstanceId i = flat_.variables[v].instance;
      if (!i.valid()) continue;
      const auto& names = firsts[flat_.instances[i.value()].type];
      if (names.empty()) continue;
      const std::string full = flat_.VariableName(VarId(v));
      const std::string path = flat_.InstancePath(i);
      if (full.size() <= path.size() + 1) continue;
      auto found = names.find(full.substr(path.size() + 1));
      if (found == names.end()) continue;
      const ComponentType& type = *flat_.instances[i.value()].type;
      if (!Present(i, type, found->second.substr(0, found->second.find('.')), params)) continue;
      node_of_var_[v] = static_cast<uint32_t>(nodes_.size());
      node_of_[{i.value(), found->second}] = static_cast<uint32_t>(nodes_.size());
      nodes_.push_back({i, found->second});
    }
  }

  uint32_t NodeOf(InstanceId i, const std::string& local, const GraphDecl& d) const {
    auto it = node_of_.find({i.value(), local});
    if (it == node_of_.end()) {
      throw ModelError(d.loc, flat_.InstancePath(i) + " (" + flat_.instances[i.value()].type->name + "): '" + local +
                                  "' in its roots or branches is not an overdetermined record potential of its connectors");
    }
    return it->second;
  }

  /// Whether a declaration's `if:` holds for instance `i` (a Boolean parameter, `not p` negated).
  bool Holds(const GraphDecl& d, InstanceId i, const std::vector<double>& params) const {
    if (d.condition.empty()) return true;
    std::string name = d.condition;
    bool negate = false;
    if (name.rfind("not ", 0) == 0) {
      negate = true;
      name = name.substr(4);
    }
    auto p = FindParameter(i, name);
    if (!p) throw ModelError(d.loc, "the condition '" + d.condition + "' names no parameter of " + flat_.instances[i.value()].type->name);
    context_.flat.structural.Set(*p, params[p->value()]);
    return (params[p->value()] != 0) != negate;
  }

  void CollectRoles(const std::vector<double>& params) {
    for (uint32_t k = 0; k < flat_.instances.size(); ++k) {
      const InstanceId i(k);
      const ComponentType* t = flat_.instances[k].type;
      for (const GraphDecl& d : t->roots) {
        if (Holds(d, i, params)) roots_.push_back({NodeOf(i, d.a, d), 0, 0, i, &d});
      }
      for (const GraphDecl& d : t->potential_roots) {
        if (Holds(d, i, params)) potential_.push_back({NodeOf(i, d.a, d), 0, d.priority, i, &d});
      }
      for (const GraphDecl& d : t->branches) {
        if (Holds(d, i, params)) branches_.push_back({NodeOf(i, d.a, d), NodeOf(i, d.b, d), 0, i, &d});
      }
    }
  }

  /// The connections' equalities between two records' first elements join their nodes.
  void JoinConnections() {
    sets_ = std::make_unique<DisjointSets>(nodes_.size());
    const ExprPool& pool = *flat_.pool;
    std::vector<std::pair<VarId, double>> terms;
    for (uint32_t k = 0; k < flat_.equations.size(); ++k) {
      const FlatEquation& eq = flat_.equations[k];
      if (eq.origin != EquationOrigin::kConnection) continue;
      std::vector<uint32_t> vars;
      if (!eq.residual.valid()) {
        double offset = 0;
        terms.clear();
        if (!context_.deferred || !context_.deferred->Form(k, &terms, &offset)) continue;
        for (const auto& [v, c] : terms) vars.push_back(v.value());
      } else {
        for (ExprId leaf : CollectLeaves(pool, eq.residual, kHasVar)) vars.push_back(pool.node(leaf).a);
      }
      if (vars.size() != 2) continue;
      auto a = node_of_var_.find(vars[0]), b = node_of_var_.find(vars[1]);
      if (a != node_of_var_.end() && b != node_of_var_.end()) sets_->Join(a->second, b->second);
    }
  }

  std::string Named(uint32_t node) const {
    const RecordNode& n = nodes_[node];
    return flat_.InstancePath(n.instance) + "." + n.local + " (" + flat_.instances[n.instance.value()].type->name + ")";
  }

  void ChooseRootsAndTree() {
    const size_t n = nodes_.size();
    // The parts of the graph: sets joined by branches.
    DisjointSets parts(n);
    for (const Role& b : branches_) parts.Join(sets_->Find(b.a), sets_->Find(b.b));
    std::map<uint32_t, uint32_t> root_of_part;  // part → the chosen root's node
    for (const Role& r : roots_) {
      const uint32_t part = parts.Find(sets_->Find(r.a));
      auto [it, fresh] = root_of_part.emplace(part, r.a);
      if (!fresh) {
        throw ModelError(flat_.instances[r.instance.value()].loc,
                         Named(r.a) + " and " + Named(it->second) +
                             " are both roots of one connected set of frames: their orientations would be defined twice "
                             "(a closed kinematic loop through two worlds or fixed frames; loops are not supported yet)");
      }
    }
    std::vector<Role> candidates = potential_;
    std::stable_sort(candidates.begin(), candidates.end(), [](const Role& x, const Role& y) { return x.priority < y.priority; });
    for (const Role& r : candidates) root_of_part.emplace(parts.Find(sets_->Find(r.a)), r.a);
    // Every node's part must have a root.
    for (uint32_t k = 0; k < n; ++k) {
      if (!root_of_part.count(parts.Find(sets_->Find(k)))) {
        throw ModelError(flat_.instances[nodes_[k].instance.value()].loc,
                         "the orientation of " + Named(k) +
                             " is defined by nothing: connect its frame, through joints or rigid parts, to a World, "
                             "a Fixed frame or a body that may integrate its orientation");
      }
    }
    for (const auto& [part, node] : root_of_part) chosen_.insert(node);
    // Spanning trees from the roots' sets along the branches.
    std::unordered_map<uint32_t, std::vector<uint32_t>> edges;  // set → branches at it
    for (uint32_t k = 0; k < branches_.size(); ++k) {
      edges[sets_->Find(branches_[k].a)].push_back(k);
      edges[sets_->Find(branches_[k].b)].push_back(k);
    }
    std::vector<bool> visited(n, false), used(branches_.size(), false);
    rooted_.assign(branches_.size(), false);
    for (const auto& [part, node] : root_of_part) {
      std::deque<uint32_t> queue{sets_->Find(node)};
      visited[queue.front()] = true;
      while (!queue.empty()) {
        const uint32_t s = queue.front();
        queue.pop_front();
        for (uint32_t k : edges[s]) {
          if (used[k]) continue;
          used[k] = true;
          const Role& b = branches_[k];
          const bool from_a = sets_->Find(b.a) == s;
          const uint32_t other = sets_->Find(from_a ? b.b : b.a);
          if (visited[other]) {
            throw ModelError(flat_.instances[b.instance.value()].loc,
                             flat_.InstancePath(b.instance) + " (" + flat_.instances[b.instance.value()].type->name +
                                 ") closes a kinematic loop: the orientation of " + Named(from_a ? b.b : b.a) +
                                 " is defined along two paths (closed loops are not supported yet)");
          }
          visited[other] = true;
          rooted_[k] = from_a;
          queue.push_back(other);
        }
      }
    }
  }

  void SetPredicates() {
    ExprPool& pool = *context_.flat.pool;
    auto set = [&](InstanceId i, const std::string& name, bool value) {
      auto p = FindParameter(i, name);
      if (p) context_.flat.parameters[p->value()].binding = pool.Const(value ? 1.0 : 0.0);
    };
    for (uint32_t k = 0; k < nodes_.size(); ++k) {
      set(nodes_[k].instance, PredicateName("isRoot", nodes_[k].local), chosen_.count(k) != 0);
    }
    for (uint32_t k = 0; k < branches_.size(); ++k) {
      const Role& b = branches_[k];
      set(b.instance, PredicateName("rooted", nodes_[b.a].local), rooted_[k]);
      set(b.instance, PredicateName("rooted", nodes_[b.b].local), !rooted_[k]);
    }
  }

  /// Instance i's parameter `name` (FlatSystem::FindParameter, from an index: one scan of every
  /// parameter per instance would make a chain of n bodies cost n^2).
  std::optional<ParamId> FindParameter(InstanceId i, const std::string& name) const {
    auto it = param_of_.find(flat_.InstancePath(i) + "." + name);
    if (it == param_of_.end()) return std::nullopt;
    return it->second;
  }

  FlattenContext& context_;
  const FlatSystem& flat_;
  std::unordered_map<std::string, ParamId> param_of_;  ///< every parameter by its full name
  std::vector<RecordNode> nodes_;
  std::unordered_map<uint32_t, uint32_t> node_of_var_;
  std::map<std::pair<uint32_t, std::string>, uint32_t> node_of_;
  std::vector<Role> roots_, potential_, branches_;
  std::unique_ptr<DisjointSets> sets_;
  std::set<uint32_t> chosen_;
  std::vector<bool> rooted_;
};

}  // namespace

void ResolveConnectionGraph(FlattenContext* context) { Graph(context).Run(); }

}  // namespace momenta::flatten_internal
