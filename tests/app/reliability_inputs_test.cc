// Issue 28, inputs built to crash, hang or mislead momenta, through the real binary: the
// reliability reproducers of 2026-11-27 that the loader, the unit parser, the result reader and
// the sweep's options answer (03 a chain of 2 500 `uses:` files, 04 a unit nested 20 000
// parentheses deep, 05 unit values outside double's range, 08 a FIFO, 09 sweep seeds outside
// 0..2^64-1, 12 a MAT header claiming 2^30 rows, 13 /dev/zero in `uses:`, 19 der() nested 200
// deep around an expression) and the small slips beside them. Each must end at once with a
// message naming the file and line (exit 1) or the option (exit 2). A hang is caught by ctest's
// timeout; the time bounds below are far above what the Release build takes (0.1 s each), so that
// the sanitizer build on a loaded CI machine passes too, and below what the old behaviour took
// where it took long (/dev/zero 6-11 s, der() 70 s).

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "app/commands.h"
#include "app/sweep_plan.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::RunMomenta;
using testing::TempDir;

const std::string kSource = MOMENTA_SOURCE_DIR;
const std::string kData = "tests/data/reliability/2026-11-27/";

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// The command's result and how long it took [s].
CliResult Timed(const std::vector<std::string>& args, const std::string& dir, double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  CliResult r = RunMomenta(args, dir);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

/// A small model with one state x; with `uses: [entry]` when `entry` is given.
std::string SmallModel(const std::string& entry = "") {
  return "model: Small\n" + (entry.empty() ? "" : "uses: [" + entry + "]\n") +
         "variables:\n  x: {start: 1, fixed: true}\nequations:\n  - der(x) = -x\noutputs: [x]\n";
}

// ---- 03: uses: chains ---------------------------------------------------------------------------

/// What 03-uses-chain.sh writes: files 0.yaml ... (n-1).yaml, each model using the next; the last
/// holds `last`.
void WriteUsesChain(const TempDir& dir, int n, const std::string& last) {
  for (int i = 0; i < n - 1; ++i) {
    dir.Write(std::to_string(i) + ".yaml", "model: U" + std::to_string(i) + "\nuses: [" +
                                               std::to_string(i + 1) + ".yaml]\n");
  }
  dir.Write(std::to_string(n - 1) + ".yaml", last);
}

TEST(ReliabilityInputsTest, Reproducer03UsesChainOf2500FilesNamesTheDepthAndTheFile) {
  // What 03-uses-chain.sh writes: model.yaml uses 0.yaml, which uses 1.yaml, ... 2499.yaml. The
  // recursive loader overflowed the stack (ASan from about 1 000 files, Release 6 000).
  TempDir dir;
  WriteUsesChain(dir, 2500, "model: U2499\nvariables: {x: {start: 1}}\nequations: [\"der(x) = -x\"]\n");
  dir.Write("model.yaml", "model: Top\nuses: [0.yaml]\ncomponents:\n  a: {type: U0}\noutputs: [time]\n");
  double seconds = 0;
  CliResult r = Timed({"check", "model.yaml"}, dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_LT(seconds, 10.0);
  // The 256th file's entry names the 257th: model.yaml is file 1, 254.yaml file 256.
  EXPECT_TRUE(Contains(r.err, "254.yaml:2:8: uses: files nested deeper than 256 levels: '255.yaml' "
                              "is file 257 of a chain of files each using the next, from model.yaml"))
      << r.err;
}

TEST(ReliabilityInputsTest, UsesChainWithinTheLimitLoadsEveryTypeInOrder) {
  // 200 files deep (inside the limit): the deepest file's type reaches the top model and runs.
  TempDir dir;
  WriteUsesChain(dir, 200, "model: Deep\nvariables: {x: {start: 1, fixed: true}}\nequations: [\"der(x) = -x\"]\n");
  dir.Write("model.yaml", "model: Top\nuses: [0.yaml]\ncomponents:\n  a: {type: Deep}\noutputs: [a.x]\n");
  CliResult r = RunMomenta({"simulate", "model.yaml", "--stop", "1", "--interval", "1", "-o", "out.csv"},
                           dir.path());
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  const auto csv = testing::ReadCsv(dir.File("out.csv"));
  ASSERT_EQ(csv.rows.size(), 2u);
  // x = exp(-t): at t = 1, 0.3679 within the default tolerance (rtol 1e-6; 1e-4 is generous).
  EXPECT_NEAR(csv.rows[1][1], std::exp(-1.0), 1e-4);
}

// ---- 04, 05: units -------------------------------------------------------------------------------

TEST(ReliabilityInputsTest, Reproducer04UnitNested20000ParenthesesIsRefusedAtItsLine) {
  CliResult r = RunMomenta({"check", kData + "04-units-deep-parens.yaml"}, kSource);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_EQ(r.err.rfind(kData + "04-units-deep-parens.yaml:5:", 0), 0u) << r.err.substr(0, 300);
  EXPECT_TRUE(Contains(r.err, "parentheses nested deeper than 256 levels at character 257")) << r.err.substr(0, 300);
  // The message quotes an excerpt, not 40 000 characters of the unit.
  EXPECT_LT(r.err.size(), 1000u);
}

TEST(ReliabilityInputsTest, Reproducer05UnitValuesOutsideDoublesRangeNameTheValue) {
  CliResult r = RunMomenta({"check", kData + "05-unit-value-out-of-range.yaml"}, kSource);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_TRUE(Contains(r.err, kData + "05-unit-value-out-of-range.yaml:9:25: the number 1e-320 is "
                                      "outside double's range (magnitudes from 2.2e-308"))
      << r.err;
  EXPECT_TRUE(Contains(r.err, "in the value of mass.m")) << r.err;
  EXPECT_FALSE(Contains(r.err, "stod")) << r.err;
  TempDir dir;
  const std::string model = R"(model: Range
components:
  wall: {type: Fixed}
  spring: {type: Spring, c: 100}
  mass: {type: Mass, m: MASS, s: {start: 0.1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
outputs: [mass.s]
)";
  auto with_mass = [&](const std::string& m) {
    std::string text = model;
    text.replace(text.find("MASS"), 4, m);
    return dir.Write("range.yaml", text);
  };
  // Too large to read, and too large once converted (3e305 km is 3e308 m... in kg: 1e308 Mg).
  for (const auto& [value, says] :
       {std::pair<std::string, std::string>{"1e999 kg", "the number 1e999 is outside double's range"},
        {"3e308 mm", "the number 3e308 is outside double's range"},
        {"1e306 Mg", "1e306 Mg is inf kg, outside double's range"}}) {
    with_mass(value);
    r = RunMomenta({"check", "range.yaml"}, dir.path());
    EXPECT_EQ(r.exit_code, kExitModel) << value << ": " << r.err;
    EXPECT_EQ(r.err.rfind("range.yaml:5:", 0), 0u) << value << ": " << r.err;
    EXPECT_TRUE(Contains(r.err, says)) << value << ": " << r.err;
  }
  // On the command line: exit 2, naming the option.
  with_mass("1");
  r = RunMomenta({"check", "range.yaml", "-p", "mass.m=1e999 g"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "-p mass.m: the number 1e999 is outside double's range")) << r.err;
  // A plain -p number is decimal as a model's values are: no hex, inf, nan or subnormal (stod
  // read 0x10 as 16 and 1e999 as a bare 'stod').
  for (const auto& [value, says] :
       {std::pair<std::string, std::string>{"mass.m=1e999", "-p mass.m: the number 1e999 is outside double's range"},
        {"mass.m=1e-320", "-p mass.m: the number 1e-320 is outside double's range"},
        {"mass.m=inf", "-p mass.m: 'inf' is not a number"},
        {"mass.m=nan", "-p mass.m: 'nan' is not a number"},
        {"mass.m=0x10", "-p mass.m: unit 'x10' does not parse"}}) {
    r = RunMomenta({"check", "range.yaml", "-p", value}, dir.path());
    EXPECT_EQ(r.exit_code, kExitUsage) << value << ": " << r.err;
    EXPECT_TRUE(Contains(r.err, says)) << value << ": " << r.err;
  }
  // Values in range still convert: 2500 g is 2.5 kg.
  with_mass("2500 g");
  r = RunMomenta({"check", "range.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitOk) << r.err;
}

// ---- 08, 13: files that are not regular files ---------------------------------------------------

TEST(ReliabilityInputsTest, Reproducer08FifoIsRefusedAtOnceAsUsesModelAndResult) {
  TempDir dir;
  std::ifstream in(kSource + "/" + kData + "08-uses-fifo.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  dir.Write("08-uses-fifo.yaml", text);
  ASSERT_EQ(mkfifo(dir.File("08-uses-fifo.pipe").c_str(), 0600), 0);
  double seconds = 0;
  CliResult r = Timed({"check", "08-uses-fifo.yaml"}, dir.path(), &seconds);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_TRUE(Contains(r.err, "08-uses-fifo.yaml:6:8: uses: 08-uses-fifo.pipe: is a FIFO (named "
                              "pipe); a file in uses: must be a regular file"))
      << r.err;
  // The FIFO as the model file, and as the result file of report and plot (exit 2: an option).
  ASSERT_EQ(mkfifo(dir.File("model.yaml").c_str(), 0600), 0);
  r = RunMomenta({"check", "model.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_EQ(r.err, "model.yaml: is a FIFO (named pipe); a model file must be a regular file\n");
  ASSERT_EQ(mkfifo(dir.File("result.csv").c_str(), 0600), 0);
  dir.Write("m.yaml", SmallModel());
  for (const auto& command : {std::vector<std::string>{"report", "result.csv", "-m", "m.yaml"},
                              std::vector<std::string>{"plot", "result.csv", "-y", "x"}}) {
    r = RunMomenta(command, dir.path());
    EXPECT_EQ(r.exit_code, kExitUsage) << command[0] << ": " << r.err;
    EXPECT_TRUE(Contains(r.err, "cannot read the result result.csv: is a FIFO (named pipe); a "
                                "result file must be a regular file"))
        << command[0] << ": " << r.err;
  }
  EXPECT_LT(seconds, 10.0);
}

TEST(ReliabilityInputsTest, Reproducer13DevZeroAndDevNullInUsesAreRefusedAtTheirEntry) {
  double seconds = 0;
  CliResult r = Timed({"check", kData + "13-uses-dev-zero.yaml"}, kSource, &seconds);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_TRUE(Contains(r.err, kData + "13-uses-dev-zero.yaml:6:8: uses: /dev/zero: is a character "
                                      "device; a file in uses: must be a regular file"))
      << r.err;
  // It was read up to 256 MiB first: 6-11 s.
  EXPECT_LT(seconds, 5.0);
  TempDir dir;
  dir.Write("null.yaml", SmallModel("/dev/null"));
  r = RunMomenta({"check", "null.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_EQ(r.err, "null.yaml:2:8: uses: /dev/null: is a character device; a file in uses: must be "
                   "a regular file\n");
}

// ---- 09 and the sweep's slips ---------------------------------------------------------------------

TEST(ReliabilityInputsTest, Reproducer09SeedOutsideItsRangeIsAUsageError) {
  const std::vector<std::string> base = {"sweep", kData + "09-sweep-seed-out-of-range.yaml", "-p",
                                         "mass1.m=uniform(1,2)", "--samples", "2", "--stop", "0.1",
                                         "-q", "-o", "-", "--seed"};
  for (const std::string seed : {"-1", "18446744073709551616", "99999999999999999999999", "1e3", "0x10", "+5"}) {
    std::vector<std::string> args = base;
    args.push_back(seed);
    CliResult r = RunMomenta(args, kSource);
    EXPECT_EQ(r.exit_code, kExitUsage) << seed << ": " << r.err;
    EXPECT_TRUE(Contains(r.err, "--seed: the seed '" + seed + "' is not a whole number from 0 to "
                                "18446744073709551615"))
        << seed << ": " << r.err;
  }
  // The largest seed is a seed.
  std::vector<std::string> args = base;
  args.push_back("18446744073709551615");
  CliResult r = RunMomenta(args, kSource);
  EXPECT_EQ(r.exit_code, kExitOk) << r.err;
}

TEST(ReliabilityInputsTest, EmptyTrajectoriesDirectoryIsAUsageError) {
  CliResult r = RunMomenta({"sweep", kData + "09-sweep-seed-out-of-range.yaml", "-p", "mass1.m=1,2",
                            "--stop", "0.1", "-q", "-o", "-", "--trajectories", ""},
                           kSource);
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "--trajectories: the directory name is empty")) << r.err;
}

TEST(ReliabilityInputsTest, SweepSpecsAreDecimalAndInRange) {
  // Hex is not read, as in expressions.
  EXPECT_THROW(
      {
        try {
          ParseSweepAxis("m=0x10");
        } catch (const UsageError& e) {
          EXPECT_STREQ(e.what(), "-p m=0x10: the value '0x10' is not a decimal number");
          throw;
        }
      },
      UsageError);
  EXPECT_THROW(ParseSweepAxis("m=1:2:0x10"), UsageError);
  // 1e-320 is finite but subnormal: said so, not "not a finite number".
  try {
    ParseSweepAxis("m=1e-320");
    ADD_FAILURE() << "1e-320 accepted";
  } catch (const UsageError& e) {
    EXPECT_TRUE(Contains(e.what(), "-p m=1e-320: the number 1e-320 is outside double's range "
                                   "(magnitudes from 2.2e-308, the smallest normal double"))
        << e.what();
  }
  // uniform(-1e308, 1e308): b - a overflows; the draws are finite, inside [a, b] and not all of
  // one sign (64 draws of a fair coin: all alike with probability 2^-63).
  const SweepPlan plan = MakeSweepPlan({ParseSweepAxis("m=uniform(-1e308,1e308)")}, 64, 7);
  int positive = 0;
  for (const auto& run : plan.values) {
    EXPECT_TRUE(std::isfinite(run[0]) && run[0] >= -1e308 && run[0] <= 1e308) << run[0];
    positive += run[0] > 0;
  }
  EXPECT_GT(positive, 0);
  EXPECT_LT(positive, 64);
  // An ordinary range draws what it always drew: a + (b - a) u.
  const SweepPlan small = MakeSweepPlan({ParseSweepAxis("m=uniform(1,2)")}, 1, 0);
  std::mt19937_64 engine(0);
  EXPECT_EQ(small.values[0][0], 1.0 + static_cast<double>(engine() >> 11) * 0x1.0p-53);
}

TEST(ReliabilityInputsTest, HexInAShapeIsRefused) {
  TempDir dir;
  dir.Write("hex.yaml", R"(model: Hex
variables:
  x: {shape: [0x10], start: 1, fixed: true}
equations:
  - der(x) = -x
outputs: ["x[1]"]
)");
  CliResult r = RunMomenta({"check", "hex.yaml"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  EXPECT_TRUE(Contains(r.err, "hex.yaml:3:15: a size in the shape of Hex.x must be a decimal number, "
                              "found '0x10'"))
      << r.err;
}

// ---- 12: MAT headers ----------------------------------------------------------------------------

TEST(ReliabilityInputsTest, Reproducer12MatHeaderClaimingHugeSizesIsNotAValidResult) {
  for (const std::string command : {"report", "plot"}) {
    std::vector<std::string> args = {command, kData + "12-mat-huge-dims.mat"};
    if (command == "report") args.insert(args.end(), {"-m", kData + "12-mat-huge-dims.yaml", "-o", "/dev/null/r.html"});
    if (command == "plot") args.insert(args.end(), {"-y", "A.r[1]", "-o", "/dev/null/p.svg"});
    double seconds = 0;
    CliResult r = Timed(args, kSource, &seconds);
    EXPECT_EQ(r.exit_code, kExitUsage) << command << ": " << r.err;
    EXPECT_TRUE(Contains(r.err, kData + "12-mat-huge-dims.mat: not a valid result file: matrix "
                                        "'dataInfo' (at byte "))
        << command << ": " << r.err;
    // 4 x 2^30 int32: 16 GiB in a 10 KB file.
    EXPECT_TRUE(Contains(r.err, "claims 4 x 1073741824 values of 4 bytes (16 GiB), where the file "
                                "holds 5958 more bytes"))
        << command << ": " << r.err;
    EXPECT_LT(seconds, 10.0);
  }
}

TEST(ReliabilityInputsTest, MatFileCutShortOrOfAnotherVersionIsNamed) {
  TempDir dir;
  // One header of a 3 x 2 double matrix named "x" with only 8 of its 48 bytes of values.
  std::string mat(20, '\0');
  mat[4] = 3;   // rows
  mat[8] = 2;   // columns
  mat[16] = 2;  // name length, with its NUL
  mat += std::string("x\0", 2) + std::string(8, '\0');
  dir.Write("short.mat", mat);
  CliResult r = RunMomenta({"plot", "short.mat", "-y", "x"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "short.mat: not a valid result file: matrix 'x' (at byte 0) claims 3 x 2 "
                              "values of 8 bytes"))
      << r.err;
  // A MAT v5 header (128 bytes, version 0x0100, "IM").
  std::string v5(128, ' ');
  v5[124] = 0;
  v5[125] = 1;
  v5[126] = 'I';
  v5[127] = 'M';
  dir.Write("v5.mat", v5);
  r = RunMomenta({"plot", "v5.mat", "-y", "x"}, dir.path());
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "v5.mat: not a valid result file: it is a MAT v5 or v7.3 file")) << r.err;
}

// ---- 19: der() nesting --------------------------------------------------------------------------

TEST(ReliabilityInputsTest, Reproducer19DerNested200DeepAroundAnExpressionEndsAtOnce) {
  double seconds = 0;
  CliResult r = Timed({"check", kData + "19-der-nest-expression-slow.yaml"}, kSource, &seconds);
  EXPECT_EQ(r.exit_code, kExitModel) << r.err;
  // The 13th der() from the inside, at column 5 + 4 * (200 - 13) of the string (1-based: 7 + 748).
  EXPECT_TRUE(Contains(r.err, kData + "19-der-nest-expression-slow.yaml:11:"))
      << r.err.substr(0, 300);
  EXPECT_TRUE(Contains(r.err, "der() applied more than 12 times to an expression")) << r.err.substr(0, 300);
  // It took 70 s and 420 MB.
  EXPECT_LT(seconds, 10.0);
}

}  // namespace
}  // namespace momenta
