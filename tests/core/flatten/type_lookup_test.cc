// Which type a name finds when a model's own types are qualified (docs/FORMAT.md, "Library and
// define: entries"): a full name first, the model's own before the library's; a short name only
// when no type has it as its full name. A model's own `Local.Feedback` therefore leaves
// `Feedback` to the library's Blocks type, and a type `Local.Resistor` can hold a library
// `Resistor` (the MSL's Examples.Utilities.Resistor does), while `Cell` still finds `Local.Cell`.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

constexpr const char* kQualifiedOwnTypes = R"(model: QualifiedOwnTypes
define:
  Local.Feedback:
    doc: a resistor pair with the name of a Blocks type's last part
    connectors: {p: Pin, n: Pin}
    components:
      r1: {type: Resistor, R: 1}
      r2: {type: Resistor, R: 1}
    connections:
      - [p, r1.p]
      - [r1.n, r2.p]
      - [r2.n, n]
  Local.Resistor:
    doc: holds the library's Resistor, as the MSL's Examples.Utilities.Resistor does
    parameters: {R: 1}
    connectors: {p: Pin, n: Pin}
    components:
      resistor: {type: Resistor, R: R}
    connections:
      - [p, resistor.p]
      - [resistor.n, n]
  Local.Cell:
    doc: found by its last part, which no other type has
    connectors: {p: Pin, n: Pin}
    components:
      r: {type: Resistor, R: 4}
    connections:
      - [p, r.p]
      - [r.n, n]
components:
  source: {type: ConstantVoltage, V: 6}
  pair: {type: Local.Feedback}
  own: {type: Local.Resistor, R: 2}
  cell: {type: Cell}
  ground: {type: Ground}
  one: {type: Constant, k: 3}
  two: {type: Constant, k: 1}
  difference: {type: Feedback}
connections:
  - [source.p, pair.p]
  - [pair.n, own.p]
  - [own.n, cell.p]
  - [cell.n, ground.p]
  - [source.n, ground.p]
  - [one.y, difference.u1]
  - [two.y, difference.u2]
experiment: {stop: 1, interval: 0.5}
outputs: [source.i, own.resistor.v, difference.y]
)";

TEST(TypeLookup, AModelsQualifiedTypesLeaveTheLibrarysShortNamesAlone) {
  testing::Built b = testing::BuildYaml(kQualifiedOwnTypes);
  testing::Trajectory tr = testing::RunDefault(b);
  ASSERT_FALSE(tr.t.empty());
  for (size_t r = 0; r < tr.t.size(); ++r) {
    // 6 V over 1 + 1 + 2 + 4 Ohm: 0.75 A from p through the source to n is -0.75 A.
    EXPECT_NEAR(tr.Column("source.i", r), -0.75, 1e-12);
    EXPECT_NEAR(tr.Column("own.resistor.v", r), 1.5, 1e-12);
    // Feedback is Blocks' y = u1 - u2.
    EXPECT_NEAR(tr.Column("difference.y", r), 2, 1e-12);
  }
}

}  // namespace
}  // namespace momenta
