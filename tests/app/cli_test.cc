// The real `momenta` binary: what each subcommand writes and prints, and its exit codes
// (0 success, 1 the model is wrong, 2 usage, 3 the solver failed).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::IsNumericRow;
using testing::Lines;
using testing::RunMomenta;
using testing::TempDir;

// A 2 kg mass pushed by F = 6 N from v = 1 m/s: a = 3, v(1) = 4, s(1) = 2.5 (exact polynomials).
constexpr const char* kPushedMass = R"yaml(model: PushedMass
parameters: {F: 6}
components:
  force: {type: ConstantForce, f_constant: F}
  mass: {type: Mass, m: 2, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
connections:
  - [force.flange, mass.flange_a]
experiment: {stop: 1, interval: 0.25, tolerance: 1e-8}
outputs: [mass.a, mass.v, mass.s, "atan2(mass.v, 1)"]
)yaml";

/// Splits a CSV data row (no quoting in data rows) into numbers; fails the test on anything else.
std::vector<double> Numbers(const std::string& line) {
  std::vector<double> v;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) {
    size_t used = 0;
    double x = 0;
    try {
      x = std::stod(cell, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    EXPECT_EQ(used, cell.size()) << "not a number: '" << cell << "' in '" << line << "'";
    v.push_back(x);
  }
  return v;
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class CliTest : public ::testing::Test {
 protected:
  // momenta chooses huge pages itself unless glibc's tunables are already set (a shell that
  // exports them for benchmarks, say): the tests of that choice need them unset.
  void SetUp() override {
    if (const char* tunables = std::getenv("GLIBC_TUNABLES")) {
      saved_tunables_ = tunables;
      unsetenv("GLIBC_TUNABLES");
    }
  }
  void TearDown() override {
    if (saved_tunables_) setenv("GLIBC_TUNABLES", saved_tunables_->c_str(), 1);
  }
  CliResult Momenta(const std::vector<std::string>& args) { return RunMomenta(args, dir_.path()); }
  TempDir dir_;
  std::optional<std::string> saved_tunables_;
};

TEST_F(CliTest, SimulateWritesCsvAndPrintsFinalValues) {
  dir_.Write("pushed.yaml", kPushedMass);
  CliResult r = Momenta({"simulate", "pushed.yaml"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_EQ(r.err, "");
  // The default results file is <model file stem>.csv in the working directory.
  const std::string csv = testing::ReadText(dir_.File("pushed.csv"));
  std::vector<std::string> lines = Lines(csv);
  ASSERT_EQ(lines.size(), 6u) << csv;  // header + t = 0, 0.25, 0.5, 0.75, 1
  // `time`, then the outputs as written; an output with a comma is quoted.
  EXPECT_EQ(lines[0], "time,mass.a,mass.v,mass.s,\"atan2(mass.v, 1)\"");
  for (size_t k = 1; k < lines.size(); ++k) {
    std::vector<double> row = Numbers(lines[k]);
    ASSERT_EQ(row.size(), 5u) << lines[k];
    const double t = 0.25 * (k - 1);
    // Output times are start + k*interval to rounding; values are exact polynomials integrated
    // at rtol 1e-8 (1e-7 on O(1)).
    EXPECT_NEAR(row[0], t, 1e-12);
    EXPECT_NEAR(row[1], 3, 1e-7);
    EXPECT_NEAR(row[2], 1 + 3 * t, 1e-7);
    EXPECT_NEAR(row[3], t + 1.5 * t * t, 1e-7);
    EXPECT_NEAR(row[4], std::atan(1 + 3 * t), 1e-7);
  }
  // The summary names the results file and prints the final values (%.10g).
  EXPECT_TRUE(Contains(r.out, "pushed.csv (5 rows)")) << r.out;
  EXPECT_TRUE(Contains(r.out, "final values at t = 1")) << r.out;
  EXPECT_TRUE(Contains(r.out, "mass.a = 3\n")) << r.out;
  EXPECT_TRUE(Contains(r.out, "mass.v = 4\n")) << r.out;
  EXPECT_TRUE(Contains(r.out, "mass.s = 2.5\n")) << r.out;
}

TEST_F(CliTest, QuietPrintsNothingAndOutChoosesTheFile) {
  dir_.Write("pushed.yaml", kPushedMass);
  CliResult r = Momenta({"simulate", "pushed.yaml", "-q", "-o", "elsewhere.csv"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "");
  EXPECT_TRUE(std::filesystem::exists(dir_.File("elsewhere.csv")));
  EXPECT_FALSE(std::filesystem::exists(dir_.File("pushed.csv")));
}

TEST_F(CliTest, ParameterOverrideChangesTheResult) {
  dir_.Write("pushed.yaml", kPushedMass);
  // A component parameter: double the mass, half the acceleration.
  CliResult heavy = Momenta({"simulate", "pushed.yaml", "-p", "mass.m=4", "-o", "heavy.csv"});
  ASSERT_EQ(heavy.exit_code, kExitOk) << heavy.err;
  EXPECT_TRUE(Contains(heavy.out, "mass.a = 1.5\n")) << heavy.out;
  EXPECT_TRUE(Contains(heavy.out, "mass.v = 2.5\n")) << heavy.out;
  // A model parameter, and two overrides at once.
  CliResult both = Momenta({"simulate", "pushed.yaml", "-p", "F=-2", "--param", "mass.m=1", "-o", "both.csv"});
  ASSERT_EQ(both.exit_code, kExitOk) << both.err;
  EXPECT_TRUE(Contains(both.out, "mass.a = -2\n")) << both.out;
  // The results file agrees with the summary.
  std::vector<std::string> lines = Lines(testing::ReadText(dir_.File("both.csv")));
  ASSERT_EQ(lines.size(), 6u);
  // v = 1 - 2t and s = t - t^2 at t = 1; rtol 1e-8 on O(1).
  EXPECT_NEAR(Numbers(lines.back())[2], -1, 1e-7);
  EXPECT_NEAR(Numbers(lines.back())[3], 0, 1e-7);
}

TEST_F(CliTest, CommandLineOptionsOverrideTheExperiment) {
  dir_.Write("pushed.yaml", kPushedMass);
  CliResult r = Momenta({"simulate", "pushed.yaml", "--stop", "2", "--interval", "0.5", "-o", "long.csv"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  std::vector<std::string> lines = Lines(testing::ReadText(dir_.File("long.csv")));
  ASSERT_EQ(lines.size(), 6u);  // header + 0, 0.5, 1, 1.5, 2
  std::vector<double> last = Numbers(lines.back());
  EXPECT_NEAR(last[0], 2, 1e-12);
  EXPECT_NEAR(last[2], 7, 1e-6);  // v = 1 + 3*2; rtol 1e-8 on O(10)
}

TEST_F(CliTest, OutDashWritesOnlyTheCsvToStandardOutput) {
  dir_.Write("pushed.yaml", kPushedMass);
  CliResult r = Momenta({"simulate", "pushed.yaml", "--out", "-"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("pushed.csv")));
  EXPECT_FALSE(std::filesystem::exists(dir_.File("-")));
  // Standard output is then the results and nothing else, so it can be piped into a CSV reader:
  // the header, then one numeric row per output time.
  std::vector<std::string> lines = Lines(r.out);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "time,mass.a,mass.v,mass.s,\"atan2(mass.v, 1)\"");
  EXPECT_EQ(lines.size(), 6u) << "standard output:\n" << r.out;
  for (size_t k = 1; k < lines.size(); ++k) {
    if (!IsNumericRow(lines[k], 5)) {
      ADD_FAILURE() << "line " << k + 1 << " of standard output is not a results row: '" << lines[k]
                    << "' (the summary belongs on standard error, or nowhere, with --out -)";
      break;
    }
  }
}

/// Transparent huge pages can be asked for ("always" or "madvise"): the restart tests need them.
bool HugePagesAvailable() {
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  return std::getline(thp, mode) && mode.find("[never]") == std::string::npos;
}

// A large model file makes momenta restart once with glibc's malloc on transparent huge pages
// (app/huge_pages.h); check says so on its total line. A small one, or MOMENTA_HUGE_PAGES=0,
// keeps ordinary pages.
TEST_F(CliTest, LargeModelFileRunsOnHugePages) {
  if (!HugePagesAvailable()) GTEST_SKIP() << "transparent huge pages are off on this machine";
  // The pushed mass with a megabyte of comment lines: a file over the threshold.
  std::string large = kPushedMass;
  const std::string comment = "# " + std::string(98, 'x') + "\n";
  while (large.size() < (1u << 20) + 4096) large += comment;
  dir_.Write("large.yaml", large);
  dir_.Write("pushed.yaml", kPushedMass);
  const char* kMarker = "(memory on huge pages)";
  CliResult big = Momenta({"check", "large.yaml"});
  ASSERT_EQ(big.exit_code, kExitOk) << big.err;
  EXPECT_TRUE(Contains(big.out, "model PushedMass (large.yaml): 2 components")) << big.out;
  EXPECT_TRUE(Contains(big.out, kMarker)) << big.out;
  CliResult small = Momenta({"check", "pushed.yaml"});
  ASSERT_EQ(small.exit_code, kExitOk) << small.err;
  EXPECT_FALSE(Contains(small.out, kMarker)) << small.out;
  // Only a model file counts: the same megabyte under another name (an earlier run's results,
  // say) does not.
  dir_.Write("large.txt", large);
  CliResult other = Momenta({"check", "large.txt"});
  ASSERT_EQ(other.exit_code, kExitOk) << other.err;
  EXPECT_FALSE(Contains(other.out, kMarker)) << other.out;
  setenv("MOMENTA_HUGE_PAGES", "0", 1);
  CliResult off = Momenta({"check", "large.yaml"});
  unsetenv("MOMENTA_HUGE_PAGES");
  ASSERT_EQ(off.exit_code, kExitOk) << off.err;
  EXPECT_FALSE(Contains(off.out, kMarker)) << off.out;
}

TEST_F(CliTest, LargeArrayBuildRunsOnHugePages) {
  if (!HugePagesAvailable()) GTEST_SKIP() << "transparent huge pages are off on this machine";
  // A small file whose count makes a large build: 8 000 masses plan about 40 MB, past
  // kLargeBuildBytes (32 MiB); momenta restarts on huge pages once the count is known.
  dir_.Write("masses.yaml", R"(model: Masses
parameters:
  n: {value: 10}
components:
  m: {type: Mass, count: n, m: 1}
)");
  const char* kMarker = "(memory on huge pages)";
  CliResult big = Momenta({"check", "masses.yaml", "-p", "n=8000"});
  ASSERT_EQ(big.exit_code, kExitOk) << big.err;
  EXPECT_TRUE(Contains(big.out, "model Masses (masses.yaml): 8000 components")) << big.out;
  EXPECT_TRUE(Contains(big.out, kMarker)) << big.out;
  CliResult small = Momenta({"check", "masses.yaml"});
  ASSERT_EQ(small.exit_code, kExitOk) << small.err;
  EXPECT_FALSE(Contains(small.out, kMarker)) << small.out;
  setenv("MOMENTA_HUGE_PAGES", "0", 1);
  CliResult off = Momenta({"check", "masses.yaml", "-p", "n=8000"});
  unsetenv("MOMENTA_HUGE_PAGES");
  ASSERT_EQ(off.exit_code, kExitOk) << off.err;
  EXPECT_FALSE(Contains(off.out, kMarker)) << off.out;
}

TEST_F(CliTest, CheckPrintsEachPass) {
  dir_.Write("pushed.yaml", kPushedMass);
  CliResult r = Momenta({"check", "pushed.yaml"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_TRUE(Contains(r.out, "model PushedMass (pushed.yaml): 2 components")) << r.out;
  // Every pass of the build (as BuildModel reports them) has its line, after the file's load.
  testing::Built built = testing::BuildYaml(kPushedMass);
  ASSERT_GE(built.report.passes.size(), 3u);
  std::vector<std::string> passes = {"load"};
  for (const auto& p : built.report.passes) passes.push_back(p.name);
  EXPECT_EQ(passes[1], "flatten");
  for (const auto& pass : passes) {
    EXPECT_TRUE(Contains(r.out, "\n  " + pass + " ")) << "no pass '" << pass << "' in:\n" << r.out;
  }
  EXPECT_TRUE(Contains(r.out, "states (2): ")) << r.out;
  EXPECT_TRUE(Contains(r.out, "outputs (4): mass.a, mass.v, mass.s, atan2(mass.v, 1)")) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("pushed.csv"))) << "check must not simulate";
  // --verbose adds the DAE in the user's names.
  CliResult v = Momenta({"check", "-v", "pushed.yaml"});
  ASSERT_EQ(v.exit_code, kExitOk) << v.err;
  EXPECT_TRUE(Contains(v.out, "equations for IDA (")) << v.out;
  EXPECT_TRUE(Contains(v.out, "initial equations (")) << v.out;
}

// check's summary gives the process's peak resident memory and that peak per component (the
// issue's memory target is per component). A model of 2 000 masses takes a few megabytes more than
// one of 10 (about 3.5 KB per Mass on this build: flat records, pool nodes, programs), and the
// figure per component is the peak divided by the count, to the three digits printed.
TEST_F(CliTest, CheckPrintsPeakMemoryPerComponent) {
  dir_.Write("masses.yaml", R"(model: Masses
parameters:
  n: {value: 10}
components:
  m: {type: Mass, count: n, m: 1, s: {fixed: true}, v: {fixed: true}}
)");
  struct Memory {
    double peak_mb = 0, per_component_kb = 0;
  };
  auto memory_of = [&](int n) {
    CliResult r = Momenta({"check", "masses.yaml", "-p", "n=" + std::to_string(n)});
    EXPECT_EQ(r.exit_code, kExitOk) << r.err;
    Memory m;
    size_t at = r.out.find("\n  peak memory ");
    EXPECT_NE(at, std::string::npos) << r.out;
    if (at == std::string::npos) return m;
    EXPECT_EQ(std::sscanf(r.out.c_str() + at, "\n  peak memory %lf MB, %lf KB per component", &m.peak_mb,
                          &m.per_component_kb),
              2)
        << r.out;
    return m;
  };
  Memory small = memory_of(10);
  Memory large = memory_of(2000);
  // The program alone is a few MB resident; a model this small stays far below 100 MB. Under
  // AddressSanitizer (CI's sanitizer stage builds the CLI with it too) the resident memory holds
  // ASan's shadow, redzones and quarantine: 121 MB for the 2 000 masses there, so the upper
  // bounds are stated for an ordinary build only.
#if defined(__SANITIZE_ADDRESS__)
  constexpr bool kPlainBuild = false;
#else
  constexpr bool kPlainBuild = true;
#endif
  EXPECT_GT(small.peak_mb, 1.0);
  if (kPlainBuild) {
    EXPECT_LT(small.peak_mb, 100.0);
    EXPECT_LT(large.peak_mb, 100.0);
  }
  // Per component = peak / components, both printed to 3 significant digits (0.5 % each).
  EXPECT_NEAR(small.per_component_kb * 10, small.peak_mb * 1e3, 0.01 * small.peak_mb * 1e3);
  EXPECT_NEAR(large.per_component_kb * 2000, large.peak_mb * 1e3, 0.01 * large.peak_mb * 1e3);
  // 1 990 more masses take memory: at least 500 bytes each (a Mass has 4 variables, 2 parameters
  // and 4 equations), and under 20 KB each.
  EXPECT_GT(large.peak_mb - small.peak_mb, 1990 * 500e-6);
  if (kPlainBuild) EXPECT_LT(large.peak_mb - small.peak_mb, 1990 * 20e-3);
}

TEST_F(CliTest, ListShowsTheLibrary) {
  CliResult r = Momenta({"list"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  // Grouped by library file, one line per type with its doc sentence.
  for (const char* part : {"components/translational.yaml\n", "components/electrical.yaml\n",
                           "components/blocks.yaml\n", "  Mass ", "Sliding mass with inertia",
                           "  SpringDamper ", "  Resistor ", "  Integrator ", "connectors: "}) {
    EXPECT_TRUE(Contains(r.out, part)) << "no '" << part << "' in:\n" << r.out;
  }
  EXPECT_TRUE(Contains(r.out, "Flange")) << r.out;
  EXPECT_TRUE(Contains(r.out, "Pin")) << r.out;
}

TEST_F(CliTest, ListOneComponentDescribesIt) {
  CliResult r = Momenta({"list", "Mass"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  for (const char* part : {"Mass: Sliding mass", "m = 1 [kg], min 0", "L = 0 [m]", "flange_a: Flange",
                           "flange_b: Flange", "s [m]", "v [m/s]", "m*a = flange_a.f + flange_b.f"}) {
    EXPECT_TRUE(Contains(r.out, part)) << "no '" << part << "' in:\n" << r.out;
  }
  CliResult c = Momenta({"list", "Flange"});
  ASSERT_EQ(c.exit_code, kExitOk) << c.err;
  EXPECT_TRUE(Contains(c.out, "Flange (connector)")) << c.out;
  EXPECT_TRUE(Contains(c.out, "potential s [m]")) << c.out;
  EXPECT_TRUE(Contains(c.out, "flow f [N]")) << c.out;
  // A misspelt name is a usage error that suggests the closest type.
  CliResult bad = Momenta({"list", "Mas"});
  EXPECT_EQ(bad.exit_code, kExitUsage);
  EXPECT_TRUE(Contains(bad.err, "'Mas'")) << bad.err;
  EXPECT_TRUE(Contains(bad.err, "did you mean Mass")) << bad.err;
}

TEST_F(CliTest, UsageErrorsExitWithTwo) {
  dir_.Write("pushed.yaml", kPushedMass);
  struct Case {
    std::vector<std::string> args;
    std::string message;  // a fragment of what stderr must say
  };
  for (const Case& c : std::vector<Case>{
           {{}, "subcommand"},
           {{"simulate"}, "model"},
           {{"check"}, "model"},
           {{"simulate", "pushed.yaml", "-p", "F"}, "NAME=VALUE"},
           {{"simulate", "pushed.yaml", "-p", "=3"}, "NAME=VALUE"},
           {{"simulate", "pushed.yaml", "-p", "F="}, "NAME=VALUE"},
           {{"simulate", "pushed.yaml", "-p", "F=abc"}, "'abc' is not a number"},
           {{"check", "pushed.yaml", "-p", "F=1x"}, "-p F: unit 'x' does not parse"},
           {{"simulate", "pushed.yaml", "--linear-solver", "lu"}, "lu"},
           {{"simulate", "pushed.yaml", "--error-test", "algebraic"}, "--error-test: algebraic not in {states,all}"},
           {{"simulate", "pushed.yaml", "--rtol", "small"}, "small"},
           {{"simulate", "pushed.yaml", "--no-such-flag"}, "--no-such-flag"},
       }) {
    std::string label;
    for (const auto& a : c.args) label += a + " ";
    CliResult r = Momenta(c.args);
    EXPECT_EQ(r.exit_code, kExitUsage) << "momenta " << label << "\n" << r.err;
    EXPECT_TRUE(Contains(r.err, c.message)) << "momenta " << label << ": no '" << c.message << "' in:\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("pushed.csv"))) << "momenta " << label;
  }
}

TEST_F(CliTest, UnknownSubcommandIsAUsageErrorThatNamesIt) {
  CliResult r = Momenta({"frobnicate", "model.yaml"});
  EXPECT_EQ(r.exit_code, kExitUsage);
  EXPECT_TRUE(Contains(r.err, "frobnicate")) << r.err;
}

TEST_F(CliTest, ModelErrorsExitWithOne) {
  dir_.Write("pushed.yaml", kPushedMass);
  // A model that is wrong in its file.
  dir_.Write("negative.yaml", "model: Negative\ncomponents:\n  A: {type: Mass, m: -1}\n");
  CliResult neg = Momenta({"simulate", "negative.yaml"});
  EXPECT_EQ(neg.exit_code, kExitModel);
  EXPECT_TRUE(Contains(neg.err, "negative.yaml:3:")) << neg.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("negative.csv"))) << "no results for a model error";
  // A file that does not exist.
  CliResult missing = Momenta({"simulate", "nowhere.yaml"});
  EXPECT_EQ(missing.exit_code, kExitModel);
  EXPECT_TRUE(Contains(missing.err, "nowhere.yaml")) << missing.err;
  // A -p that puts a parameter out of its range is the model's business (exit 1); one that names
  // no parameter is a usage error (cli_values_test.cc).
  CliResult range = Momenta({"check", "pushed.yaml", "-p", "mass.m=-3"});
  EXPECT_EQ(range.exit_code, kExitModel);
  EXPECT_TRUE(Contains(range.err, "mass.m")) << range.err;
}

TEST_F(CliTest, SolverFailureExitsWithThreeAndKeepsTheRows) {
  // x' = x^2, x(0) = 1: x = 1/(1 - t) blows up at t = 1.
  dir_.Write("blowup.yaml", R"(model: Blowup
define:
  Blow:
    variables:
      x: {start: 1, fixed: true}
    equations:
      - der(x) = x^2
components:
  b: {type: Blow}
experiment: {stop: 2, interval: 0.1}
outputs: [b.x]
)");
  CliResult r = Momenta({"simulate", "blowup.yaml"});
  EXPECT_EQ(r.exit_code, kExitSolver) << r.err;
  EXPECT_TRUE(Contains(r.err, "at t = ")) << r.err;
  EXPECT_TRUE(Contains(r.err, "b.x")) << r.err;
  std::vector<std::string> lines = Lines(testing::ReadText(dir_.File("blowup.csv")));
  // Rows t = 0 .. 0.9 exist (10 rows); none at or past the singularity.
  ASSERT_GE(lines.size(), 10u);
  EXPECT_LE(lines.size(), 11u);
  std::vector<double> last = Numbers(lines.back());
  EXPECT_LT(last[0], 1);
  EXPECT_NEAR(last[1], 1 / (1 - last[0]), 1e-3 * last[1]);  // default rtol 1e-6, near a pole
}

TEST_F(CliTest, HelpAndVersionSucceed) {
  CliResult help = Momenta({"--help"});
  EXPECT_EQ(help.exit_code, kExitOk);
  EXPECT_TRUE(Contains(help.out, "simulate")) << help.out;
  CliResult version = Momenta({"--version"});
  EXPECT_EQ(version.exit_code, kExitOk);
  EXPECT_TRUE(Contains(version.out, "momenta")) << version.out;
}

}  // namespace
}  // namespace momenta
