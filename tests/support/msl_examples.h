#pragma once
// What the MSL conformance tests (tests/msl/) share besides the tube (tests/support/msl_tube.h):
// where an example's model lives, how its test is named, and how its reference's times were written.

#include <string>

#include "tests/support/msl_tube.h"
#include "tests/support/test_models.h"

namespace momenta::testing {

/// models/msl/<the name without a leading "Modelica.", dots as folders>.yaml
/// (Modelica.Mechanics.MultiBody.Examples.Elementary.Pendulum ->
/// models/msl/Mechanics/MultiBody/Examples/Elementary/Pendulum.yaml; ModelicaTest.MultiBody.Forces.Damper ->
/// models/msl/ModelicaTest/MultiBody/Forces/Damper.yaml).
std::string MslModelFile(const std::string& name);

/// A test's name for the example: the name without a leading "Modelica.", dots as underscores.
std::string MslTestName(const std::string& name);

/// Whether `relative` (to the source tree) exists.
bool SourceExists(const std::string& relative);

/// Whether the reference's times were written in single precision, as the EddyCurrentBrake's are
/// (0.0044999998 for 0.0045, no row of ours there): every time has at most 9 significant digits
/// (a float's), and some differ from their 7-digit rounding (the float's noise). A double-precision
/// reference's event times have 17 digits (0.37588609721210020); one whose every time is a short
/// decimal of the grid (0.0015) has no noise, and is matched as it always was.
bool SinglePrecisionTimes(const Csv& ref);

/// Dymola's accepted steps, state events and time events in the reference run.
struct DymolaFigures {
  long steps;
  int state_events, time_events;
};

/// Runs the example's model (models/msl/...) with its own experiment against `reference_csv`
/// (relative to the source tree) in `tube`, and prints its steps and events beside Dymola's.
void CheckMslExample(const std::string& name, const std::string& model, const std::string& reference_csv,
                     TubeWidth tube, const DymolaFigures& dymola);

}  // namespace momenta::testing
