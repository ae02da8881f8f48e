// The evaluation of one expression on arrays (core/lang/array_expression.h): a walk of the syntax
// tree that gives every node its shape and its elements' scalar trees, counting the nodes it makes.

#include "core/lang/array_expression.h"

#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>

#include "core/lang/parser.h"

namespace momenta {

std::string SubscriptText(const Shape& shape, size_t flat) {
  if (shape.size() == 2) {
    const size_t cols = static_cast<size_t>(shape[1]);
    return std::to_string(flat / cols + 1) + "," + std::to_string(flat % cols + 1);
  }
  return std::to_string(flat + 1);
}

namespace {

/// "a scalar" or "shape [2]", for messages.
std::string Described(const Shape& shape) {
  return shape.empty() ? "a scalar" : "shape " + ShapeText(shape);
}

bool IsArrayFunction(const std::string& name) {
  return name == "transpose" || name == "cross" || name == "norm" || name == "identity" ||
         name == "zeros" || name == "sum";
}

/// UsesArraySyntax on a tree that is there.
bool UsesArraySyntaxIn(const Ast& a, bool any_subscript) {
  if (a.kind == Ast::Kind::kArray) return true;
  if (a.kind == Ast::Kind::kCall && IsArrayFunction(a.op)) return true;
  if (a.kind == Ast::Kind::kName) {
    for (const NameSegment& s : a.path) {
      if (s.index2) return true;
    }
    return any_subscript && a.path.back().index;
  }
  for (const AstPtr& x : a.args) {
    if (UsesArraySyntaxIn(*x, any_subscript)) return true;
  }
  return false;
}

// The nodes one scalar form has made so far (ArrayNodeBudget).
constexpr size_t kMaxArrayNodes = 1000000;
thread_local size_t t_nodes = 0;
thread_local int t_budget_depth = 0;

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
    case Ast::Kind::kNumber:
      return a.number;
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
          case '+':
            r += *x;
            break;
          case '-':
            r -= *x;
            break;
          case '*':
            r *= *x;
            break;
          default:
            r /= *x;
            break;
        }
      }
      return r;
    }
    case Ast::Kind::kBinary: {
      if (a.op != "^") return std::nullopt;
      auto x = ConstantValue(*a.args[0]), y = ConstantValue(*a.args[1]);
      return x && y ? std::optional<double>(std::pow(*x, *y)) : std::nullopt;
    }
    default:
      return std::nullopt;
  }
}

/// The operator in front of operand k, for messages: '+' or '-' in a sum.
std::string OpAt(const Ast& a, const std::string& op, size_t k) {
  if (a.kind == Ast::Kind::kSum) return std::string(1, a.op[k == 0 ? 1 : k]);
  return op;
}

/// A copy of node `a` over new operands.
AstPtr Rebuild(const Ast& a, std::vector<AstPtr> args) {
  AstPtr n = Node(a.kind, a.column, a.op, std::move(args));
  auto m = std::const_pointer_cast<Ast>(n);
  m->number = a.number;
  return n;
}

}  // namespace

bool UsesArraySyntax(const AstPtr& a, bool any_subscript) {
  return a && UsesArraySyntaxIn(*a, any_subscript);
}

ArrayNodeBudget::ArrayNodeBudget() {
  if (t_budget_depth++ == 0) t_nodes = 0;
}

ArrayNodeBudget::~ArrayNodeBudget() { --t_budget_depth; }

// ---------------------------------------------------------------------------------------------
// Evaluation of one expression

ArrayEvaluator::ArrayEvaluator(const ArrayScope& scope, const std::string& text,
                               const SourceLoc& loc)
    : scope_(scope), text_(Excerpt(text, 0)), loc_(loc) {}

ArrayValue ArrayEvaluator::Eval(const AstPtr& p) {
  ArrayValue v = EvalNode(p);
  CheckBudget(p->column);
  return v;
}

void ArrayEvaluator::CheckBudget(int column) const {
  if (t_nodes > kMaxArrayNodes) {
    Fail(column, "the arrays expand to more than " + std::to_string(kMaxArrayNodes) +
                     " scalar expression nodes; use smaller arrays or fewer array operations");
  }
}

AstPtr ArrayEvaluator::Scalar(const AstPtr& p, const std::string& what) {
  ArrayValue v = Eval(p);
  if (!v.scalar()) Fail(p->column, what + " must be a scalar, found shape " + ShapeText(v.shape));
  return v.elements[0];
}

void ArrayEvaluator::Fail(int column, const std::string& what) const {
  throw ModelError(loc_.Shifted(column), what + ", in '" + text_ + "'" +
                                             (scope_.owner.empty() ? "" : " of " + scope_.owner));
}

ArrayValue ArrayEvaluator::EvalNode(const AstPtr& p) {
  const Ast& a = *p;
  switch (a.kind) {
    case Ast::Kind::kNumber:
    case Ast::Kind::kBool:
      return {{}, {p}};
    case Ast::Kind::kName:
      return Name(p);
    case Ast::Kind::kArray:
      return Literal(a);
    case Ast::Kind::kUnary:
    case Ast::Kind::kSum:
      return Elementwise(p, Operands(a), a.op == "-" ? "-" : "+", false);
    case Ast::Kind::kProduct:
      return Multiply(p);
    case Ast::Kind::kBinary: {
      std::vector<ArrayValue> ops = Operands(a);
      for (const ArrayValue& v : ops) {
        if (!v.scalar()) {
          Fail(a.column,
               "'" + a.op + "' takes scalars, found an operand of shape " + ShapeText(v.shape));
        }
      }
      return Elementwise(p, std::move(ops), a.op, true);
    }
    case Ast::Kind::kIf: {
      std::vector<ArrayValue> ops = Operands(a);
      for (size_t k = 0; k + 1 < ops.size(); k += 2) {
        if (!ops[k].scalar()) {
          Fail(a.args[k]->column,
               "an if condition must be a scalar, found shape " + ShapeText(ops[k].shape));
        }
      }
      return Elementwise(p, std::move(ops), "if", true);
    }
    case Ast::Kind::kCall:
      if (IsArrayFunction(a.op)) return ArrayFunction(a);
      if (const FunctionDecl* f = LibraryFunction(a)) {
        if (!f->record.empty()) {
          Fail(a.column, a.op + "() returns a record (" + f->record +
                             "): use it in a record equation or as a function's record argument");
        }
        return CallFunction(a, *f);
      }
      if (!IsBuiltinFunction(a.op)) {
        Fail(a.column, "unknown function '" + a.op + "' (valid functions: " + KnownFunctionList() +
                           ", and the library's, such as Frames.resolve2)");
      }
      return Elementwise(p, Operands(a), a.op + "()", true);
  }
  return {{}, {p}};
}

std::vector<ArrayValue> ArrayEvaluator::Operands(const Ast& a) {
  std::vector<ArrayValue> ops;
  ops.reserve(a.args.size());
  for (const AstPtr& x : a.args) ops.push_back(Eval(x));
  return ops;
}

/// Node `p` applied element by element. Array operands must have the same shape; scalar
/// operands apply to every element when `broadcast` (functions, if conditions), and are a
/// shape mismatch otherwise (`a + b`).
ArrayValue ArrayEvaluator::Elementwise(const AstPtr& p, std::vector<ArrayValue> ops,
                                       const std::string& op, bool broadcast) {
  const Ast& a = *p;
  Shape shape;
  bool same = true;
  for (size_t k = 0; k < ops.size(); ++k) {
    same = same && ops[k].scalar() && ops[k].elements[0] == a.args[k];
    if (ops[k].scalar()) continue;
    if (shape.empty()) {
      shape = ops[k].shape;
    } else if (ops[k].shape != shape) {
      Fail(a.kind == Ast::Kind::kSum ? a.args[k]->column : a.column,
           "the operands of '" + OpAt(a, op, k) + "' have different shapes: " + ShapeText(shape) +
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
        Fail(a.args[k]->column, "the operands of '" + OpAt(a, op, k) +
                                    "' have different shapes: " + ShapeText(shape) +
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
ArrayValue ArrayEvaluator::Name(const AstPtr& p) {
  const Ast& a = *p;
  const NameSegment& last = a.path.back();
  if (!bound_.empty()) {
    std::string joined;
    for (const NameSegment& s : a.path) joined += (joined.empty() ? "" : ".") + s.name;
    if (auto b = bound_.find(joined); b != bound_.end()) return Pick(b->second, a);
  }
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
size_t ArrayEvaluator::Subscript(const Ast& name, const Ast& index, int size) {
  auto v = ConstantValue(index);
  // Appended piece by piece: `"'" + text` trips GCC 12's -Wrestrict here (a false positive).
  std::string what = "'";
  what += name.PathText();
  what += '\'';
  if (!v) {
    Fail(name.column, "the subscript '" + AstToString(index) + "' of " + what +
                          " must be a constant whole number (a subscript picks a fixed element)");
  }
  if (*v != std::floor(*v) || *v < 1 || *v > size) {
    std::ostringstream s;
    s << *v;
    Fail(name.column, what + ": subscript " + s.str() + " is out of range 1.." +
                          std::to_string(size) + " (" + name.path.back().name + " has shape " +
                          ShapeText(*scope_.shape_of(name)) + ")");
  }
  return static_cast<size_t>(*v) - 1;
}

/// `[a, b, …]`: elements of one shape make a vector of them, or a matrix of rows.
ArrayValue ArrayEvaluator::Literal(const Ast& a) {
  std::vector<ArrayValue> items = Operands(a);
  const Shape& inner = items[0].shape;
  for (const ArrayValue& v : items) {
    if (v.shape != inner) {
      Fail(a.column, "the elements of an array literal have different shapes: " + ShapeText(inner) +
                         " and " + ShapeText(v.shape));
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

void ArrayEvaluator::CheckSize(const Shape& shape, int column) const {
  double n = 1;
  for (int d : shape) n *= d;
  if (n > static_cast<double>(kMaxArrayElements)) {
    Fail(column, "an array of shape " + ShapeText(shape) + " has more than " +
                     std::to_string(kMaxArrayElements) + " elements");
  }
}

/// A chain of * and /: scalars scale, a vector times a vector is their scalar product, and
/// matrices multiply matrices and vectors; only a scalar divides.
ArrayValue ArrayEvaluator::Multiply(const AstPtr& p) {
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
        Fail(a.column,
             "division by an array of shape " + ShapeText(y.shape) + "; only a scalar divides");
      }
      for (AstPtr& e : acc.elements) e = Product(e, '/', y.elements[0], a.column);
      continue;
    }
    acc = Times(acc, y, a.column);
  }
  return acc;
}

ArrayValue ArrayEvaluator::Times(const ArrayValue& x, const ArrayValue& y, int column) {
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
                     ": the inner dimensions " + std::to_string(k) + " and " + std::to_string(k2) +
                     " differ");
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

ArrayValue ArrayEvaluator::ArrayFunction(const Ast& a) {
  const std::string f = a.op + "()";
  if (a.op == "identity" || a.op == "zeros") {
    Shape shape;
    for (const AstPtr& x : a.args) shape.push_back(Size(*x, f));
    if (a.op == "identity") shape.push_back(shape[0]);
    CheckSize(shape, a.column);
    ArrayValue out{shape, {}};
    for (size_t i = 0; i < ElementCount(shape); ++i) {
      const bool diagonal = a.op == "identity" &&
                            i % static_cast<size_t>(shape[0]) == i / static_cast<size_t>(shape[0]);
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
int ArrayEvaluator::Size(const Ast& x, const std::string& f) {
  auto v = ConstantValue(x);
  if (!v || *v != std::floor(*v) || *v < 1 || *v > static_cast<double>(kMaxArrayElements)) {
    Fail(x.column, "the size '" + AstToString(x) + "' given to " + f +
                       " must be a constant whole number from 1 to " +
                       std::to_string(kMaxArrayElements));
  }
  return static_cast<int>(*v);
}

}  // namespace momenta

namespace momenta {

namespace {

/// Functions inline functions at most this deep (a function that calls itself is an error).
constexpr int kMaxInlineDepth = 32;

std::string JoinedPath(const Ast& a) {
  std::string joined;
  for (const NameSegment& s : a.path) joined += (joined.empty() ? "" : ".") + s.name;
  return joined;
}

bool HasSubscripts(const Ast& a) {
  for (const NameSegment& s : a.path) {
    if (s.index) return true;
  }
  return false;
}

}  // namespace

const FunctionDecl* ArrayEvaluator::LibraryFunction(const Ast& a) const {
  if (!scope_.library || a.kind != Ast::Kind::kCall || IsBuiltinFunction(a.op)) return nullptr;
  return scope_.library->FindFunction(a.op);
}

ArrayValue ArrayEvaluator::Pick(const ArrayValue& v, const Ast& a) {
  const NameSegment& last = a.path.back();
  if (!last.index) return v;
  if (v.scalar()) Fail(a.column, "'" + a.PathText() + "': " + last.name + " is a scalar, so it has no elements");
  if (last.index2 && v.shape.size() != 2) {
    Fail(a.column, "'" + a.PathText() + "' has two subscripts, but " + last.name + " has shape " + ShapeText(v.shape));
  }
  const size_t i = Subscript(a, *last.index, v.shape[0]);
  if (v.shape.size() == 1) return {{}, {v.elements[i]}};
  const size_t cols = static_cast<size_t>(v.shape[1]);
  if (last.index2) return {{}, {v.elements[i * cols + Subscript(a, *last.index2, v.shape[1])]}};
  ArrayValue row{{v.shape[1]}, {}};
  for (size_t j = 0; j < cols; ++j) row.elements.push_back(v.elements[i * cols + j]);
  return row;
}

bool ArrayEvaluator::IsRecord(const AstPtr& p) const {
  const Ast& a = *p;
  if (a.kind == Ast::Kind::kName) {
    if (HasSubscripts(a)) return false;
    const std::string name = JoinedPath(a);
    return bound_records_.count(name) || (scope_.records && scope_.records->count(name));
  }
  const FunctionDecl* f = LibraryFunction(a);
  return f && !f->record.empty();
}

ArrayEvaluator::RecordValue ArrayEvaluator::EvalRecord(const AstPtr& p) {
  const Ast& a = *p;
  if (a.kind == Ast::Kind::kName && !HasSubscripts(a)) {
    const std::string name = JoinedPath(a);
    if (auto b = bound_records_.find(name); b != bound_records_.end()) return b->second;
    if (scope_.records && scope_.library) {
      if (auto r = scope_.records->find(name); r != scope_.records->end()) {
        RecordValue v;
        v.type = scope_.library->FindRecord(r->second);
        if (!v.type) Fail(a.column, "unknown record type '" + r->second + "' of " + name);
        for (const ConnectorVariable& f : v.type->fields) {
          auto field = std::make_shared<Ast>(a);
          field->path.push_back({f.name, nullptr, nullptr});
          v.fields.push_back(Eval(field));
          if (v.fields.back().shape != f.shape) {
            Fail(a.column, "'" + name + "." + f.name + "' has shape " + ShapeText(v.fields.back().shape) + ", but the field " +
                               v.type->name + "." + f.name + " has shape " + ShapeText(f.shape));
          }
        }
        return v;
      }
    }
  }
  if (const FunctionDecl* f = LibraryFunction(a); f && !f->record.empty()) return CallRecordFunction(a, *f);
  Fail(a.column, "expected a record here (a record variable, a connector's record potential or a function returning a record)");
}

void ArrayEvaluator::BindInputs(const Ast& a, const FunctionDecl& f, ArrayEvaluator* inner) {
  if (++inner->depth_ > kMaxInlineDepth) {
    Fail(a.column, a.op + "(): functions call each other more than " + std::to_string(kMaxInlineDepth) +
                       " deep (does a function call itself?)");
  }
  if (a.args.size() != f.inputs.size()) {
    Fail(a.column, a.op + "() takes " + std::to_string(f.inputs.size()) + (f.inputs.size() == 1 ? " argument" : " arguments") +
                       ", found " + std::to_string(a.args.size()));
  }
  for (size_t k = 0; k < f.inputs.size(); ++k) {
    const FunctionDecl::Input& in = f.inputs[k];
    if (!in.record.empty()) {
      if (!IsRecord(a.args[k])) Fail(a.args[k]->column, "argument " + std::to_string(k + 1) + " of " + a.op + "() must be a record (" + in.record + ")");
      RecordValue r = EvalRecord(a.args[k]);
      for (size_t j = 0; j < r.type->fields.size(); ++j) inner->bound_[in.name + "." + r.type->fields[j].name] = r.fields[j];
      inner->bound_records_[in.name] = std::move(r);
      continue;
    }
    ArrayValue v = Eval(a.args[k]);
    if (v.shape != in.shape) {
      Fail(a.args[k]->column, "argument " + std::to_string(k + 1) + " (" + in.name + ") of " + a.op + "() has shape " +
                                  ShapeText(v.shape) + ", but the function takes " + ShapeText(in.shape));
    }
    inner->bound_[in.name] = std::move(v);
  }
}

ArrayValue ArrayEvaluator::CallFunction(const Ast& a, const FunctionDecl& f) {
  ArrayEvaluator inner(scope_, f.value_text, f.loc);
  inner.depth_ = depth_;
  BindInputs(a, f, &inner);
  return inner.Eval(f.value);
}

ArrayEvaluator::RecordValue ArrayEvaluator::CallRecordFunction(const Ast& a, const FunctionDecl& f) {
  RecordValue out;
  out.type = scope_.library->FindRecord(f.record);
  if (!out.type) Fail(a.column, a.op + "() returns '" + f.record + "', which is no record type of the library");
  // The arguments are evaluated once; each field's expression then sees them (its own text quoted).
  ArrayEvaluator bound(scope_, a.op, f.loc);
  bound.depth_ = depth_;
  BindInputs(a, f, &bound);
  for (const ConnectorVariable& field : out.type->fields) {
    size_t k = 0;
    while (k < f.fields.size() && f.fields[k].first != field.name) ++k;
    if (k == f.fields.size()) Fail(a.column, a.op + "() gives no value for the field " + field.name + " of " + f.record);
    ArrayEvaluator inner(scope_, f.field_texts[k], f.loc);
    inner.depth_ = bound.depth_;
    inner.bound_ = bound.bound_;
    inner.bound_records_ = bound.bound_records_;
    out.fields.push_back(inner.Eval(f.fields[k].second));
    if (out.fields.back().shape != field.shape) {
      Fail(a.column, a.op + "() gives " + f.record + "." + field.name + " shape " + ShapeText(out.fields.back().shape) +
                         ", but the field has shape " + ShapeText(field.shape));
    }
  }
  return out;
}

}  // namespace momenta
