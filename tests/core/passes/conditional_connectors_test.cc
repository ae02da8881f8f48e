// Conditional connectors (core/passes/conditional_connectors.h, docs/FORMAT.md "Conditional
// connectors"): a connector declared with `condition: useHeatPort` exists only when that Boolean
// parameter is true. Absent, its component works as if it had never been declared (the equations
// naming it are left out, its variables drop out); connecting it, or naming its variables in a
// model equation or output, is an error naming the component and the parameter; the parameter
// fixes the structure.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/base/error.h"
#include "core/compile/model_state.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::BuildError;
using testing::Built;
using testing::Trajectory;

/// A mass on a damper (d = 2) from a wall, thrown at 1 m/s; `damper` adds keys to the damper's
/// entry, `more` adds components and connections.
std::string DamperYaml(const std::string& damper, const std::string& more_components = "",
                       const std::string& more_connections = "", const std::string& outputs = "[mass.v]") {
  return R"(model: Thrown
components:
  wall: {type: Fixed}
  damper: {type: Damper, d: 2)" + damper + R"(}
  mass: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
)" + more_components + R"(connections:
  - [wall.flange, damper.flange_a]
  - [damper.flange_b, mass.flange_a]
)" + more_connections + R"(experiment: {stop: 1, tolerance: 1e-10, interval: 0.01}
outputs: )" + outputs + "\n";
}

// Present or absent, the mechanics are the same: v = e^(-2t). Absent, the heat port's two
// variables drop out as constants, as if the damper had none (the same number of unknowns as a
// Damper written without it: compared through the build report's alias counts is brittle, so
// through the solution and the heat the capacitor receives).
TEST(ConditionalConnectorsTest, AbsentOrPresentTheMechanicsAgree) {
  Built absent = testing::BuildYaml(DamperYaml(""));
  EXPECT_TRUE(absent.report.warnings.empty());
  Built present = testing::BuildYaml(DamperYaml(", useHeatPort: true", "  heat: {type: HeatCapacitor, C: 1, T: {start: 300, fixed: true}}\n",
                                                "  - [damper.heatPort, heat.port]\n", "[mass.v, heat.T, damper.heatPort.Q_flow]"));
  EXPECT_TRUE(present.report.warnings.empty());
  Trajectory a = testing::RunDefault(absent), p = testing::RunDefault(present);
  ASSERT_EQ(a.t.size(), p.t.size());
  for (size_t k = 0; k < a.t.size(); ++k) {
    const double v = std::exp(-2 * a.t[k]);
    EXPECT_NEAR(a.Column("mass.v", k), v, 1e-8);
    EXPECT_NEAR(p.Column("mass.v", k), v, 1e-8);
    // The heat is the kinetic energy lost: (1 - v^2)/2 J into C = 1 J/K.
    EXPECT_NEAR(p.Column("heat.T", k), 300 + (1 - v * v) / 2, 1e-7);
    EXPECT_NEAR(p.Column("damper.heatPort.Q_flow", k), -2 * v * v, 1e-7);
  }
}

TEST(ConditionalConnectorsTest, ConnectingAnAbsentConnectorIsAnError) {
  std::string msg = BuildError(DamperYaml("", "  heat: {type: HeatCapacitor, C: 1}\n", "  - [damper.heatPort, heat.port]\n"));
  EXPECT_NE(msg.find("test.yaml:10:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot connect damper.heatPort: damper (Damper) has the connector heatPort only when "
                     "useHeatPort is true, and damper.useHeatPort is false; set useHeatPort: true in damper's entry"),
            std::string::npos)
      << msg;
  // The same when a model parameter sets the condition to false.
  std::string yaml = DamperYaml(", useHeatPort: withHeat", "  heat: {type: HeatCapacitor, C: 1}\n",
                                "  - [damper.heatPort, heat.port]\n");
  yaml.insert(yaml.find("components:"), "parameters: {withHeat: {value: false, type: Boolean}}\n");
  msg = BuildError(yaml);
  EXPECT_NE(msg.find("damper.useHeatPort is false"), std::string::npos) << msg;
  EXPECT_EQ(BuildError(yaml, {{"withHeat", 1}}), "");
}

TEST(ConditionalConnectorsTest, NamingAnAbsentConnectorsVariablesIsAnError) {
  std::string msg = BuildError(DamperYaml("", "", "", "[mass.v, damper.heatPort.T]"));
  EXPECT_NE(msg.find("the output 'damper.heatPort.T' names damper.heatPort.T, but damper has no connector heatPort "
                     "(damper.useHeatPort is false)"),
            std::string::npos)
      << msg;
  std::string yaml = DamperYaml("", "", "", "[mass.v, q]");
  yaml.insert(yaml.find("experiment:"), "variables: {q: {unit: W}}\nequations: [\"q = damper.heatPort.Q_flow\"]\n");
  msg = BuildError(yaml);
  EXPECT_NE(msg.find("the equation 'q = damper.heatPort.Q_flow' names damper.heatPort.Q_flow, but damper has no "
                     "connector heatPort"),
            std::string::npos)
      << msg;
}

TEST(ConditionalConnectorsTest, TheConditionFixesTheStructure) {
  Built b = testing::BuildYaml(DamperYaml(""));
  ModelState state(b.model);
  try {
    state.SetParameters({{"damper.useHeatPort", 1}});
    FAIL() << "expected an error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("damper.useHeatPort shapes the model's structure"), std::string::npos) << e.what();
  }
}

TEST(ConditionalConnectorsTest, TheConditionIsABooleanParameterOfTheType) {
  const std::string head = "model: Bad\ndefine:\n  Leaky:\n    parameters: {useIt: {value: 1, type: Integer}, on: {value: true, type: Boolean}}\n";
  std::string msg = BuildError(head + R"(    connectors:
      flange: Flange
      heatPort: {type: HeatPort, condition: useIt}
    equations: ["flange.s = 0", "heatPort.T = 300"]
components:
  leak: {type: Leaky}
)");
  EXPECT_NE(msg.find("the condition of connector Leaky.heatPort must be a Boolean parameter of Leaky, found 'useIt' "
                     "(a Integer parameter) (Boolean parameters: on)"),
            std::string::npos)
      << msg;
  msg = BuildError(head + R"(    connectors:
      heatPort: {type: HeatPort, condition: missing}
    equations: ["heatPort.T = 300"]
components:
  leak: {type: Leaky}
)");
  EXPECT_NE(msg.find("found 'missing' (Boolean parameters: on)"), std::string::npos) << msg;
  // A type with parts may make its own connectors conditional: absent, its connections to its
  // parts vanish (docs/FORMAT.md, "Conditional parts").
  for (const char* on : {"true", "false"}) {
    msg = BuildError(head + R"(    connectors:
      flange: {type: Flange, condition: on}
    components:
      mass: {type: Mass, s: {start: 0, fixed: true}, v: {start: 0, fixed: true}}
    connections:
      - [flange, mass.flange_a]
components:
  leak: {type: Leaky, on: )" + on + R"(}
outputs: [leak.mass.s]
)");
    EXPECT_EQ(msg, "") << "on: " << on;
  }
}

// A part's conditional connector inside a composite: absent by default (the Cell of
// docs/FORMAT.md builds as before), present when the composite sets the condition and connects it,
// and an error when the composite connects it while absent.
TEST(ConditionalConnectorsTest, PartsOfACompositeType) {
  auto cell = [](const std::string& damper_keys, const std::string& more_parts, const std::string& more_connections) {
    return R"(model: Cells
define:
  Cell:
    parameters: {x0: 0.1}
    connectors: {flange: Flange}
    components:
      mass: {type: Mass, m: 1, s: {start: x0, fixed: true}, v: {start: 0, fixed: true}}
      spring: {type: SpringDamper, c: 100, d: 2)" + damper_keys + R"(}
)" + more_parts + R"(    connections:
      - [flange, spring.flange_a]
      - [spring.flange_b, mass.flange_a]
)" + more_connections + R"(components:
  wall: {type: Fixed}
  cell: {type: Cell}
connections:
  - [wall.flange, cell.flange]
experiment: {stop: 5, tolerance: 1e-10, interval: 0.01}
outputs: [cell.mass.v]
)";
  };
  EXPECT_EQ(BuildError(cell("", "", "")), "");
  const std::string heat = "      heat: {type: HeatCapacitor, C: 10, T: {start: 300, fixed: true}}\n";
  const std::string joined = "      - [spring.heatPort, heat.port]\n";
  std::string yaml = cell(", useHeatPort: true", heat, joined);
  yaml.replace(yaml.find("outputs: [cell.mass.v]"), 23,
               "outputs: [\"0.5 - (0.5*cell.mass.m*cell.mass.v^2 + 0.5*cell.spring.c*cell.spring.s_rel^2) - cell.heat.C*(cell.heat.T - 300)\"]");
  Trajectory tr = testing::RunDefault(testing::BuildYaml(yaml));
  for (size_t k = 0; k < tr.t.size(); ++k) EXPECT_NEAR(tr.values[k][0], 0, 3e-6) << "t = " << tr.t[k];
  std::string msg = BuildError(cell("", heat, joined));
  EXPECT_NE(msg.find("cannot connect cell.spring.heatPort: cell.spring (SpringDamper) has the connector heatPort only "
                     "when useHeatPort is true, and cell.spring.useHeatPort is false"),
            std::string::npos)
      << msg;
}

// A conditional signal input (EddyCurrentForce's excitation): absent, the component uses its
// parameter and the input may not be connected; present, it must be.
TEST(ConditionalConnectorsTest, ConditionalSignalInput) {
  auto brake = [](const std::string& keys, const std::string& connections) {
    return R"(model: Brake
components:
  brake: {type: EddyCurrentForce, f_nominal: 10, v_nominal: 1)" + keys + R"(}
  mass: {type: Mass, m: 1, s: {start: 0, fixed: true}, v: {start: 1, fixed: true}}
  one: {type: Constant, k: 0.5}
connections:
  - [brake.flange, mass.flange_a]
)" + connections + R"(experiment: {stop: 1}
outputs: [brake.exc]
)";
  };
  EXPECT_EQ(BuildError(brake("", "")), "");
  EXPECT_EQ(BuildError(brake(", useExcitationInput: true", "  - [one.y, brake.excitation]\n")), "");
  std::string msg = BuildError(brake("", "  - [one.y, brake.excitation]\n"));
  EXPECT_NE(msg.find("cannot connect brake.excitation: brake (EddyCurrentForce) has the connector excitation only "
                     "when useExcitationInput is true"),
            std::string::npos)
      << msg;
  msg = BuildError(brake(", useExcitationInput: true", ""));
  EXPECT_NE(msg.find("brake.excitation"), std::string::npos) << msg;
  EXPECT_NE(msg.find("connect it to an output"), std::string::npos) << msg;
  Trajectory tr = testing::RunDefault(testing::BuildYaml(brake(", useExcitationInput: true", "  - [one.y, brake.excitation]\n")));
  EXPECT_EQ(tr.Column("brake.exc", 0), 0.5);
  tr = testing::RunDefault(testing::BuildYaml(brake(", constantExcitation: 0.25", "")));
  EXPECT_EQ(tr.Column("brake.exc", 0), 0.25);
}

}  // namespace
}  // namespace momenta
