// What the MSL conformance tests share (tests/support/msl_examples.h).

#include "tests/support/msl_examples.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace momenta::testing {

namespace {

/// The name without a leading "Modelica." with every dot replaced by `sep`.
std::string Flattened(const std::string& name, char sep) {
  std::string rest = name.rfind("Modelica.", 0) == 0 ? name.substr(9) : name;
  for (char& c : rest) {
    if (c == '.') c = sep;
  }
  return rest;
}

/// `t` rounded to `digits` significant decimal digits.
double Rounded(double t, int digits) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, t);
  return std::strtod(text, nullptr);
}

}  // namespace

std::string MslModelFile(const std::string& name) { return "models/msl/" + Flattened(name, '/') + ".yaml"; }

std::string MslTestName(const std::string& name) { return Flattened(name, '_'); }

bool SourceExists(const std::string& relative) { return std::filesystem::exists(SourcePath(relative)); }

bool SinglePrecisionTimes(const Csv& ref) {
  bool noisy = false;
  for (const auto& row : ref.rows) {
    const double t = row[0];
    if (Rounded(t, 9) != t) return false;
    noisy = noisy || Rounded(t, 7) != t;
  }
  return noisy;
}

void CheckMslExample(const std::string& name, const std::string& model, const std::string& reference_csv,
                     TubeWidth tube, const DymolaFigures& dymola) {
  TubeCheck check;
  check.rtol = 0;  // the example's own (1e-6 unless it says otherwise)
  check.tube = tube;
  const Csv ref = ReadCsv(SourcePath(reference_csv));
  check.single_precision = SinglePrecisionTimes(ref);
  SolverStats stats;
  CheckAgainstReference(name, model, ref, check, &stats);
  std::printf("[   INFO   ] %s: %ld steps, %ld state events, %ld time events (Dymola: %ld, %d, %d)\n", name.c_str(),
              stats.steps, stats.events - stats.time_events, stats.time_events, dymola.steps, dymola.state_events,
              dymola.time_events);
}

}  // namespace momenta::testing
