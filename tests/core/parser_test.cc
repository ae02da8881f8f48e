#include "core/parser.h"

#include <gtest/gtest.h>

namespace momenta {
namespace {

TEST(ParserTest, PrecedenceAndAssociativity) {
  SourceLoc loc{"m.yaml", 3, 7};
  EXPECT_EQ(AstToString(*ParseExpression("a + b*c^2^3", loc)), "(a + (b * (c ^ (2 ^ 3))))");
  EXPECT_EQ(AstToString(*ParseExpression("-x^2", loc)), "-(x ^ 2)");
  EXPECT_EQ(AstToString(*ParseExpression("if a < b then 1 else 2", loc)), "if (a < b) then 1 else 2");
}

}  // namespace
}  // namespace momenta
