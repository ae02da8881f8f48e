// Units on the command line: -p values with units converted to the parameter's unit (the
// carrier collision's closed form with mA given in grams), an incompatible or unparsable unit as
// a usage error naming both units, and the companion file that gives every CSV column's unit.

#include <gtest/gtest.h>

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

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class UnitsCliTest : public ::testing::Test {
 protected:
  CliResult Simulate(std::vector<std::string> args) {
    std::vector<std::string> all = {"simulate",
                                    testing::SourcePath("models/carrier_collision.yaml")};
    all.insert(all.end(), args.begin(), args.end());
    return testing::RunMomentaWithDeadline(all, dir_.path(), 60);
  }
  TempDir dir_;
};

TEST_F(UnitsCliTest, ParameterValuesWithUnitsAreConverted) {
  // mA = 80 000 g = 80 kg, vA0 = 18 km/h = 5 m/s; eC = 0.8; B at rest: after the carriers' impact
  // vB = mA*vA0*(1 + eC)/(mA + mB) = 80*5*1.8/120 = 6 m/s and vA = (mA - eC*mB)*vA0/(mA + mB) =
  // (80 - 32)*5/120 = 2 m/s, which the model's Collision block computes algebraically (B then
  // meets the suitcase; A does not). The impact algebra is exact to rounding: 1e-9.
  CliResult r =
      Simulate({"-p", "mA=80000 g", "-p", "vA0=18km/h", "--stop", "0.3", "-o", "out.csv"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  const auto& last = csv.rows.back();
  EXPECT_NEAR(last[csv.Index("A.v")], 2, 1e-9);
  EXPECT_NEAR(last[csv.Index("carriers.v_K1")], 6, 1e-9);
}

TEST_F(UnitsCliTest, AnIncompatibleOrUnknownUnitIsAUsageError) {
  CliResult r = Simulate({"-p", "mA=4 m/s", "-o", "out.csv"});
  EXPECT_EQ(r.exit_code, kExitUsage);
  EXPECT_TRUE(Contains(r.err, "-p mA=4 m/s: mA is in kg: m/s (m/s) cannot be converted to kg (kg)"))
      << r.err;
  r = Simulate({"-p", "eC=4 kg", "-o", "out.csv"});
  EXPECT_EQ(r.exit_code, kExitUsage);
  EXPECT_TRUE(Contains(r.err, "eC declares no unit, so a value in kg cannot be converted"))
      << r.err;
  r = Simulate({"-p", "mA=4 lbs", "-o", "out.csv"});
  EXPECT_EQ(r.exit_code, kExitUsage);
  EXPECT_TRUE(Contains(r.err, "-p mA: unit 'lbs' does not parse: unknown unit 'lbs'")) << r.err;
}

TEST_F(UnitsCliTest, TheUnitsOfTheCsvColumnsAreInACompanionFile) {
  CliResult r = Simulate({"-o", "out.csv"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  // The CSV header stays plain names (readers of momenta's CSV and OpenModelica-style tools).
  testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  EXPECT_EQ(csv.header[1], "A.v");
  const std::vector<std::string> lines =
      testing::Lines(testing::ReadText(dir_.File("out.units.csv")));
  ASSERT_EQ(lines.size(), csv.header.size() + 1);
  EXPECT_EQ(lines[0], "name,unit");
  EXPECT_EQ(lines[1], "time,s");
  EXPECT_EQ(lines[2], "A.v,m/s");
  EXPECT_EQ(lines[5], "A.s,m");
  EXPECT_EQ(lines[8], "carriers.v_J1,");  // declared without a unit in the model's own type
}

}  // namespace
}  // namespace momenta
