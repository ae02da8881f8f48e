// SIGINT and SIGTERM during `momenta simulate`: the run stops at the next step, every row computed
// so far is in the CSV and every line of it is complete, a message says where it stopped, and the
// exit status is 128 + the signal number. Tested on the real binary in a child process.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::IsNumericRow;
using testing::Lines;
using testing::MomentaProcess;
using testing::TempDir;

/// The number after `prefix` in `text` (NaN when absent).
double NumberAfter(const std::string& text, const std::string& prefix) {
  size_t at = text.find(prefix);
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + prefix.size()));
}

/// Runs the RC ladder (2000 stages) far longer than the test waits, signals it once the first
/// rows are in the file, and checks what it leaves.
void InterruptAndCheck(int signal_number, int expected_exit) {
  TempDir dir;
  MomentaProcess p({"simulate", testing::SourcePath("models/rc_ladder.yaml"), "-p", "n=2000", "--stop", "100000",
                    "--interval", "0.01", "-o", "out.csv"},
                   dir.path());
  ASSERT_TRUE(p.started());
  // Wait (at most 60 s) until rows have appeared after the header.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (Lines(testing::ReadText(dir.File("out.csv"))).size() < 3 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(Lines(testing::ReadText(dir.File("out.csv"))).size(), 3u) << "no rows after 60 s:\n" << p.err();
  p.Signal(signal_number);
  const int status = p.Wait(60);
  const std::string err = p.err();
  ASSERT_EQ(status, expected_exit) << err;

  // "models/rc_ladder.yaml: interrupted at t = 1.23; 124 rows kept in out.csv (up to t = 1.23)"
  EXPECT_NE(err.find(": interrupted at t = "), std::string::npos) << err;
  EXPECT_NE(err.find(" rows kept in out.csv (up to t = "), std::string::npos) << err;
  const double t_stop = NumberAfter(err, "interrupted at t = ");
  const double rows = NumberAfter(err, "; ");
  const double last_t = NumberAfter(err, "(up to t = ");
  EXPECT_GT(t_stop, 0) << err;
  EXPECT_LT(t_stop, 100000) << err;
  EXPECT_LE(last_t, t_stop) << err;

  // Every line is complete: the header's column count, every cell a number; as many rows as the
  // message says, the last at the time it says.
  const std::vector<std::string> lines = Lines(testing::ReadText(dir.File("out.csv")));
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0], "time,C[1].v,C[n].v");
  EXPECT_EQ(static_cast<double>(lines.size() - 1), rows) << err;
  const std::string text = testing::ReadText(dir.File("out.csv"));
  EXPECT_EQ(text.back(), '\n') << "the file ends inside a row";
  for (size_t k = 1; k < lines.size(); ++k) {
    EXPECT_TRUE(IsNumericRow(lines[k], 3)) << "line " << k + 1 << " is not a complete row: " << lines[k];
  }
  EXPECT_EQ(std::stod(lines.back()), last_t) << lines.back();
}

TEST(InterruptTest, SigintKeepsEveryCompleteRowAndExitsWith130) { InterruptAndCheck(SIGINT, 130); }

TEST(InterruptTest, SigtermKeepsEveryCompleteRowAndExitsWith143) { InterruptAndCheck(SIGTERM, 143); }

}  // namespace
}  // namespace momenta
