// Records, expression functions, conditional blocks and the connection graph (docs/FORMAT.md,
// "Records, functions and the connection graph"), on a small 3-D library written for this test
// (tests/data/multibody-language/library.yaml): a world, a revolute joint and a body.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "core/build.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "solver/simulator.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::RunDefault;
using testing::SourcePath;
using testing::Trajectory;

std::string ReadText(const std::string& relative) {
  std::ifstream in(SourcePath(relative));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Library TestLibrary() {
  Library lib = BuiltinLibrary();
  LoadLibraryString(ReadText("tests/data/multibody-language/library.yaml"), "library.yaml", &lib);
  return lib;
}

Built BuildWith(const Library& lib, const std::string& model_text) {
  Built b;
  b.model = BuildModel(LoadModelString(model_text, "model.yaml"), lib, BuildOptions(), &b.report);
  return b;
}

// A pendulum: a point mass of 1 kg at 0.5 m on a revolute joint about z, gravity along -y. The
// orientation of each frame is defined by the world (a root) and then the joint (a branch): the
// body is no root, its quaternion is its dummy [0, 0, 0, 1]. Energy is conserved and the angle
// follows the planar pendulum's equation (m L^2 + I33) phi'' = -m g L cos(phi).
TEST(ConnectionGraphTest, PendulumOnARevoluteJointFollowsThePlanarEquation) {
  Library lib = TestLibrary();
  Built b = BuildWith(lib, ReadText("tests/data/multibody-language/pendulum.yaml"));
  Trajectory tr = RunDefault(b);
  ASSERT_GT(tr.t.size(), 10u);
  const double m = 1, L = 0.5, g = 9.80665, I33 = 0.001;
  // The planar equation integrated with a fine RK4 as the reference.
  double phi = 0, w = 0, t = 0;
  const double h = 1e-4;
  size_t row = 0;
  double worst = 0;
  auto f = [&](double p) { return -m * g * L * std::cos(p) / (m * L * L + I33); };
  for (; row < tr.t.size(); ++row) {
    while (t < tr.t[row] - 1e-12) {
      const double step = std::min(h, tr.t[row] - t);
      double k1p = w, k1w = f(phi);
      double k2p = w + 0.5 * step * k1w, k2w = f(phi + 0.5 * step * k1p);
      double k3p = w + 0.5 * step * k2w, k3w = f(phi + 0.5 * step * k2p);
      double k4p = w + step * k3w, k4w = f(phi + step * k3p);
      phi += step / 6 * (k1p + 2 * k2p + 2 * k3p + k4p);
      w += step / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
      t += step;
    }
    worst = std::max(worst, std::fabs(tr.values[row][0] - phi));
  }
  // rtol 1e-8 over 5 s (about three swings): 1e-5 rad bounds the integration error.
  EXPECT_LT(worst, 1e-5);
}

// A free body is a potential root: it integrates its orientation as a quaternion (3 of the 4
// chosen during the run). Torque-free, its angular momentum in the world frame is constant and
// its kinetic energy too; its centre of mass falls with g.
TEST(ConnectionGraphTest, FreeBodyIntegratesItsQuaternion) {
  Library lib = TestLibrary();
  Built b = BuildWith(lib, ReadText("tests/data/multibody-language/free_body.yaml"));
  Trajectory tr = RunDefault(b);
  ASSERT_GT(tr.t.size(), 10u);
  const double g = 9.80665, I[3] = {0.1, 0.2, 0.3};
  auto col = [&](const std::string& name) {
    for (size_t k = 0; k < tr.names.size(); ++k) {
      if (tr.names[k] == name) return k;
    }
    ADD_FAILURE() << "no output " << name;
    return size_t{0};
  };
  // World-frame angular momentum T' I w from the quaternion (MSL's from_Q), and the energy.
  auto momentum = [&](size_t row) {
    const auto& v = tr.values[row];
    const double q1 = v[col("body.Q[1]")], q2 = v[col("body.Q[2]")], q3 = v[col("body.Q[3]")], q4 = v[col("body.Q[4]")];
    const double T[3][3] = {{2 * (q1 * q1 + q4 * q4) - 1, 2 * (q1 * q2 + q3 * q4), 2 * (q1 * q3 - q2 * q4)},
                            {2 * (q2 * q1 - q3 * q4), 2 * (q2 * q2 + q4 * q4) - 1, 2 * (q2 * q3 + q1 * q4)},
                            {2 * (q3 * q1 + q2 * q4), 2 * (q3 * q2 - q1 * q4), 2 * (q3 * q3 + q4 * q4) - 1}};
    std::array<double, 4> out{};
    for (int i = 0; i < 3; ++i) {
      const double w = v[col("body.w_a[" + std::to_string(i + 1) + "]")];
      for (int j = 0; j < 3; ++j) out[j] += T[i][j] * I[i] * w;
      out[3] += 0.5 * I[i] * w * w;
    }
    return out;
  };
  const auto first = momentum(0);
  double worst = 0;
  for (size_t row = 0; row < tr.t.size(); ++row) {
    const auto now = momentum(row);
    for (int j = 0; j < 4; ++j) worst = std::max(worst, std::fabs(now[j] - first[j]));
    // The quaternion stays of unit length (its constraint is among the equations).
    const auto& v = tr.values[row];
    double qq = 0;
    for (int j = 1; j <= 4; ++j) qq += std::pow(v[col("body.Q[" + std::to_string(j) + "]")], 2);
    EXPECT_NEAR(qq, 1.0, 1e-7);  // solved by IDA's Newton iteration to within its tolerance (rtol 1e-8)
  }
  // rtol 1e-8 over 2 s: momentum and energy (about 0.6 and 0.9) to 1e-6.
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(first[1], 0.6, 1e-12);
  const auto& last = tr.values.back();
  EXPECT_NEAR(last[col("body.frame_a.r_0[2]")], 2 * 2 - 0.5 * g * 4, 1e-6);
  EXPECT_NEAR(last[col("body.v_0[2]")], 2 - g * 2, 1e-6);
}

// The bodies read gravity from the model's component `world` (outer: {world: World3}); without
// one they keep the world's defaults. A free body with a world of g = 2 along -z.
TEST(ConnectionGraphTest, BodiesReadGravityFromTheModelsWorld) {
  Library lib = TestLibrary();
  std::string text = ReadText("tests/data/multibody-language/free_body.yaml");
  text.replace(text.find("components:\n"), 12, "components:\n  world: {type: World3, g: 2, n: [0, 0, -1]}\n");
  Built b = BuildWith(lib, text);
  Trajectory tr = RunDefault(b);
  const auto& last = tr.values.back();
  EXPECT_NEAR(last[2], -0.5 * 2 * 4, 1e-6);  // body.frame_a.r_0[3] after 2 s
  EXPECT_NEAR(last[1], 2 * 2, 1e-6);         // no gravity along y
  // -p on the world's parameter reaches the body.
  tr = testing::Run(b, OptionsFromExperiment(b.model->experiment), {{"world.g", 4}});
  EXPECT_NEAR(tr.values.back()[2], -0.5 * 4 * 4, 1e-6);
  // A component named world of another type is an error naming both.
  std::string wrong = ReadText("tests/data/multibody-language/free_body.yaml");
  wrong.replace(wrong.find("components:\n"), 12, "components:\n  world: {type: FixedTranslation3}\n");
  try {
    BuildWith(lib, wrong);
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("world is a FixedTranslation3, but body (Body3) needs the model's world to be a World3"),
              std::string::npos)
        << e.what();
  }
}

std::string Error(const std::function<void()>& f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  }
  return "no error";
}

// What the graph and the blocks refuse, by their messages.
TEST(ConnectionGraphTest, RefusesTwoRootsALoopNoRootAndUnequalBranches) {
  Library lib = TestLibrary();
  auto model = [](const std::string& components, const std::string& connections) {
    return "model: M\ncomponents:\n" + components + "connections:\n" + connections;
  };
  // Two worlds joined by a rigid part: the orientation is defined twice.
  EXPECT_NE(Error([&] {
              BuildWith(lib, model("  w1: {type: World3}\n  w2: {type: World3}\n  bar: {type: FixedTranslation3}\n",
                                   "  - [w1.frame_b, bar.frame_a]\n  - [bar.frame_b, w2.frame_b]\n"));
            }).find("w2.frame_b.R (World3) and w1.frame_b.R (World3) are both roots of one connected set of frames"),
            std::string::npos);
  // A chain of two rigid parts closed on itself, with a body to root it: a loop.
  EXPECT_NE(Error([&] {
              BuildWith(lib, model("  a: {type: FixedTranslation3}\n  b: {type: FixedTranslation3}\n  body: {type: Body3}\n",
                                   "  - [a.frame_b, b.frame_a]\n  - [b.frame_b, a.frame_a]\n  - [body.frame_a, a.frame_a]\n"));
            }).find("closes a kinematic loop"),
            std::string::npos);
  // Rigid parts alone: nothing defines the orientation.
  EXPECT_NE(Error([&] { BuildWith(lib, model("  bar: {type: FixedTranslation3}\n", "  []\n")); })
                .find("the orientation of bar.frame_a.R (FixedTranslation3) is defined by nothing"),
            std::string::npos);
  // A block whose branches determine different numbers of unknowns, refused at the block.
  Library bad = TestLibrary();
  EXPECT_NE(Error([&] {
              LoadLibraryString(R"y(
Lopsided:
  parameters: {p: true}
  variables: {x: {}, y: {}}
  equations:
    - x = 1
    - if: p
      then: [y = 2]
      else: []
)y", "lopsided.yaml", &bad);
              bad.FindComponent("Lopsided");
            }).find("lopsided.yaml:7:7: the branches of this conditional block of Lopsided determine different numbers of "
                    "unknowns: then 1 equation, else 0 equations"),
            std::string::npos);
}

// A model's own record variable (MSL ModelicaTest.MultiBody.Frames.AngularVelocity: `R =
// body.frame_a.R`, a whole record equation in the model): the body's angular velocity in the
// world frame computed two ways, resolve1(R, angularVelocity2(R)) and angularVelocity1(R), agrees
// to rounding (w_err), and R's first column stays a unit vector (T is quadratic in the quaternion,
// which IDA holds to its tolerance, 1e-6 here: 1.2e-6 seen, 1e-5 allowed).
TEST(ConnectionGraphTest, AModelsOwnRecordVariable) {
  const Trajectory t = RunDefault(testing::BuildFile("models/msl/ModelicaTest/MultiBody/Frames/AngularVelocity.yaml"));
  double largest_w = 0;
  for (size_t r = 0; r < t.t.size(); ++r) {
    for (int k = 1; k <= 3; ++k) {
      const std::string i = std::to_string(k);
      EXPECT_NEAR(t.Column("w_err[" + i + "]", r), 0.0, 1e-12) << "at t = " << t.t[r];
      largest_w = std::max(largest_w, std::fabs(t.Column("w1[" + i + "]", r)));
    }
    const double c1 = t.Column("R.T[1,1]", r), c2 = t.Column("R.T[2,1]", r), c3 = t.Column("R.T[3,1]", r);
    EXPECT_NEAR(c1 * c1 + c2 * c2 + c3 * c3, 1.0, 1e-5) << "at t = " << t.t[r];
  }
  EXPECT_GT(largest_w, 1.0);  // the body turns: the comparison is not of zeros
}

}  // namespace
}  // namespace momenta
