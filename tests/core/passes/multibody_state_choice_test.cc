// Which variables a 3-D multibody model keeps as states: the joints' coordinates, as the MSL's
// stateSelect asks, also in blocks too large for the pivoting choice (a chain of eight links), and
// `stateSelect: always` on a spherical joint's relative angular velocity with quaternion states
// (the MSL's Spherical with enforceStates), at the world and between two moving bodies; and the
// bodies' own quaternions and angular velocities where the joints have no states and the bodies'
// frames are the roots of the connection graph.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/compile/model_state.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using States = std::vector<std::string>;

/// Two box bodies hanging from the world on spherical joints s1 and s2, as the MSL's
/// SphericalDoublePendulum; `joint` is each joint's entry after its type, `outputs` the list.
std::string SphericalBoxPendulum(const std::string& model, const std::string& joint1, const std::string& joint2,
                                 const std::string& outputs) {
  return "model: " + model + R"(
components:
  world: {type: MultiBody.World}
  s1: {type: MultiBody.Joints.Spherical, )" + joint1 + R"(}
  box1: {type: MultiBody.Parts.BodyBox, width: 0.06, r: [0.4, 0, -0.3]}
  s2: {type: MultiBody.Joints.Spherical, )" + joint2 + R"(}
  box2: {type: MultiBody.Parts.BodyBox, width: 0.06, r: [0.3, -0.4, 0]}
connections:
  - [world.frame_b, s1.frame_a]
  - [s1.frame_b, box1.frame_a]
  - [box1.frame_b, s2.frame_a]
  - [s2.frame_b, box2.frame_a]
outputs: )" + outputs + "\n";
}

TEST(MultiBodyStateChoiceTest, ALongChainKeepsTheJointAngles) {
  // Eight links make one block of more than 200 differentiated equations, chosen by matching
  // rather than by pivoting: each Revolute's phi and w (stateSelect prefer) stay the states, not
  // the bodies' positions (default), which for this planar motion would be singular.
  const std::string yaml = R"(
model: Chain
components:
  world: {type: MultiBody.World}
  rev: {type: MultiBody.Joints.Revolute, count: 8, phi: {start: 0.1, fixed: true}, w: {fixed: true}}
  link: {type: MultiBody.Parts.BodyShape, count: 8, r: [0.5, 0, 0], r_CM: [0.25, 0, 0], m: 1}
connections:
  - [world.frame_b, "rev[1].frame_a"]
  - for: i in 1:8
    connect: ["rev[i].frame_b", "link[i].frame_a"]
  - for: i in 1:7
    connect: ["link[i].frame_b", "rev[i+1].frame_a"]
outputs: ["rev[1].phi", "rev[8].phi"]
)";
  testing::Built built = testing::BuildYaml(yaml);
  States expected;
  for (int i = 1; i <= 8; ++i) {
    expected.push_back("rev[" + std::to_string(i) + "].phi");
    expected.push_back("rev[" + std::to_string(i) + "].w");
  }
  EXPECT_EQ(built.report.states, expected);
}

TEST(MultiBodyStateChoiceTest, AlwaysOnASphericalJointsAngularVelocityIsHonoured) {
  // Two spherical joints with quaternion states, as the MSL's enforceStates sets them (Q prefer,
  // w_rel always): at the world, w_rel is an alias of the body's w_a, whose derivative appears
  // and its own does not; between two bodies, w_rel appears only in der(Q)'s equation. Both are
  // states, with three elements of each Q.
  const std::string yaml = SphericalBoxPendulum(
      "SphericalPair",
      "enforceStates: true, angles_fixed: true, w_rel_a_fixed: true, w_rel_a_start: [0.05, 0.03, 0.01], Q: {stateSelect: prefer}, w_rel: {stateSelect: always}",
      "enforceStates: true, angles_fixed: true, w_rel_a_fixed: true, Q: {stateSelect: prefer}, w_rel: {stateSelect: always}",
      R"(["s1.w_rel[1]", "s2.w_rel[1]"])");
  testing::Built built = testing::BuildYaml(yaml);
  const States& states = built.report.states;
  for (const char* joint : {"s1", "s2"}) {
    for (int k = 1; k <= 3; ++k) {
      const std::string w = std::string(joint) + ".w_rel[" + std::to_string(k) + "]";
      EXPECT_NE(std::find(states.begin(), states.end(), w), states.end()) << w << " is not a state";
    }
  }
  EXPECT_EQ(states.size(), 12u);
}

TEST(MultiBodyStateChoiceTest, BodiesAsRootsKeepTheirQuaternionsAndAngularVelocities) {
  // Spherical joints without enforceStates give the bodies' frames to the connection graph as
  // roots: each body integrates its quaternion Q (stateSelect avoid, der(Q) in the body's
  // equations) and w_a (avoid), as Dymola chooses for ModelicaTest.MultiBody.
  // SphericalDoublePendulum. Neither the frame's transformation matrix R.T (default, but
  // differentiated only by index reduction) nor the second body's frame position r_0 (default,
  // an alias of the body's r_0, avoid) may take their place: three elements of T are a choice
  // that goes singular within half a second of this swing.
  const std::string yaml = SphericalBoxPendulum(
      "FreeBodiesPendulum", "angles_fixed: true, w_rel_a_fixed: true, w_rel_a_start: [0.05, 0.03, 0.01]",
      "angles_fixed: true, w_rel_a_fixed: true", R"(["box1.body.Q[1]"])");
  testing::Built built = testing::BuildYaml(yaml);
  // box1's Q is chosen with its frame's R.T in one block (its position is held by the joint at
  // the world): three of Q, statically. box2's Q block is Q*der(Q) = 0 alone: three of its four
  // elements, chosen during the run (Dymola: "3 states to be selected from body.Q[]").
  const States expected{"box1.body.w_a[1]", "box1.body.w_a[2]", "box1.body.w_a[3]", "box1.body.Q[1]",
                        "box1.body.Q[2]",   "box1.body.Q[3]",   "box2.body.w_a[1]", "box2.body.w_a[2]",
                        "box2.body.w_a[3]", "stateSet1.x[1]",   "stateSet1.x[2]",   "stateSet1.x[3]"};
  EXPECT_EQ(built.report.states, expected);
  bool dynamic = false;
  for (const std::string& c : built.report.state_choices) {
    dynamic |= c.find("dynamic: 3 of {box2.body.Q[1], box2.body.Q[2], box2.body.Q[3], box2.body.Q[4]} are states") !=
               std::string::npos;
  }
  EXPECT_TRUE(dynamic);
}

TEST(MultiBodyStateChoiceTest, AContactDoesNotTakeTheBodysStates) {
  // Two free spheres with a sphere-sphere contact: the bodies' positions (avoid, as the MSL's
  // Body.r_0, differentiated by each body's v_0 = der(r_0)) would rank with the contact's distance
  // d and normal velocity v_n, whose der(d) the contact's equations also hold, and d and v_n took
  // the place of A's r_0[1] and v_0[1]. The contact's are `never`: each body keeps its r_0 and
  // v_0 as states, as it has without the contact.
  const std::string yaml = R"(
model: TwoSpheres
components:
  world: {type: MultiBody.World, gravityType: 1}
  A: {type: MultiBody.Parts.Body, m: 1, r_0: {start: [0, 0, 0], fixed: true}, v_0: {start: [1, 0, 0], fixed: true}, angles_fixed: true, w_0_fixed: true}
  B: {type: MultiBody.Parts.Body, m: 1, r_0: {start: [2, 0.3, 0.2], fixed: true}, v_0: {start: [0, 0, 0], fixed: true}, angles_fixed: true, w_0_fixed: true}
  contact: {type: MultiBody.Contacts.SphereSphere, ra: 0.25, rb: 0.25, e: 1}
connections:
  - [A.frame_a, contact.frame_a]
  - [B.frame_a, contact.frame_b]
outputs: [contact.d]
)";
  testing::Built built = testing::BuildYaml(yaml);
  States expected;
  for (const char* body : {"A", "B"}) {
    for (const char* var : {"frame_a.r_0", "v_0", "w_a"}) {
      for (int i = 1; i <= 3; ++i) expected.push_back(std::string(body) + "." + var + "[" + std::to_string(i) + "]");
    }
  }
  for (const char* set : {"stateSet1", "stateSet2"}) {  // three of each body's Q
    for (int i = 1; i <= 3; ++i) expected.push_back(std::string(set) + ".x[" + std::to_string(i) + "]");
  }
  EXPECT_EQ(built.report.states, expected);
}

// The connection graph's conditions (a Spherical joint's branch `if: enforceStates`) shape the
// structure: a built model refuses another value, as for any structural parameter. (The graph's
// own record of them was overwritten when flattening ended until 2026-11-29; enforceStates was
// kept by its if-blocks, a parameter that only the graph reads was not.)
TEST(MultiBodyStateChoiceTest, TheConnectionGraphsConditionsAreStructural) {
  const testing::Built built = testing::BuildYaml(SphericalBoxPendulum(
      "Graph", "angles_fixed: true, w_rel_a_fixed: true", "angles_fixed: true, w_rel_a_fixed: true", R"(["s1.w_rel[1]"])"));
  const double* built_with = built.model->flat->StructuralValue("s1.enforceStates");
  ASSERT_NE(built_with, nullptr);
  EXPECT_EQ(*built_with, 0);
  ModelState state(built.model);
  try {
    state.SetParameters({{"s1.enforceStates", 1}});
    FAIL() << "expected an error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("s1.enforceStates shapes the model's structure"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace momenta
