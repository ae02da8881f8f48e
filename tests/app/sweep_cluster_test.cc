// What the ranks of an MPI sweep send one another: a run's result packed and unpacked unchanged
// (bit for bit: the summary must be the same as on threads), and a damaged message refused. The
// sweep under mpirun itself: sweep_test.cc.

#include "app/sweep_cluster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace momenta {
namespace {

TEST(SweepClusterTest, AResultCrossesUnchanged) {
  SweepRunResult r;
  r.done = true;
  r.finals = {0.1, -0.0, 1e-310, std::numeric_limits<double>::max(), 2.9045454545454546};
  r.steps = 123456789012;
  r.events = 2;
  r.status = 3;
  r.message = "simulation failed at t = 0.99: \"quoted\", a comma\nand a line end";
  r.trajectory = "time,B.v\n0,0\n0.1,2.5\n";
  r.signal = 0;
  int64_t run = -7;
  const SweepRunResult back = UnpackRunResult(PackRunResult(9876543210, r), &run);
  EXPECT_EQ(run, 9876543210);
  EXPECT_TRUE(back.done);
  ASSERT_EQ(back.finals.size(), r.finals.size());
  for (size_t k = 0; k < r.finals.size(); ++k) {
    EXPECT_EQ(std::memcmp(&back.finals[k], &r.finals[k], sizeof(double)), 0) << k;  // -0.0 stays -0.0
  }
  EXPECT_EQ(back.steps, r.steps);
  EXPECT_EQ(back.events, 2);
  EXPECT_EQ(back.status, 3);
  EXPECT_EQ(back.message, r.message);
  EXPECT_EQ(back.trajectory, r.trajectory);
  // An interrupted run, and a first ask that carries nothing.
  SweepRunResult stopped;
  stopped.done = false;
  stopped.signal = 15;
  const SweepRunResult s = UnpackRunResult(PackRunResult(-1, stopped), &run);
  EXPECT_EQ(run, -1);
  EXPECT_FALSE(s.done);
  EXPECT_EQ(s.signal, 15);
  EXPECT_TRUE(s.finals.empty());
  EXPECT_TRUE(s.message.empty());
}

TEST(SweepClusterTest, ADamagedMessageIsRefused) {
  SweepRunResult r;
  r.finals = {1, 2, 3};
  r.message = "m";
  std::vector<char> bytes = PackRunResult(4, r);
  int64_t run = 0;
  for (size_t cut : {size_t{0}, size_t{7}, bytes.size() / 2, bytes.size() - 1}) {
    std::vector<char> short_bytes(bytes.begin(), bytes.begin() + cut);
    try {
      UnpackRunResult(short_bytes, &run);
      ADD_FAILURE() << "a message cut to " << cut << " bytes was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "a sweep result message is cut short") << cut;
    }
  }
  bytes.push_back('x');
  try {
    UnpackRunResult(bytes, &run);
    ADD_FAILURE() << "a message with a byte too many was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "a sweep result message has bytes left over");
  }
}

}  // namespace
}  // namespace momenta
