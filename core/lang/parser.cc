// The parser of momenta's equation language (core/lang/parser.h): recursive descent over the
// tokens of core/lang/lexer.h, chains of one operator collected by loops into one node.

#include "core/lang/parser.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <sstream>
#include <string_view>

#include "core/lang/lexer.h"

namespace momenta {

namespace {

const std::map<std::string, int>& Functions() {
  static const std::map<std::string, int> kFunctions = {
      {"sin", 1},  {"cos", 1},   {"tan", 1},   {"asin", 1},  {"acos", 1},    {"atan", 1},
      {"atan2", 2}, {"sinh", 1}, {"cosh", 1},  {"tanh", 1},  {"exp", 1},     {"log", 1},
      {"log10", 1}, {"sqrt", 1}, {"abs", 1},   {"sign", 1},  {"min", 2},     {"max", 2},
      {"floor", 1},
      {"der", 1},  {"pre", 1},   {"edge", 1},  {"change", 1}, {"initial", 0}, {"noEvent", 1},
      {"reinit", 2},
      // Array functions (core/lang/arrays.h); zeros takes 1 or 2 (kOneOrTwo).
      {"transpose", 1}, {"cross", 2}, {"norm", 1}, {"identity", 1}, {"zeros", -2}, {"sum", 1},
      // interpolate(table, x) or interpolate(table, x, column): 2 or 3 (kTwoOrThree).
      {"interpolate", -3}, {"timeTable", 5}, {"booleanTable", 2},
      // The connection graph's predicates (core/lang/records.h): structural Booleans.
      {"isRoot", 1}, {"rooted", 1},
  };
  return kFunctions;
}

/// The library's expression functions (`kind: function`), by every dotted tail of their names.
struct UserFunctions {
  std::mutex mutex;
  std::map<std::string, int> arity;
};
UserFunctions& Registered() {
  static UserFunctions* f = new UserFunctions();
  return *f;
}

std::atomic<void (*)()> library_function_reader{nullptr};

/// Runs the library's function reader, once; whether it ran now.
bool ReadLibraryFunctions() {
  void (*read)() = library_function_reader.exchange(nullptr);
  if (read) read();
  return read != nullptr;
}

}  // namespace

std::string Excerpt(const std::string& text, int column) {
  constexpr size_t kHalf = 60;
  if (text.size() <= 2 * kHalf) return text;
  size_t at = std::min(static_cast<size_t>(std::max(column, 0)), text.size());
  size_t from = at > kHalf ? at - kHalf : 0;
  size_t to = std::min(text.size(), from + 2 * kHalf);
  return (from > 0 ? "…" : "") + text.substr(from, to - from) + (to < text.size() ? "…" : "");
}

namespace {

class Parser {
 public:
  Parser(const std::string& text, const SourceLoc& loc)
      : text_(text), loc_(loc), tokens_(Tokenize(text, loc)) {}

  /// if-expression or or-chain. The one recursive entry: nested constructs come back here.
  AstPtr Expression() {
    if (++depth_ > kMaxExpressionDepth) TooDeep(Peek().column);
    AstPtr e = IsKeyword("if") ? If() : Disjunction();
    --depth_;
    return e;
  }

  AstEquation Equation() {
    AstEquation eq;
    eq.lhs = Expression();
    if (!(Peek().kind == TokenKind::kOp && Peek().text == "=")) {
      Fail("expected '=' between the two sides of the equation");
    }
    Next();
    eq.rhs = Expression();
    ExpectEnd();
    return eq;
  }

  AstPtr Name() {
    AstPtr n = Primary();
    if (n->kind != Ast::Kind::kName) Fail("expected a name such as A.flange_a");
    ExpectEnd();
    return n;
  }

  void ExpectEnd() {
    if (Peek().kind != TokenKind::kEnd) Fail("unexpected '" + Peek().text + "'");
  }

 private:
  const Token& Peek() const { return tokens_[pos_]; }
  const Token& Next() { return tokens_[pos_ < tokens_.size() - 1 ? pos_++ : pos_]; }
  bool IsKeyword(const char* k) const { return Peek().kind == TokenKind::kIdent && Peek().text == k; }
  bool IsOp(const char* op) const { return Peek().kind == TokenKind::kOp && Peek().text == op; }

  [[noreturn]] void Fail(const std::string& what) const {
    std::string found = Peek().kind == TokenKind::kEnd ? "end of text" : "'" + Peek().text + "'";
    std::string msg = what;
    if (what.find("unexpected") == std::string::npos) msg += ", found " + found;
    throw ModelError(loc_.Shifted(Peek().column), msg + " in '" + Excerpt(text_, Peek().column) + "'");
  }

  [[noreturn]] void TooDeep(int column) const {
    throw ModelError(loc_.Shifted(column),
                     NestedTooDeep("expression") + " in '" + Excerpt(text_, column) +
                         "'; split it with intermediate variables or parameters");
  }

  /// A node over `args`, one level above the highest of them.
  AstPtr Make(Ast::Kind kind, int column, std::string op, std::vector<AstPtr> args) const {
    AstPtr a = MakeAst(kind, column, std::move(op), std::move(args));
    if (a->height > kMaxExpressionDepth) TooDeep(column);
    return a;
  }

  /// One operand alone, or the chain node over all of them.
  AstPtr Chain(Ast::Kind kind, int column, std::string op, std::vector<AstPtr> operands) const {
    if (operands.size() == 1) return std::move(operands[0]);
    return Make(kind, column, std::move(op), std::move(operands));
  }

  /// if c1 then v1 elseif c2 then v2 … else e: one node, the branches collected by a loop.
  AstPtr If() {
    int col = Next().column;
    std::vector<AstPtr> args;
    while (true) {
      args.push_back(Expression());
      if (!IsKeyword("then")) Fail("expected 'then'");
      Next();
      args.push_back(Expression());
      if (!IsKeyword("elseif")) break;
      Next();
    }
    if (!IsKeyword("else")) Fail("expected 'else' (an if-expression needs both branches)");
    Next();
    args.push_back(Expression());
    return Make(Ast::Kind::kIf, col, "if", std::move(args));
  }

  /// a or b or …, each operand an and-chain of negations.
  AstPtr Disjunction() {
    std::vector<AstPtr> disjuncts;
    int or_col = Peek().column;
    while (true) {
      std::vector<AstPtr> conjuncts;
      int and_col = Peek().column;
      while (true) {
        conjuncts.push_back(Negation());
        if (!IsKeyword("and")) break;
        and_col = Next().column;
      }
      disjuncts.push_back(Chain(Ast::Kind::kBinary, and_col, "and", std::move(conjuncts)));
      if (!IsKeyword("or")) break;
      or_col = Next().column;
    }
    return Chain(Ast::Kind::kBinary, or_col, "or", std::move(disjuncts));
  }

  /// not … not relation; a relation is sum [op sum] (relations do not chain).
  AstPtr Negation() {
    std::vector<int> nots;
    while (IsKeyword("not")) nots.push_back(Next().column);
    AstPtr r = Sum();
    if (Peek().kind == TokenKind::kOp &&
        (Peek().text == "<" || Peek().text == "<=" || Peek().text == ">" || Peek().text == ">=" ||
         Peek().text == "==" || Peek().text == "<>")) {
      const Token& t = Next();
      r = Make(Ast::Kind::kBinary, t.column, t.text, {r, Sum()});
    }
    for (size_t k = nots.size(); k-- > 0;) r = Make(Ast::Kind::kUnary, nots[k], "not", {r});
    return r;
  }

  /// term (+|- term)*, each term a product factor (*|/ factor)*: one kSum of kProducts.
  AstPtr Sum() {
    std::vector<AstPtr> terms;
    std::string signs = "+";
    int sum_col = Peek().column;
    while (true) {
      std::vector<AstPtr> factors{Signed()};
      std::string factor_ops = "*";
      int product_col = Peek().column;
      while (IsOp("*") || IsOp("/")) {
        const Token& t = Next();
        product_col = t.column;
        factor_ops += t.text;
        factors.push_back(Signed());
      }
      terms.push_back(Chain(Ast::Kind::kProduct, product_col, factor_ops, std::move(factors)));
      if (!(IsOp("+") || IsOp("-"))) break;
      const Token& t = Next();
      sum_col = t.column;
      signs += t.text;
    }
    return Chain(Ast::Kind::kSum, sum_col, signs, std::move(terms));
  }

  /// Signs, a primary, and a right-associative power chain whose exponents may carry signs:
  /// -x^-y^2 = -(x^(-(y^2))). Collected level by level, then built from the right.
  AstPtr Signed() {
    struct Level {
      std::vector<int> minus;  // columns of the '-' signs before the base ('+' signs vanish)
      AstPtr base;
      int caret = -1;          // column of the '^' after the base, if any
    };
    std::vector<Level> levels;
    while (true) {
      Level level;
      while (IsOp("-") || IsOp("+")) {
        const Token& t = Next();
        if (t.text == "-") level.minus.push_back(t.column);
      }
      level.base = Primary();
      bool more = IsOp("^");
      if (more) level.caret = Next().column;
      levels.push_back(std::move(level));
      if (!more) break;
    }
    AstPtr r;
    for (size_t k = levels.size(); k-- > 0;) {
      Level& level = levels[k];
      r = r ? Make(Ast::Kind::kBinary, level.caret, "^", {level.base, r}) : level.base;
      for (size_t j = level.minus.size(); j-- > 0;) r = Make(Ast::Kind::kUnary, level.minus[j], "-", {r});
    }
    return r;
  }

  /// An operand: a number, a parenthesised expression, an array literal, true or false, a call or
  /// a name.
  AstPtr Primary() {
    const Token& t = Peek();
    if (t.kind == TokenKind::kNumber) {
      Next();
      auto a = std::make_shared<Ast>();
      a->kind = Ast::Kind::kNumber;
      a->number = t.number;
      a->column = t.column;
      return a;
    }
    if (t.kind == TokenKind::kLParen) {
      Next();
      AstPtr inner = Expression();
      if (Peek().kind != TokenKind::kRParen) Fail("expected ')'");
      Next();
      return inner;
    }
    if (t.kind == TokenKind::kLBracket) return ArrayLiteral();
    if (t.kind != TokenKind::kIdent) Fail("expected a number, a name, '(' or '['");
    if (t.text == "true" || t.text == "false") {
      Next();
      auto a = std::make_shared<Ast>();
      a->kind = Ast::Kind::kBool;
      a->number = t.text == "true" ? 1 : 0;
      a->column = t.column;
      return a;
    }
    static const char* kReserved[] = {"then", "else", "elseif", "and", "or", "not", "if"};
    for (const char* r : kReserved) {
      if (t.text == r) Fail("expected an operand");
    }
    if (tokens_[pos_ + 1].kind == TokenKind::kLParen || DottedCall()) return Call();
    return DottedName();
  }

  /// Whether the tokens from here are `a.b.c(`: a library function called by a qualified name.
  bool DottedCall() const {
    size_t k = pos_ + 1;
    while (k + 1 < tokens_.size() && tokens_[k].kind == TokenKind::kDot && tokens_[k + 1].kind == TokenKind::kIdent) k += 2;
    return k > pos_ + 1 && k < tokens_.size() && tokens_[k].kind == TokenKind::kLParen;
  }

  /// A function call `f(a, b)`: a known function with as many arguments as it takes.
  AstPtr Call() {
    Token name = Next();
    while (Peek().kind == TokenKind::kDot) {
      Next();
      name.text += "." + Next().text;
    }
    Next();
    int arity = 0;
    // A qualified name is a library function, which the library resolves when it is inlined
    // (a model may be read before the library's functions are).
    if (IsKnownFunction(name.text, &arity) && arity == -1 && ReadLibraryFunctions()) {
      IsKnownFunction(name.text, &arity);
    }
    if (!IsKnownFunction(name.text, &arity) && name.text.find('.') != std::string::npos) arity = -1;
    else if (!IsKnownFunction(name.text, &arity)) {
      throw ModelError(loc_.Shifted(name.column),
                       "unknown function '" + name.text + "' in '" + Excerpt(text_, name.column) +
                           "' (valid functions: " + KnownFunctionList() + ")");
    }
    std::vector<AstPtr> args;
    if (Peek().kind != TokenKind::kRParen) args = ExpressionList();
    if (Peek().kind != TokenKind::kRParen) Fail("expected ')' or ','");
    Next();
    const int count = static_cast<int>(args.size());
    const bool bad_count = arity == -1   ? false  // a library function named before it is read
                           : arity == -2 ? count < 1 || count > 2
                           : arity == -3 ? count < 2 || count > 3
                                         : count != arity;
    if (bad_count) {
      throw ModelError(loc_.Shifted(name.column),
                       name.text + "() takes " +
                           (arity == -2 ? "1 or 2" : arity == -3 ? "2 or 3" : std::to_string(arity)) +
                           " argument" + (arity == 1 ? "" : "s") + ", found " +
                           std::to_string(args.size()) + " in '" + Excerpt(text_, name.column) + "'");
    }
    if (name.text == "der") CheckDifferentiationOrder(*args[0], name.column);
    return Make(Ast::Kind::kCall, name.column, name.text, std::move(args));
  }

  /// der() around an expression (not a variable) builds its time derivative symbolically, and
  /// each order multiplies its size: more orders than index reduction may take are refused here,
  /// before any derivative is built (200 around `x*x + sin(x)` took 70 s and 420 MB).
  void CheckDifferentiationOrder(const Ast& argument, int column) const {
    if (DerivativeOrder(argument) + 1 <= static_cast<int>(kMaxDifferentiations)) return;
    throw ModelError(loc_.Shifted(column),
                     "der() applied more than " + std::to_string(kMaxDifferentiations) +
                         " times to an expression in '" + Excerpt(text_, column) +
                         "'; index reduction differentiates at most " +
                         std::to_string(kMaxDifferentiations) +
                         " times: introduce variables for the intermediate derivatives");
  }

  /// How many der() a tree holds around its deepest operator (der(der(x*y)): 2), or -1 when it
  /// holds none but around names and numbers, whose derivatives cost nothing to make. Subscripts
  /// are not differentiated. The recursion follows the tree's height, which the parser bounds.
  static int DerivativeOrder(const Ast& a) {
    if (a.kind == Ast::Kind::kNumber || a.kind == Ast::Kind::kBool || a.kind == Ast::Kind::kName) {
      return -1;
    }
    if (a.kind == Ast::Kind::kCall && a.op == "der" && a.args.size() == 1) {
      const int inner = DerivativeOrder(*a.args[0]);
      return inner < 0 ? -1 : inner + 1;
    }
    int order = 0;
    for (const AstPtr& arg : a.args) order = std::max(order, DerivativeOrder(*arg));
    return order;
  }

  /// A dotted name with optional subscripts: `R[i+1].p.v`, `body.R[1, 2]`.
  AstPtr DottedName() {
    auto a = std::make_shared<Ast>();
    a->kind = Ast::Kind::kName;
    a->column = Peek().column;
    while (true) {
      if (Peek().kind != TokenKind::kIdent) Fail("expected a name after '.'");
      NameSegment seg;
      seg.name = Next().text;
      if (Peek().kind == TokenKind::kLBracket) {
        Next();
        seg.index = Expression();
        a->height = std::max(a->height, seg.index->height + 1);
        if (Peek().kind == TokenKind::kComma) {
          Next();
          seg.index2 = Expression();
          a->height = std::max(a->height, seg.index2->height + 1);
        }
        if (Peek().kind != TokenKind::kRBracket) Fail(seg.index2 ? "expected ']'" : "expected ']' or ','");
        Next();
      }
      a->path.push_back(std::move(seg));
      if (Peek().kind != TokenKind::kDot) break;
      Next();
    }
    if (a->height > kMaxExpressionDepth) TooDeep(a->column);
    return a;
  }

  /// One or more expressions separated by commas (call arguments, array elements).
  std::vector<AstPtr> ExpressionList() {
    std::vector<AstPtr> list{Expression()};
    while (Peek().kind == TokenKind::kComma) {
      Next();
      list.push_back(Expression());
    }
    return list;
  }

  /// `[a, b, …]`: the elements of a vector, or the rows of a matrix `[[1, 0], [0, 1]]`.
  AstPtr ArrayLiteral() {
    int col = Next().column;
    if (++depth_ > kMaxExpressionDepth) TooDeep(col);
    if (Peek().kind == TokenKind::kRBracket) Fail("expected the elements of an array, e.g. [1, 2]");
    std::vector<AstPtr> elements = ExpressionList();
    if (Peek().kind != TokenKind::kRBracket) Fail("expected ']' or ','");
    Next();
    --depth_;
    return Make(Ast::Kind::kArray, col, "[]", std::move(elements));
  }

  const std::string& text_;
  const SourceLoc& loc_;
  std::vector<Token> tokens_;
  size_t pos_ = 0;
  int depth_ = 0;  ///< nesting of Expression() calls
};

}  // namespace

bool IsKnownFunction(const std::string& name, int* arity) {
  auto it = Functions().find(name);
  if (it == Functions().end()) {
    UserFunctions& user = Registered();
    std::lock_guard<std::mutex> lock(user.mutex);
    auto u = user.arity.find(name);
    if (u == user.arity.end()) return false;
    if (arity) *arity = u->second;
    return true;
  }
  if (arity) *arity = it->second;
  return true;
}

bool IsBuiltinFunction(const std::string& name) { return Functions().count(name) != 0; }

void RegisterFunction(const std::string& name, int arity) {
  UserFunctions& user = Registered();
  std::lock_guard<std::mutex> lock(user.mutex);
  for (size_t from = 0;;) {
    user.arity[name.substr(from)] = arity;
    size_t dot = name.find('.', from);
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
}

void SetLibraryFunctionReader(void (*read)()) { library_function_reader = read; }

std::string KnownFunctionList() {
  std::string s;
  for (const auto& [name, arity] : Functions()) {
    if (name == "reinit") continue;
    if (!s.empty()) s += ", ";
    s += name;
  }
  return s;
}

namespace {

/// The tree of a text that is one decimal number and nothing else (a parameter value, a start
/// value: most texts of a large model), made without tokens; null for any other text, which the
/// parser reads. The same tree the parser gives: a number node at column 0.
AstPtr PlainNumber(const std::string& text) {
  if (text.empty() ||
      !(IsDigit(text[0]) || (text[0] == '.' && text.size() > 1 && IsDigit(text[1])))) {
    return nullptr;
  }
  if (DecimalEnd(text, 0) != text.size()) return nullptr;
  const double value = std::strtod(text.c_str(), nullptr);
  // The parser's "number out of range", for numbers beyond double's range and subnormals.
  if (!std::isfinite(value) || (value != 0 && !std::isnormal(value))) return nullptr;
  auto a = std::make_shared<Ast>();
  a->kind = Ast::Kind::kNumber;
  a->number = value;
  return a;
}

/// The tree of a text that is a dotted name and nothing else (`mass1.flange_b`: a connection
/// end, an output), made without tokens; null for any other text (IsPlainName), which the
/// parser reads. The same tree the parser gives: a name node at column 0.
AstPtr PlainName(const std::string& text) {
  if (!IsPlainName(text)) return nullptr;
  auto a = std::make_shared<Ast>();
  a->kind = Ast::Kind::kName;
  a->path.reserve(static_cast<size_t>(std::count(text.begin(), text.end(), '.')) + 1);
  for (size_t i = 0; i <= text.size();) {
    const size_t dot = std::min(text.find('.', i), text.size());
    NameSegment seg;
    seg.name = text.substr(i, dot - i);
    a->path.push_back(std::move(seg));
    i = dot + 1;
  }
  return a;
}

}  // namespace

bool IsPlainName(std::string_view text) {
  size_t i = 0;
  while (true) {
    if (i >= text.size() || !IsNameStart(text[i])) return false;
    size_t j = i;
    while (j < text.size() && IsNameChar(text[j])) ++j;
    if (j == text.size()) break;
    if (text[j] != '.') return false;
    i = j + 1;
  }
  // A first word the parser reads otherwise: true/false, a keyword.
  const std::string_view first = text.substr(0, text.find('.'));
  static const char* kWords[] = {"true", "false", "then", "else", "elseif",
                                 "and",  "or",    "not",  "if"};
  for (const char* w : kWords) {
    if (first == w) return false;
  }
  return true;
}

AstPtr ParseExpression(const std::string& text, const SourceLoc& loc) {
  if (AstPtr number = PlainNumber(text)) return number;
  Parser p(text, loc);
  AstPtr e = p.Expression();
  p.ExpectEnd();
  return e;
}

AstEquation ParseEquation(const std::string& text, const SourceLoc& loc) {
  return Parser(text, loc).Equation();
}

AstPtr ParseName(const std::string& text, const SourceLoc& loc) {
  if (AstPtr name = PlainName(text)) return name;
  return Parser(text, loc).Name();
}

}  // namespace momenta
