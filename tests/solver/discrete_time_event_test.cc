// A relation of time, parameters and discrete values (MSL Pulse's `time >= startTime +
// (pre(count) + 1)*period`) is a time event: the discrete values are constant between events, so
// its instant is computed after each event and hit exactly, as a relation of time alone is, not
// searched for as a state event (which locates it to the solver's resolution, ~1e-12 s late).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

TEST(DiscreteTimeEventTest, ARelationOfTimeAndADiscreteCounterIsScheduledExactly) {
  testing::Built b = testing::BuildYaml(R"yaml(
model: Ticks
parameters: {period: 0.1}
variables:
  n: {type: Integer, start: 0}
  x: {start: 0, fixed: true}
equations:
  - der(x) = 1
initial_equations:
  - pre(n) = 0
when:
  - when: time >= (pre(n) + 1)*period
    then: ["n = pre(n) + 1"]
experiment: {stop: 1.05, interval: 0.25}
outputs: [n, x]
)yaml");
  SimulationOptions o;
  o.stop = 1.05;
  o.interval = 0.25;
  o.rows_at_every_event = true;
  testing::Trajectory tr = testing::Run(b, o);
  EXPECT_EQ(tr.stats.time_events, 10);
  EXPECT_EQ(tr.stats.events, tr.stats.time_events) << "no state events";
  // Every row is a grid time or the event instant k*0.1 itself (to the last bits of the product).
  for (size_t r = 0; r < tr.t.size(); ++r) {
    const double t = tr.t[r];
    const double k = std::round(t / 0.1), g = std::round(t / 0.25);
    EXPECT_TRUE(std::fabs(t - k * 0.1) <= 1e-15 || std::fabs(t - g * 0.25) <= 1e-15 || t == 1.05) << "a row at t = " << t;
  }
  EXPECT_EQ(tr.Column("n", tr.t.size() - 1), 10);
}

}  // namespace
}  // namespace momenta
