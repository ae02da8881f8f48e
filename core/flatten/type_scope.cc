#include "core/flatten/type_scope.h"

#include <cmath>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/expr/expr_chain.h"
#include "core/lang/arrays.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

namespace {

/// Lowers the expressions of one text of a type into one template.
class TypeLowering {
 public:
  TypeLowering(const TypeLayout& layout, std::string text, const SourceLoc& loc, bool params_only,
               const LoopIndex* loop, Template* out)
      : layout_(layout), text_(std::move(text)), loc_(loc), params_only_(params_only), loop_(loop), out_(*out) {}

  int32_t Add(const Ast& a);

 private:
  int32_t Push(const TNode& node) {
    out_.nodes.push_back(node);
    return static_cast<int32_t>(out_.nodes.size() - 1);
  }
  /// The local name a dotted path inside a type stands for, subscripts evaluated: links[2].phi.
  std::string LocalPath(const Ast& a);
  /// The table operand of `interpolate(table, x[, column])`: a table of the type, and a column
  /// that is a whole number (default 2), checked against the declared columns.
  TNode TableOperand(const Ast& a, size_t dims);

  const TypeLayout& layout_;
  const std::string text_;  ///< as messages quote it
  const SourceLoc loc_;
  const bool params_only_;
  const LoopIndex* loop_;
  Template& out_;
};

int32_t TypeLowering::Add(const Ast& a) {
  TNode n;
  auto child = [&](size_t k) { return Add(*a.args[k]); };
  const std::string& owner = layout_.type->name;
  const std::string& text = text_;
  const SourceLoc& loc = loc_;
  const bool params_only = params_only_;
  switch (a.kind) {
    case Ast::Kind::kNumber:
    case Ast::Kind::kBool:
      n.kind = TNode::kConst;
      n.value = a.number;
      return Push(n);
    case Ast::Kind::kName: {
      if (loop_ && a.path.size() == 1 && !a.path[0].index && a.path[0].name == loop_->first) {
        n.kind = TNode::kConst;  // the element index i in a part array's modifiers
        n.value = loop_->second;
        return Push(n);
      }
      std::string local = LocalPath(a);
      auto v = layout_.var_index.find(local);
      if (v != layout_.var_index.end()) {
        if (params_only) {
          throw ModelError(loc.Shifted(a.column), "'" + local + "' is a variable of " + owner +
                                                      "; a parameter's value or a start value may only use parameters, in '" + text + "'");
        }
        n.kind = TNode::kLocalVar;
        n.local = v->second;
        return Push(n);
      }
      if (layout_.table_index.count(local)) {
        throw ModelError(loc.Shifted(a.column), "'" + local + "' is a table of " + owner +
                                                    "; read it with interpolate(" + local + ", x), in '" + text + "'");
      }
      auto p = layout_.param_index.find(local);
      if (p != layout_.param_index.end()) {
        n.kind = TNode::kLocalParam;
        n.local = p->second;
        return Push(n);
      }
      if (local == "time" && !params_only) {
        n.kind = TNode::kTime;
        return Push(n);
      }
      if (local == "pi") {
        n.kind = TNode::kConst;
        n.value = M_PI;
        return Push(n);
      }
      auto names = layout_.LocalNames();
      auto close = ClosestNames(local, names);
      throw ModelError(loc.Shifted(a.column),
                       "unknown name '" + local + "' in '" + text + "' of " + owner +
                           (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                           " (valid names: " + JoinNames(names) + ", time, pi)");
    }
    case Ast::Kind::kArray:
      throw ModelError(loc.Shifted(a.column), "an array where a number is expected, in '" + text + "' of " + owner);
    case Ast::Kind::kUnary:
      n.kind = TNode::kOp;
      n.op = a.op == "not" ? Op::kNot : Op::kNeg;
      n.a = child(0);
      return Push(n);
    case Ast::Kind::kBinary:
    case Ast::Kind::kSum:
    case Ast::Kind::kProduct: {
      // A chain as a balanced tree, as in the model scope.
      std::vector<int32_t> operands;
      for (size_t k = 0; k < a.args.size(); ++k) operands.push_back(child(k));
      return BuildChain(operands, ChainInverse(a), [&](int32_t x, bool inverse, int32_t y) {
        TNode op;
        op.kind = TNode::kOp;
        op.op = ChainOp(a, inverse);
        op.a = x;
        op.b = y;
        return Push(op);
      });
    }
    case Ast::Kind::kIf: {
      // An elseif chain nested from the last branch.
      std::vector<int32_t> operands;
      for (size_t k = 0; k < a.args.size(); ++k) operands.push_back(child(k));
      return BuildIfChain(operands, [&](int32_t c, int32_t x, int32_t y) {
        TNode branch;
        branch.kind = TNode::kOp;
        branch.op = Op::kIf;
        branch.a = c;
        branch.b = x;
        branch.c = y;
        return Push(branch);
      });
    }
    case Ast::Kind::kCall: {
      Op op;
      if (FunctionOp(a.op, &op)) {
        n.kind = TNode::kOp;
        n.op = op;
        n.a = child(0);
        if (Arity(op) == 2) n.b = child(1);
        return Push(n);
      }
      SourceLoc at = loc.Shifted(a.column);
      if (params_only) throw ModelError(at, a.op + "() cannot be used in a parameter's value, in '" + text + "'");
      if (a.op == "noEvent") {
        n.kind = TNode::kNoEvent;
        n.a = child(0);
        return Push(n);
      }
      if (a.op == "timeTable" || a.op == "booleanTable") {
        const bool boolean = a.op == "booleanTable";
        TNode table = TableOperand(a, boolean ? 1 : 2);
        if (table.value == 0) table.c = child(2);
        n.kind = boolean ? TNode::kBooleanTable : TNode::kTimeTable;
        n.a = child(1);
        n.b = Push(table);
        if (!boolean) {
          n.c = child(3);
          n.local = static_cast<uint32_t>(child(4));
        }
        return Push(n);
      }
      if (a.op == "interpolate") {
        TNode table = TableOperand(a, 2);
        if (table.value == 0) table.c = child(2);
        n.kind = TNode::kOp;
        n.op = Op::kInterp;
        n.a = child(1);
        n.b = Push(table);
        return Push(n);
      }
      if (a.op == "der") {
        n.kind = TNode::kDerOf;
        n.a = child(0);
        return Push(n);
      }
      if (a.op == "initial") {
        n.kind = TNode::kInitial;
        return Push(n);
      }
      if (a.op == "reinit") throw ModelError(at, "reinit() belongs in a when-clause, in '" + text + "'");
      int32_t x = child(0);
      if (out_.nodes[x].kind != TNode::kLocalVar) {
        throw ModelError(at, a.op + "() takes a variable, in '" + text + "'");
      }
      TNode pre;
      pre.kind = TNode::kPre;
      pre.local = out_.nodes[x].local;
      int32_t pre_id = Push(pre);
      if (a.op == "pre") return pre_id;
      TNode r;
      r.kind = TNode::kOp;
      if (a.op == "edge") {
        TNode notp;
        notp.kind = TNode::kOp;
        notp.op = Op::kNot;
        notp.a = pre_id;
        int32_t not_id = Push(notp);
        r.op = Op::kAnd;
        r.a = x;
        r.b = not_id;
      } else {  // change
        r.op = Op::kNe;
        r.a = x;
        r.b = pre_id;
      }
      return Push(r);
    }
  }
  return -1;
}

std::string TypeLowering::LocalPath(const Ast& a) {
  std::string local;
  for (size_t k = 0; k < a.path.size(); ++k) {
    if (k) local += ".";
    local += a.path[k].name;
    if (!a.path[k].index) continue;
    std::optional<double> i = ConstantValue(*a.path[k].index, loop_);
    if (!i || !std::isfinite(*i) || *i != std::floor(*i)) {
      throw ModelError(loc_.Shifted(a.column), "a subscript inside a type must be a whole number (or the index i of an array part), in '" + text_ + "'");
    }
    local += "[" + NumberText(*i) + "]";
  }
  return local;
}

TNode TypeLowering::TableOperand(const Ast& a, size_t dims) {
  const std::string& owner = layout_.type->name;
  const std::string& text = text_;
  const SourceLoc& loc = loc_;
  const Ast& name = *a.args[0];
  std::vector<std::string> tables;
  for (const auto& slot : layout_.tables) tables.push_back(slot.decl->name);
  const std::string valid = " (tables of " + owner + ": " + (tables.empty() ? "none; declare one with shape: [\":\", 2]" : JoinNames(tables)) + ")";
  auto found = name.kind == Ast::Kind::kName && name.path.size() == 1 && !name.path[0].index
                   ? layout_.table_index.find(name.path[0].name)
                   : layout_.table_index.end();
  if (found == layout_.table_index.end()) {
    throw ModelError(loc.Shifted(name.column), "the first argument of interpolate() must name a table, found '" +
                                                   AstToString(name) + "' in '" + text + "' of " + owner + valid);
  }
  const ParameterDecl& d = *layout_.tables[found->second].decl;
  if (d.shape.size() != dims) {
    throw ModelError(loc.Shifted(name.column),
                     a.op + "() takes " + (dims == 2 ? "a table of rows {x, y1, y2, …}" : "a vector of times") + ", but " +
                         owner + "." + d.name + " has shape " + ShapeText(d.shape) + ", in '" + text + "'");
  }
  double column = dims == 2 ? 2 : 1;
  if (dims == 2 && a.args.size() >= 3) {
    std::optional<double> c = ConstantValue(*a.args[2], loop_);
    if (!c && a.args[2]->kind == Ast::Kind::kName) {
      column = 0;  // a parameter: the caller adds it as the node's child c
    } else if (!c || *c != std::floor(*c) || *c < 1 || (d.shape[1] != kOpenSize && *c > d.shape[1])) {
      throw ModelError(loc.Shifted(a.args[2]->column),
                       "the column of " + a.op + "() must be a whole number from 1 to the table's columns" +
                           std::string(d.shape[1] != kOpenSize ? " (" + std::to_string(d.shape[1]) + ")" : "") +
                           ", found '" + AstToString(*a.args[2]) + "' in '" + text + "' of " + owner);
    } else {
      column = *c;
    }
  }
  TNode n;
  n.kind = TNode::kTable;
  n.local = found->second;
  n.value = column;
  return n;
}

}  // namespace

std::optional<double> ConstantValue(const Ast& a, const LoopIndex* loop) {
  switch (a.kind) {
    case Ast::Kind::kNumber:
      return a.number;
    case Ast::Kind::kName:
      if (loop && a.path.size() == 1 && !a.path[0].index && a.path[0].name == loop->first) return loop->second;
      return std::nullopt;
    case Ast::Kind::kUnary: {
      if (a.op != "-") return std::nullopt;
      auto x = ConstantValue(*a.args[0], loop);
      if (!x) return std::nullopt;
      return -*x;
    }
    case Ast::Kind::kSum:
    case Ast::Kind::kProduct: {
      std::vector<bool> inverse = InverseFlags(a.op);
      double r = a.kind == Ast::Kind::kSum ? 0 : 1;
      for (size_t k = 0; k < a.args.size(); ++k) {
        auto x = ConstantValue(*a.args[k], loop);
        if (!x) return std::nullopt;
        if (a.kind == Ast::Kind::kSum) {
          r += inverse[k] ? -*x : *x;
        } else {
          r = inverse[k] ? r / *x : r * *x;
        }
      }
      return r;
    }
    default:
      return std::nullopt;
  }
}

Template MakeTemplate(const TypeLayout& layout, const Ast& a, const std::string& text, const SourceLoc& loc,
                      bool params_only, const LoopIndex* loop) {
  Template t;
  t.root = TypeLowering(layout, Excerpt(text, 0), loc, params_only, loop, &t).Add(a);
  return t;
}

Template EquationTemplate(const TypeLayout& layout, const EquationDecl& e) {
  Template t;
  TypeLowering lowering(layout, Excerpt(e.text, 0), e.loc, false, nullptr, &t);  // messages quote the text
  int32_t lhs = lowering.Add(*e.ast.lhs);
  int32_t rhs = lowering.Add(*e.ast.rhs);
  TNode n;
  n.kind = TNode::kOp;
  n.op = Op::kSub;
  n.a = lhs;
  n.b = rhs;
  t.nodes.push_back(n);
  t.root = static_cast<int32_t>(t.nodes.size() - 1);
  return t;
}

}  // namespace momenta::flatten_internal
