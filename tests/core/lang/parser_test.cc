#include "core/lang/parser.h"

#include <gtest/gtest.h>

#include "core/lang/model_spec.h"
#include "core/lang/yaml_loader.h"

namespace momenta {
namespace {

std::string P(const std::string& text) {
  return AstToString(*ParseExpression(text, SourceLoc{"m.yaml", 3, 7}));
}

/// The message of parsing `text` (placed at m.yaml line 3, column 7), or "" when it parses.
std::string ParseError(const std::string& text) {
  try {
    ParseExpression(text, SourceLoc{"m.yaml", 3, 7});
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

std::string Prefix(const std::string& message) { return message.substr(0, message.find(": ") + 2); }

TEST(ParserTest, PrecedenceAndAssociativity) {
  SourceLoc loc{"m.yaml", 3, 7};
  EXPECT_EQ(AstToString(*ParseExpression("a + b*c^2^3", loc)), "(a + (b * (c ^ (2 ^ 3))))");
  EXPECT_EQ(AstToString(*ParseExpression("-x^2", loc)), "-(x ^ 2)");
  EXPECT_EQ(AstToString(*ParseExpression("if a < b then 1 else 2", loc)), "if (a < b) then 1 else 2");
}

TEST(ParserTest, ArithmeticPrecedence) {
  EXPECT_EQ(P("a - b - c"), "((a - b) - c)");
  EXPECT_EQ(P("a / b / c"), "((a / b) / c)");
  EXPECT_EQ(P("a - b * c / d + e"), "((a - ((b * c) / d)) + e)");
  EXPECT_EQ(P("(a + b) * c"), "((a + b) * c)");
  EXPECT_EQ(P("a * (b - (c + d))"), "(a * (b - (c + d)))");
  EXPECT_EQ(P("2^3^2"), "(2 ^ (3 ^ 2))");
  EXPECT_EQ(P("(2^3)^2"), "((2 ^ 3) ^ 2)");
}

TEST(ParserTest, UnaryMinusBindsLooserThanPower) {
  EXPECT_EQ(P("-x^2"), "-(x ^ 2)");
  EXPECT_EQ(P("-2^2"), "-(2 ^ 2)");
  EXPECT_EQ(P("(-x)^2"), "(-x ^ 2)");
  EXPECT_EQ(P("a*-b"), "(a * -b)");
  EXPECT_EQ(P("-a*b"), "(-a * b)");
  EXPECT_EQ(P("- -a"), "--a");
  EXPECT_EQ(P("+a - +b"), "(a - b)");
  // A signed exponent.
  EXPECT_EQ(P("x^-2"), "(x ^ -2)");
  EXPECT_EQ(P("x^-y^2"), "(x ^ -(y ^ 2))");
  EXPECT_EQ(P("2*x^-1*y"), "((2 * (x ^ -1)) * y)");
}

TEST(ParserTest, IfElseifElse) {
  EXPECT_EQ(P("if a then 1 elseif b then 2 else 3"), "if a then 1 else if b then 2 else 3");
  EXPECT_EQ(P("if a then 1 elseif b then 2 elseif c then 3 else 4"),
            "if a then 1 else if b then 2 else if c then 3 else 4");
  // The lowest precedence: the branches take whole sums.
  EXPECT_EQ(P("if x > 0 then x + 1 else x - 1"), "if (x > 0) then (x + 1) else (x - 1)");
  // Parenthesised inside arithmetic.
  EXPECT_EQ(P("2*(if c then a else b) + 1"), "((2 * if c then a else b) + 1)");
  EXPECT_EQ(P("if if a then b else c then 1 else 2"), "if if a then b else c then 1 else 2");
  EXPECT_NE(ParseError("if a then 1").find("expected 'else'"), std::string::npos)
      << ParseError("if a then 1");
  EXPECT_NE(ParseError("if a 1 else 2").find("expected 'then'"), std::string::npos);
}

TEST(ParserTest, RelationsAndLogic) {
  EXPECT_EQ(P("a < b"), "(a < b)");
  EXPECT_EQ(P("a <= b"), "(a <= b)");
  EXPECT_EQ(P("a > b"), "(a > b)");
  EXPECT_EQ(P("a >= b"), "(a >= b)");
  EXPECT_EQ(P("a == b"), "(a == b)");
  EXPECT_EQ(P("a <> b"), "(a <> b)");
  EXPECT_EQ(P("a != b"), "(a <> b)");
  EXPECT_EQ(P("a + 1 < b * 2"), "((a + 1) < (b * 2))");
  EXPECT_EQ(P("a or b and c"), "(a or (b and c))");
  EXPECT_EQ(P("a and b or c and d"), "((a and b) or (c and d))");
  EXPECT_EQ(P("not a and b"), "(not a and b)");
  EXPECT_EQ(P("not a < b"), "not (a < b)");
  EXPECT_EQ(P("not not a"), "not not a");
  EXPECT_EQ(P("x < 1 or true and not false"), "((x < 1) or (true and not false))");
  // A relation is not associative.
  EXPECT_NE(ParseError("a < b < c"), "");
  EXPECT_NE(ParseError("a ! b").find("unexpected character '!'"), std::string::npos);
}

std::string Repeat(const std::string& s, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) out += s;
  return out;
}

TEST(ParserTest, NestingUpToTheLimitParses) {
  const int n = kMaxExpressionDepth - 1;  // the innermost operand is the last level
  EXPECT_EQ(ParseError(Repeat("(", n) + "x" + Repeat(")", n)), "");
  EXPECT_EQ(ParseError(Repeat("abs(", n) + "x" + Repeat(")", n)), "");
  EXPECT_EQ(ParseError(Repeat("-", n) + "x"), "");
  EXPECT_EQ(ParseError(Repeat("not ", n) + "x"), "");
  EXPECT_EQ(ParseError(Repeat("x^", n) + "x"), "");
  EXPECT_EQ(ParseError("R[" + Repeat("-", n - 1) + "i].p"), "");
  EXPECT_EQ(ParseExpression(Repeat("-", n) + "x", SourceLoc{})->height, kMaxExpressionDepth);
}

TEST(ParserTest, NestingPastTheLimitIsAnErrorAtItsColumn) {
  const int n = kMaxExpressionDepth;
  const std::string limit = "expression nested deeper than 256 levels";
  // The parenthesis that opens level 257 is at offset 255; the text starts at column 7.
  std::string msg = ParseError(Repeat("(", n) + "x" + Repeat(")", n));
  EXPECT_EQ(Prefix(msg), "m.yaml:3:263: ") << msg;
  EXPECT_NE(msg.find(limit), std::string::npos) << msg;
  EXPECT_NE(msg.find("split it with intermediate variables or parameters"), std::string::npos) << msg;
  // The quoted text is an excerpt around that column.
  EXPECT_LT(msg.size(), 300u) << msg;
  // Level 257 of a chain of signs is its first sign.
  msg = ParseError(Repeat("-", n) + "x");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:7: ") << msg;
  EXPECT_NE(msg.find(limit), std::string::npos) << msg;
  for (const std::string& text : {Repeat("abs(", n) + "x" + Repeat(")", n), Repeat("not ", n) + "x",
                                  Repeat("x^", n) + "x", "R[" + Repeat("-", n) + "i].p",
                                  "1 + " + Repeat("(", 2 * n) + "x" + Repeat(")", 2 * n),
                                  Repeat("if c then ", n) + "1" + Repeat(" else 2", n)}) {
    EXPECT_NE(ParseError(text).find(limit), std::string::npos) << text.substr(0, 40);
  }
  // 40 000 levels: the same error, no stack overflow.
  EXPECT_NE(ParseError(Repeat("-", 40000) + "x").find(limit), std::string::npos);
  EXPECT_NE(ParseError(Repeat("(", 40000) + "x" + Repeat(")", 40000)).find(limit), std::string::npos);
}

TEST(ParserTest, DerAroundAnExpressionNestsAtMostTheDifferentiationLimit) {
  const int n = static_cast<int>(kMaxDifferentiations);
  // Around names, der() nests as any call does; around an expression, up to 12 deep.
  EXPECT_EQ(ParseError(Repeat("der(", 200) + "x" + Repeat(")", 200)), "");
  EXPECT_EQ(ParseError(Repeat("der(", n) + "x*x + sin(x)" + Repeat(")", n)), "");
  EXPECT_EQ(ParseError("der(" + Repeat("der(", n - 1) + "x*y" + Repeat(")", n - 1) + " + der(x))"), "");
  // The 13th der() from the inside (offset 0 of the text, at column 7) is named.
  std::string msg = ParseError(Repeat("der(", n + 1) + "x*x + sin(x)" + Repeat(")", n + 1));
  EXPECT_EQ(Prefix(msg), "m.yaml:3:7: ") << msg;
  EXPECT_NE(msg.find("der() applied more than 12 times to an expression"), std::string::npos) << msg;
  // 200 deep (reproducer 19): the 13th from the inside, at offset 4 * (200 - 13).
  msg = ParseError(Repeat("der(", 200) + "x*x + sin(x)" + Repeat(")", 200));
  EXPECT_EQ(Prefix(msg), "m.yaml:3:" + std::to_string(7 + 4 * (200 - 13)) + ": ") << msg;
  // An expression anywhere inside counts, also beside a plain der(x).
  msg = ParseError(Repeat("der(", n) + "der(x) + der(2*x)" + Repeat(")", n));
  EXPECT_NE(msg.find("der() applied more than 12 times"), std::string::npos) << msg;
  // Subscripts are not differentiated.
  EXPECT_EQ(ParseError(Repeat("der(", 20) + "x[2*i]" + Repeat(")", 20)), "");
}

TEST(ParserTest, ChainsOfOneOperatorAreOneNode) {
  // 100 000 terms: one sum node of height 2, whatever the signs.
  std::string text = "1";
  for (int k = 2; k <= 100000; ++k) text += (k % 3 ? " + " : " - ") + std::to_string(k);
  AstPtr sum = ParseExpression(text, SourceLoc{});
  EXPECT_EQ(sum->kind, Ast::Kind::kSum);
  EXPECT_EQ(sum->args.size(), 100000u);
  EXPECT_EQ(sum->height, 2);
  EXPECT_EQ(sum->op.substr(0, 4), "++-+");
  AstPtr product = ParseExpression("a * b / c * d", SourceLoc{});
  EXPECT_EQ(product->kind, Ast::Kind::kProduct);
  EXPECT_EQ(product->op, "**/*");
  AstPtr conj = ParseExpression(Repeat("a and ", 50000) + "b or c", SourceLoc{});
  ASSERT_EQ(conj->kind, Ast::Kind::kBinary);
  EXPECT_EQ(conj->op, "or");
  EXPECT_EQ(conj->args[0]->args.size(), 50001u);
  AstPtr branches = ParseExpression("if a then 1" + Repeat(" elseif b then 2", 12000) + " else 3", SourceLoc{});
  EXPECT_EQ(branches->kind, Ast::Kind::kIf);
  EXPECT_EQ(branches->args.size(), 2u * 12001 + 1);
  EXPECT_EQ(branches->height, 2);
  // A syntax error at the end of a long chain quotes the text around it.
  std::string msg = ParseError(text + " + ");
  EXPECT_NE(msg.find("found end of text in '…"), std::string::npos) << msg.substr(0, 300);
  EXPECT_LT(msg.size(), 300u);
}

TEST(ParserTest, NumbersAndNames) {
  EXPECT_EQ(P(".5"), "0.5");
  EXPECT_EQ(P("1e-3"), "0.001");
  EXPECT_EQ(P("2.5E+2"), "250");
  EXPECT_EQ(P("12"), "12");
  EXPECT_EQ(P("R[i+1].p.v"), "R[(i + 1)].p.v");
  EXPECT_EQ(P("flange_a.s - _x2"), "(flange_a.s - _x2)");
  EXPECT_EQ(P("der(flange.s)"), "der(flange.s)");
  EXPECT_EQ(P("atan2(y, x)"), "atan2(y, x)");
  EXPECT_EQ(P("initial()"), "initial()");
  EXPECT_EQ(P("noEvent(x > 0)"), "noEvent((x > 0))");
}

TEST(ParserTest, MalformedNumbers) {
  for (const char* text : {"2x", "1e", "1.5e+", "3abc + 1", "0x10", "1.2.3"}) {
    EXPECT_NE(ParseError(text), "") << "'" << text << "' was accepted as " << P(text);
  }
  // "2x" at column 7: the bad character is 1 further.
  std::string msg = ParseError("2x");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:8: ") << msg;
  EXPECT_NE(msg.find("malformed number '2x'"), std::string::npos) << msg;
  msg = ParseError("a + 1e");
  EXPECT_NE(msg.find("malformed number '1e'"), std::string::npos) << msg;
}

TEST(ParserTest, UnknownFunctionListsTheValidOnesAndPointsAtIt) {
  // "x + foo(1)": foo starts 4 characters into text that starts at column 7.
  std::string msg = ParseError("x + foo(1)");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:11: ") << msg;
  EXPECT_NE(msg.find("unknown function 'foo'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("valid functions:"), std::string::npos) << msg;
  for (const char* f : {"sin", "atan2", "log10", "max", "der", "noEvent", "initial"}) {
    EXPECT_NE(msg.find(f), std::string::npos) << f << " missing from: " << msg;
  }
  EXPECT_EQ(msg.find("reinit"), std::string::npos) << msg;
  // The list is what KnownFunctionList() says.
  EXPECT_NE(msg.find(KnownFunctionList()), std::string::npos);
  int arity = -1;
  EXPECT_TRUE(IsKnownFunction("atan2", &arity));
  EXPECT_EQ(arity, 2);
  EXPECT_TRUE(IsKnownFunction("initial", &arity));
  EXPECT_EQ(arity, 0);
  EXPECT_FALSE(IsKnownFunction("foo", &arity));
}

TEST(ParserTest, FunctionArityErrors) {
  std::string msg = ParseError("1 + sin(x, y)");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:11: ") << msg;
  EXPECT_NE(msg.find("sin() takes 1 argument, found 2"), std::string::npos) << msg;
  msg = ParseError("atan2(y)");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:7: ") << msg;
  EXPECT_NE(msg.find("atan2() takes 2 arguments, found 1"), std::string::npos) << msg;
  msg = ParseError("max()");
  EXPECT_NE(msg.find("max() takes 2 arguments, found 0"), std::string::npos) << msg;
  msg = ParseError("initial(x)");
  EXPECT_NE(msg.find("initial() takes 0 arguments, found 1"), std::string::npos) << msg;
  msg = ParseError("min(a, b, c)");
  EXPECT_NE(msg.find("found 3"), std::string::npos) << msg;
  // A missing parenthesis or comma.
  msg = ParseError("sin(x");
  EXPECT_NE(msg.find("expected ')' or ','"), std::string::npos) << msg;
  EXPECT_EQ(Prefix(msg), "m.yaml:3:12: ") << msg;
}

TEST(ParserTest, SyntaxErrorsNameTheColumnAndTheText) {
  std::string msg = ParseError("a + ");
  EXPECT_NE(msg.find("expected a number, a name, '(' or '['"), std::string::npos) << msg;
  EXPECT_NE(msg.find("found end of text"), std::string::npos) << msg;
  EXPECT_NE(msg.find("in 'a + '"), std::string::npos) << msg;
  msg = ParseError("(a + b");
  EXPECT_NE(msg.find("expected ')'"), std::string::npos) << msg;
  msg = ParseError("a b");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:9: ") << msg;
  EXPECT_NE(msg.find("unexpected 'b'"), std::string::npos) << msg;
  msg = ParseError("a + then");
  EXPECT_NE(msg.find("expected an operand"), std::string::npos) << msg;
  msg = ParseError("x # y");
  EXPECT_EQ(Prefix(msg), "m.yaml:3:9: ") << msg;
  EXPECT_NE(msg.find("unexpected character '#'"), std::string::npos) << msg;
  msg = ParseError("A.");
  EXPECT_NE(msg.find("expected a name after '.'"), std::string::npos) << msg;
  msg = ParseError("R[1");
  EXPECT_NE(msg.find("expected ']'"), std::string::npos) << msg;
  // An unknown place: no prefix.
  try {
    ParseExpression("a +", SourceLoc{});
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("expected", 0), 0u) << e.what();
  }
}

TEST(ParserTest, Equations) {
  SourceLoc loc{"m.yaml", 5, 9};
  AstEquation eq = ParseEquation("m*der(v) = f - d*v", loc);
  EXPECT_EQ(AstToString(*eq.lhs), "(m * der(v))");
  EXPECT_EQ(AstToString(*eq.rhs), "(f - (d * v))");
  // '==' is a relation, not the equation's '='.
  eq = ParseEquation("b = x == 1", loc);
  EXPECT_EQ(AstToString(*eq.rhs), "(x == 1)");
  try {
    ParseEquation("a + b", loc);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("expected '=' between the two sides"), std::string::npos);
    EXPECT_EQ(Prefix(e.what()), "m.yaml:5:14: ") << e.what();
  }
  EXPECT_THROW(ParseEquation("a = b = c", loc), ModelError);
  EXPECT_THROW(ParseEquation("= b", loc), ModelError);
}

TEST(ParserTest, Names) {
  SourceLoc loc{"m.yaml", 2, 4};
  EXPECT_EQ(ParseName("A.flange_a", loc)->PathText(), "A.flange_a");
  AstPtr n = ParseName("R[i+1].p", loc);
  ASSERT_EQ(n->path.size(), 2u);
  EXPECT_EQ(n->path[0].name, "R");
  ASSERT_TRUE(n->path[0].index);
  EXPECT_EQ(AstToString(*n->path[0].index), "(i + 1)");
  EXPECT_FALSE(n->path[1].index);
  EXPECT_THROW(ParseName("1 + x", loc), ModelError);
  EXPECT_THROW(ParseName("A.b + 1", loc), ModelError);
  EXPECT_THROW(ParseName("sin(x)", loc), ModelError);
}

TEST(ParserTest, ColumnsInAModelFileCountFromTheScalar) {
  // The equation text starts at line 6, column 9 (after "      - "); foo is 4 further. A quoted
  // scalar's text starts one column after the quote.
  const char* yaml = R"yaml(model: M
define:
  T:
    variables: {x: {}}
    equations:
      - x = foo(1)
components:
  t: {type: T}
)yaml";
  try {
    LoadModelString(yaml, "m.yaml");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_EQ(Prefix(e.what()), "m.yaml:6:13: ") << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown function 'foo'"), std::string::npos);
  }
  const char* quoted = R"yaml(model: M
define:
  T:
    variables: {x: {}}
    equations:
      - "x = sin(1, 2)"
components:
  t: {type: T}
)yaml";
  try {
    LoadModelString(quoted, "m.yaml");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_EQ(Prefix(e.what()), "m.yaml:6:14: ") << e.what();
    EXPECT_NE(std::string(e.what()).find("sin() takes 1 argument"), std::string::npos);
  }
  // An output expression.
  const char* output = R"yaml(model: M
outputs: [time, "2 + $"]
)yaml";
  try {
    LoadModelString(output, "m.yaml");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_EQ(Prefix(e.what()), "m.yaml:2:22: ") << e.what();
  }
}

}  // namespace
}  // namespace momenta

namespace momenta {
namespace {

// A text that is one number or one dotted name is read without tokens (core/lang/parser.cc): the same
// tree as the parser's (which the same text in parentheses or after a space still goes through),
// at column 0; anything else, keywords and malformed numbers included, is the parser's.
TEST(ParserTest, PlainNumbersAndNamesGiveTheParsersTrees) {
  const SourceLoc loc{"m.yaml", 3, 7};
  for (const std::string text :
       {"0", "1e4", "2.5", ".5", "1.", "1E-3", "7e+2", "12345678901234567890", "2.2250738585072014e-308",
        "0e-400"}) {
    const AstPtr plain = ParseExpression(text, loc);
    const AstPtr parsed = ParseExpression("(" + text + ")", loc);
    EXPECT_EQ(plain->kind, Ast::Kind::kNumber) << text;
    EXPECT_EQ(plain->number, parsed->number) << text;
    EXPECT_EQ(plain->height, parsed->height) << text;
    EXPECT_EQ(plain->column, 0) << text;
  }
  for (const std::string text : {"a", "mass1.flange_b", "_x.y1._z", "der", "R.p.v"}) {
    const AstPtr plain = ParseName(text, loc);
    const AstPtr parsed = ParseName(" " + text, loc);
    EXPECT_EQ(plain->kind, Ast::Kind::kName) << text;
    EXPECT_EQ(plain->PathText(), parsed->PathText()) << text;
    EXPECT_EQ(plain->path.size(), parsed->path.size()) << text;
    EXPECT_EQ(plain->height, parsed->height) << text;
    EXPECT_EQ(plain->column, 0) << text;
  }
  EXPECT_EQ(ParseError("1e400"), "m.yaml:3:7: number out of range '1e400' (double's range: magnitudes from 2.2e-308 to 1.8e308)");
  // A subnormal, alone or not, as a value with a unit is (core/lang/units.h, ParseDecimal).
  EXPECT_EQ(ParseError("4.9e-324"), "m.yaml:3:7: number out of range '4.9e-324' (double's range: magnitudes from 2.2e-308 to 1.8e308)");
  EXPECT_EQ(ParseError("(4.9e-324)"), "m.yaml:3:8: number out of range '4.9e-324' (double's range: magnitudes from 2.2e-308 to 1.8e308)");
  EXPECT_EQ(ParseError("1e"), "m.yaml:3:8: malformed number '1e'");
  EXPECT_EQ(P("true"), "true");
  EXPECT_THROW(ParseName("true", loc), ModelError);
  EXPECT_THROW(ParseName("a..b", loc), ModelError);
  EXPECT_THROW(ParseName("if.x", loc), ModelError);
  EXPECT_EQ(ParseName("a.b[2]", loc)->PathText(), "a.b[2]");
}

TEST(ParserTest, PlainNamesAreTheNamesParseNameReadsAlone) {
  for (const char* plain : {"a", "mass1.flange_b", "_x.y_2.z"}) {
    EXPECT_TRUE(IsPlainName(plain)) << plain;
    EXPECT_EQ(ParseName(plain, SourceLoc())->PathText(), plain);
  }
  for (const char* other : {"", "a.", ".a", "a..b", "a[1].p", "a .b", "1a.b", "true", "if.x", "a.b "}) {
    EXPECT_FALSE(IsPlainName(other)) << other;
  }
}

}  // namespace
}  // namespace momenta
