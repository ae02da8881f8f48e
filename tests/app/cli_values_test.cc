// Command-line values out of range: each is a usage error (exit 2) whose message names the option
// and the value, never silently replaced by the experiment's value, never a run "from 0 to 0 s",
// never a hang. Also: -p names that are no parameter, and a results file that cannot be written.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/commands.h"
#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// x' = -x from x = 1 on [1, 3]: a start time that is not 0.
constexpr const char* kDecay = R"yaml(model: Decay
variables:
  x: {start: 1, fixed: true}
equations:
  - der(x) = -x
experiment: {start: 1, stop: 3, interval: 0.5}
outputs: [x]
)yaml";

struct Case {
  std::vector<std::string> args;  ///< after `simulate <model>`
  std::string message;            ///< what stderr must contain
};

class CliValuesTest : public ::testing::Test {
 protected:
  /// Runs `momenta simulate <model> args -o out.csv` with a deadline (a hang fails the test).
  CliResult Simulate(const std::string& model, std::vector<std::string> args) {
    std::vector<std::string> all = {"simulate", model};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), {"-o", "out.csv"});
    return testing::RunMomentaWithDeadline(all, dir_.path(), 60);
  }

  void ExpectUsageError(const std::string& model, const Case& c) {
    std::string label = model;
    for (const auto& a : c.args) label += " " + a;
    CliResult r = Simulate(model, c.args);
    EXPECT_EQ(r.exit_code, kExitUsage) << label << "\n" << r.out << r.err;
    EXPECT_TRUE(Contains(r.err, c.message)) << label << ": no '" << c.message << "' in:\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("out.csv"))) << label << ": a results file was written";
    std::filesystem::remove(dir_.File("out.csv"));
  }

  TempDir dir_;
};

TEST_F(CliValuesTest, StopThatIsNotAFiniteTimeAfterTheStartIsAUsageError) {
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  const std::string why = ": the stop time must be a finite number after the start time 0 (experiment.start)";
  for (const Case& c : std::vector<Case>{
           {{"--stop", "-1"}, "--stop -1" + why},
           {{"--stop", "nan"}, "--stop nan" + why},
           {{"--stop", "inf"}, "--stop inf" + why},
           {{"--stop", "0"}, "--stop 0" + why},
       }) {
    ExpectUsageError(rc, c);
  }
  // Before a start time that is not 0.
  dir_.Write("decay.yaml", kDecay);
  ExpectUsageError("decay.yaml", {{"--stop", "0.5"},
                                  "--stop 0.5: the stop time must be a finite number after the start time 1 (experiment.start)"});
  ExpectUsageError("decay.yaml", {{"--stop", "1"}, "--stop 1: the stop time must be a finite number after the start time 1"});
}

TEST_F(CliValuesTest, ToleranceThatIsNotPositiveOrBelowDoublePrecisionIsAUsageError) {
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  const std::string rtol = ": the relative tolerance must be a number from 1e-15 to below 1 (double precision resolves "
                           "relative differences of about 2.2e-16)";
  const std::string atol = ": the absolute tolerance must be a positive finite number, at least 2.2e-308";
  for (const Case& c : std::vector<Case>{
           {{"--rtol", "0"}, "--rtol 0" + rtol},
           {{"--rtol", "-1"}, "--rtol -1" + rtol},
           {{"--rtol", "nan"}, "--rtol nan" + rtol},
           {{"--rtol", "1e-300"}, "--rtol 1e-300" + rtol},
           {{"--rtol", "1e-16"}, "--rtol 1e-16" + rtol},
           {{"--rtol", "1"}, "--rtol 1" + rtol},
           {{"--atol", "0"}, "--atol 0" + atol},
           {{"--atol", "-1"}, "--atol -1" + atol},
           {{"--atol", "nan"}, "--atol nan" + atol},
           {{"--atol", "inf"}, "--atol inf" + atol},
           {{"--atol", "1e-320"}, "--atol 1e-320" + atol},
       }) {
    ExpectUsageError(rc, c);
  }
}

TEST_F(CliValuesTest, IntervalThatIsNotPositiveOrGivesTooManyRowsIsAUsageError) {
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  const std::string why = ": the output interval must be a positive finite number";
  for (const Case& c : std::vector<Case>{
           {{"--interval", "0"}, "--interval 0" + why},
           {{"--interval", "-1"}, "--interval -1" + why},
           {{"--interval", "nan"}, "--interval nan" + why},
           {{"--interval", "inf"}, "--interval inf" + why},
           // Today's "simulated 0 to 0 s" (the number of intervals overflowed a cast to long).
           {{"--interval", "1e-300", "--stop", "1"},
            "--interval 1e-300: from 0 to 1 s that is 1e+300 output rows; at most 1e9 can be written"},
           // The experiment's interval (0.01 s) with a far stop time: --stop is named.
           {{"--stop", "1e12"},
            "--stop 1e+12: with the output interval 0.01 s (experiment.interval) from 0 to 1e+12 s that is 1e+14 "
            "output rows; at most 1e9 can be written; choose a larger --interval"},
       }) {
    ExpectUsageError(rc, c);
  }
}

TEST_F(CliValuesTest, MaxOrderThatIsNotAWholeNumberFromOneToFiveIsAUsageError) {
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  const std::string why = ": the maximum BDF order must be a whole number from 1 to 5 (IDA's default is 5)";
  for (const Case& c : std::vector<Case>{
           {{"--max-order", "0"}, "--max-order 0" + why},
           {{"--max-order", "6"}, "--max-order 6" + why},
           {{"--max-order", "2.5"}, "--max-order 2.5" + why},
           {{"--max-order", "nan"}, "--max-order nan" + why},
       }) {
    ExpectUsageError(rc, c);
  }
}

TEST_F(CliValuesTest, MaxOrderReachesIda) {
  // The decay x' = -x at rtol 1e-8: backward Euler (order 1) needs many more steps than IDA's
  // variable order up to 5 for the same tolerance. Both end near exp(-1) = 0.3678794412: order 5
  // to 1e-8; order 1 to 1.5e-5 (its local errors, each within the tolerance, add up over its
  // 12 000 steps).
  dir_.Write("decay.yaml", kDecay);
  auto steps_of = [](const std::string& out) {
    const size_t at = out.find(" steps,");
    if (at == std::string::npos) return -1L;
    size_t begin = out.rfind(' ', at - 1);
    return std::stol(out.substr(begin + 1, at - begin - 1));
  };
  CliResult first = Simulate("decay.yaml", {"--stop", "2", "--rtol", "1e-8", "--atol", "1e-10", "--max-order", "1"});
  CliResult fifth = Simulate("decay.yaml", {"--stop", "2", "--rtol", "1e-8", "--atol", "1e-10"});
  ASSERT_EQ(first.exit_code, kExitOk) << first.err;
  ASSERT_EQ(fifth.exit_code, kExitOk) << fifth.err;
  EXPECT_TRUE(Contains(first.out, "x = 0.3678")) << first.out;
  EXPECT_TRUE(Contains(fifth.out, "x = 0.3678794")) << fifth.out;
  const long order1 = steps_of(first.out), order5 = steps_of(fifth.out);
  ASSERT_GT(order1, 0) << first.out;
  ASSERT_GT(order5, 0) << fifth.out;
  EXPECT_GT(order1, 5 * order5) << first.out << fifth.out;
}

TEST_F(CliValuesTest, ExperimentMaxOrderReachesIdaAndTheCommandLineOverridesIt) {
  // The decay of MaxOrderReachesIda with `max_order: 1` in its experiment: as many steps as
  // --max-order 1 (the same run), and --max-order 5 gives IDA's full order back.
  dir_.Write("decay.yaml", kDecay);
  std::string capped = kDecay;
  const size_t at = capped.find("experiment: {");
  ASSERT_NE(at, std::string::npos);
  capped.insert(at + std::string("experiment: {").size(), "max_order: 1, ");
  dir_.Write("capped.yaml", capped);
  const std::vector<std::string> run = {"--stop", "2", "--rtol", "1e-8", "--atol", "1e-10"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = run;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  CliResult by_option = Simulate("decay.yaml", with({"--max-order", "1"}));
  CliResult by_model = Simulate("capped.yaml", run);
  CliResult overridden = Simulate("capped.yaml", with({"--max-order", "5"}));
  CliResult full = Simulate("decay.yaml", run);
  for (const CliResult* r : {&by_option, &by_model, &overridden, &full}) ASSERT_EQ(r->exit_code, kExitOk) << r->err;
  // The solver line (steps, evaluations, failures): the two order-1 runs and the two order-5
  // runs agree, and the orders differ.
  auto summary = [](const std::string& out) {
    const size_t at = out.find("IDA with");
    return at == std::string::npos ? out : out.substr(at, out.find('\n', at) - at);
  };
  EXPECT_EQ(summary(by_model.out), summary(by_option.out));
  EXPECT_EQ(summary(overridden.out), summary(full.out));
  EXPECT_NE(summary(by_model.out), summary(full.out));
}

TEST_F(CliValuesTest, ValidValuesAreUsedNotReplaced) {
  // The smallest accepted tolerances run, and --stop and --interval shape the grid exactly.
  dir_.Write("decay.yaml", kDecay);
  CliResult r = Simulate("decay.yaml", {"--stop", "2", "--interval", "0.25", "--rtol", "1e-12", "--atol", "1e-14"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_TRUE(Contains(r.out, "simulated 1 to 2 s")) << r.out;
  EXPECT_TRUE(Contains(r.out, "out.csv (5 rows)")) << r.out;  // 1, 1.25, 1.5, 1.75, 2
  // x(2) = exp(-1) at rtol 1e-12.
  EXPECT_TRUE(Contains(r.out, "x = 0.3678794412")) << r.out;
}

TEST_F(CliValuesTest, ReproducerStopInfIsAUsageErrorNotAHang) {
  // tests/data/reliability/12-hang-cli-stop-inf.yaml: IDA integrated towards t = inf forever.
  const std::string file = testing::SourcePath("tests/data/reliability/12-hang-cli-stop-inf.yaml");
  CliResult r = testing::RunMomentaWithDeadline({"simulate", file, "--stop", "inf", "-o", "out.csv", "-q"},
                                                dir_.path(), 60);
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "--stop inf: the stop time must be a finite number after the start time 0")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("out.csv")));
}

TEST_F(CliValuesTest, UnknownParameterIsAUsageErrorWithCloseNames) {
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  for (const Case& c : std::vector<Case>{
           {{"-p", "nosuch=1"}, "-p nosuch: no parameter of that name in RCLadder (model parameters: n; component "
                                "parameters are named like A.m)"},
           {{"-p", "R[0].R=1"}, "-p R[0].R: no parameter of that name in RCLadder (R has elements R[1] to R[10]) "
                                "(did you mean R[10].R, R[1].R, R[2].R?)"},
           {{"-p", "R[99].R=1"}, "-p R[99].R: no parameter of that name in RCLadder (R has elements R[1] to R[10]) "
                                 "(did you mean R[9].R"},
           {{"-p", "R[1].r=1"}, "-p R[1].r: no parameter of that name in RCLadder (R has elements R[1] to R[10]) "
                                "(did you mean R[1].R"},
       }) {
    ExpectUsageError(rc, c);
  }
  // check names it the same way.
  CliResult r = testing::RunMomentaWithDeadline({"check", rc, "-p", "nosuch=1"}, dir_.path(), 60);
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "-p nosuch: no parameter of that name")) << r.err;
}

TEST_F(CliValuesTest, ResultsFileThatCannotBeWrittenExitsWithThree) {
  // /dev/full accepts the open and fails every write (ENOSPC): exit 3 naming the file, not 0.
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this system";
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  CliResult r = testing::RunMomentaWithDeadline({"simulate", rc, "-o", "/dev/full"}, dir_.path(), 60);
  EXPECT_EQ(r.exit_code, kExitSolver) << r.out << r.err;
  EXPECT_TRUE(Contains(r.err, "momenta: cannot write the results file /dev/full: No space left on device")) << r.err;
  EXPECT_FALSE(Contains(r.out, "simulated")) << "no success summary after a failed write:\n" << r.out;
}

TEST_F(CliValuesTest, ResultsFileThatCannotBeCreatedExitsWithThree) {
  // The same exit code as a MAT file in a missing directory (mat_test.cc), and as a failed write.
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  CliResult r = testing::RunMomentaWithDeadline({"simulate", rc, "-o", "no-such-dir/x.csv"}, dir_.path(), 60);
  EXPECT_EQ(r.exit_code, kExitSolver) << r.out << r.err;
  EXPECT_TRUE(Contains(r.err, "momenta: cannot write the results file no-such-dir/x.csv: No such file or directory"))
      << r.err;
  EXPECT_EQ(r.out, "");
}

TEST_F(CliValuesTest, PendulumChainOfTwoHundredLinksInitialisesAndSimulates) {
  // The chain's kept body positions start at 0 while its joint angles add up to radians: Newton
  // fails from the start values, and initialisation starts over from the guesses the frame
  // constraints give. (It failed for n >= ~100 before.)
  const std::string chain = testing::SourcePath("models/pendulum_chain.yaml");
  CliResult r = testing::RunMomentaWithDeadline(
      {"simulate", chain, "-p", "n=200", "--stop", "0.05", "-o", dir_.File("chain.csv")}, dir_.path(), 120);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(Contains(r.out, "simulated 0 to 0.05 s")) << r.out;
}

}  // namespace
}  // namespace momenta
