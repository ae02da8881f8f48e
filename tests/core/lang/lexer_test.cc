// The tokens of an expression (core/lang/lexer.h): kinds, texts and columns, two-character
// operators, numbers that end where a decimal ends; and the three mistakes it reports by column.

#include "core/lang/lexer.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace momenta {
namespace {

std::string Kinds(const std::vector<Token>& tokens) {
  static const char* kNames[] = {"end", "number", "name", "op", "(", ")", "[", "]", ",", "."};
  std::string s;
  for (const Token& t : tokens) {
    s += (s.empty() ? "" : " ") + std::string(kNames[static_cast<int>(t.kind)]);
  }
  return s;
}

std::string ErrorOf(const std::string& text) {
  try {
    Tokenize(text, SourceLoc("m.yaml", 2, 5));
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(LexerTest, TokensWithTheirColumns) {
  const std::vector<Token> tokens = Tokenize("R[1, 2].v <= 2.5e3 != x", SourceLoc("m.yaml"));
  EXPECT_EQ(Kinds(tokens), "name [ number , number ] . name op number op name end");
  EXPECT_EQ(tokens[8].text, "<=");
  EXPECT_EQ(tokens[8].column, 10);
  EXPECT_EQ(tokens[9].number, 2500);
  EXPECT_EQ(tokens[10].text, "<>");  // != is <>
  EXPECT_EQ(tokens.back().column, 23);
}

TEST(LexerTest, NumbersEndWhereADecimalEnds) {
  EXPECT_EQ(DecimalEnd("1.5e-3*x", 0), 6u);
  EXPECT_EQ(DecimalEnd(".5", 0), 2u);
  EXPECT_EQ(DecimalEnd("2e", 0), 1u);  // an 'e' without digits is not part of the number
  EXPECT_EQ(Kinds(Tokenize(".5 * 2", SourceLoc("m.yaml"))), "number op number end");
}

TEST(LexerTest, MistakesAreReportedAtTheirColumn) {
  EXPECT_EQ(ErrorOf("1 + 2x"), "m.yaml:2:10: malformed number '2x'");
  EXPECT_EQ(ErrorOf("1e999"), "m.yaml:2:5: number out of range '1e999' (double's range: magnitudes from 2.2e-308 to 1.8e308)");
  EXPECT_EQ(ErrorOf("a $ b"), "m.yaml:2:7: unexpected character '$'");
  // A subnormal keeps a few digits of what was written (1e-320 reads as 9.99989e-321).
  EXPECT_EQ(ErrorOf("x * 1e-320"), "m.yaml:2:9: number out of range '1e-320' (double's range: magnitudes from 2.2e-308 to 1.8e308)");
  EXPECT_EQ(Kinds(Tokenize("0e-400 + 2.2250738585072014e-308", SourceLoc("m.yaml"))), "number op number end");
}

}  // namespace
}  // namespace momenta
