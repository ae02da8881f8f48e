// Numbers that were silently wrong (tests/data/reliability/2026-11-27/06, 07, 14, 16, 17, 18):
// 0/0 folded to 0 at build time, inf and NaN rows with exit 0, reinit of a non-state, a reinit to
// inf dropped, Integer and Boolean values not enforced, a system singular at an event without its
// cause. Each is now an error: exit 1 at file:line when it is known at build time, exit 2 for an
// option, exit 3 naming the variable and the time at run time, with the rows before it kept. Each
// case runs the real CLI.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::RunMomenta;
using testing::TempDir;

std::string Reproducer(const std::string& name) {
  return testing::SourcePath("tests/data/reliability/2026-11-27/" + name);
}

class ReliabilityNumbersTest : public ::testing::Test {
 protected:
  CliResult Momenta(const std::vector<std::string>& args) { return RunMomenta(args, dir_.path()); }
  /// `simulate FILE -q -o out.csv ARGS...`.
  CliResult Simulate(const std::string& file, std::vector<std::string> args = {}) {
    std::vector<std::string> all = {"simulate", file, "-q", "-o", dir_.File("out.csv")};
    all.insert(all.end(), args.begin(), args.end());
    return Momenta(all);
  }
  /// The reproducer's text with `from` replaced by `to` (which must be there), written to `name`.
  std::string Variant(const std::string& reproducer, const std::string& name,
                      const std::vector<std::pair<std::string, std::string>>& edits) {
    std::string text = testing::ReadText(Reproducer(reproducer));
    for (const auto& [from, to] : edits) {
      const size_t at = text.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      if (at != std::string::npos) text.replace(at, from.size(), to);
    }
    return dir_.Write(name, text);
  }
  static bool Has(const CliResult& r, const std::string& text) { return r.err.find(text) != std::string::npos; }
  TempDir dir_;
};

// 06: 0/0, 0*(1/0) and (x-x)/(x-x) were folded to 0; reinit(x, 0/0) set x to 0; exit 0.
TEST_F(ReliabilityNumbersTest, ZeroOverZeroIsAnErrorAtItsLine) {
  const std::string file = Reproducer("06-zero-over-zero-folded.yaml");
  CliResult r = Simulate(file);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(Has(r, file + ":11:5: division by zero in '0 / 0', in reinit(x, ...) of when-clause 'time > 0.05'"))
      << r.err;
  // Each output alone, without the reinit: the output's own line and column, the division named.
  struct Case {
    const char* output;
    const char* message;
  };
  for (const Case& c : {Case{"\"0/0\"", ":14:15: division by zero in '0 / 0', in output '0/0'"},
                        Case{"\"0*(1/0)\"", ":14:15: division by zero in '1 / 0', in output '0*(1/0)'"},
                        Case{"\"(x - x)/(x - x)\"", ":14:15: division by zero in '0 / 0', in output '(x - x)/(x - x)'"},
                        Case{"\"1e308*10\"", ":14:15: '1e+308 * 10' is inf, in output '1e308*10'"},
                        Case{"\"sqrt(-1)\"", ":14:15: 'sqrt(-1)' is NaN, in output 'sqrt(-1)'"}}) {
    const std::string variant =
        Variant("06-zero-over-zero-folded.yaml", "06.yaml",
                {{"then: [\"reinit(x, 0/0)\"]", "then: [\"reinit(x, 2)\"]"},
                 {"outputs: [x, \"0/0\", \"0*(1/0)\", \"(x - x)/(x - x)\"]", std::string("outputs: [x, ") + c.output + "]"}});
    CliResult v = Simulate(variant);
    EXPECT_EQ(v.exit_code, 1) << c.output << ": " << v.err;
    EXPECT_TRUE(Has(v, variant + c.message)) << c.output << ": " << v.err;
  }
}

// 07: y = x/0 that only an output reads, and sqrt(x - 2): inf and NaN in every row, exit 0.
TEST_F(ReliabilityNumbersTest, NonFiniteOutputsStopTheRunNamingTheOutputAndTheTime) {
  // x/0 is a division by the constant zero: known at build time.
  const std::string file = Reproducer("07-division-by-zero-output-exit-0.yaml");
  CliResult r = Simulate(file);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(Has(r, file + ":10:5: division by zero in 'x / 0', in equation 'y = x/0'")) << r.err;
  // sqrt(x - 2) with x = exp(-t) < 2 is NaN from the start: no row, exit 3.
  const std::string sqrt_only = Variant("07-division-by-zero-output-exit-0.yaml", "07.yaml",
                                        {{"  - y = x/0", "  - y = x/2"}});
  CliResult s = Simulate(sqrt_only);
  EXPECT_EQ(s.exit_code, 3) << s.err;
  EXPECT_TRUE(Has(s, "at t = 0: the output sqrt(x - 2) is NaN")) << s.err;
  EXPECT_TRUE(testing::ReadCsv(dir_.File("out.csv")).rows.empty());
  // Turning NaN during the run: x = 1 - t, sqrt(x - 0.45) is NaN from t = 0.55 on. The rows of
  // t = 0 … 0.5 are kept, each the closed form to rounding (1e-12).
  const std::string file2 = dir_.Write("late.yaml", R"yaml(model: LateNaN
variables:
  x: {start: 1, fixed: true}
equations:
  - der(x) = -1
experiment: {stop: 1, interval: 0.1}
outputs: [x, "sqrt(x - 0.45)"]
)yaml");
  CliResult late = Simulate(file2);
  EXPECT_EQ(late.exit_code, 3) << late.err;
  EXPECT_TRUE(Has(late, "at t = 0.6")) << late.err;
  EXPECT_TRUE(Has(late, ": the output sqrt(x - 0.45) is NaN")) << late.err;
  const testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  ASSERT_EQ(csv.rows.size(), 6u) << late.err;
  for (const auto& row : csv.rows) EXPECT_NEAR(row[2], std::sqrt(1 - row[0] - 0.45), 1e-12) << row[0];
}

// 17: reinit(y, 100) of y = 2*x was accepted and moved the state x.
TEST_F(ReliabilityNumbersTest, ReinitOfAVariableThatIsNotAStateIsAnError) {
  const std::string file = Reproducer("17-reinit-algebraic.yaml");
  CliResult r = Simulate(file);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(Has(r, file + ":12:5: reinit(y, …) in 'time > 0.05': y is not a state (der() of it appears in no equation; it is computed from x)"))
      << r.err;
  // reinit of the state itself is what the model means: x jumps to 50 at t = 0.05 (y = 2*x).
  const std::string state = Variant("17-reinit-algebraic.yaml", "17.yaml", {{"reinit(y, 100)", "reinit(x, 50)"}});
  CliResult s = Simulate(state);
  EXPECT_EQ(s.exit_code, 0) << s.err;
  const testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  ASSERT_FALSE(csv.rows.empty());
  // x(0.1) = 50 exp(-(0.1 - t_event)), t_event within the crossing's location error of 0.05.
  EXPECT_NEAR(csv.rows.back()[1], 50 * std::exp(-0.05), 1e-3);
  EXPECT_NEAR(csv.rows.back()[2], 2 * csv.rows.back()[1], 1e-9);
}

// 18: reinit(x, 1e308*10) at initial(): in a larger model the inf row was followed by x = 1 (the
// reinit dropped), exit 0.
TEST_F(ReliabilityNumbersTest, ReinitToANonFiniteValueIsAnError) {
  // The constant overflow is known at build time.
  const std::string file = Reproducer("18-reinit-overflow-dropped.yaml");
  CliResult r = Simulate(file, {"--stop", "0.2", "--interval", "0.01"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(Has(r, file + ":33:7: '10 * 1e+308' is inf, in reinit(wt.x, ...) of when-clause 'initial()'")) << r.err;
  // Through time it overflows at run time: exit 3 naming the variable, the value and the
  // when-clause, at initial() and at a later event (whose rows before it are kept).
  const std::string at_start = Variant("18-reinit-overflow-dropped.yaml", "18.yaml",
                                       {{"'reinit(x, 1e308*10)'", "'reinit(x, 1e308*(10 + time))'"}});
  CliResult s = Simulate(at_start, {"--stop", "0.2", "--interval", "0.01"});
  EXPECT_EQ(s.exit_code, 3) << s.err;
  EXPECT_TRUE(Has(s, "at t = 0: reinit sets wt.x = inf in when-clause 'initial()'")) << s.err;
  EXPECT_TRUE(testing::ReadCsv(dir_.File("out.csv")).rows.empty());
  const std::string later = Variant("18-reinit-overflow-dropped.yaml", "18b.yaml",
                                    {{"'reinit(x, 1e308*10)'", "'reinit(x, 1e308*(10 + time))'"},
                                     {"- when: initial()", "- when: time > 0.1"}});
  CliResult l = Simulate(later, {"--stop", "0.2", "--interval", "0.01"});
  EXPECT_EQ(l.exit_code, 3) << l.err;
  EXPECT_TRUE(Has(l, "at t = 0.1: reinit sets wt.x = inf in when-clause 'time > 0.1'")) << l.err;
  const testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  ASSERT_EQ(csv.rows.size(), 11u);  // t = 0 … 0.1
  EXPECT_NEAR(csv.rows.back().back(), std::exp(-10 * 0.1), 1e-4);  // wt.x before the event
}

// 14: singular at the event at t = 0.05 (0*y = x): the message blamed "the discrete values" and
// the left-limit row was dropped.
TEST_F(ReliabilityNumbersTest, SingularAtAnEventNamesTheEquationAndKeepsTheLeftLimit) {
  const std::string file = Reproducer("14-singular-after-event.yaml");
  CliResult r = Simulate(file);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(Has(r, "at t = 0.05: ")) << r.err;
  EXPECT_TRUE(Has(r, "the equation '(if time < 0.05 then 1 else 0)*y = x' (" + file +
                         ":11:5) no longer depends on any unknown; y is determined by no equation any more"))
      << r.err;
  // Rows t = 0 … 0.04 and the left limit at t = 0.05: x = y = exp(-t) (rtol 1e-6 by default).
  const testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  ASSERT_EQ(csv.rows.size(), 6u) << r.err;
  EXPECT_DOUBLE_EQ(csv.rows.back()[0], 0.05);
  EXPECT_NEAR(csv.rows.back()[1], std::exp(-0.05), 1e-5);
  EXPECT_NEAR(csv.rows.back()[2], std::exp(-0.05), 1e-5);
}

// 16: Integer and Boolean values were not enforced.
TEST_F(ReliabilityNumbersTest, IntegerAndBooleanValuesAreEnforced) {
  const std::string file = Reproducer("16-integer-not-enforced.yaml");
  CliResult r = Simulate(file);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(Has(r, file + ":15:5: division by zero in '1 / 0', in the value of j of when-clause 'time > 0.05'")) << r.err;
  // Without the division: the parameter p = 2.5 at its line.
  const std::string no_div = Variant("16-integer-not-enforced.yaml", "16.yaml", {{"pre(j) + 1/0", "pre(j) + 1"}});
  CliResult p = Simulate(no_div);
  EXPECT_EQ(p.exit_code, 1) << p.err;
  EXPECT_TRUE(Has(p, no_div + ":6:14: p = 2.5: an Integer parameter takes whole numbers only")) << p.err;
  // p = 2, and -p p=3.7: a usage error naming the option.
  const std::string whole = Variant("16-integer-not-enforced.yaml", "16b.yaml",
                                    {{"pre(j) + 1/0", "pre(j) + 1"}, {"value: 2.5", "value: 2"}});
  CliResult o = Simulate(whole, {"-p", "p=3.7"});
  EXPECT_EQ(o.exit_code, 2) << o.err;
  EXPECT_TRUE(Has(o, "-p p=3.7: an Integer parameter takes whole numbers only")) << o.err;
  // The Integer k is given 1.5 by its equation: a number that is not whole, known at build time.
  CliResult k = Simulate(whole);
  EXPECT_EQ(k.exit_code, 1) << k.err;
  EXPECT_TRUE(Has(k, whole + ":13:5: the Integer k is given 1.5 by 'k = if x > 0.95 then p else 1.5': "
                            "an Integer takes whole numbers only")) << k.err;
  // Given 2*x instead, k's value is known at run time only: where x falls below 0.95 (t = ln(1/0.95)
  // = 0.0513), k = 1.9: exit 3 there, the rows before it kept (with the event of j at t = 0.05:
  // two rows), k = p = 2.
  const std::string real = Variant("16-integer-not-enforced.yaml", "16r.yaml",
                                   {{"pre(j) + 1/0", "pre(j) + 1"}, {"value: 2.5", "value: 2"}, {"else 1.5", "else 2*x"}});
  CliResult r3 = Simulate(real);
  EXPECT_EQ(r3.exit_code, 3) << r3.err;
  EXPECT_TRUE(Has(r3, "at t = 0.0512")) << r3.err;
  EXPECT_TRUE(Has(r3, ": the Integer k is 1.899")) << r3.err;
  EXPECT_TRUE(Has(r3, ": an Integer takes whole numbers only")) << r3.err;
  const testing::Csv csv = testing::ReadCsv(dir_.File("out.csv"));
  ASSERT_EQ(csv.rows.size(), 7u) << r3.err;  // t = 0 … 0.05, and 0.05 after j's event
  EXPECT_EQ(csv.rows.back()[2], 2.0);
  EXPECT_EQ(csv.rows.back()[3], 1.0);
  // A when-assignment giving an Integer a number that is not whole: at the when-clause.
  const std::string half = Variant("16-integer-not-enforced.yaml", "16h.yaml",
                                   {{"pre(j) + 1/0", "pre(j) + 0.5"}, {"value: 2.5", "value: 2"}, {"else 1.5", "else 1"}});
  CliResult h = Simulate(half);
  EXPECT_EQ(h.exit_code, 1) << h.err;
  EXPECT_TRUE(Has(h, half + ":15:5: the Integer j is given 0.5 in when-clause 'time > 0.05'")) << h.err;
  // A non-finite Integer at run time: pre(j) + big*10 with big = 1e308 at t = 0.05.
  const std::string overflow = Variant("16-integer-not-enforced.yaml", "16c.yaml",
                                       {{"pre(j) + 1/0", "pre(j) + big*10"},
                                        {"value: 2.5, type: Integer}", "value: 2, type: Integer}\n  big: {value: 1e308}"},
                                        {"else 1.5", "else 1"}});
  CliResult j = Simulate(overflow);
  EXPECT_EQ(j.exit_code, 3) << j.err;
  EXPECT_TRUE(Has(j, ": j = inf in when-clause 'time > 0.05': a value must be a finite number")) << j.err;
  // Boolean parameters take true, false, 1 or 0: 1.5 and 2 are refused, also where a
  // parameter is a connector's condition.
  const std::string boolean = dir_.Write("bool.yaml", R"yaml(model: BooleanParameter
parameters:
  b: {value: 1.5, type: Boolean}
variables:
  x: {start: 1, fixed: true}
equations:
  - der(x) = if b then -x else x
experiment: {stop: 0.1, interval: 0.01}
)yaml");
  CliResult b = Simulate(boolean);
  EXPECT_EQ(b.exit_code, 1) << b.err;
  EXPECT_TRUE(Has(b, boolean + ":3:14: b = 1.5: a Boolean parameter takes true, false, 1 or 0 only")) << b.err;
  const std::string condition = dir_.Write("condition.yaml", R"yaml(model: ConditionalConnector
components:
  fixed: {type: Rotational.Fixed}
  J: {type: Rotational.Inertia, J: 1, phi: {start: 1, fixed: true}, w: {start: 0, fixed: true}}
  damper: {type: Rotational.Damper, d: 1, useHeatPort: 2}
connections:
  - [fixed.flange, damper.flange_a]
  - [damper.flange_b, J.flange_a]
experiment: {stop: 0.1, interval: 0.01}
)yaml");
  CliResult c = Simulate(condition);
  EXPECT_EQ(c.exit_code, 1) << c.err;
  EXPECT_TRUE(Has(c, condition + ":5:56: damper.useHeatPort")) << c.err;
  EXPECT_TRUE(Has(c, " = 2: a Boolean parameter takes true, false, 1 or 0 only")) << c.err;
  // when: of a Real expression.
  const std::string real_when = dir_.Write("when.yaml", R"yaml(model: RealWhen
variables:
  x: {start: 1, fixed: true}
  k: {type: Integer, start: 0}
equations:
  - der(x) = -x
when:
  - when: x
    then: ["k = pre(k) + 1"]
experiment: {stop: 0.1, interval: 0.01}
)yaml");
  CliResult w = Simulate(real_when);
  EXPECT_EQ(w.exit_code, 1) << w.err;
  EXPECT_TRUE(Has(w, real_when + ":8:5: the when-condition 'x' is a Real expression, not a truth value")) << w.err;
}

// The README's slip: `--interval 1e-9 --stop 1` (1e9 rows) was accepted and would have filled the
// disk (CSV) or the memory (MAT, held until the run ends). With 1 000 outputs the rows need
// terabytes on any machine: refused before the run (exit 2), with the figures.
TEST_F(ReliabilityNumbersTest, RowsThatCannotBeKeptAreRefusedBeforeTheRun) {
  const std::string file = dir_.Write("wide.yaml", R"(model: Wide
variables: {x: {shape: [1000], start: 1, fixed: true}}
equations: ["der(x) = -x"]
outputs: [x]
)");
  for (const char* out : {"out.csv", "out.mat"}) {
    CliResult r = Momenta({"simulate", file, "-q", "--interval", "1e-9", "--stop", "1", "-o", dir_.File(out)});
    EXPECT_EQ(r.exit_code, 2) << out << ": " << r.err;
    EXPECT_TRUE(Has(r, "momenta: --interval 1e-09 from 0 to 1 s: 1000000000 rows of 1001 columns")) << r.err;
    EXPECT_TRUE(Has(r, std::string(out) == "out.csv" ? " of CSV, more than the " : " of memory until the MAT file is written"))
        << r.err;
    EXPECT_TRUE(Has(r, "; choose a larger --interval")) << r.err;
    EXPECT_NE(access(dir_.File(out).c_str(), F_OK), 0) << out << " was created";
  }
  // A grid that fits runs as before.
  CliResult ok = Momenta({"simulate", file, "-q", "--interval", "0.1", "--stop", "1", "-o", dir_.File("out.csv")});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// The README's slip: `count: 3000000` took 8 GB without a word (the budget is all the machine's
// available memory). A build planned past half the budget now says so before it takes it; with a
// budget of 48 MiB the RC ladder of n = 2000 (about 28 MiB by the estimate: 2 000 resistors with
// the MSL's heat port and temperature dependence, then 2 000 capacitors) is such a build.
TEST_F(ReliabilityNumbersTest, BuildTakingMostOfTheMemoryBudgetSaysSoFirst) {
  const std::string ladder = testing::SourcePath("models/rc_ladder.yaml");
  const char* old = std::getenv("MOMENTA_MEMORY_MB");
  const std::string saved = old ? old : "";
  setenv("MOMENTA_MEMORY_MB", "48", 1);
  CliResult r = Momenta({"check", ladder, "-p", "n=2000"});
  setenv("MOMENTA_MEMORY_MB", "1000", 1);
  CliResult roomy = Momenta({"check", ladder, "-p", "n=2000"});
  if (old) setenv("MOMENTA_MEMORY_MB", saved.c_str(), 1); else unsetenv("MOMENTA_MEMORY_MB");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r, ladder + ": note: building this model takes about ")) << r.err;
  EXPECT_TRUE(Has(r, " of memory (an estimate), more than half of the 48 MiB available (MOMENTA_MEMORY_MB=48)")) << r.err;
  EXPECT_EQ(roomy.exit_code, 0) << roomy.err;
  EXPECT_FALSE(Has(roomy, "note: building this model")) << roomy.err;
}

}  // namespace
}  // namespace momenta
