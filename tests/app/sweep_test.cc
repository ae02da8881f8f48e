// `momenta sweep`, the real binary: on the carrier collision (closed-form velocities at every grid
// point, the same table for any --jobs and under mpirun on 2 ranks, Monte Carlo reproducible from
// its seed across jobs and ranks), failing runs recorded while the others go on, usage errors,
// per-run trajectories and SIGINT. The SPEC parser and the plan: sweep_plan_test.cc.

#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/commands.h"
#include "app/sweep.h"
#include "app/sweep_cluster.h"
#include "core/base/error.h"
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

// ---- The binary -------------------------------------------------------------------------------

class SweepTest : public ::testing::Test {
 protected:
  CliResult Momenta(const std::vector<std::string>& args) {
    return testing::RunMomentaWithDeadline(args, dir_.path(), 300);
  }
  /// Waits until `p` has written a few rows of s.csv, interrupts it with SIGINT and checks what
  /// it kept: the note, and whole rows of finished runs in run order. Returns its exit status.
  int InterruptAndCheckRows(testing::MomentaProcess& p, size_t runs) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (Lines(testing::ReadText(dir_.File("s.csv"))).size() < 4 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    p.Signal(SIGINT);
    const int code = p.Wait(60);
    EXPECT_NE(code, -2) << "still running 60 s after SIGINT:\n" << p.err();
    EXPECT_TRUE(Contains(p.err(), "sweep interrupted: ")) << p.err();
    EXPECT_TRUE(Contains(p.err(), " of " + std::to_string(runs) + " runs finished; their rows are kept in s.csv"))
        << p.err();
    Summary s = ReadSummary(dir_.File("s.csv"));
    EXPECT_GE(s.rows.size(), 3u);
    EXPECT_LT(s.rows.size(), runs);
    long previous = -1;
    for (size_t k = 0; k < s.rows.size(); ++k) {
      const long run = std::stol(s.rows[k]["run"]);
      EXPECT_GT(run, previous);
      previous = run;
      EXPECT_EQ(s.rows[k]["status"], "0");
      EXPECT_FALSE(s.rows[k]["B.v"].empty());
    }
    return code;
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
  // 400000 runs take a minute or more on two threads (about 0.3 ms each); SIGINT once some rows
  // are written.
  testing::MomentaProcess p({"sweep", carrier_, "-p", "eC=0:1:200000", "-p", "eS=0,1", "-j", "2", "-o", "s.csv"},
                            dir_.path());
  ASSERT_TRUE(p.started());
  EXPECT_EQ(InterruptAndCheckRows(p, 400000), 130) << p.err();
}

// ---- Under mpirun ------------------------------------------------------------------------------

/// `mpirun -n <ranks>` as root on a machine with fewer cores than ranks, or empty when this build
/// cannot run under MPI (the test then skips, saying why).
std::vector<std::string> Mpirun(int ranks, std::string* why) {
  const std::string mpirun = MOMENTA_MPIEXEC;
  if (!HaveMpi()) {
    *why = "momenta was built without MPI (install libopenmpi-dev and openmpi-bin, then reconfigure)";
    return {};
  }
  if (mpirun.empty() || access(mpirun.c_str(), X_OK) != 0) {
    *why = "no mpirun found when configuring (MPIEXEC_EXECUTABLE = '" + mpirun + "')";
    return {};
  }
  return {mpirun, "--allow-run-as-root", "--oversubscribe", "-n", std::to_string(ranks)};
}

class SweepMpiTest : public SweepTest {
 protected:
  void SetUp() override {
    mpirun_ = Mpirun(2, &why_);
    if (mpirun_.empty()) GTEST_SKIP() << why_;
  }
  CliResult MpiMomenta(const std::vector<std::string>& args) {
    return testing::RunMomentaWithDeadline(args, dir_.path(), 300, mpirun_);
  }
  std::vector<std::string> mpirun_;
  std::string why_;
};

TEST_F(SweepMpiTest, TwoRanksWriteTheThreadedTableAndTrajectories) {
  const std::vector<std::string> sweep = {"sweep", carrier_, "-p", "eC=0.5,0.8,1", "-p", "eS=0:1:3"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = sweep;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  CliResult threads = Momenta(with({"-j", "2", "-o", "threads.csv", "--trajectories", "t"}));
  ASSERT_EQ(threads.exit_code, kExitOk) << threads.err;
  CliResult one = MpiMomenta(with({"-j", "1", "-o", "mpi1.csv", "--trajectories", "m1"}));
  ASSERT_EQ(one.exit_code, kExitOk) << one.err;
  EXPECT_TRUE(Contains(one.out, "9 runs on 2 MPI ranks x 1 thread")) << one.out;
  // 2 ranks x 2 threads on this machine's cores: oversubscribed, the table the same.
  CliResult two = MpiMomenta(with({"-j", "2", "-o", "mpi2.csv", "--trajectories", "m2"}));
  ASSERT_EQ(two.exit_code, kExitOk) << two.err;
  EXPECT_TRUE(Contains(two.out, "9 runs on 2 MPI ranks x 2 threads")) << two.out;
  // Byte for byte: the summary, and every run's trajectory that rank 0 wrote.
  const std::string table = testing::ReadText(dir_.File("threads.csv"));
  EXPECT_EQ(testing::ReadText(dir_.File("mpi1.csv")), table);
  EXPECT_EQ(testing::ReadText(dir_.File("mpi2.csv")), table);
  for (int k = 0; k < 9; ++k) {
    const std::string name = "/run-" + std::to_string(k) + ".csv";
    const std::string trajectory = testing::ReadText(dir_.File("t" + name));
    EXPECT_GT(Lines(trajectory).size(), 100u) << name;
    EXPECT_EQ(testing::ReadText(dir_.File("m1" + name)), trajectory) << name;
    EXPECT_EQ(testing::ReadText(dir_.File("m2" + name)), trajectory) << name;
  }
  // And the MPI table is the closed form at every grid point.
  Summary s = ReadSummary(dir_.File("mpi2.csv"));
  ASSERT_EQ(s.rows.size(), 9u);
  for (size_t k = 0; k < 9; ++k) {
    const Closed c = CarrierClosedForm(40, 40, 15, 5, s.Num(k, "eC"), s.Num(k, "eS"));
    EXPECT_NEAR(s.Num(k, "B.v"), c.vB, 1e-12 * 5) << k;  // exact impacts: rounding only
    EXPECT_NEAR(s.Num(k, "S.v"), c.vS, 1e-12 * 5) << k;
  }
}

TEST_F(SweepMpiTest, RunsAreSpreadOverTheRanks) {
  // Twelve runs of about 30 ms each (some 40000 steps of a 1 kHz oscillator): both ranks get work,
  // as the summary's "runs by rank" line says, and x(t) = cos(w t) at the end.
  const std::string model = testing::SourcePath("tests/data/oscillator_1khz.yaml");
  CliResult r = MpiMomenta({"sweep", model, "-p", "w=6000:7000:12", "--stop", "0.5", "-j", "1", "-o", "osc.csv"});
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  const size_t at = r.out.find("runs by rank: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::istringstream counts(r.out.substr(at + 14));
  size_t rank0 = 0, rank1 = 0;
  counts >> rank0 >> rank1;
  EXPECT_EQ(rank0 + rank1, 12u) << r.out;
  EXPECT_GT(rank0, 0u) << r.out;
  EXPECT_GT(rank1, 0u) << r.out;
  Summary s = ReadSummary(dir_.File("osc.csv"));
  ASSERT_EQ(s.rows.size(), 12u);
  for (size_t k = 0; k < 12; ++k) {
    // About 500 periods at rtol 1e-6: BDF's phase error grows with the periods (4e-3 in x at most
    // on this grid, measured); 2e-2 leaves room and still fails on a wrong w or a swapped row.
    EXPECT_NEAR(s.Num(k, "o.x"), std::cos(s.Num(k, "w") * 0.5), 2e-2) << k;
  }
}

TEST_F(SweepMpiTest, MonteCarloIsTheSameOnRanksAsOnThreads) {
  const std::vector<std::string> sweep = {"sweep", carrier_, "-p", "vA0=normal(5,0.5)", "-p", "eC=uniform(0.5,1)",
                                          "--samples", "16", "--seed", "11", "-q"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = sweep;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  CliResult threads = Momenta(with({"-j", "1", "-o", "threads.csv"}));
  ASSERT_EQ(threads.exit_code, kExitOk) << threads.err;
  CliResult ranks = MpiMomenta(with({"-j", "2", "-o", "ranks.csv"}));
  ASSERT_EQ(ranks.exit_code, kExitOk) << ranks.err;
  EXPECT_EQ(testing::ReadText(dir_.File("ranks.csv")), testing::ReadText(dir_.File("threads.csv")));
  CliResult other = MpiMomenta({"sweep", carrier_, "-p", "vA0=normal(5,0.5)", "-p", "eC=uniform(0.5,1)", "--samples",
                                "16", "--seed", "12", "-q", "-o", "other.csv"});
  ASSERT_EQ(other.exit_code, kExitOk) << other.err;
  EXPECT_NE(testing::ReadText(dir_.File("other.csv")), testing::ReadText(dir_.File("threads.csv")));
}

TEST_F(SweepMpiTest, FailingRunsAreRecordedOnEveryRank) {
  dir_.Write("riccati.yaml", kRiccati);
  CliResult threads = Momenta({"sweep", "riccati.yaml", "-p", "k=0.25,1,0.4,3,0.3,1.5", "-j", "1", "-o", "t.csv"});
  EXPECT_EQ(threads.exit_code, kExitSolver) << threads.err;
  CliResult ranks = MpiMomenta({"sweep", "riccati.yaml", "-p", "k=0.25,1,0.4,3,0.3,1.5", "-j", "1", "-o", "m.csv"});
  // mpirun exits with the first non-zero exit status of a rank: rank 0's.
  EXPECT_EQ(ranks.exit_code, kExitSolver) << ranks.err;
  EXPECT_TRUE(Contains(ranks.err, "riccati.yaml: run 1 (k = 1) failed with status 3: simulation failed at t = "))
      << ranks.err;
  EXPECT_TRUE(Contains(ranks.out, "3 succeeded, 3 failed")) << ranks.out;
  EXPECT_EQ(testing::ReadText(dir_.File("m.csv")), testing::ReadText(dir_.File("t.csv")));
}

TEST_F(SweepMpiTest, AUsageErrorIsReportedOnceByRankZero) {
  CliResult r = MpiMomenta({"sweep", carrier_, "-p", "eX=0.5,0.8", "-o", "s.csv"});
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  const std::string message = "-p eX: no parameter of that name in CarrierCollision (did you mean eC";
  const size_t first = r.err.find(message);
  ASSERT_NE(first, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(message, first + 1), std::string::npos) << "printed by more than one rank:\n" << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.File("s.csv")));
}

TEST_F(SweepMpiTest, CtrlCKeepsTheFinishedRowsInRunOrder) {
  // mpirun passes SIGINT on to the ranks; rank 0 writes the rows finished so far and says so.
  testing::MomentaProcess p({"sweep", carrier_, "-p", "eC=0:1:200000", "-p", "eS=0,1", "-j", "1", "-o", "s.csv"},
                            dir_.path(), mpirun_);
  ASSERT_TRUE(p.started());
  const int code = InterruptAndCheckRows(p, 400000);
  EXPECT_NE(code, 0) << p.err();  // mpirun's own status for an interrupted job
}

TEST_F(SweepTest, MpirunWithoutMpiIsAUsageError) {
  if (HaveMpi()) GTEST_SKIP() << "momenta was built with MPI; this checks the message of a build without it";
  // What mpirun puts in each rank's environment, as if this were one of 2 ranks.
  setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  CliResult r = Momenta({"sweep", carrier_, "-p", "eC=0.5,0.8", "-o", "s.csv"});
  unsetenv("OMPI_COMM_WORLD_SIZE");
  EXPECT_EQ(r.exit_code, kExitUsage) << r.err;
  EXPECT_TRUE(Contains(r.err, "momenta: started by mpirun on 2 ranks, but this momenta was built without MPI")) << r.err;
}

}  // namespace
}  // namespace momenta
