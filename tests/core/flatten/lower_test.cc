// The one lowering walk (core/flatten/lower.h) over a scope that writes each node it is asked to
// make as text, in order: what every construct means, in which order its nodes are made (the
// expression pool's node ids follow it), and which errors the walk raises itself. The model
// scope and the type scope are tested through whole models (flatten_test.cc, composite_test.cc).

#include "core/flatten/lower.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "core/base/messages.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {
namespace {

/// A LoweringScope whose nodes are their own text; `made` lists them in the order they are made.
template <bool kSecondFirst>
class TextScope {
 public:
  using Node = std::string;
  static constexpr bool kSecondOperandFirst = kSecondFirst;

  explicit TextScope(std::string text) : text_(std::move(text)) {}

  Node Constant(double value) { return Make(NumberText(value)); }
  Node Name(const Ast& a) {
    variables_.insert(a.PathText());
    return Make(a.PathText());
  }
  Node Unary(Op op, Node x) { return Make(std::string(OpName(op)) + "(" + x + ")"); }
  Node Negate(Node x) { return Make("-(" + x + ")"); }
  Node Binary(Op op, Node x, Node y) { return Make("(" + x + " " + OpName(op) + " " + y + ")"); }
  Node If(Node c, Node x, Node y) { return Make("if(" + c + ", " + x + ", " + y + ")"); }
  Node NoEvent(Node x) { return Make("noEvent(" + x + ")"); }
  Node Der(Node x) { return Make("der(" + x + ")"); }
  Node Initial() { return Make("initial()"); }
  Node Pre(Node x) { return Make("pre(" + x + ")"); }
  bool IsVariable(Node x) const { return variables_.count(x) > 0; }
  void CheckCall(const Ast& a) const {
    if (a.op == "der" && no_der) Fail(a, "der() is not allowed here");
  }
  std::optional<Node> TableCall(const Ast& a) {
    if (a.op != "interpolate") return std::nullopt;
    return Make("table(" + Lower(*a.args[1], this) + ")");
  }
  const std::string& text() const { return text_; }
  std::string OfOwner() const { return " of Cell"; }
  [[noreturn]] void Fail(const Ast& at, const std::string& message) const {
    throw ModelError(SourceLoc("cell.yaml", 1, 1).Shifted(at.column), message);
  }

  std::vector<std::string> made;
  bool no_der = false;

 private:
  Node Make(Node n) {
    made.push_back(n);
    return n;
  }
  std::string text_;
  std::set<std::string> variables_;
};
static_assert(LoweringScope<TextScope<false>> && LoweringScope<TextScope<true>>);

template <bool kSecondFirst = false>
TextScope<kSecondFirst> Lowered(const std::string& text) {
  TextScope<kSecondFirst> scope(text);
  Lower(*ParseExpression(text, SourceLoc("cell.yaml", 1, 1)), &scope);
  return scope;
}

std::string ErrorOf(const std::string& text) {
  try {
    Lowered(text);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LowerTest, OperandsInTheOrderTheScopeAsks) {
  const std::vector<std::string> written = {"a", "b", "(a * b)", "c", "d", "(c + d)", "((a * b) max (c + d))"};
  EXPECT_EQ(Lowered<false>("max(a*b, c + d)").made, written);
  // The model scope makes a function's second operand first.
  const std::vector<std::string> second_first = {"c", "d", "(c + d)", "a", "b", "(a * b)", "((a * b) max (c + d))"};
  EXPECT_EQ(Lowered<true>("max(a*b, c + d)").made, second_first);
  // Operators other than functions keep the written order in both.
  EXPECT_EQ(Lowered<true>("a*b - c").made.back(), "((a * b) - c)");
}

TEST(LowerTest, ChainsAndElseifChains) {
  EXPECT_EQ(Lowered("a - b + c - d").made.back(), "(((a - b) + c) - d)");
  EXPECT_EQ(Lowered("a / b * c").made.back(), "((a / b) * c)");
  EXPECT_EQ(Lowered("if x > 0 then 1 elseif x < -1 then 2 else 3").made.back(),
            "if((x > 0), 1, if((x < -(1)), 2, 3))");
  EXPECT_EQ(Lowered("not b and -x < 0").made.back(), "(not(b) and (-(x) < 0))");
}

TEST(LowerTest, EdgeAndChangeOfAVariable) {
  const std::vector<std::string> edge = {"b", "pre(b)", "not(pre(b))", "(b and not(pre(b)))"};
  EXPECT_EQ(Lowered("edge(b)").made, edge);
  EXPECT_EQ(Lowered("change(b)").made.back(), "(b <> pre(b))");
  EXPECT_EQ(Lowered("pre(b)").made.back(), "pre(b)");
  EXPECT_EQ(Lowered("noEvent(der(x)) + initial()").made.back(), "(noEvent(der(x)) + initial())");
}

TEST(LowerTest, TheScopeLowersItsTableCalls) {
  EXPECT_EQ(Lowered("interpolate(f, 2*x)").made.back(), "table((2 * x))");
}

TEST(LowerTest, ErrorsNameTheCallAndTheText) {
  EXPECT_EQ(ErrorOf("pre(x + 1)"), "cell.yaml:1:1: pre() takes a variable, in 'pre(x + 1)'");
  EXPECT_EQ(ErrorOf("1 + [1, 2]"), "cell.yaml:1:5: an array where a number is expected, in '1 + [1, 2]' of Cell");
  TextScope<false> scope("der(x)");
  scope.no_der = true;
  EXPECT_THROW(Lower(*ParseExpression("der(x)", SourceLoc()), &scope), ModelError);
  // A function the pool computes is not the scope's to refuse.
  EXPECT_EQ(Lowered("sin(x)").made.back(), "sin(x)");
}

}  // namespace
}  // namespace momenta::flatten_internal
