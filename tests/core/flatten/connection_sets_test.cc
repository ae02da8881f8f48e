// Connection sets on their own: which slots form a set, where a set was first connected, and the
// order and kind of the equations a set stands for, read through a writer that records them (the
// composite's and the model's writers are tested through whole models in composite_test.cc and
// flatten_test.cc).

#include "core/flatten/connection_sets.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace momenta::flatten_internal {
namespace {

ConnectorType Physical() {
  ConnectorType t;
  t.name = "Pin";
  t.potentials = {{"v", "V", ""}};
  t.flows = {{"i", "A", ""}};
  return t;
}

ConnectorType Signal(bool is_input) {
  ConnectorType t;
  t.name = is_input ? "RealInput" : "RealOutput";
  t.is_signal = true;
  t.is_input = is_input;
  return t;
}

/// Records each call as text: "unconnected 4", "equal 1 0 k0 @3", "sum {0,1} f0 @3".
class RecordingWriter {
 public:
  explicit RecordingWriter(std::vector<const ConnectorType*> types) : types_(std::move(types)) {}

  const ConnectorType& TypeOf(uint32_t slot) const { return *types_[slot]; }
  void Unconnected(uint32_t slot) { calls.push_back("unconnected " + std::to_string(slot)); }
  uint32_t Driver(const std::vector<uint32_t>& set, const SourceLoc& loc) {
    for (uint32_t s : set) {
      if (!types_[s]->is_input) return s;
    }
    throw ModelError(loc, "no driver");
  }
  void Equal(uint32_t slot, uint32_t to, uint32_t k, const SourceLoc& loc) {
    calls.push_back("equal " + std::to_string(slot) + " " + std::to_string(to) + " k" + std::to_string(k) + " @" +
                    std::to_string(loc.line));
  }
  void FlowSum(const std::vector<uint32_t>& set, uint32_t flow, const SourceLoc& loc) {
    std::string members;
    for (uint32_t s : set) members += (members.empty() ? "" : ",") + std::to_string(s);
    calls.push_back("sum {" + members + "} f" + std::to_string(flow) + " @" + std::to_string(loc.line));
  }

  std::vector<std::string> calls;

 private:
  std::vector<const ConnectorType*> types_;
};
static_assert(ConnectionWriter<RecordingWriter>);

SourceLoc Line(int line) { return SourceLoc("model.yaml", line, 1); }

TEST(ConnectionSetsTest, SetsInSlotOrderWhicheverWayTheyWereJoined) {
  ConnectionSets sets(6);
  sets.Join(4, 1);
  sets.Join(2, 5);
  sets.Join(5, 4);
  const std::vector<std::vector<uint32_t>> expected = {{0}, {1, 2, 4, 5}, {3}};
  EXPECT_EQ(sets.Sets(), expected);
}

TEST(ConnectionSetsTest, OnlyTheFirstConnectionLocatesASlot) {
  ConnectionSets sets(2);
  EXPECT_TRUE(sets.Locate(0, Line(3)));
  EXPECT_FALSE(sets.Locate(0, Line(7)));
  EXPECT_TRUE(sets.Locate(1, Line(7)));
}

TEST(ConnectionSetsTest, PhysicalSetsMakeEqualPotentialsThenFlowSums) {
  const ConnectorType pin = Physical();
  // Slots 0, 1, 2 joined (first named at lines 5, then 4), slot 3 alone.
  ConnectionSets sets(4);
  sets.Locate(2, Line(5));
  sets.Locate(1, Line(5));
  sets.Join(2, 1);
  sets.Locate(0, Line(4));
  sets.Join(0, 2);
  RecordingWriter writer({&pin, &pin, &pin, &pin});
  sets.WriteEquations(sets.Sets(), &writer);
  // The set's location is its first located slot in slot order (slot 0, line 4), not the first
  // connection written.
  const std::vector<std::string> expected = {"equal 1 0 k0 @4", "equal 2 0 k0 @4", "sum {0,1,2} f0 @4",
                                             "unconnected 3"};
  EXPECT_EQ(writer.calls, expected);
}

TEST(ConnectionSetsTest, SignalSetsEquateEveryInputToTheDriver) {
  const ConnectorType in = Signal(true), out = Signal(false);
  ConnectionSets sets(3);
  sets.Locate(0, Line(9));
  sets.Locate(2, Line(9));
  sets.Join(0, 2);
  sets.Join(1, 2);
  RecordingWriter writer({&in, &out, &in});
  sets.WriteEquations(sets.Sets(), &writer);
  const std::vector<std::string> expected = {"equal 0 1 k0 @9", "equal 2 1 k0 @9"};
  EXPECT_EQ(writer.calls, expected);
}

TEST(ConnectionSetsTest, ConnectorsOfDifferentKindsAreRefusedWithAHintForFlanges) {
  ConnectorType translational = Physical(), rotational = Physical(), real_in = Signal(true), real_out = Signal(false);
  translational.name = "Translational.Flange";
  rotational.name = "Rotational.Flange";
  EXPECT_TRUE(Compatible(&real_in, &real_out));
  EXPECT_FALSE(Compatible(&translational, &rotational));
  try {
    CheckCompatible(&translational, "wall.flange", &rotational, "shaft.flange", Line(2), " in Drive");
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot connect wall.flange (Translational.Flange) to shaft.flange "
                           "(Rotational.Flange) in Drive: connectors of different kinds"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("flanges of two domains"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace momenta::flatten_internal
