// TerminalText: control characters become visible, everything else (UTF-8 text, newlines, tabs)
// passes unchanged.
#include "core/base/messages.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace momenta
