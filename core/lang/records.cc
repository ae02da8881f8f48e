// Records, conditional blocks and the graph's predicates in a type's scalar form
// (core/lang/records.h).

#include "core/lang/records.h"

#include <algorithm>
#include <functional>
#include <map>
#include <set>

#include "core/base/messages.h"
#include "core/lang/arrays.h"
#include "core/lang/parser.h"

namespace momenta {

namespace {

const RecordType& FindRecordOrFail(const Library& library, const std::string& name, const SourceLoc& loc,
                                   const std::string& who) {
  const RecordType* r = library.FindRecord(name);
  if (!r) {
    throw ModelError(loc, "unknown type '" + name + "' for " + who +
                              " (valid types: Real, Integer, Boolean, or a record type of the library)");
  }
  return *r;
}

bool IsPredicate(const Ast& a) { return a.kind == Ast::Kind::kCall && (a.op == "isRoot" || a.op == "rooted"); }

/// Whether a tree calls a predicate or a function that is not momenta's own (a library's).
bool CallsAny(const AstPtr& a) {
  if (!a) return false;
  if (a->kind == Ast::Kind::kCall) {
    if (IsPredicate(*a)) return true;
    // A library's function, or a name the parser let through for the library to resolve.
    if (!IsBuiltinFunction(a->op)) return true;
  }
  for (const AstPtr& x : a->args) {
    if (CallsAny(x)) return true;
  }
  return false;
}

/// `a` with each predicate call replaced by its hidden parameter's name; `found` collects them.
AstPtr ReplacePredicates(const AstPtr& a, std::set<std::string>* found, const ComponentType& type,
                         const SourceLoc& loc) {
  if (!a) return a;
  if (IsPredicate(*a)) {
    if (a->args.size() != 1 || a->args[0]->kind != Ast::Kind::kName) {
      throw ModelError(loc, a->op + "() takes a record potential of a connector, such as " + a->op +
                                "(frame_a.R), in " + type.name);
    }
    const std::string record = a->args[0]->PathText();
    const std::string name = PredicateName(a->op, record);
    found->insert(name);
    auto n = std::make_shared<Ast>();
    n->kind = Ast::Kind::kName;
    n->column = a->column;
    n->path.push_back({name, nullptr, nullptr});
    return n;
  }
  bool changed = false;
  std::vector<AstPtr> args;
  args.reserve(a->args.size());
  for (const AstPtr& x : a->args) {
    args.push_back(ReplacePredicates(x, found, type, loc));
    changed = changed || args.back() != x;
  }
  if (!changed) return a;
  auto n = std::make_shared<Ast>(*a);
  n->args = std::move(args);
  return n;
}

/// `name` with every name that is a parameter of `inner` prefixed by `prefix.`.
AstPtr Prefixed(const AstPtr& a, const std::string& prefix, const ComponentType& inner) {
  if (!a) return a;
  if (a->kind == Ast::Kind::kName) {
    const std::string first = a->path[0].name;
    const bool own = std::any_of(inner.parameters.begin(), inner.parameters.end(), [&](const ParameterDecl& p) {
      return p.name == first || p.name.rfind(first + "[", 0) == 0;
    });
    if (!own) return a;
    auto n = std::make_shared<Ast>(*a);
    n->path.insert(n->path.begin(), NameSegment{prefix, nullptr, nullptr});
    return n;
  }
  bool changed = false;
  std::vector<AstPtr> args;
  for (const AstPtr& x : a->args) {
    args.push_back(Prefixed(x, prefix, inner));
    changed = changed || args.back() != x;
  }
  if (!changed) return a;
  auto n = std::make_shared<Ast>(*a);
  n->args = std::move(args);
  return n;
}

/// An outer component's parameters as the type's own, named `world.g`, `world.n[1]` …, with the
/// outer type's defaults; the flattener binds them to the model's component (flatten's
/// ResolveOuters). Its arrays are seen whole (`world.n`).
void DeclareOuters(const ComponentType& type, const Library& library, ComponentType* out) {
  for (const auto& [prefix, type_name] : type.outers) {
    const ComponentType* found = library.FindComponent(type_name);
    if (!found) {
      throw ModelError(type.loc, "the outer " + prefix + " of " + type.name + " is of the unknown type '" + type_name + "'");
    }
    // Its scalar form (a library read whole is scalarised type by type, perhaps this one first).
    const ComponentType scalar = found->arrays.empty() && NeedsScalarForm(*found, library) ? ScalarForm(*found, library) : ComponentType();
    const ComponentType* inner = scalar.name.empty() ? found : &scalar;
    for (const ParameterDecl& p : inner->parameters) {
      ParameterDecl q = p;
      q.name = prefix + "." + p.name;
      q.value = Prefixed(p.value, prefix, *inner);
      q.doc = "the parameter " + p.name + " of the model's " + prefix + " (" + type_name + ")";
      out->parameters.push_back(std::move(q));
    }
    for (const auto& [array_name, shape] : inner->arrays) {
      const std::string name = array_name;  // a copy: a lambda cannot capture a structured binding in C++20
      const bool parameter = std::any_of(inner->parameters.begin(), inner->parameters.end(),
                                         [&](const ParameterDecl& p) { return p.name.rfind(name + "[", 0) == 0; });
      if (parameter) out->arrays[prefix + "." + name] = shape;
    }
  }
}

}  // namespace

bool CallsLibraryFunction(const AstPtr& a) { return CallsAny(a); }

std::string PredicateName(const std::string& predicate, const std::string& record) {
  return predicate + "(" + record + ")";
}

bool UsesRecordsOrBlocks(const ComponentType& type, const Library& library) {
  if (!type.outers.empty() || !type.blocks.empty() || !type.roots.empty() || !type.potential_roots.empty() || !type.branches.empty()) return true;
  for (const auto& v : type.variables) {
    if (!v.record.empty()) return true;
  }
  for (const auto& c : type.connectors) {
    const ConnectorType* ct = library.FindConnector(c.type);
    if (ct && !ct->records.empty()) return true;
  }
  for (const auto* list : {&type.equations, &type.initial_equations}) {
    for (const auto& e : *list) {
      if (CallsAny(e.ast.lhs) || CallsAny(e.ast.rhs)) return true;
    }
  }
  return false;
}

ConnectorType ExpandRecords(ConnectorType connector, const Library& library) {
  std::vector<ConnectorVariable> out;
  for (const ConnectorVariable& v : connector.potentials) {
    if (v.record.empty()) {
      out.push_back(v);
      continue;
    }
    const RecordType& r = FindRecordOrFail(library, v.record, connector.loc, connector.name + "." + v.name);
    connector.records[v.name] = r.name;
    size_t counted = 0;
    for (const ConnectorVariable& f : r.fields) {
      const std::string field = v.name + "." + f.name;
      if (!f.shape.empty()) connector.arrays[field] = f.shape;
      for (size_t i = 0; i < ElementCount(f.shape); ++i) {
        ConnectorVariable e = f;
        e.name = f.shape.empty() ? field : ElementName(field, f.shape, i);
        e.shape.clear();
        e.counted = r.residues == 0 || counted++ < static_cast<size_t>(r.residues);
        out.push_back(std::move(e));
      }
    }
  }
  connector.potentials = std::move(out);
  return connector;
}

std::vector<VariableDecl> ExpandRecordVariables(const std::vector<VariableDecl>& variables, const Library& library,
                                                const std::string& owner, std::map<std::string, std::string>* records) {
  std::vector<VariableDecl> out;
  for (const VariableDecl& v : variables) {
    if (v.record.empty()) {
      out.push_back(v);
      continue;
    }
    const RecordType& r = FindRecordOrFail(library, v.record, v.loc, owner + v.name);
    (*records)[v.name] = r.name;
    for (const ConnectorVariable& f : r.fields) {
      VariableDecl e;
      e.name = v.name + "." + f.name;
      e.unit = f.unit;
      e.doc = f.doc;
      e.shape = f.shape;
      e.loc = v.loc;
      e.state_priority = v.state_priority;
      out.push_back(std::move(e));
    }
  }
  return out;
}

ComponentType ExpandRecordDeclarations(const ComponentType& type, const Library& library) {
  ComponentType out = type;
  for (const auto& c : type.connectors) {
    const ConnectorType* ct = library.FindConnector(c.type);
    if (!ct) continue;
    for (const auto& [name, record] : ct->records) out.records[c.name + "." + name] = record;
  }
  out.variables = ExpandRecordVariables(type.variables, library, type.name + ".", &out.records);
  DeclareOuters(type, library, &out);
  // The graph's predicates: hidden Boolean parameters, false until the graph sets them.
  std::set<std::string> predicates;
  for (auto* list : {&out.equations, &out.initial_equations}) {
    for (EquationDecl& e : *list) {
      e.guard = ReplacePredicates(e.guard, &predicates, type, e.loc);
      e.ast.lhs = ReplacePredicates(e.ast.lhs, &predicates, type, e.loc);
      e.ast.rhs = ReplacePredicates(e.ast.rhs, &predicates, type, e.loc);
    }
  }
  for (const std::string& name : predicates) {
    const std::string record = name.substr(name.find('(') + 1, name.size() - name.find('(') - 2);
    if (!out.records.count(record)) {
      throw ModelError(type.loc, name + " in " + type.name + ": " + record +
                                     " is not a record potential of one of its connectors");
    }
    ParameterDecl p;
    p.name = name;
    p.type = ValueType::kBoolean;
    auto f = std::make_shared<Ast>();
    f->kind = Ast::Kind::kBool;
    p.value = f;
    p.value_text = "false";
    p.doc = "set by the connection graph";
    p.loc = type.loc;
    out.parameters.push_back(std::move(p));
  }
  return out;
}

namespace {

/// Counts the local balance's equations of a type's blocks; throws at a block whose branches differ.
class BlockCounter {
 public:
  BlockCounter(const ComponentType& type) : type_(type) {}

  /// The counted equations: those outside any block, and one branch of each outermost block.
  size_t Count() {
    size_t outside = 0;
    for (const EquationDecl& e : type_.equations) {
      if (!e.counted) continue;
      if (e.blocks.empty()) {
        ++outside;
        continue;
      }
      ++direct_[{e.blocks.back().block, e.blocks.back().branch}];
      for (size_t k = 1; k < e.blocks.size(); ++k) {
        children_[{e.blocks[k - 1].block, e.blocks[k - 1].branch}].insert(e.blocks[k].block);
      }
      top_.insert(e.blocks.front().block);
    }
    // A block both of whose branches are empty of counted equations counts 0; so does a block
    // that appears in no equation.
    size_t total = outside;
    for (uint32_t b : top_) total += Block(b);
    return total;
  }

 private:
  size_t Branch(uint32_t block, uint32_t branch) {
    size_t n = direct_[{block, branch}];
    for (uint32_t child : children_[{block, branch}]) n += Block(child);
    return n;
  }
  size_t Block(uint32_t block) {
    const size_t a = Branch(block, 0), b = Branch(block, 1);
    if (a != b) {
      throw ModelError(type_.blocks[block],
                       "the branches of this conditional block of " + type_.name + " determine different numbers of unknowns: " +
                           "then " + Counted(a, "equation") + ", else " + Counted(b, "equation") +
                           " (an overdetermined record's equation counts as its residues); each branch must hold as many");
    }
    return a;
  }

  const ComponentType& type_;
  std::map<std::pair<uint32_t, uint32_t>, size_t> direct_;
  std::map<std::pair<uint32_t, uint32_t>, std::set<uint32_t>> children_;
  std::set<uint32_t> top_;
};

/// `0 = if guard then lhs - rhs else 0`.
void Guard(EquationDecl* e) {
  auto zero = [&] {
    auto z = std::make_shared<Ast>();
    z->kind = Ast::Kind::kNumber;
    z->column = e->ast.lhs->column;
    return AstPtr(z);
  };
  AstPtr diff = MakeAst(Ast::Kind::kSum, e->ast.lhs->column, "+-", {e->ast.lhs, e->ast.rhs});
  e->ast.rhs = MakeAst(Ast::Kind::kIf, e->ast.lhs->column, "if", {e->guard, diff, zero()});
  e->ast.lhs = zero();
}

}  // namespace

void FinishRecordsAndBlocks(ComponentType* type, const Library& library) {
  // The record variables' elements, in declaration order: the first residues are counted.
  std::map<std::string, size_t> seen;
  for (VariableDecl& v : type->variables) {
    for (const auto& [name, record] : type->records) {
      if (v.name.compare(0, name.size() + 1, name + ".") != 0) continue;
      const RecordType* r = library.FindRecord(record);
      if (r && r->residues > 0) v.counted = seen[name]++ < static_cast<size_t>(r->residues);
    }
  }
  size_t own = 0;
  for (const EquationDecl& e : type->equations) own += e.counted;
  const size_t counted = BlockCounter(*type).Count();
  size_t uncounted_by_records = 0;
  for (const EquationDecl& e : type->equations) uncounted_by_records += !e.counted;
  type->uncounted_equations = uncounted_by_records + (own - counted);
  for (auto* list : {&type->equations, &type->initial_equations}) {
    for (EquationDecl& e : *list) {
      if (e.guard) Guard(&e);
    }
  }
}

}  // namespace momenta
