// TerminalText: control characters become visible, everything else (UTF-8 text, newlines, tabs)
// passes unchanged.
#include "core/base/messages.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace momenta {
namespace {

TEST(TerminalTextTest, ControlCharactersBecomeVisible) {
  EXPECT_EQ(TerminalText("Esc\x1b[31mRED\x1b]0;TITLE\a"), "Esc\\x1b[31mRED\\x1b]0;TITLE\\x07");
  EXPECT_EQ(TerminalText(std::string("a\0b\rc\x7f", 6)), "a\\x00b\\x0dc\\x7f");
  // C1 controls written as UTF-8 (U+009B is CSI on terminals that honour C1).
  EXPECT_EQ(TerminalText("x\xc2\x9b"
                         "2J"),
            "x\\u009b2J");
}

TEST(TerminalTextTest, TextNewlinesAndTabsPass) {
  const std::string text =
      "line 1\n\tR\xc3\xa9sistance \xc2\xb0"
      "C \xe2\x80\xa6\n";
  EXPECT_EQ(TerminalText(text), text);
}

TEST(NumberTextTest, NotANumberIsWrittenOneWay) {
  // printf gives "nan" or "-nan" by the sign bit; a message says NaN whatever the bit.
  EXPECT_EQ(NumberText(std::nan("")), "NaN");
  EXPECT_EQ(NumberText(-std::nan("")), "NaN");
  EXPECT_EQ(NumberText(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(NumberText(2.5), "2.5");
}

}  // namespace
}  // namespace momenta
