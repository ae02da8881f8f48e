// Variable attributes set per component entry (docs/FORMAT.md, "Model files"): `nominal`, `min`
// and `max` beside `start`, `fixed` and `stateSelect`, as the MSL's modifiers
// (`w_rel(nominal=1e-4)`).
//
// The accuracy case: an undamped torsional oscillator J phi'' + c phi = 0 with J = c = 1 and
// phi(0) = 1e-4 rad, w(0) = 0, so phi = 1e-4 cos(t), w = -1e-4 sin(t), run over 20 s (about three
// periods) at the default tolerances (rtol = atol = 1e-6). IDA keeps each local error below
// rtol*|x| + atol*nominal: with the default nominal 1 the absolute part, 1e-6, is 1 % of the
// signal, and over three periods the error grows to several times that; with `nominal: 1e-4` on
// phi and w it is 1e-10, and the relative part rules.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/physics_checks.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildClean;
using testing::BuildError;
using testing::MaxError;
using testing::Trajectory;

/// The oscillator, with `attributes` appended to the inertia's phi and w entries (e.g.
/// ", nominal: 1e-4").
std::string SmallOscillator(const std::string& attributes) {
  return R"(model: SmallOscillator
components:
  fixed: {type: Rotational.Fixed}
  spring: {type: Rotational.Spring, c: 1}
  inertia: {type: Inertia, J: 1, phi: {start: 1e-4, fixed: true)" +
         attributes + R"(}, w: {start: 0, fixed: true)" + attributes + R"(}}
connections:
  - [fixed.flange, spring.flange_a]
  - [spring.flange_b, inertia.flange_a]
experiment: {stop: 20, interval: 0.01}
outputs: [inertia.phi]
)";
}

/// The same oscillator as a composite type whose part carries the attributes.
std::string SmallOscillatorComposite(const std::string& attributes) {
  return R"(model: SmallOscillatorComposite
define:
  Oscillator:
    components:
      fixed: {type: Rotational.Fixed}
      spring: {type: Rotational.Spring, c: 1}
      inertia: {type: Inertia, J: 1, phi: {start: 1e-4, fixed: true)" +
         attributes + R"(}, w: {start: 0, fixed: true)" + attributes + R"(}}
    connections:
      - [fixed.flange, spring.flange_a]
      - [spring.flange_b, inertia.flange_a]
components:
  osc: {type: Oscillator}
experiment: {stop: 20, interval: 0.01}
outputs: [osc.inertia.phi]
)";
}

double RelativeError(const std::string& yaml, const std::string& column) {
  Trajectory tr = testing::RunDefault(BuildClean(yaml));
  return MaxError(tr, column, [](double t) { return 1e-4 * std::cos(t); }) / 1e-4;
}

TEST(InstanceAttributes, NominalOfAComponentEntryScalesTheAbsoluteTolerance) {
  // Observed: 5.9e-2 of the amplitude with nominal 1, 5.6e-6 with nominal 1e-4 (both as a
  // model's entry and as a composite's part). The bounds sit between the two, a factor of five
  // or more from each: the first must stay coarse, the second fine.
  const double coarse = RelativeError(SmallOscillator(""), "inertia.phi");
  const double fine = RelativeError(SmallOscillator(", nominal: 1e-4"), "inertia.phi");
  EXPECT_GT(coarse, 1e-2);
  EXPECT_LT(fine, 3e-5);
  const double fine_part = RelativeError(SmallOscillatorComposite(", nominal: 1e-4"), "osc.inertia.phi");
  const double coarse_part = RelativeError(SmallOscillatorComposite(""), "osc.inertia.phi");
  EXPECT_GT(coarse_part, 1e-2);
  EXPECT_LT(fine_part, 3e-5);
}

TEST(InstanceAttributes, MinAndMaxAreAccepted) {
  EXPECT_EQ(BuildError(SmallOscillator(", min: -1, max: 1")), "");
  EXPECT_EQ(BuildError(SmallOscillator(", max: 0.5")), "");
}

TEST(InstanceAttributes, BadValuesAreNamedWithTheirPlace) {
  // Line 5 is the inertia's entry; the columns are those of the offending value (of the key, for an
  // unknown key) in phi's mapping.
  EXPECT_EQ(BuildError(SmallOscillator(", nominal: 0")),
            "test.yaml:5:75: inertia.phi.nominal must be a positive number (the variable's typical magnitude), "
            "found 0");
  EXPECT_EQ(BuildError(SmallOscillator(", nominal: -1e-4")),
            "test.yaml:5:75: inertia.phi.nominal must be a positive number (the variable's typical magnitude), "
            "found -1e-4");
  EXPECT_EQ(BuildError(SmallOscillator(", nominal: .nan")),
            "test.yaml:5:75: inertia.phi.nominal must be a finite number, found '.nan'");
  EXPECT_EQ(BuildError(SmallOscillator(", nominal: small")),
            "test.yaml:5:75: inertia.phi.nominal must be a decimal number, found 'small'");
  EXPECT_EQ(BuildError(SmallOscillator(", min: 1, max: -1")),
            "test.yaml:5:79: inertia.phi.max = -1 is below its min = 1");
  EXPECT_EQ(BuildError(SmallOscillator(", min: [0]")),
            "test.yaml:5:71: inertia.phi.min must be a single value, not a list or mapping");
  const std::string unknown = BuildError(SmallOscillator(", nominl: 1"));
  EXPECT_NE(unknown.find("test.yaml:5:66: unknown key 'nominl' in inertia.phi (valid keys: start, fixed, nominal, "
                         "min, max, stateSelect)"),
            std::string::npos)
      << unknown;
}

}  // namespace
}  // namespace momenta
