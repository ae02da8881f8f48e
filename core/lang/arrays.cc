// The scalar form of arrays (core/lang/arrays.h). An expression is evaluated into an ArrayValue — a
// shape and the scalar syntax tree of each element, row by row — and the declarations and
// equations of a type or a model are rewritten element by element. A scalar subtree that contains
// no array is returned as it is (the same node), so scalar equations stay untouched.

#include "core/lang/arrays.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "core/lang/parser.h"

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

namespace {

/// "1" or "1,2": the subscripts of element `flat` (0-based, row-major).
std::string SubscriptText(const Shape& shape, size_t flat) {
  if (shape.size() == 2) {
    const size_t cols = static_cast<size_t>(shape[1]);
    return std::to_string(flat / cols + 1) + "," + std::to_string(flat % cols + 1);
  }
  return std::to_string(flat + 1);
}

}  // namespace

std::string ElementName(const std::string& name, const Shape& shape, size_t flat) {
  return name + "[" + SubscriptText(shape, flat) + "]";
}

namespace {

/// "a scalar" or "shape [2]", for messages.
std::string Described(const Shape& shape) { return shape.empty() ? "a scalar" : "shape " + ShapeText(shape); }

bool IsArrayFunction(const std::string& name) {
  return name == "transpose" || name == "cross" || name == "norm" || name == "identity" ||
         name == "zeros" || name == "sum";
}

/// Whether a tree uses array syntax: a literal, an array function, a matrix subscript, or (when
/// `any_subscript`) any subscript on a name's last segment.
bool UsesArraySyntax(const Ast& a, bool any_subscript) {
  if (a.kind == Ast::Kind::kArray) return true;
  if (a.kind == Ast::Kind::kCall && IsArrayFunction(a.op)) return true;
  if (a.kind == Ast::Kind::kName) {
    for (const NameSegment& s : a.path) {
      if (s.index2) return true;
    }
    return any_subscript && a.path.back().index;
  }
  for (const AstPtr& x : a.args) {
    if (UsesArraySyntax(*x, any_subscript)) return true;
  }
  return false;
}

bool UsesArraySyntax(const AstPtr& a, bool any_subscript) {
  return a && UsesArraySyntax(*a, any_subscript);
}

// The nodes one scalar form has made so far: matrix products and long chains of array operations
// multiply nodes, so they are counted and bounded (kMaxArrayNodes, about 150 MB of trees).
constexpr size_t kMaxArrayNodes = 1000000;
thread_local size_t t_nodes = 0;
thread_local int t_budget_depth = 0;

/// Starts the count of nodes for an outermost call (ScalarForm, ScalarModifiers, ScalarModel).
struct NodeBudget {
  NodeBudget() {
    if (t_budget_depth++ == 0) t_nodes = 0;
  }
  ~NodeBudget() { --t_budget_depth; }
  NodeBudget(const NodeBudget&) = delete;
  NodeBudget& operator=(const NodeBudget&) = delete;
};

AstPtr Node(Ast::Kind kind, int column, std::string op, std::vector<AstPtr> args) {
  ++t_nodes;
  return MakeAst(kind, column, std::move(op), std::move(args));
}

AstPtr Number(double v, int column) {
  ++t_nodes;
  auto a = std::make_shared<Ast>();
  a->kind = Ast::Kind::kNumber;
  a->number = v;
  a->column = column;
  return a;
}

/// x*y or x/y.
AstPtr Product(const AstPtr& x, char op, const AstPtr& y, int column) {
  return Node(Ast::Kind::kProduct, column, std::string("*") + op, {x, y});
}

/// The sum of `terms` (one term alone as it is).
AstPtr Sum(std::vector<AstPtr> terms, int column) {
  if (terms.size() == 1) return terms[0];
  std::string signs(terms.size(), '+');
  return Node(Ast::Kind::kSum, column, signs, std::move(terms));
}

/// The value of a tree of numbers and arithmetic, if it is one.
std::optional<double> ConstantValue(const Ast& a) {
  switch (a.kind) {
    case Ast::Kind::kNumber: return a.number;
    case Ast::Kind::kUnary: {
      if (a.op != "-") return std::nullopt;
      auto x = ConstantValue(*a.args[0]);
      return x ? std::optional<double>(-*x) : std::nullopt;
    }
    case Ast::Kind::kSum:
    case Ast::Kind::kProduct: {
      double r = a.kind == Ast::Kind::kSum ? 0 : 1;
      for (size_t k = 0; k < a.args.size(); ++k) {
        auto x = ConstantValue(*a.args[k]);
        if (!x) return std::nullopt;
        switch (a.op[k]) {
          case '+': r += *x; break;
          case '-': r -= *x; break;
          case '*': r *= *x; break;
          default: r /= *x; break;
        }
      }
      return r;
    }
    case Ast::Kind::kBinary: {
      if (a.op != "^") return std::nullopt;
      auto x = ConstantValue(*a.args[0]), y = ConstantValue(*a.args[1]);
      return x && y ? std::optional<double>(std::pow(*x, *y)) : std::nullopt;
    }
    default: return std::nullopt;
  }
}

/// A shape and the scalar tree of each element, row by row.
struct ArrayValue {
  Shape shape;
  std::vector<AstPtr> elements;
  bool scalar() const { return shape.empty(); }
};

// ---------------------------------------------------------------------------------------------
// Evaluation of one expression

class Evaluator {
 public:
  Evaluator(const ArrayScope& scope, const std::string& text, const SourceLoc& loc)
      : scope_(scope), text_(Excerpt(text, 0)), loc_(loc) {}

  ArrayValue Eval(const AstPtr& p) {
    ArrayValue v = EvalNode(p);
    CheckBudget(p->column);
    return v;
  }

  /// Stops when the nodes made so far exceed kMaxArrayNodes.
  void CheckBudget(int column) const {
    if (t_nodes > kMaxArrayNodes) {
      Fail(column, "the arrays expand to more than " + std::to_string(kMaxArrayNodes) +
                       " scalar expression nodes; use smaller arrays or fewer array operations");
    }
  }

  /// The scalar value of a tree that must not be an array (`what` names it in the message).
  AstPtr Scalar(const AstPtr& p, const std::string& what) {
    ArrayValue v = Eval(p);
    if (!v.scalar()) Fail(p->column, what + " must be a scalar, found shape " + ShapeText(v.shape));
    return v.elements[0];
  }

  [[noreturn]] void Fail(int column, const std::string& what) const {
    throw ModelError(loc_.Shifted(column), what + ", in '" + text_ + "'" +
                                               (scope_.owner.empty() ? "" : " of " + scope_.owner));
  }

 private:
  ArrayValue EvalNode(const AstPtr& p) {
    const Ast& a = *p;
    switch (a.kind) {
      case Ast::Kind::kNumber:
      case Ast::Kind::kBool: return {{}, {p}};
      case Ast::Kind::kName: return Name(p);
      case Ast::Kind::kArray: return Literal(a);
      case Ast::Kind::kUnary:
      case Ast::Kind::kSum: return Elementwise(p, Operands(a), a.op == "-" ? "-" : "+", false);
      case Ast::Kind::kProduct: return Multiply(p);
      case Ast::Kind::kBinary: {
        std::vector<ArrayValue> ops = Operands(a);
        for (const ArrayValue& v : ops) {
          if (!v.scalar()) {
            Fail(a.column, "'" + a.op + "' takes scalars, found an operand of shape " + ShapeText(v.shape));
          }
        }
        return Elementwise(p, std::move(ops), a.op, true);
      }
      case Ast::Kind::kIf: {
        std::vector<ArrayValue> ops = Operands(a);
        for (size_t k = 0; k + 1 < ops.size(); k += 2) {
          if (!ops[k].scalar()) {
            Fail(a.args[k]->column, "an if condition must be a scalar, found shape " + ShapeText(ops[k].shape));
          }
        }
        return Elementwise(p, std::move(ops), "if", true);
      }
      case Ast::Kind::kCall:
        if (IsArrayFunction(a.op)) return ArrayFunction(a);
        return Elementwise(p, Operands(a), a.op + "()", true);
    }
    return {{}, {p}};
  }

  std::vector<ArrayValue> Operands(const Ast& a) {
    std::vector<ArrayValue> ops;
    ops.reserve(a.args.size());
    for (const AstPtr& x : a.args) ops.push_back(Eval(x));
    return ops;
  }

  /// The operator in front of operand k, for messages: '+' or '-' in a sum.
  static std::string OpAt(const Ast& a, const std::string& op, size_t k) {
    if (a.kind == Ast::Kind::kSum) return std::string(1, a.op[k == 0 ? 1 : k]);
    return op;
  }

  /// A copy of node `a` over new operands.
  static AstPtr Rebuild(const Ast& a, std::vector<AstPtr> args) {
    AstPtr n = Node(a.kind, a.column, a.op, std::move(args));
    auto m = std::const_pointer_cast<Ast>(n);
    m->number = a.number;
    return n;
  }

  /// Node `p` applied element by element. Array operands must have the same shape; scalar
  /// operands apply to every element when `broadcast` (functions, if conditions), and are a
  /// shape mismatch otherwise (`a + b`).
  ArrayValue Elementwise(const AstPtr& p, std::vector<ArrayValue> ops, const std::string& op, bool broadcast) {
    const Ast& a = *p;
    Shape shape;
    bool same = true;
    for (size_t k = 0; k < ops.size(); ++k) {
      same = same && ops[k].scalar() && ops[k].elements[0] == a.args[k];
      if (ops[k].scalar()) continue;
      if (shape.empty()) {
        shape = ops[k].shape;
      } else if (ops[k].shape != shape) {
        Fail(a.kind == Ast::Kind::kSum ? a.args[k]->column : a.column, "the operands of '" + OpAt(a, op, k) + "' have different shapes: " + ShapeText(shape) +
                           " and " + ShapeText(ops[k].shape));
      }
    }
    if (shape.empty()) {
      if (same) return {{}, {p}};
      std::vector<AstPtr> args;
      for (auto& v : ops) args.push_back(v.elements[0]);
      return {{}, {Rebuild(a, std::move(args))}};
    }
    if (!broadcast) {
      for (size_t k = 0; k < ops.size(); ++k) {
        if (ops[k].scalar()) {
          Fail(a.args[k]->column, "the operands of '" + OpAt(a, op, k) + "' have different shapes: " + ShapeText(shape) +
                             " and scalar (add arrays of one shape; scale with * and /)");
        }
      }
    }
    ArrayValue out{shape, {}};
    const size_t n = ElementCount(shape);
    out.elements.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      std::vector<AstPtr> args;
      for (const ArrayValue& v : ops) args.push_back(v.scalar() ? v.elements[0] : v.elements[i]);
      out.elements.push_back(Rebuild(a, std::move(args)));
      CheckBudget(a.column);
    }
    return out;
  }

  /// A name: a scalar, a whole array, an element (`r[2]`, `R[1, 2]`) or a row of a matrix (`R[1]`).
  ArrayValue Name(const AstPtr& p) {
    const Ast& a = *p;
    const NameSegment& last = a.path.back();
    const Shape* shape = scope_.shape_of(a);
    if (!shape) {
      const bool component_element = scope_.component_arrays && a.path.size() == 1 && !last.index2;
      if (last.index && !component_element) {
        Fail(a.column, "'" + a.PathText() + "': " + last.name +
                           " is not an array (declare it with shape: [n]), so it has no elements");
      }
      return {{}, {p}};
    }
    auto element = [&](size_t flat) {
      ++t_nodes;
      auto n = std::make_shared<Ast>(a);
      n->path.back().name = ElementName(last.name, *shape, flat);
      n->path.back().index = nullptr;
      n->path.back().index2 = nullptr;
      n->height = 1;
      return AstPtr(n);
    };
    const size_t count = ElementCount(*shape);
    if (!last.index) {
      ArrayValue out{*shape, {}};
      out.elements.reserve(count);
      for (size_t i = 0; i < count; ++i) out.elements.push_back(element(i));
      return out;
    }
    if (last.index2 && shape->size() != 2) {
      Fail(a.column, "'" + a.PathText() + "' has two subscripts, but " + last.name + " has shape " +
                         ShapeText(*shape) + " (one subscript)");
    }
    const size_t i = Subscript(a, *last.index, (*shape)[0]);
    if (shape->size() == 1) return {{}, {element(i)}};
    const size_t cols = static_cast<size_t>((*shape)[1]);
    if (last.index2) return {{}, {element(i * cols + Subscript(a, *last.index2, (*shape)[1]))}};
    ArrayValue row{{(*shape)[1]}, {}};
    for (size_t j = 0; j < cols; ++j) row.elements.push_back(element(i * cols + j));
    return row;
  }

  /// A constant subscript within 1..size, 0-based.
  size_t Subscript(const Ast& name, const Ast& index, int size) {
    auto v = ConstantValue(index);
    const std::string what = "'" + name.PathText() + "'";
    if (!v) {
      Fail(name.column, "the subscript '" + AstToString(index) + "' of " + what +
                            " must be a constant whole number (a subscript picks a fixed element)");
    }
    if (*v != std::floor(*v) || *v < 1 || *v > size) {
      std::ostringstream s;
      s << *v;
      Fail(name.column, what + ": subscript " + s.str() + " is out of range 1.." + std::to_string(size) +
                            " (" + name.path.back().name + " has shape " + ShapeText(*scope_.shape_of(name)) + ")");
    }
    return static_cast<size_t>(*v) - 1;
  }

  /// `[a, b, …]`: elements of one shape make a vector of them, or a matrix of rows.
  ArrayValue Literal(const Ast& a) {
    std::vector<ArrayValue> items = Operands(a);
    const Shape& inner = items[0].shape;
    for (const ArrayValue& v : items) {
      if (v.shape != inner) {
        Fail(a.column, "the elements of an array literal have different shapes: " + ShapeText(inner) + " and " +
                           ShapeText(v.shape));
      }
    }
    if (inner.size() > 1) Fail(a.column, "arrays have one or two dimensions (vectors and matrices)");
    ArrayValue out;
    out.shape.push_back(static_cast<int>(items.size()));
    out.shape.insert(out.shape.end(), inner.begin(), inner.end());
    CheckSize(out.shape, a.column);
    for (ArrayValue& v : items) {
      for (AstPtr& e : v.elements) out.elements.push_back(std::move(e));
    }
    return out;
  }

  void CheckSize(const Shape& shape, int column) const {
    double n = 1;
    for (int d : shape) n *= d;
    if (n > static_cast<double>(kMaxArrayElements)) {
      Fail(column, "an array of shape " + ShapeText(shape) + " has more than " +
                       std::to_string(kMaxArrayElements) + " elements");
    }
  }

  /// A chain of * and /: scalars scale, a vector times a vector is their scalar product, and
  /// matrices multiply matrices and vectors; only a scalar divides.
  ArrayValue Multiply(const AstPtr& p) {
    const Ast& a = *p;
    std::vector<ArrayValue> ops = Operands(a);
    bool all_scalar = true;
    for (const ArrayValue& v : ops) all_scalar = all_scalar && v.scalar();
    if (all_scalar) return Elementwise(p, std::move(ops), "*", false);
    ArrayValue acc = std::move(ops[0]);
    for (size_t k = 1; k < ops.size(); ++k) {
      const ArrayValue& y = ops[k];
      if (a.op[k] == '/') {
        if (!y.scalar()) {
          Fail(a.column, "division by an array of shape " + ShapeText(y.shape) + "; only a scalar divides");
        }
        for (AstPtr& e : acc.elements) e = Product(e, '/', y.elements[0], a.column);
        continue;
      }
      acc = Times(acc, y, a.column);
    }
    return acc;
  }

  ArrayValue Times(const ArrayValue& x, const ArrayValue& y, int column) {
    ArrayValue out;
    if (x.scalar() || y.scalar()) {
      const ArrayValue& array = x.scalar() ? y : x;
      out.shape = array.shape;
      for (const AstPtr& e : array.elements) {
        out.elements.push_back(x.scalar() ? Product(x.elements[0], '*', e, column)
                                          : Product(e, '*', y.elements[0], column));
      }
      return out;
    }
    // x is n×k (a vector as 1×k), y is k×m (a vector as k×1).
    const bool x_vector = x.shape.size() == 1, y_vector = y.shape.size() == 1;
    const int n = x_vector ? 1 : x.shape[0], k = x_vector ? x.shape[0] : x.shape[1];
    const int k2 = y.shape[0], m = y_vector ? 1 : y.shape[1];
    if (k != k2) {
      Fail(column, "product of shapes " + ShapeText(x.shape) + " and " + ShapeText(y.shape) +
                       ": the inner dimensions " + std::to_string(k) + " and " + std::to_string(k2) + " differ");
    }
    if (!x_vector) out.shape.push_back(n);
    if (!y_vector) out.shape.push_back(m);
    CheckSize(out.shape, column);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) {
        std::vector<AstPtr> terms;
        for (int l = 0; l < k; ++l) {
          terms.push_back(Product(x.elements[static_cast<size_t>(i * k + l)], '*',
                                  y.elements[static_cast<size_t>(l * m + j)], column));
        }
        out.elements.push_back(Sum(std::move(terms), column));
        CheckBudget(column);
      }
    }
    return out;
  }

  ArrayValue ArrayFunction(const Ast& a) {
    const std::string f = a.op + "()";
    if (a.op == "identity" || a.op == "zeros") {
      Shape shape;
      for (const AstPtr& x : a.args) shape.push_back(Size(*x, f));
      if (a.op == "identity") shape.push_back(shape[0]);
      CheckSize(shape, a.column);
      ArrayValue out{shape, {}};
      for (size_t i = 0; i < ElementCount(shape); ++i) {
        const bool diagonal = a.op == "identity" && i % static_cast<size_t>(shape[0]) == i / static_cast<size_t>(shape[0]);
        out.elements.push_back(Number(diagonal ? 1 : 0, a.column));
      }
      return out;
    }
    std::vector<ArrayValue> ops = Operands(a);
    const ArrayValue& x = ops[0];
    auto expect = [&](bool ok, const std::string& wanted, const std::string& found) {
      if (!ok) Fail(a.column, f + " takes " + wanted + ", found " + found);
    };
    if (a.op == "transpose") {
      expect(x.shape.size() == 2, "a matrix", Described(x.shape));
      const size_t n = static_cast<size_t>(x.shape[0]), m = static_cast<size_t>(x.shape[1]);
      ArrayValue out{{x.shape[1], x.shape[0]}, std::vector<AstPtr>(n * m)};
      for (size_t i = 0; i < n; ++i) {
        for (size_t j = 0; j < m; ++j) out.elements[j * n + i] = x.elements[i * m + j];
      }
      return out;
    }
    if (a.op == "cross") {
      const ArrayValue& y = ops[1];
      expect(x.shape == Shape{3} && y.shape == Shape{3}, "two vectors of shape [3]",
             Described(x.shape) + " and " + Described(y.shape));
      ArrayValue out{{3}, {}};
      for (size_t i = 0; i < 3; ++i) {
        const size_t j = (i + 1) % 3, k = (i + 2) % 3;
        out.elements.push_back(Node(Ast::Kind::kSum, a.column, "+-",
                                    {Product(x.elements[j], '*', y.elements[k], a.column),
                                     Product(x.elements[k], '*', y.elements[j], a.column)}));
      }
      return out;
    }
    if (a.op == "norm") {
      expect(x.shape.size() == 1, "a vector", Described(x.shape));
      std::vector<AstPtr> squares;
      for (const AstPtr& e : x.elements) squares.push_back(Product(e, '*', e, a.column));
      return {{}, {Node(Ast::Kind::kCall, a.column, "sqrt", {Sum(std::move(squares), a.column)})}};
    }
    // sum
    expect(!x.scalar(), "an array", "a scalar");
    return {{}, {Sum(x.elements, a.column)}};
  }

  /// A size given to identity() or zeros(): a constant whole number of at least 1.
  int Size(const Ast& x, const std::string& f) {
    auto v = ConstantValue(x);
    if (!v || *v != std::floor(*v) || *v < 1 || *v > static_cast<double>(kMaxArrayElements)) {
      Fail(x.column, "the size '" + AstToString(x) + "' given to " + f +
                         " must be a constant whole number from 1 to " + std::to_string(kMaxArrayElements));
    }
    return static_cast<int>(*v);
  }

  const ArrayScope& scope_;
  std::string text_;
  SourceLoc loc_;
};

// ---------------------------------------------------------------------------------------------
// Declarations of a type or of the model

/// The shape of an array literal as written (before any name is looked up), or empty.
Shape LiteralShape(const AstPtr& a) {
  if (!a || a->kind != Ast::Kind::kArray) return {};
  Shape s{static_cast<int>(a->args.size())};
  if (a->args[0]->kind == Ast::Kind::kArray) s.push_back(static_cast<int>(a->args[0]->args.size()));
  return s;
}

/// Rewrites the declarations of one scope (a type or the model) element by element.
class Scalariser {
 public:
  Scalariser(ArrayScope scope, ArrayShapes* table, std::string who)
      : scope_(std::move(scope)), table_(table), who_(std::move(who)) {}

  const ArrayScope& scope() const { return scope_; }

  /// The value of `a` (written at `loc`, text `text`) with the shape `shape` must have: a scalar
  /// fills every element; an array must have that shape.
  std::vector<AstPtr> Fill(const AstPtr& a, const std::string& text, const SourceLoc& loc, const Shape& shape,
                           const std::string& what) {
    Evaluator ev(scope_, text, loc);
    ArrayValue v = ev.Eval(a);
    if (v.scalar()) return std::vector<AstPtr>(ElementCount(shape), v.elements[0]);
    if (v.shape != shape) {
      ev.Fail(a->column, what + " has shape " + ShapeText(v.shape) + ", but " +
                             (shape.empty() ? "it is a scalar (declare shape: " + ShapeText(v.shape) + ")"
                                            : "it is declared with shape " + ShapeText(shape)));
    }
    return v.elements;
  }

  std::vector<ParameterDecl> Parameters(const std::vector<ParameterDecl>& params) {
    // Shapes first (declared, or of a literal value), so that values may use later arrays.
    for (const auto& p : params) {
      Shape s = p.shape.empty() ? LiteralShape(p.value) : p.shape;
      if (!s.empty()) (*table_)[p.name] = s;
    }
    std::vector<ParameterDecl> out;
    for (const auto& p : params) {
      auto found = table_->find(p.name);
      Shape shape = found == table_->end() ? Shape{} : found->second;
      if (shape.empty()) {
        // A parameter without shape whose value is an array expression takes its shape.
        Evaluator ev(scope_, p.value_text, p.loc);
        ArrayValue v = ev.Eval(p.value);
        if (v.scalar()) {
          out.push_back(p);
          out.back().value = v.elements[0];
          continue;
        }
        shape = (*table_)[p.name] = v.shape;
      }
      std::vector<AstPtr> values = Fill(p.value, p.value_text, p.loc, shape, "the value of " + Who(p.name));
      for (size_t i = 0; i < values.size(); ++i) {
        ParameterDecl e = p;
        e.name = ElementName(p.name, shape, i);
        e.value = values[i];
        e.value_text = AstToString(*values[i]);
        e.shape.clear();
        out.push_back(std::move(e));
      }
    }
    return out;
  }

  /// `signals`: shaped signal connectors, whose attributes `variables:` may give under their name.
  std::vector<VariableDecl> Variables(const std::vector<VariableDecl>& vars, const ArrayShapes& signals) {
    for (const auto& v : vars) {
      auto sig = signals.find(v.name);
      if (sig != signals.end() && !v.shape.empty() && v.shape != sig->second) {
        throw ModelError(v.loc, Who(v.name) + " is declared with shape " + ShapeText(v.shape) +
                                    ", but its connector has shape " + ShapeText(sig->second));
      }
      if (!v.shape.empty()) (*table_)[v.name] = v.shape;
    }
    std::vector<VariableDecl> out;
    for (const auto& v : vars) {
      auto sig = signals.find(v.name);
      const Shape shape = sig != signals.end() ? sig->second : v.shape;
      if (shape.empty()) {
        out.push_back(v);
        if (v.start) {
          Evaluator ev(scope_, AstToString(*v.start), v.loc);
          out.back().start = ev.Scalar(v.start, "the start value of " + Who(v.name));
        }
        continue;
      }
      std::vector<AstPtr> starts;
      if (v.start) starts = Fill(v.start, AstToString(*v.start), v.loc, shape, "the start value of " + Who(v.name));
      for (size_t i = 0; i < ElementCount(shape); ++i) {
        VariableDecl e = v;
        e.name = ElementName(v.name, shape, i);
        if (v.start) e.start = starts[i];
        e.shape.clear();
        out.push_back(std::move(e));
      }
    }
    return out;
  }

  std::vector<EquationDecl> Equations(const std::vector<EquationDecl>& eqs) {
    std::vector<EquationDecl> out;
    out.reserve(eqs.size());
    for (const auto& e : eqs) {
      Evaluator ev(scope_, e.text, e.loc);
      ArrayValue l = ev.Eval(e.ast.lhs), r = ev.Eval(e.ast.rhs);
      if (l.shape != r.shape) {
        ev.Fail(e.ast.rhs->column, "the two sides of the equation have different shapes: " + ShapeText(l.shape) +
                                       " and " + ShapeText(r.shape));
      }
      if (l.scalar()) {
        out.push_back(e);
        out.back().ast = {l.elements[0], r.elements[0]};
        continue;
      }
      for (size_t i = 0; i < l.elements.size(); ++i) {
        out.push_back({e.text + " (element " + SubscriptText(l.shape, i) + ")", {l.elements[i], r.elements[i]}, e.loc});
      }
    }
    return out;
  }

  /// When-clauses: a scalar condition; a statement on an array runs on each element.
  std::vector<WhenDecl> Whens(const std::vector<WhenDecl>& whens) {
    std::vector<WhenDecl> out;
    for (const auto& w : whens) {
      WhenDecl d = w;
      d.condition = Evaluator(scope_, w.text, w.loc).Scalar(w.condition, "a when condition");
      d.statements.clear();
      for (const auto& st : w.statements) {
        Evaluator ev(scope_, st.text, st.loc);
        ArrayValue target = ev.Eval(ParseName(st.target, st.loc));
        ArrayValue value = ev.Eval(st.value);
        if (!value.scalar() && value.shape != target.shape) {
          ev.Fail(st.value->column, "the value has shape " + ShapeText(value.shape) + ", but '" + st.target +
                                        "' has shape " + ShapeText(target.shape));
        }
        for (size_t i = 0; i < target.elements.size(); ++i) {
          StatementDecl e = st;
          e.target = target.elements[i]->PathText();
          e.value = value.scalar() ? value.elements[0] : value.elements[i];
          if (!target.scalar()) e.text += " (element " + SubscriptText(target.shape, i) + ")";
          d.statements.push_back(std::move(e));
        }
      }
      out.push_back(std::move(d));
    }
    return out;
  }

  std::string Who(const std::string& name) const { return who_.empty() ? name : who_ + "." + name; }

 private:
  ArrayScope scope_;
  ArrayShapes* table_;
  std::string who_;
};

/// The local name a kName refers to: its segments' names joined by '.', subscripts left out.
std::string JoinedName(const Ast& a, size_t from) {
  std::string s;
  for (size_t k = from; k < a.path.size(); ++k) {
    if (k > from) s += '.';
    s += a.path[k].name;
  }
  return s;
}

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
  if (ConnectorHasArrays(type, library)) return true;
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

ComponentType ScalarForm(const ComponentType& type, const Library& library) {
  NodeBudget budget;
  ComponentType out = type;
  out.arrays.clear();
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
  Scalariser s(TypeScope(&table, type.name), &table, type.name);
  out.parameters = s.Parameters(type.parameters);
  out.variables = s.Variables(type.variables, signals);
  out.equations = s.Equations(type.equations);
  out.initial_equations = s.Equations(type.initial_equations);
  out.whens = s.Whens(type.whens);
  for (auto& im : out.impacts) {
    auto scalar = [&](AstPtr* a, const std::string& text) {
      *a = Evaluator(s.scope(), text, im.loc).Scalar(*a, "an impact's expression");
    };
    scalar(&im.gap, im.gap_text);
    scalar(&im.velocity, im.velocity_text);
    scalar(&im.restitution, im.restitution_text);
    scalar(&im.v_small, im.v_small_text);
    scalar(&im.release, im.release_text);
  }
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
  NodeBudget budget;
  std::vector<Modifier> out;
  Scalariser s(scope, nullptr, "");
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
    if (!v.shape.empty() || UsesArraySyntax(v.start, false)) return true;
  }
  for (const auto* list : {&spec.equations, &spec.initial_equations}) {
    for (const auto& e : *list) {
      if (UsesArraySyntax(e.ast.lhs, false) || UsesArraySyntax(e.ast.rhs, false)) return true;
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
  Evaluator ev(scope, text, loc);
  ArrayValue v = ev.Eval(end);
  EndElements out{v.shape, {}, {}};
  for (size_t i = 0; i < v.elements.size(); ++i) {
    out.ends.push_back(v.elements[i]);
    out.texts.push_back(v.scalar() ? (v.elements[0] == end ? text : v.elements[0]->PathText())
                                   : ElementName(text, v.shape, i));
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
  NodeBudget budget;

  ModelSpec out = spec;
  // The types first: the model's names see their arrays.
  defined.clear();
  for (auto& d : out.defines) {
    if (NeedsScalarForm(d, library)) d = ScalarForm(d, library);
    defined[d.name] = &d;
  }
  std::unordered_map<std::string, const ComponentType*> component_type;
  for (const auto& c : spec.components) component_type[c.name] = type_of(c.type);
  // The parts of composite types: their modifiers in the scope of the type that holds them.
  for (auto& d : out.defines) {
    for (auto& c : d.components) {
      if (const ComponentType* t = type_of(c.type)) c.modifiers = ScalarModifiers(c, *t, ScopeOf(d));
    }
  }

  // The model scope: model parameters and variables, and `component.name` in a component's type.
  ArrayShapes table;
  ArrayScope scope;
  scope.component_arrays = true;
  scope.shape_of = [&](const Ast& name) -> const Shape* {
    if (name.path.size() == 1) {
      auto it = table.find(name.path[0].name);
      return it == table.end() ? nullptr : &it->second;
    }
    auto c = component_type.find(name.path[0].name);
    if (c == component_type.end() || !c->second) return nullptr;
    // Down through the parts of composite types (pair.body.r), then the type's own arrays.
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
  Scalariser s(scope, &table, "");
  out.parameters = s.Parameters(spec.parameters);
  out.variables = s.Variables(spec.variables, {});
  out.equations = s.Equations(spec.equations);
  out.initial_equations = s.Equations(spec.initial_equations);
  out.whens = s.Whens(spec.whens);
  for (auto& c : out.components) {
    if (const ComponentType* t = component_type[c.name]) c.modifiers = ScalarModifiers(c, *t, scope);
  }

  // Connections: shaped signal connectors are joined element by element.
  out.connections.clear();
  for (const auto& c : spec.connections) {
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
      out.connections.push_back(std::move(e));
    }
  }

  // Outputs: a whole array is one column per element.
  out.outputs.clear();
  for (const auto& o : spec.outputs) {
    ArrayValue v = Evaluator(scope, o.text, o.loc).Eval(o.expr);
    const bool name = o.expr->kind == Ast::Kind::kName;
    for (size_t i = 0; i < v.elements.size(); ++i) {
      OutputSpec e = o;
      e.expr = v.elements[i];
      if (!v.scalar()) e.text = ElementName(name ? o.text : "(" + o.text + ")", v.shape, i);
      out.outputs.push_back(std::move(e));
    }
  }
  return out;
}

}  // namespace momenta
