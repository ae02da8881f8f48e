// The passes before Pantelides' algorithm, run as the build runs them, for the pass tests
// (tests/support/reduced_system.h).

#include "tests/support/reduced_system.h"

#include <gtest/gtest.h>

#include "core/flatten/flatten.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "core/passes/discrete_partition.h"

namespace momenta::testing {

uint32_t ReducedSystem::Var(const std::string& name) const {
  const FlatSystem& f = *sys.flat;
  for (uint32_t k = 0; k < f.variables.size(); ++k) {
    if (f.VariableName(VarId(k)) == name) return k;
  }
  ADD_FAILURE() << "no variable " << name;
  return 0;
}

ReducedSystem Reduce(const std::string& yaml) {
  ReducedSystem r;
  ModelSpec spec = LoadModelString(yaml, "test.yaml");
  r.flat = std::make_shared<FlatSystem>(Flatten(spec, BuiltinLibrary(), {}));
  r.sys = MakeEquationSystem(r.flat);
  for (int round = 0; round < 20; ++round) {
    size_t before = r.sys.num_unknowns(), der_before = r.index.derivative_aliases;
    r.sys = EliminateAliases(std::move(r.sys), &r.alias);
    r.sys = ReduceIndex(std::move(r.sys), &r.index);
    if (r.sys.num_unknowns() == before && r.index.derivative_aliases == der_before) break;
  }
  return r;
}

ReducedSystem ReduceForPantelides(const std::string& yaml) {
  ReducedSystem r = Reduce(yaml);
  DiscreteStats discrete;
  r.sys = PartitionDiscrete(std::move(r.sys), &discrete);
  return r;
}

const char* const kCartesianPendulum = R"(
model: CartesianPendulum
define:
  Pendulum:
    parameters:
      L: {value: 1, unit: m}
      g: {value: 9.81, unit: m/s2}
      m: {value: 1, unit: kg}
      theta0: {value: 0.5, unit: rad}
    variables:
      x: {unit: m, start: L*sin(theta0), fixed: true}
      y: {unit: m, start: -L*cos(theta0)}
      vx: {unit: m/s, start: 0, fixed: true}
      vy: {unit: m/s, start: 0}
      F: {unit: N, start: m*g}
    equations:
      - der(x) = vx
      - der(y) = vy
      - m*der(vx) = -x*F/L
      - m*der(vy) = -y*F/L - m*g
      - x^2 + y^2 = L^2
components:
  pendulum: {type: Pendulum}
experiment: {stop: 1, tolerance: 1e-8, interval: 0.01}
outputs: [pendulum.x, pendulum.y, pendulum.vx, pendulum.vy, pendulum.F]
)";

}  // namespace momenta::testing
