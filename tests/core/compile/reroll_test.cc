// Loop rerolling (core/compile/reroll.h): the rolled description reproduces every compiled program of
// every model exactly, rolled evaluation equals Program::Run bitwise, and runs of identical
// components become loops.

#include "core/compile/reroll.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

std::vector<std::pair<std::string, const Program*>> AllPrograms(const CompiledModel& m) {
  return {{"residual", &m.residual},
          {"jacobian", &m.jacobian},
          {"outputs", &m.outputs},
          {"start_values", &m.start_values},
          {"start_guesses", &m.start_guesses},
          {"init_residual", &m.init_residual},
          {"init_jacobian", &m.init_jacobian},
          {"redundant_residual", &m.redundant_residual},
          {"guard_values", &m.guard_values},
          {"parameters", &m.parameters},
          {"discrete_starts", &m.discrete_starts},
          {"discrete_update", &m.discrete_update},
          {"zero_crossings", &m.zero_crossings},
          {"zero_crossing_rates", &m.zero_crossing_rates},
          {"when_conditions", &m.when_conditions},
          {"when_values", &m.when_values},
          {"impact_values", &m.impact_values}};
}

bool SameInstruction(const Instruction& x, const Instruction& y) {
  return x.op == y.op && x.dst == y.dst && x.a == y.a && x.b == y.b && x.c == y.c;
}

/// The segments cover the program in order, without gaps, each with `len` strides, and expand
/// to the program instruction for instruction.
void ExpectExact(const Program& p, const std::vector<LoopSegment>& segments, const std::string& what) {
  uint32_t at = 0;
  for (const LoopSegment& s : segments) {
    ASSERT_EQ(s.begin, at) << what;
    ASSERT_GE(s.count, 1u) << what;
    ASSERT_GE(s.len, 1u) << what;
    ASSERT_EQ(s.stride.size(), s.len) << what;
    at += s.len * s.count;
  }
  ASSERT_EQ(at, p.size()) << what;
  const std::vector<Instruction> expanded = Expand(p.code(), segments);
  ASSERT_EQ(expanded.size(), p.size()) << what;
  for (size_t k = 0; k < expanded.size(); ++k) {
    ASSERT_TRUE(SameInstruction(expanded[k], p.code()[k])) << what << " instruction " << k;
  }
}

/// RolledProgram::Run and Program::Run on the same random registers: the same outputs and
/// registers, bit for bit.
void ExpectSameRun(const Program& p, size_t num_registers, uint64_t seed, const std::string& what) {
  size_t outs = 1;
  for (const Instruction& in : p.code()) {
    if (in.op == kStore) outs = std::max<size_t>(outs, in.dst + 1);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<double> regs(num_registers);
  for (double& r : regs) r = u(rng);
  std::vector<double> regs2 = regs, out(outs, 0.0), out2(outs, 0.0);
  p.Run(regs.data(), out.data());
  RolledProgram(p).Run(regs2.data(), out2.data());
  EXPECT_EQ(std::memcmp(out.data(), out2.data(), outs * sizeof(double)), 0) << what;
  EXPECT_EQ(std::memcmp(regs.data(), regs2.data(), regs.size() * sizeof(double)), 0) << what;
}

TEST(RerollTest, EveryModelsProgramsRollExactly) {
  std::vector<std::string> files;
  for (const char* dir : {"models", "models/msl"}) {
    for (const auto& entry : std::filesystem::directory_iterator(testing::SourcePath(dir))) {
      if (entry.path().extension() == ".yaml") files.push_back(std::string(dir) + "/" + entry.path().filename().string());
    }
  }
  ASSERT_GE(files.size(), 30u);
  uint64_t seed = 1;
  for (const std::string& file : files) {
    testing::Built b = testing::BuildFile(file);
    for (const auto& [name, program] : AllPrograms(*b.model)) {
      const std::string what = file + " " + name;
      ExpectExact(*program, Reroll(*program), what);
      // Loops of two repetitions too: the most segments boundaries to get right.
      ExpectExact(*program, Reroll(*program, {2, 1u << 16}), what + " (min_count 2)");
      ExpectSameRun(*program, b.model->layout.size, seed++, what);
    }
  }
}

TEST(RerollTest, LargerChainAndLadderRollExactly) {
  for (const char* file : {"models/spring_damper_chain.yaml", "models/rc_ladder.yaml", "models/pendulum_chain.yaml"}) {
    testing::Built b = testing::BuildFile(file, {{"n", 57}});
    for (const auto& [name, program] : AllPrograms(*b.model)) {
      ExpectExact(*program, Reroll(*program), std::string(file) + " " + name);
      ExpectSameRun(*program, b.model->layout.size, 7, std::string(file) + " " + name);
    }
  }
}

/// A prologue, a loop whose registers step by different amounts (a temporary that stays, an
/// input that advances by 2, an output that advances by 1, one going down), an epilogue.
TEST(RerollTest, FindsLoopBetweenPrologueAndEpilogue) {
  Program p;
  auto add = [&](Op op, uint32_t dst, uint32_t a, uint32_t b) {
    p.code().push_back({static_cast<uint8_t>(op), dst, a, b, 0});
  };
  add(Op::kSin, 100, 3, 0);
  add(Op::kAdd, 101, 100, 4);
  for (uint32_t i = 0; i < 10; ++i) {
    add(Op::kMul, 100, 10 + 2 * i, 5);
    add(Op::kSub, 101, 100, 60 - i);
    p.code().push_back({kStore, i, 101, 0, 0});
  }
  add(Op::kCos, 100, 3, 0);
  p.code().push_back({kStore, 10, 100, 0, 0});
  const std::vector<LoopSegment> segments = Reroll(p);
  ExpectExact(p, segments, "synthetic");
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[1].begin, 2u);
  EXPECT_EQ(segments[1].len, 3u);
  EXPECT_EQ(segments[1].count, 10u);
  EXPECT_EQ(segments[1].stride[0].dst, 0u);  // the temporary stays
  EXPECT_EQ(segments[1].stride[0].a, 2u);
  EXPECT_EQ(static_cast<int32_t>(segments[1].stride[1].b), -1);
  EXPECT_EQ(segments[1].stride[2].dst, 1u);
  EXPECT_EQ(segments[0].count, 1u);
  EXPECT_EQ(segments[2].count, 1u);
}

/// A body whose temporaries alternate between two registers repeats with twice its length.
TEST(RerollTest, AlternatingTemporariesGiveTheLongerPeriod) {
  Program p;
  for (uint32_t i = 0; i < 12; ++i) {
    const uint32_t t = 200 + (i % 2);
    p.code().push_back({static_cast<uint8_t>(Op::kNeg), t, 10 + i, 0, 0});
    p.code().push_back({kStore, i, t, 0, 0});
  }
  const std::vector<LoopSegment> segments = Reroll(p);
  ExpectExact(p, segments, "alternating");
  ASSERT_EQ(segments.size(), 1u);
  EXPECT_EQ(segments[0].len, 4u);
  EXPECT_EQ(segments[0].count, 6u);
}

/// Straight-line code with no repetition is one segment; an empty program has none.
TEST(RerollTest, IrregularCodeStaysStraight) {
  Program p;
  for (uint32_t i = 0; i < 20; ++i) {
    p.code().push_back({static_cast<uint8_t>(i % 3 ? Op::kAdd : Op::kMul), 100 + i * i, i * 7 % 13, i * i % 11, 0});
  }
  const std::vector<LoopSegment> segments = Reroll(p);
  ExpectExact(p, segments, "irregular");
  for (const LoopSegment& s : segments) EXPECT_LT(s.count, 4u);
  EXPECT_TRUE(Reroll(Program()).empty());
}

/// Runs of identical components: the chain's and the ladder's residuals and Jacobians are almost
/// all loops, whatever n.
TEST(RerollTest, ChainAndLadderAreLoops) {
  for (const char* file : {"models/spring_damper_chain.yaml", "models/rc_ladder.yaml"}) {
    for (double n : {100.0, 1000.0}) {
      testing::Built b = testing::BuildFile(file, {{"n", n}});
      for (const auto& [name, program] : AllPrograms(*b.model)) {
        if (name != "residual" && name != "jacobian") continue;
        const RerollCoverage c = Coverage(Reroll(*program));
        EXPECT_GE(c.share(), 0.9) << file << " n=" << n << " " << name;
        // The rolled form does not grow with n: a few segments of bodies only.
        EXPECT_LE(c.segments, 40u) << file << " n=" << n << " " << name;
      }
    }
  }
}

}  // namespace
}  // namespace momenta
