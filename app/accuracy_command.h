#pragma once
/// `momenta accuracy MODEL [-p NAME=VALUE]... [--rtol 1e-3:1e-10] [--reference FILE]`: the model
/// run at a range of tolerances, each run's error against a reference and its cost, printed as the
/// work-precision table and drawn with gnuplot (app/plot.h), optionally into the HTML report.

#include <string>
#include <vector>

#include "app/result_reader.h"

namespace momenta {

struct AccuracyArgs {
  std::string model;
  std::vector<std::string> params;  ///< -p NAME=VALUE
  std::string rtol = "1e-3:1e-10";  ///< LOOSE:TIGHT, a decade apart
  std::string reference;            ///< a result file; empty: a run at a tighter tolerance
  std::string out;                  ///< the plot (.svg or .png); empty: <model stem>.accuracy.svg
  std::string table;                ///< the table as CSV; empty: none
  std::string report;               ///< the HTML report; empty: none
};

int RunAccuracy(const AccuracyArgs& args);

/// The tolerances of "LOOSE:TIGHT" (or one tolerance), a decade apart from the loose one down to
/// the tight one. Throws UsageError naming --rtol when the text is not that, a tolerance is not
/// from 1e-14 to below 1, or the range holds more than 15 decades.
std::vector<double> ToleranceRange(const std::string& text);

/// The error of a run against `reference`: the largest over the columns compared (`columns[k]`
/// of the run against `ref_columns[k]` of the reference) and over the run's rows of
/// |y - y_ref(t)| / s, where y_ref(t) is the reference interpolated linearly in time and s the
/// largest |y_ref| of the column (1 where it is 0). Rows at an event (two rows at one time, in
/// either result) and outside the reference's time span are left out. NaN when no row is compared.
double ResultError(const ResultTable& run, const std::vector<size_t>& columns, const ResultTable& reference,
                   const std::vector<size_t>& ref_columns);

}  // namespace momenta
