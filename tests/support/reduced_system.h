#pragma once
// A model's equation system as the build has it before Pantelides' algorithm, for the tests of
// the passes that follow flattening (index reduction, Pantelides, dummy derivatives).

#include <memory>
#include <string>

#include "core/flatten/flat_system.h"
#include "core/passes/alias_elimination.h"
#include "core/passes/equation_system.h"
#include "core/passes/index_reduction.h"

namespace momenta::testing {

/// A flattened model and its equation system after some passes.
struct ReducedSystem {
  std::shared_ptr<FlatSystem> flat;  ///< as flattened (the system may have extended a copy)
  EquationSystem sys;
  AliasStats alias;
  IndexStats index;
  /// The flat variable named `name` in the system's flat system (a test failure when none).
  uint32_t Var(const std::string& name) const;
  VarRole role(const std::string& name) const { return sys.role[Var(name)]; }
};

/// Flattens the inline model, then eliminates aliases and reduces the index in rounds until
/// nothing changes (as BuildModel does).
ReducedSystem Reduce(const std::string& yaml);

/// Reduce, and the discrete equations set apart: the system Pantelides' algorithm takes.
ReducedSystem ReduceForPantelides(const std::string& yaml);

/// A point mass on a rod in Cartesian coordinates (models/pendulum_cartesian.yaml): the rod's
/// constraint x^2 + y^2 = L^2 between two states makes it of index 3.
extern const char* const kCartesianPendulum;

}  // namespace momenta::testing
