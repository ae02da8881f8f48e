// The type scope: a type's expressions lowered into templates over its local indices
// (TypeLowering), names resolved to its variables, parameters and tables.

#include "core/flatten/type_scope.h"

#include <cmath>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/expr/expr_chain.h"
#include "core/lang/arrays.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

namespace {

/// The type scope as a LoweringScope: the expressions of one text of a type lowered into one
/// template.
class TypeLowering {
 public:
  using Node = int32_t;  ///< a node of the template
  /// Operands in the order written, as a template lists its nodes.
  static constexpr bool kSecondOperandFirst = false;

  TypeLowering(const TypeLayout& layout, std::string text, const SourceLoc& loc, bool params_only,
               const LoopIndex* loop, Template* out)
      : layout_(layout), text_(std::move(text)), loc_(loc), params_only_(params_only), loop_(loop), out_(*out) {}

  Node Constant(double value) {
    TNode n;
    n.kind = TNode::kConst;
    n.value = value;
    return Push(n);
  }
  Node Name(const Ast& a);
  Node Unary(Op op, Node x) {
    TNode n;
    n.kind = TNode::kOp;
    n.op = op;
    n.a = x;
    return Push(n);
  }
  Node Negate(Node x) { return Unary(Op::kNeg, x); }
  Node Binary(Op op, Node x, Node y) {
    TNode n;
    n.kind = TNode::kOp;
    n.op = op;
    n.a = x;
    n.b = y;
    return Push(n);
  }
  Node If(Node c, Node x, Node y) {
    TNode n;
    n.kind = TNode::kOp;
    n.op = Op::kIf;
    n.a = c;
    n.b = x;
    n.c = y;
    return Push(n);
  }
  Node NoEvent(Node x) { return Wrap(TNode::kNoEvent, x); }
  Node Der(Node x) { return Wrap(TNode::kDerOf, x); }
  Node Initial() {
    TNode n;
    n.kind = TNode::kInitial;
    return Push(n);
  }
  bool IsVariable(Node x) const { return out_.nodes[x].kind == TNode::kLocalVar; }
  Node Pre(Node x) {
    TNode n;
    n.kind = TNode::kPre;
    n.local = out_.nodes[x].local;
    return Push(n);
  }
  /// A parameter's value and a start value may call nothing but the pool's functions; reinit()
  /// belongs in a when-clause.
  void CheckCall(const Ast& a) const {
    if (params_only_) Fail(a, a.op + "() cannot be used in a parameter's value, in '" + text_ + "'");
    if (a.op == "reinit") Fail(a, "reinit() belongs in a when-clause, in '" + text_ + "'");
  }
  std::optional<Node> TableCall(const Ast& a);
  const std::string& text() const { return text_; }
  std::string OfOwner() const { return " of " + layout_.type->name; }
  [[noreturn]] void Fail(const Ast& at, const std::string& message) const {
    throw ModelError(loc_.Shifted(at.column), message);
  }

 private:
  Node Push(const TNode& node) {
    out_.nodes.push_back(node);
    return static_cast<Node>(out_.nodes.size() - 1);
  }
  /// A node of `kind` over x (noEvent, der).
  Node Wrap(TNode::Kind kind, Node x) {
    TNode n;
    n.kind = kind;
    n.a = x;
    return Push(n);
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

TypeLowering::Node TypeLowering::Name(const Ast& a) {
  const std::string& owner = layout_.type->name;
  if (loop_ && a.path.size() == 1 && !a.path[0].index && a.path[0].name == loop_->first) {
    return Constant(loop_->second);  // the element index i in a part array's modifiers
  }
  std::string local = LocalPath(a);
  auto v = layout_.var_index.find(local);
  if (v != layout_.var_index.end()) {
    if (params_only_) {
      Fail(a, "'" + local + "' is a variable of " + owner +
                  "; a parameter's value or a start value may only use parameters, in '" + text_ + "'");
    }
    TNode n;
    n.kind = TNode::kLocalVar;
    n.local = v->second;
    return Push(n);
  }
  if (layout_.table_index.count(local)) {
    Fail(a, "'" + local + "' is a table of " + owner + "; read it with interpolate(" + local + ", x), in '" + text_ + "'");
  }
  auto p = layout_.param_index.find(local);
  if (p != layout_.param_index.end()) {
    TNode n;
    n.kind = TNode::kLocalParam;
    n.local = p->second;
    return Push(n);
  }
  if (local == "time" && !params_only_) {
    TNode n;
    n.kind = TNode::kTime;
    return Push(n);
  }
  if (local == "pi") return Constant(M_PI);
  auto names = layout_.LocalNames();
  auto close = ClosestNames(local, names);
  Fail(a, "unknown name '" + local + "' in '" + text_ + "' of " + owner +
              (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
              " (valid names: " + JoinNames(names) + ", time, pi)");
}

/// interpolate(table, x[, column]) as an interpolation of the table's node; timeTable(table, x,
/// column, smoothness, extrapolation) and booleanTable(table, x) as nodes that each instance
/// expands (TableExpansion). A column given by a parameter is lowered first, as the table node's
/// child c.
std::optional<TypeLowering::Node> TypeLowering::TableCall(const Ast& a) {
  auto operand = [&](size_t k) { return Lower(*a.args[k], this); };
  TNode n;
  if (a.op == "timeTable" || a.op == "booleanTable") {
    const bool boolean = a.op == "booleanTable";
    TNode table = TableOperand(a, boolean ? 1 : 2);
    if (table.value == 0) table.c = operand(2);
    n.kind = boolean ? TNode::kBooleanTable : TNode::kTimeTable;
    n.a = operand(1);
    n.b = Push(table);
    if (!boolean) {
      n.c = operand(3);
      n.local = static_cast<uint32_t>(operand(4));
    }
    return Push(n);
  }
  if (a.op == "interpolate") {
    TNode table = TableOperand(a, 2);
    if (table.value == 0) table.c = operand(2);
    n.kind = TNode::kOp;
    n.op = Op::kInterp;
    n.a = operand(1);
    n.b = Push(table);
    return Push(n);
  }
  return std::nullopt;
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
    local += '[';
    local += NumberText(*i);
    local += ']';
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
  const ParameterDecl& decl = *layout_.tables[found->second].decl;
  if (decl.shape.size() != dims) {
    throw ModelError(loc.Shifted(name.column),
                     a.op + "() takes " + (dims == 2 ? "a table of rows {x, y1, y2, …}" : "a vector of times") + ", but " +
                         owner + "." + decl.name + " has shape " + ShapeText(decl.shape) + ", in '" + text + "'");
  }
  double column = dims == 2 ? 2 : 1;
  if (dims == 2 && a.args.size() >= 3) {
    std::optional<double> c = ConstantValue(*a.args[2], loop_);
    if (!c && a.args[2]->kind == Ast::Kind::kName) {
      column = 0;  // a parameter: the caller adds it as the node's child c
    } else if (!c || *c != std::floor(*c) || *c < 1 || (decl.shape[1] != kOpenSize && *c > decl.shape[1])) {
      throw ModelError(loc.Shifted(a.args[2]->column),
                       "the column of " + a.op + "() must be a whole number from 1 to the table's columns" +
                           std::string(decl.shape[1] != kOpenSize ? " (" + std::to_string(decl.shape[1]) + ")" : "") +
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
  TypeLowering scope(layout, Excerpt(text, 0), loc, params_only, loop, &t);  // messages quote the text
  t.root = Lower(a, &scope);
  return t;
}

Template EquationTemplate(const TypeLayout& layout, const EquationDecl& e) {
  Template t;
  TypeLowering scope(layout, Excerpt(e.text, 0), e.loc, false, nullptr, &t);  // messages quote the text
  const int32_t lhs = Lower(*e.ast.lhs, &scope);
  const int32_t rhs = Lower(*e.ast.rhs, &scope);
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
