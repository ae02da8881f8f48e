#pragma once
/// `momenta simulate --report` and `momenta report RESULT --model MODEL`: the HTML report
/// (app/report.h) from a run as it happens, or from a result file written before.

#include <string>
#include <vector>

#include "app/commands.h"
#include "app/report.h"
#include "solver/simulator.h"

namespace momenta {

struct ReportArgs {
  std::string result;               ///< a CSV or MAT result written by simulate
  std::string model;                ///< the model file it was simulated from
  std::vector<std::string> params;  ///< the -p values it was simulated with
  std::string out;                  ///< empty: <result stem>.html
};

int RunReport(const ReportArgs& args);

/// The model's part of a report: name, doc, parameters and their values, build statistics.
ReportData ReportFromModel(const std::string& model_path, const LoadedModel& loaded);

/// Adds a run's options and solver statistics.
void AddRunStats(const SimulationOptions& options, const SolverStats& stats, ReportData* data);

/// Writes the report and sets `*summary` to a line with its path, size and time to write;
/// returns kExitOk, or kExitSolver after printing why it could not be written.
int SaveReport(const std::string& path, const ReportData& data, std::string* summary);

}  // namespace momenta
