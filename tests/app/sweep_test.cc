// `momenta sweep`: the SPEC parser and the run plan (grids, lists, distributions and their seed),
// and the real binary on the carrier collision (closed-form velocities at every grid point, the
// same table for any --jobs, Monte Carlo reproducible from its seed), failing runs recorded while
// the others go on, usage errors, per-run trajectories and SIGINT.

#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/commands.h"
#include "app/sweep.h"
#include "core/error.h"
#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::Lines;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// A summary CSV: the header, and per row its cells (the message unquoted).
struct Summary {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  double Num(size_t row, const std::string& column) const {
    const std::string& cell = rows.at(row).at(column);
    size_t used = 0;
    double v = std::stod(cell, &used);
    EXPECT_EQ(used, cell.size()) << column << " = '" << cell << "'";
    return v;
  }
};

/// Splits one CSV line (quoted fields may hold commas and doubled quotes).
std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted) {
      if (c == '"' && k + 1 < line.size() && line[k + 1] == '"') {
        cells.back() += '"';
        ++k;
      } else if (c == '"') {
        quoted = false;
      } else {
        cells.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

Summary ReadSummary(const std::string& path) {
  Summary s;
  std::vector<std::string> lines = Lines(testing::ReadText(path));
  if (lines.empty()) return s;
  s.header = Cells(lines[0]);
  for (size_t k = 1; k < lines.size(); ++k) {
    std::vector<std::string> cells = Cells(lines[k]);
    EXPECT_EQ(cells.size(), s.header.size()) << lines[k];
    std::map<std::string, std::string> row;
    for (size_t j = 0; j < cells.size() && j < s.header.size(); ++j) row[s.header[j]] = cells[j];
    s.rows.push_back(row);
  }
  return s;
}

/// B's and the suitcase's velocities after both impacts: A (mA, vA0) hits B (mB, at rest) with
/// restitution eC, then B's rear wall hits the suitcase (mS, at rest) with eS.
struct Closed {
  double vB, vS;
};
Closed CarrierClosedForm(double mA, double mB, double mS, double vA0, double eC, double eS) {
  const double vB1 = mA * vA0 * (1 + eC) / (mA + mB);
  return {(mB - eS * mS) * vB1 / (mB + mS), mB * vB1 * (1 + eS) / (mB + mS)};
}

// ---- The SPEC parser and the plan -------------------------------------------------------------

TEST(SweepSpecTest, ValuesListsAndGrids) {
  EXPECT_EQ(ParseSweepAxis("eC=0.8").values, (std::vector<double>{0.8}));
  EXPECT_FALSE(ParseSweepAxis("eC=0.8").swept());
  EXPECT_EQ(ParseSweepAxis("eC=0.5,0.8,1").values, (std::vector<double>{0.5, 0.8, 1}));
  EXPECT_TRUE(ParseSweepAxis("eC=0.5,0.8,1").swept());
  EXPECT_EQ(ParseSweepAxis("eS=0:1:3").values, (std::vector<double>{0, 0.5, 1}));
  EXPECT_EQ(ParseSweepAxis("x=-1:1:5").values, (std::vector<double>{-1, -0.5, 0, 0.5, 1}));
  EXPECT_EQ(ParseSweepAxis("on=true,false").values, (std::vector<double>{1, 0}));
  const std::vector<double> log = ParseSweepAxis("k=1e-2:1e2:log:5").values;
  ASSERT_EQ(log.size(), 5u);
  const double expected[] = {1e-2, 1e-1, 1, 10, 100};
  for (size_t k = 0; k < 5; ++k) EXPECT_NEAR(log[k], expected[k], 1e-14 * expected[k]) << k;
  EXPECT_EQ(log.front(), 1e-2);  // the ends exactly as given
  EXPECT_EQ(log.back(), 1e2);
  SweepAxis n = ParseSweepAxis("vA0=normal(5,0.5)");
  EXPECT_EQ(n.kind, SweepAxis::Kind::kNormal);
  EXPECT_EQ(n.a, 5);
  EXPECT_EQ(n.b, 0.5);
  SweepAxis u = ParseSweepAxis("eC=uniform(0.5, 1)");
  EXPECT_EQ(u.kind, SweepAxis::Kind::kUniform);
  EXPECT_EQ(u.a, 0.5);
  EXPECT_EQ(u.b, 1);
}

TEST(SweepSpecTest, BadSpecsNameTheOptionAndTheProblem) {
  const std::pair<const char*, const char*> cases[] = {
      {"eC", "-p takes NAME=SPEC"},
      {"eC=", "-p takes NAME=SPEC"},
      {"eC=0.5,x", "-p eC=0.5,x: the value 'x' is not a finite number"},
      {"eC=0.5,,1", "-p eC=0.5,,1: the value '' is not a finite number"},
      {"eS=0:1:x", "-p eS=0:1:x: the number of grid points 'x' is not a whole number from 1 to 10000000"},
      {"eS=0:1:2.5", "the number of grid points '2.5' is not a whole number"},
      {"eS=0:1:0", "the number of grid points '0' is not a whole number"},
      {"eS=0:1", "-p eS=0:1: a grid is a:b:n (linear) or a:b:log:n (logarithmic)"},
      {"eS=0:1:lin:3", "a grid is a:b:n"},
      {"k=0:1:log:3", "-p k=0:1:log:3: a logarithmic grid needs a positive start and end"},
      {"eS=nan:1:3", "the grid's start 'nan' is not a finite number"},
      {"eC=normal(1)", "-p eC=normal(1): normal(mu,sigma) takes two numbers"},
      {"eC=normal(1,-1)", "the standard deviation must not be negative"},
      {"eC=uniform(1,0)", "the upper bound is below the lower bound"},
      {"eC=uniform(0,1", "uniform(a,b) must end with ')'"},
  };
  for (const auto& [text, message] : cases) {
    try {
      ParseSweepAxis(text);
      ADD_FAILURE() << text << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_TRUE(Contains(e.what(), message)) << text << ": " << e.what();
    }
  }
}

TEST(SweepPlanTest, CartesianProductFirstParameterSlowest) {
  SweepPlan plan = MakeSweepPlan({ParseSweepAxis("eC=0.5,0.8,1"), ParseSweepAxis("mA=40"), ParseSweepAxis("eS=0:1:3")}, 0, 0);
  EXPECT_EQ(plan.names, (std::vector<std::string>{"eC", "mA", "eS"}));
  ASSERT_EQ(plan.values.size(), 9u);
  for (size_t k = 0; k < 9; ++k) {
    EXPECT_EQ(plan.values[k][0], (std::vector<double>{0.5, 0.8, 1})[k / 3]) << k;
    EXPECT_EQ(plan.values[k][1], 40) << k;
    EXPECT_EQ(plan.values[k][2], (std::vector<double>{0, 0.5, 1})[k % 3]) << k;
  }
}

TEST(SweepPlanTest, DrawsAreReproducibleFromTheSeedAndShared) {
  auto plan = [](uint64_t seed) {
    return MakeSweepPlan({ParseSweepAxis("eS=0,1"), ParseSweepAxis("vA0=normal(5,0.5)"),
                          ParseSweepAxis("eC=uniform(0.5,1)")}, 4, seed);
  };
  SweepPlan a = plan(42), b = plan(42), c = plan(43);
  ASSERT_EQ(a.values.size(), 8u);  // 2 grid points x 4 draws, the draw fastest
  EXPECT_EQ(a.values, b.values);
  EXPECT_NE(a.values, c.values);
  for (size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(a.values[k][0], k < 4 ? 0 : 1);
    // Every grid point gets the same draws (common random numbers).
    EXPECT_EQ(a.values[k][1], a.values[k % 4][1]);
    EXPECT_EQ(a.values[k][2], a.values[k % 4][2]);
    EXPECT_GE(a.values[k][2], 0.5);
    EXPECT_LT(a.values[k][2], 1);
  }
  // The draws' first values are fixed by std::mt19937_64 (whose output the standard specifies) and
  // our own transforms, so they are the same with every standard library: the engine's first
  // output for seed 42 gives u1, its second u2.
  std::mt19937_64 engine(42);
  const double u1 = 1.0 - static_cast<double>(engine() >> 11) * 0x1.0p-53;
  const double u2 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  EXPECT_EQ(a.values[0][1], 5 + 0.5 * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
  // The sample mean and spread of many draws.
  SweepPlan many = MakeSweepPlan({ParseSweepAxis("x=normal(5,0.5)"), ParseSweepAxis("y=uniform(-1,3)")}, 20000, 7);
  double sx = 0, sxx = 0, sy = 0;
  for (const auto& v : many.values) {
    sx += v[0];
    sxx += v[0] * v[0];
    sy += v[1];
  }
  const double n = many.values.size(), mean = sx / n;
  EXPECT_NEAR(mean, 5, 0.02);                              // 4 standard errors (0.5/sqrt(20000))
  EXPECT_NEAR(std::sqrt(sxx / n - mean * mean), 0.5, 0.02);
  EXPECT_NEAR(sy / n, 1, 0.04);                            // uniform(-1,3): mean 1, sd 1.15
}

TEST(SweepPlanTest, PlanErrors) {
  auto message = [](const std::vector<std::string>& specs, size_t samples) {
    std::vector<SweepAxis> axes;
    for (const auto& s : specs) axes.push_back(ParseSweepAxis(s));
    try {
      MakeSweepPlan(axes, samples, 0);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(message({"eC=normal(0.8,0.1)"}, 0), "-p eC=normal(0.8,0.1) is a distribution: give the number of draws with --samples K");
  EXPECT_EQ(message({"eC=0.5,0.8"}, 10), "--samples 10: no -p is a distribution (normal(mu,sigma) or uniform(a,b)) to draw from");
  EXPECT_EQ(message({"eC=0.5", "eC=0.8"}, 0), "-p eC is given twice");
  EXPECT_TRUE(Contains(message({"a=0:1:10000", "b=0:1:10000"}, 0), "more than 10000000 runs")) << message({"a=0:1:10000", "b=0:1:10000"}, 0);
}

// ---- The binary -------------------------------------------------------------------------------

class SweepTest : public ::testing::Test {
 protected:
  CliResult Momenta(const std::vector<std::string>& args) {
    return testing::RunMomentaWithDeadline(args, dir_.path(), 300);
  }
  std::string carrier_ = testing::SourcePath("models/carrier_collision.yaml");
  TempDir dir_;
};

TEST_F(SweepTest, CarrierGridMatchesTheClosedFormAndAnyJobs) {
  CliResult one = Momenta({"sweep", carrier_, "-p", "eC=0.5,0.8,1", "-p", "eS=0:1:3", "--jobs", "1", "-o", "one.csv"});
  ASSERT_EQ(one.exit_code, kExitOk) << one.err;
  EXPECT_EQ(one.err, "");  // no progress line on a pipe
  EXPECT_TRUE(Contains(one.out, "9 runs on 1 thread")) << one.out;
  EXPECT_TRUE(Contains(one.out, "9 succeeded, 0 failed")) << one.out;
  CliResult two = Momenta({"sweep", carrier_, "-p", "eC=0.5,0.8,1", "-p", "eS=0:1:3", "--jobs", "2", "-o", "two.csv"});
  ASSERT_EQ(two.exit_code, kExitOk) << two.err;
  EXPECT_TRUE(Contains(two.out, "9 runs on 2 threads")) << two.out;
  // The same table, byte for byte, whatever the number of threads.
  const std::string text = testing::ReadText(dir_.File("one.csv"));
  EXPECT_EQ(text, testing::ReadText(dir_.File("two.csv")));

  Summary s = ReadSummary(dir_.File("one.csv"));
  EXPECT_EQ(s.header, (std::vector<std::string>{"run", "eC", "eS", "A.v", "B.v", "S.v", "A.s", "B.s", "S.s",
                                                "carriers.v_J1", "carriers.v_K1", "suitcase.v_J1", "suitcase.v_K1",
                                                "steps", "events", "status", "message"}));
  ASSERT_EQ(s.rows.size(), 9u);
  const double eCs[] = {0.5, 0.8, 1}, eSs[] = {0, 0.5, 1};
  for (size_t k = 0; k < 9; ++k) {
    EXPECT_EQ(s.rows[k]["run"], std::to_string(k));
    const double eC = eCs[k / 3], eS = eSs[k % 3];
    EXPECT_EQ(s.Num(k, "eC"), eC);
    EXPECT_EQ(s.Num(k, "eS"), eS);
    const Closed c = CarrierClosedForm(40, 40, 15, 5, eC, eS);
    // Exact impacts, then free motion: only rounding (1e-12 relative is generous).
    EXPECT_NEAR(s.Num(k, "B.v"), c.vB, 1e-12 * 5) << "eC = " << eC << ", eS = " << eS;
    EXPECT_NEAR(s.Num(k, "S.v"), c.vS, 1e-12 * 5) << "eC = " << eC << ", eS = " << eS;
    EXPECT_NEAR(s.Num(k, "A.v"), 5 * (1 - eC) / 2, 1e-12 * 5);
    // The seed's Collision blocks compute the same algebraically.
    EXPECT_NEAR(s.Num(k, "suitcase.v_J1"), c.vB, 1e-12 * 5);
    EXPECT_EQ(s.rows[k]["status"], "0");
    EXPECT_EQ(s.rows[k]["message"], "");
    EXPECT_EQ(s.rows[k]["events"], "2");  // two impacts
    EXPECT_GT(s.Num(k, "steps"), 10);
  }
}

TEST_F(SweepTest, MonteCarloIsReproducibleFromItsSeed) {
  auto run = [&](const std::string& out, const std::string& jobs, const std::string& seed) {
    CliResult r = Momenta({"sweep", carrier_, "-p", "vA0=normal(5,0.5)", "-p", "eC=uniform(0.5,1)", "--samples", "8",
                           "--seed", seed, "--jobs", jobs, "-o", out, "-q"});
    EXPECT_EQ(r.exit_code, kExitOk) << r.err;
    EXPECT_EQ(r.out, "");
    return testing::ReadText(dir_.File(out));
  };
  const std::string a = run("a.csv", "1", "11"), b = run("b.csv", "2", "11"), c = run("c.csv", "2", "12");
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  Summary s = ReadSummary(dir_.File("a.csv"));
  ASSERT_EQ(s.rows.size(), 8u);
  for (size_t k = 0; k < 8; ++k) {
    const double vA0 = s.Num(k, "vA0"), eC = s.Num(k, "eC");
    EXPECT_GE(eC, 0.5);
    EXPECT_LT(eC, 1);
    EXPECT_GT(vA0, 2);  // 6 sigma
    const Closed cf = CarrierClosedForm(40, 40, 15, vA0, eC, 0.3);
    EXPECT_NEAR(s.Num(k, "B.v"), cf.vB, 1e-11 * vA0) << "vA0 = " << vA0 << ", eC = " << eC;
  }
}

constexpr const char* kRiccati = R"(model: Riccati
parameters:
  k: {value: 0.25, max: 2, doc: x' = k x^2 blows up at t = 1/k}
define:
  Blow:
    parameters:
      k: {value: 1}
    variables:
      x: {start: 1, fixed: true}
    equations:
      - der(x) = k*x^2
components:
  b: {type: Blow, k: k}
experiment: {stop: 2, interval: 0.1}
outputs: [b.x]
)";

TEST_F(SweepTest, FailingRunsAreRecordedAndTheOthersRun) {
  // x = 1/(1 - k t): k = 1 blows up at t = 1 < 2 (the solver fails: status 3), k = 3 is above the
  // parameter's maximum (status 1); k = 0.25 and 0.4 end at 1/(1 - 2k).
  dir_.Write("riccati.yaml", kRiccati);
  CliResult r = Momenta({"sweep", "riccati.yaml", "-p", "k=0.25,1,0.4,3", "-j", "2", "-o", "s.csv"});
  EXPECT_EQ(r.exit_code, kExitSolver) << r.err;
  EXPECT_TRUE(Contains(r.err, "riccati.yaml: run 1 (k = 1) failed with status 3: simulation failed at t = ")) << r.err;
  EXPECT_TRUE(Contains(r.err, "riccati.yaml: run 3 (k = 3) failed with status 1: ")) << r.err;
  EXPECT_TRUE(Contains(r.out, "2 succeeded, 2 failed")) << r.out;
  Summary s = ReadSummary(dir_.File("s.csv"));
  ASSERT_EQ(s.rows.size(), 4u);
  EXPECT_EQ(s.rows[0]["status"], "0");
  EXPECT_NEAR(s.Num(0, "b.x"), 2, 1e-4);
  EXPECT_EQ(s.rows[1]["status"], "3");
  EXPECT_EQ(s.rows[1]["b.x"], "");  // no final value for a failed run
  EXPECT_TRUE(Contains(s.rows[1]["message"], "simulation failed at t = ")) << s.rows[1]["message"];
  EXPECT_GT(s.Num(1, "steps"), 0);
  EXPECT_EQ(s.rows[2]["status"], "0");
  EXPECT_NEAR(s.Num(2, "b.x"), 5, 5e-4);
  EXPECT_EQ(s.rows[3]["status"], "1");
  EXPECT_TRUE(Contains(s.rows[3]["message"], "-p k: k = 3 is above its maximum 2")) << s.rows[3]["message"];
  EXPECT_EQ(s.rows[3]["steps"], "0");
}

TEST_F(SweepTest, UsageErrorsExitWithTwoNamingTheParameter) {
  const std::string rc = testing::SourcePath("models/rc_ladder.yaml");
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  for (const Case& c : std::vector<Case>{
           {{"sweep", carrier_, "-p", "eS=0:1:x"}, "momenta: -p eS=0:1:x: the number of grid points 'x' is not a whole number"},
           {{"sweep", carrier_, "-p", "eC=normal(1)"}, "momenta: -p eC=normal(1): normal(mu,sigma) takes two numbers"},
           {{"sweep", carrier_, "-p", "eX=0.5,0.8"}, "-p eX: no parameter of that name in CarrierCollision (did you mean eC"},
           {{"sweep", carrier_, "-p", "eX=0.5"}, "-p eX: no parameter of that name in CarrierCollision"},
           {{"sweep", carrier_, "-p", "eC=normal(0.8,0.1)"}, "--samples K"},
           {{"sweep", carrier_, "-p", "eC=0.5,1", "--stop", "-1"}, "momenta: --stop -1: the stop time must be"},
           {{"sweep", carrier_, "-p", "eC=0.5,1", "--jobs", "0"}, "--jobs"},
           {{"sweep", rc, "-p", "n=1,2"},
            "momenta: -p n=1,2: n is a structural parameter (a count, a connection index or a Boolean or Integer "
            "if-condition; the model was built with n = 10); a sweep builds the model once"},
           {{"sweep", rc, "-p", "n=2", "-p", "R[3].R=1,2"}, "-p R[3].R: no parameter of that name in RCLadder"},
       }) {
    CliResult r = Momenta(c.args);
    std::string label;
    for (const auto& a : c.args) label += a + " ";
    EXPECT_EQ(r.exit_code, kExitUsage) << label << "\n" << r.err;
    EXPECT_TRUE(Contains(r.err, c.message)) << label << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir_.File("carrier_collision_sweep.csv"))) << label;
  }
  // A structural parameter with one value is applied when building: the two-stage ladder.
  CliResult ok = Momenta({"sweep", rc, "-p", "n=2", "-p", "R[2].R=0.5,1", "--stop", "0.1", "-o", "rc.csv", "-q"});
  EXPECT_EQ(ok.exit_code, kExitOk) << ok.err;
  Summary s = ReadSummary(dir_.File("rc.csv"));
  EXPECT_EQ(s.rows.size(), 2u);
  EXPECT_EQ(s.header[1], "n");
  EXPECT_EQ(s.header[2], "R[2].R");
}

TEST_F(SweepTest, TrajectoriesAreEachRunsCsv) {
  CliResult r = Momenta({"sweep", carrier_, "-p", "eS=0.2,0.6", "--trajectories", "runs", "-o", "s.csv", "-q"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  Summary s = ReadSummary(dir_.File("s.csv"));
  ASSERT_EQ(s.rows.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const std::string path = dir_.File("runs/run-" + std::to_string(k) + ".csv");
    std::vector<std::string> lines = Lines(testing::ReadText(path));
    ASSERT_GT(lines.size(), 100u) << path;
    EXPECT_EQ(lines[0], "time,A.v,B.v,S.v,A.s,B.s,S.s,carriers.v_J1,carriers.v_K1,suitcase.v_J1,suitcase.v_K1");
    // Its last row is the summary's final values.
    std::vector<std::string> last = Cells(lines.back());
    EXPECT_EQ(last[2], s.rows[k]["B.v"]);
    EXPECT_EQ(last[3], s.rows[k]["S.v"]);
  }
}

TEST_F(SweepTest, UnwritableSummaryExitsWithThree) {
  CliResult r = Momenta({"sweep", carrier_, "-p", "eS=0.2,0.6", "-o", "no-such-dir/s.csv"});
  EXPECT_EQ(r.exit_code, kExitSolver) << r.err;
  EXPECT_TRUE(Contains(r.err, "momenta: cannot write the summary file no-such-dir/s.csv: No such file or directory")) << r.err;
}

TEST_F(SweepTest, InterruptKeepsTheFinishedRows) {
  // 4000 runs take a minute or more on one thread; SIGINT once some rows are written.
  testing::MomentaProcess p({"sweep", carrier_, "-p", "eC=0:1:2000", "-p", "eS=0,1", "-j", "2", "-o", "s.csv"},
                            dir_.path());
  ASSERT_TRUE(p.started());
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (Lines(testing::ReadText(dir_.File("s.csv"))).size() < 4 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  p.Signal(SIGINT);
  const int code = p.Wait(60);
  EXPECT_EQ(code, 130) << p.err();
  EXPECT_TRUE(Contains(p.err(), "sweep interrupted: ")) << p.err();
  EXPECT_TRUE(Contains(p.err(), " of 4000 runs finished; their rows are kept in s.csv")) << p.err();
  Summary s = ReadSummary(dir_.File("s.csv"));
  ASSERT_GE(s.rows.size(), 3u);
  EXPECT_LT(s.rows.size(), 4000u);
  // Whole rows, in run order, each a finished run.
  long previous = -1;
  for (size_t k = 0; k < s.rows.size(); ++k) {
    const long run = std::stol(s.rows[k]["run"]);
    EXPECT_GT(run, previous);
    previous = run;
    EXPECT_EQ(s.rows[k]["status"], "0");
    EXPECT_FALSE(s.rows[k]["B.v"].empty());
  }
}

}  // namespace
}  // namespace momenta
