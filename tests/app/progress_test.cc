// The progress line: its texts (simulated time, percent, elapsed and left; a sweep's runs), nothing
// on a pipe, and on a real terminal (a pseudo-terminal from forkpty) the line redrawn in place,
// erased before the command's own output, and Ctrl-C still stopping cleanly with the rows kept.

#include "app/progress.h"

#include <gtest/gtest.h>

#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>
#include <string>
#include <vector>

#include "app/commands.h"
#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(ProgressTest, Durations) {
  EXPECT_EQ(FormatDuration(0), "0.0 s");
  EXPECT_EQ(FormatDuration(0.44), "0.4 s");
  EXPECT_EQ(FormatDuration(9.96), "10.0 s");
  EXPECT_EQ(FormatDuration(12.7), "12 s");
  EXPECT_EQ(FormatDuration(185), "3 min 05 s");
  EXPECT_EQ(FormatDuration(7620), "2 h 07 min");
  EXPECT_EQ(FormatDuration(-1), "0.0 s");
}

TEST(ProgressTest, SimulationText) {
  // 12.5 of 100 s in 3.2 s: the other 87.5 s at the same pace take 3.2 * 7 = 22.4 s.
  EXPECT_EQ(FormatSimulationProgress(12.5, 0, 100, 3.2), "t = 12.5 / 100 s (12.5%), 3.2 s elapsed, about 22 s left");
  // From a start other than 0: 3 of [2, 6] is a quarter.
  EXPECT_EQ(FormatSimulationProgress(3, 2, 6, 1.5), "t = 3 / 6 s (25.0%), 1.5 s elapsed, about 4.5 s left");
  // Nothing done yet: no estimate; the end: none needed; a time past the ends is clamped.
  EXPECT_EQ(FormatSimulationProgress(0, 0, 10, 1.2), "t = 0 / 10 s (0.0%), 1.2 s elapsed");
  EXPECT_EQ(FormatSimulationProgress(10, 0, 10, 2), "t = 10 / 10 s (100.0%), 2.0 s elapsed");
  EXPECT_EQ(FormatSimulationProgress(11, 0, 10, 2), "t = 10 / 10 s (100.0%), 2.0 s elapsed");
  EXPECT_EQ(FormatSimulationProgress(0.123456789, 0, 1, 60), "t = 0.1235 / 1 s (12.3%), 1 min 00 s elapsed, about 7 min 06 s left");
}

TEST(ProgressTest, SweepText) {
  // 40 of 200 runs in 3.25 s: 12.3 runs/s, the other 160 in 13 s.
  EXPECT_EQ(FormatSweepProgress(40, 200, 1, 3.25), "sweep: 40/200 runs, 1 failed, 12.3 runs/s, about 13 s left");
  EXPECT_EQ(FormatSweepProgress(0, 200, 0, 1.1), "sweep: 0/200 runs, 0 failed, 0 runs/s");
}

/// A 1 kHz oscillator to t = 1000 s: a minute or more, stopped by SIGINT in these tests.
std::string Oscillator() { return testing::SourcePath("tests/data/oscillator_1khz.yaml"); }

TEST(ProgressTest, NothingOnAPipe) {
  testing::TempDir dir;
  // Longer than the second after which a terminal would see the line: stopped by SIGINT once the
  // rows show that 1.5 s have passed.
  testing::MomentaProcess p({"simulate", Oscillator(), "-o", "osc.csv"}, dir.path());
  ASSERT_TRUE(p.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  p.Signal(SIGINT);
  EXPECT_EQ(p.Wait(60), 130) << p.err();
  const std::string err = p.err();
  EXPECT_FALSE(Contains(err, "\r")) << err;
  EXPECT_FALSE(Contains(err, "elapsed")) << err;
  EXPECT_TRUE(Contains(err, "oscillator_1khz.yaml: interrupted at t = ")) << err;
}

TEST(ProgressTest, OnATerminalTheLineIsRedrawnAndErasedAndCtrlCStops) {
  testing::TempDir dir;
  const std::string binary = MOMENTA_BINARY, model = Oscillator(), out = dir.File("osc.csv");
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0) << "forkpty failed";
  if (pid == 0) {
    execl(binary.c_str(), binary.c_str(), "simulate", model.c_str(), "-o", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Read what the terminal shows; once a progress line with its estimate has come, Ctrl-C.
  std::string screen;
  bool signalled = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd fd = {master, POLLIN, 0};
    if (poll(&fd, 1, 100) > 0) {
      char buf[4096];
      const ssize_t n = read(master, buf, sizeof buf);
      if (n <= 0) break;  // the child has ended (EIO on Linux)
      screen.append(buf, n);
    }
    if (!signalled && Contains(screen, " left\033[K")) {
      kill(pid, SIGINT);
      signalled = true;
    }
  }
  int status = 0;
  if (waitpid(pid, &status, WNOHANG) == 0) kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  close(master);
  ASSERT_TRUE(signalled) << "no progress line within 120 s:\n" << screen;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << screen;
  // Drawn in place: a carriage return, the text, the rest of the line erased.
  EXPECT_TRUE(Contains(screen, "\rt = ")) << screen;
  EXPECT_TRUE(Contains(screen, " / 1000 s (")) << screen;
  EXPECT_TRUE(Contains(screen, " elapsed, about ")) << screen;
  // Erased before the note, which is then alone on its line.
  const size_t erased = screen.rfind("\r\033[K");
  ASSERT_NE(erased, std::string::npos) << screen;
  const std::string after = screen.substr(erased + 4);
  EXPECT_TRUE(Contains(after, "oscillator_1khz.yaml: interrupted at t = ")) << after;
  EXPECT_FALSE(Contains(after, "\rt = ")) << after;
  // The rows so far are in the file, whole.
  std::vector<std::string> lines = testing::Lines(testing::ReadText(out));
  ASSERT_GT(lines.size(), 100u);
  EXPECT_EQ(lines[0], "time,o.x");
  EXPECT_TRUE(testing::IsNumericRow(lines.back(), 2)) << lines.back();
}

}  // namespace
}  // namespace momenta
