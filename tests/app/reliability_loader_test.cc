// Issue 11, the loader and structural bounds, through the real binary: the reliability
// reproducer 11 (a billion-long `for:` range that hung `momenta check`), `-p n=1e300` on a
// count, and files that are not models (a directory, an empty file, a key given twice, a second
// YAML document, YAML nested a thousand levels). Each must end at once with exit code 1 and a
// message naming the file, the place and the value. (ctest's timeout guards against a hang.)

#include <gtest/gtest.h>

#include <string>

#include "app/commands.h"
#include "tests/support/cli_runner.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::RunMomenta;
using testing::TempDir;

const std::string kSource = MOMENTA_SOURCE_DIR;

TEST(ReliabilityLoaderTest, Reproducer11ForRangeOfABillionIsRefused) {
  CliResult r = RunMomenta({"check", "tests/data/reliability/11-hang-for-range-1e9.yaml"}, kSource);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_NE(r.err.find("tests/data/reliability/11-hang-for-range-1e9.yaml:12:10: the range of "
                       "'for: i in 1:1000000000' makes 1000000000 connections, more than the model's 6 "
                       "connectors can need"),
            std::string::npos)
      << r.err;
}

TEST(ReliabilityLoaderTest, CountOf1e300FromTheCommandLineSaysSo) {
  CliResult r = RunMomenta({"check", "models/rc_ladder.yaml", "-p", "n=1e300"}, kSource);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_NE(r.err.find("models/rc_ladder.yaml:12:6: count of R ('n') is 1e300: 1e300 Resistor components"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("-9223372036854775808"), std::string::npos) << r.err;
}

TEST(ReliabilityLoaderTest, DirectoryAndEmptyFile) {
  TempDir dir;
  CliResult r = RunMomenta({"check", dir.path()}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel);
  EXPECT_EQ(r.err, dir.path() + ": is a directory, not a model file\n");
  dir.Write("empty.yaml", "");
  r = RunMomenta({"check", "empty.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel);
  EXPECT_EQ(r.err, "empty.yaml: the model file is empty\n");
}

TEST(ReliabilityLoaderTest, KeyGivenTwiceNamesBothLines) {
  TempDir dir;
  dir.Write("twice.yaml", R"(model: Twice
components:
  s: {type: Sine, amplitude: 1}
outputs: [s.y]
outputs: [s.u]
)");
  CliResult r = RunMomenta({"simulate", "twice.yaml", "-q", "-o", "out.csv"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel);
  EXPECT_EQ(r.err,
            "twice.yaml:5:1: 'outputs' is given twice in the model file (first at line 4, column 1); "
            "remove one of them\n");
}

TEST(ReliabilityLoaderTest, SecondDocumentAndDeepYaml) {
  TempDir dir;
  dir.Write("two.yaml", "model: A\ncomponents: {m: {type: Mass}}\n---\nmodel: B\n");
  CliResult r = RunMomenta({"check", "two.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel);
  EXPECT_EQ(r.err, "two.yaml:3:1: a second YAML document starts here; a model file holds one document\n");
  dir.Write("deep.yaml", "model: D\ndoc: " + std::string(1000, '[') + std::string(1000, ']') + "\n");
  r = RunMomenta({"check", "deep.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel);
  EXPECT_NE(r.err.find("deep.yaml:2:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("YAML nested too deeply"), std::string::npos) << r.err;
}

// The built-in library's functions are read on first use (core/lang/builtin_library.cc): a model
// that calls one with the wrong count still hears of it at its own call.
TEST(ReliabilityLoaderTest, LibraryFunctionReadOnFirstUseChecksItsArgumentCount) {
  TempDir dir;
  dir.Write("arity.yaml", "model: A\ncomponents: {}\nvariables:\n  x: {start: 0}\nequations:\n"
                          "  - der(x) = Frames.skew(1, 2)\n");
  CliResult r = RunMomenta({"check", "arity.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel);
  EXPECT_EQ(r.err, "arity.yaml:6:14: Frames.skew() takes 1 argument, found 2, in 'der(x) = Frames.skew(1, 2)'\n");
}

}  // namespace
}  // namespace momenta
