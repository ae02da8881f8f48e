// Sizes and whole numbers that shape a model's structure: `count:` against the memory budget,
// `for:` ranges against the model's connectors, and every double checked before it becomes an
// integer (a count, a range bound, an index) — with the value the user gave in the message.

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "core/flatten/flat_system.h"
#include "core/lang/model_spec.h"
#include "core/flatten/flatten.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace momenta {
namespace {

std::string FlattenError(const std::string& yaml, const ParameterOverrides& overrides = {}) {
  try {
    ModelSpec spec = LoadModelString(yaml, "test.yaml");
    Flatten(spec, BuiltinLibrary(), overrides);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

/// Sets MOMENTA_MEMORY_MB for one test and restores what was there.
class MemoryBudgetOverride {
 public:
  explicit MemoryBudgetOverride(const char* mb) {
    if (const char* old = std::getenv("MOMENTA_MEMORY_MB")) old_ = old;
    setenv("MOMENTA_MEMORY_MB", mb, 1);
  }
  ~MemoryBudgetOverride() {
    if (old_) {
      setenv("MOMENTA_MEMORY_MB", old_->c_str(), 1);
    } else {
      unsetenv("MOMENTA_MEMORY_MB");
    }
  }

 private:
  std::optional<std::string> old_;
};

const char* kLadder = R"(model: Ladder
parameters:
  n: 10
components:
  g: {type: Ground}
  R: {type: Resistor, count: n}
connections:
  - for: i in 1:n
    connect: ["R[i].n", g.p]
)";

TEST(FlattenBoundsTest, HugeCountSaysTheValueAndTheMemory) {
  std::string msg = FlattenError(kLadder, {{"n", 1e300}});
  EXPECT_NE(msg.find("test.yaml:6:6: count of R ('n') is 1e300: 1e300 Resistor components (11 variables, "
                     "5 parameters each) need about "),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("GiB of memory to build, more than the budget of "), std::string::npos) << msg;
  EXPECT_EQ(msg.find("-9223372036854775808"), std::string::npos) << msg;
}

TEST(FlattenBoundsTest, CountAgainstTheBudget) {
  MemoryBudgetOverride budget("1");
  // A Resistor (with the MSL's heat port and temperature dependence) is estimated at about 9.4 kB:
  // 100 fit in 1 MiB, 1000 do not.
  EXPECT_EQ(FlattenError(kLadder, {{"n", 100}}), "");
  std::string msg = FlattenError(kLadder, {{"n", 1000}});
  EXPECT_EQ(msg,
            "test.yaml:6:6: count of R ('n') is 1000: 1000 Resistor components (11 variables, 5 "
            "parameters each) need about 9.2 MiB of memory to build, more than the budget of 1 MiB "
            "(MOMENTA_MEMORY_MB=1)");
}

TEST(FlattenBoundsTest, CountMustBeAWholeNumberOfAtLeastOne) {
  EXPECT_EQ(FlattenError(kLadder, {{"n", 0}}), "test.yaml:6:6: count of R ('n') must be at least 1, found 0");
  EXPECT_EQ(FlattenError(kLadder, {{"n", 2.5}}), "test.yaml:6:6: count of R must be a whole number, found 2.5");
}

TEST(FlattenBoundsTest, ForRangeLongerThanTheModelsConnectors) {
  // The reliability reproducer's shape: the ends do not use i, the range is a billion long.
  std::string msg = FlattenError(R"(model: Long
components:
  a: {type: Mass}
  b: {type: Mass}
connections:
  - for: i in 1:1000000000
    connect: [a.flange_b, b.flange_a]
)");
  EXPECT_EQ(msg,
            "test.yaml:6:10: the range of 'for: i in 1:1000000000' makes 1000000000 connections, more than "
            "the model's 4 connectors can need; a range runs over the elements of an array, e.g. i in 1:n");
}

TEST(FlattenBoundsTest, ForRangeOf1e300IsNotSilentlyEmpty) {
  std::string msg = FlattenError(R"(model: Long
components:
  g: {type: Ground}
  R: {type: Resistor, count: 3}
connections:
  - for: i in 1:1e300
    connect: ["R[i].n", g.p]
)");
  EXPECT_NE(msg.find("test.yaml:6:10: the range of 'for: i in 1:1e300' makes 1e300 connections"),
            std::string::npos)
      << msg;
}

TEST(FlattenBoundsTest, ForRangeBoundsMustBeWholeNumbers) {
  std::string msg = FlattenError(R"(model: Half
parameters: {n: 3}
components:
  g: {type: Ground}
  R: {type: Resistor, count: n}
connections:
  - for: i in 1:n/2
    connect: ["R[i].n", g.p]
)");
  EXPECT_EQ(msg, "test.yaml:7:10: the end of the range of 'for: i in 1:n/2' must be a whole number, found 1.5");
}

TEST(FlattenBoundsTest, EmptyRangeMakesNoConnections) {
  // i in 1:n-1 with n = 1 is the usual empty range: no error.
  EXPECT_EQ(FlattenError(R"(model: One
parameters: {n: 1}
components:
  R: {type: Resistor, count: n}
  g: {type: Ground}
connections:
  - ["R[1].p", g.p]
  - ["R[1].n", g.p]
  - for: i in 1:n-1
    connect: ["R[i].n", "R[i+1].p"]
)"),
            "");
}

TEST(FlattenBoundsTest, HugeIndexSaysItsValue) {
  std::string msg = FlattenError(R"(model: Idx
components:
  g: {type: Ground}
  R: {type: Resistor, count: 3}
connections:
  - ["R[1e300].n", g.p]
)");
  EXPECT_EQ(msg, "test.yaml:6:7: R[1e300] is out of range 1..3 in 'R[1e300].n'");
}

}  // namespace
}  // namespace momenta
