// Fuzz findings in the parser, flattening and compilation (tests/data/reliability/01–10): every
// one must end with exit 0 (long expressions work) or exit 1 with a message at file:line:col
// (expressions nested too deep, a bad model), never with a crash. Each case runs the real CLI.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/lang/parser.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::RunMomenta;
using testing::TempDir;

std::string Reproducer(const std::string& name) {
  return testing::SourcePath("tests/data/reliability/" + name);
}

class ReliabilityCoreTest : public ::testing::Test {
 protected:
  CliResult Momenta(const std::vector<std::string>& args) { return RunMomenta(args, dir_.path()); }
  /// `simulate FILE -q -o out.csv`; the CSV's last row.
  std::vector<double> SimulateLastRow(const std::string& file, testing::Csv* csv) {
    CliResult r = Momenta({"simulate", file, "-q", "-o", dir_.File("out.csv")});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    *csv = testing::ReadCsv(dir_.File("out.csv"));
    if (csv->rows.empty()) {
      ADD_FAILURE() << "no rows";
      return {};
    }
    return csv->rows.back();
  }
  TempDir dir_;
};

struct TooDeep {
  const char* file;
  const char* place;  ///< line:col of the level past the limit
};

TEST_F(ReliabilityCoreTest, ExpressionsNestedTooDeepAreReportedAtTheirColumn) {
  const std::string limit = "expression nested deeper than " + std::to_string(kMaxExpressionDepth) + " levels";
  for (const TooDeep& c : {TooDeep{"01-parser-deep-parens.yaml", "7:268"},
                           TooDeep{"02-parser-nested-calls.yaml", "7:1036"},
                           TooDeep{"03-parser-unary-minus-chain.yaml", "7:39756"},
                           TooDeep{"04-parser-not-chain.yaml", "7:158991"},
                           TooDeep{"05-parser-power-chain.yaml", "7:79501"}}) {
    CliResult r = Momenta({"check", Reproducer(c.file)});
    EXPECT_EQ(r.exit_code, 1) << c.file << ": " << r.err;
    EXPECT_NE(r.err.find(std::string(c.file) + ":" + c.place + ": " + limit), std::string::npos)
        << c.file << ": " << r.err.substr(0, 500);
    // The message quotes an excerpt, not the whole 40 000-operator text.
    EXPECT_LT(r.err.size(), 600u) << c.file;
  }
}

TEST_F(ReliabilityCoreTest, ElseifChainOf12000BranchesParses) {
  // The reproducer's branches name an unknown 'x': a plain model error at that name.
  CliResult r = Momenta({"check", Reproducer("06-parser-elseif-chain.yaml")});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("06-parser-elseif-chain.yaml:7:38: unknown name 'x' in 'if time > 1 then 1 elseif x"),
            std::string::npos)
      << r.err.substr(0, 500);
  EXPECT_LT(r.err.size(), 600u);
  // With valid branches the chain simulates: no condition holds before time 1, so the value is the
  // else-branch's.
  std::string text = "if time > 1 then 1";
  for (int k = 0; k < 12000; ++k) text += " elseif m.s > 1 then " + std::to_string(k);
  text += " else 7 + m.s";
  std::string file = dir_.Write("elseif.yaml", R"(model: ElseifChain
components:
  m: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
experiment: {stop: 0.5}
outputs: [")" + text + "\"]\n");
  testing::Csv csv;
  std::vector<double> last = SimulateLastRow(file, &csv);
  ASSERT_EQ(last.size(), 2u);
  EXPECT_EQ(last[1], 7.0);
}

TEST_F(ReliabilityCoreTest, LongSumInAnOutputWorks) {
  const std::string file = Reproducer("07-flatten-long-sum-output.yaml");
  CliResult r = Momenta({"check", file});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // m.s stays 0; the output is the number of "+ 1" terms, 40 000.
  testing::Csv csv;
  std::vector<double> last = SimulateLastRow(file, &csv);
  ASSERT_EQ(last.size(), 2u);
  EXPECT_EQ(last[1], 40000.0);
}

TEST_F(ReliabilityCoreTest, LongSumInAComponentEquationWorks) {
  // der(x) = -x + 0 + … (12 000 terms), x(0) = 1: x(1) = exp(-1).
  const std::string file = Reproducer("08-flatten-long-sum-equation.yaml");
  CliResult r = Momenta({"check", file});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  testing::Csv csv;
  std::vector<double> last = SimulateLastRow(file, &csv);
  ASSERT_EQ(last.size(), 2u);
  EXPECT_EQ(last[0], 1.0);
  EXPECT_NEAR(last[1], std::exp(-1.0), 1e-4);
}

TEST_F(ReliabilityCoreTest, ALoadErrorAfterA200000TermSumIsReported) {
  CliResult r = Momenta({"check", Reproducer("09-ast-destructor-long-sum.yaml")});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("09-ast-destructor-long-sum.yaml:11:23: unknown key 'colour' in experiment"),
            std::string::npos)
      << r.err.substr(0, 500);
}

TEST_F(ReliabilityCoreTest, WhenConditionOnTheVariableItAssignsWorks) {
  // `when k > 0 then k = 1` with k = 0: the condition reads k's current value (Modelica's
  // semantics, settled by the event iteration); it never becomes true, and x decays.
  const std::string file = Reproducer("10-when-on-own-discrete-variable.yaml");
  CliResult r = Momenta({"check", file});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  testing::Csv csv;
  std::vector<double> last = SimulateLastRow(file, &csv);
  ASSERT_EQ(last.size(), 2u);
  EXPECT_NEAR(last[1], std::exp(-1.0), 1e-4);
}

TEST_F(ReliabilityCoreTest, RelationsOnDiscreteVariablesChainAtOneEvent) {
  // x = exp(-t) crosses 0.5 at ln 2: k becomes 1, which makes `k > 0` true at the same event, so
  // j becomes 1 there too; both stay.
  std::string file = dir_.Write("relations.yaml", R"(model: DiscreteRelations
define:
  Counter:
    variables:
      x: {start: 1, fixed: true}
      k: {type: Integer, start: 0}
      j: {type: Integer, start: 0}
    equations: [der(x) = -x]
    when:
      - when: x < 0.5
        then: [k = pre(k) + 1]
      - when: k > 0
        then: [j = pre(j) + 1]
components:
  c: {type: Counter}
experiment: {stop: 1, interval: 0.01}
outputs: [c.k, c.j]
)");
  testing::Csv csv;
  std::vector<double> last = SimulateLastRow(file, &csv);
  ASSERT_EQ(last.size(), 3u);
  EXPECT_EQ(last[1], 1.0);
  EXPECT_EQ(last[2], 1.0);
  // Before ln 2 both are 0.
  for (const auto& row : csv.rows) {
    if (row[0] < std::log(2.0) - 1e-6) {
      EXPECT_EQ(row[1], 0.0) << "t = " << row[0];
      EXPECT_EQ(row[2], 0.0) << "t = " << row[0];
    }
  }
}

TEST_F(ReliabilityCoreTest, DerivativeOfADiscreteVariableIsAModelError) {
  std::string file = dir_.Write("der.yaml", R"yaml(model: DerOfDiscrete
define:
  Counter:
    variables:
      x: {start: 1, fixed: true}
      y: {start: 0}
      k: {type: Integer, start: 0}
    equations: [der(x) = -x, "y = der(k + x)"]
    when:
      - when: x < 0.5
        then: [k = pre(k) + 1]
components:
  c: {type: Counter}
experiment: {stop: 1}
outputs: [c.y]
)yaml");
  CliResult r = Momenta({"check", file});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("der.yaml:8:31: der(c.k) in c (Counter, "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'y = der(k + x)': c.k is a discrete variable"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace momenta
