#pragma once
/// The structure of the initialisation system [F(t0, y, y') = 0; G = 0] (unknowns y and the
/// states' y'): which fixed start values and initial equations G are redundant, and which start
/// values must stand in for missing initial conditions.
///
/// - Too many (Dulmage–Mendelsohn over-determined part): the conditions are taken in declaration
///   order, each kept while it still determines something; the others are redundant — they
///   follow from the kept ones and the model's equations (a pendulum's x and y fixed, with
///   x^2 + y^2 = L^2). They are left out of the system, and initialisation checks that they hold
///   at its solution (consistent: accepted with a note, as OpenModelica does; inconsistent: an
///   error naming them and the equations).
/// - Too few (under-determined part): as Modelica tools do, the start values of states complete
///   them, with a warning giving the number of degrees of freedom and naming the variables; after
///   index reduction the variables whose derivatives became dummy (a mechanism's positions and
///   velocities, what a user would fix) are taken before the internal states of state sets.

#include <string>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/passes/equation_system.h"

namespace momenta {

struct InitialConditionPlan {
  std::vector<uint32_t> redundant;          ///< indices into m.initial_exprs, ascending
  std::vector<std::string> redundant_from;  ///< for each: what it follows from, one item a line
  std::vector<uint32_t> defaulted;          ///< y indices whose start values are taken as fixed
};

/// `y_of_var`: flat variable -> y index (-1: none); `state_of_y`: y index -> state slot (-1).
/// Throws ModelError when unknowns remain undetermined.
InitialConditionPlan PlanInitialConditions(const EquationSystem& sys, const CompiledModel& m,
                                           const std::vector<int32_t>& y_of_var,
                                           const std::vector<int32_t>& state_of_y);

}  // namespace momenta
