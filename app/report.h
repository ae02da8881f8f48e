#pragma once
/// The HTML report (README, "Reports"): one self-contained page with the model's name, doc and
/// parameters, build and solver statistics, interactive plots of the outputs (uPlot) and, when the
/// model's parts declare an animation, the scene drawn from the recorded positions (planar on a
/// canvas, 3-D with three.js).

#include <string>
#include <utility>
#include <vector>

#include "app/report_scene.h"

namespace momenta {

struct ReportParameter {
  std::string name, unit, doc;
  double value = 0;
};

/// A section of label/value lines (build passes, solver statistics).
using ReportTable = std::vector<std::pair<std::string, std::string>>;

/// Everything a report shows. Columns are stored column by column; the first `num_plotted` are
/// the model's outputs (plotted), the rest hold the scene's quantities.
struct ReportData {
  std::string model_name, model_file, doc, result_file;
  std::vector<ReportParameter> parameters;
  ReportTable build, solver;
  std::vector<std::string> columns;
  std::vector<std::string> units;  ///< per column; "" when not known
  size_t num_plotted = 0;
  std::vector<double> time;
  std::vector<std::vector<double>> values;  ///< values[column][row]
  Scene scene;
  std::vector<std::string> notes;  ///< shown at the top of the page

  /// Appends one row (time, then every column).
  void Row(double t, const std::vector<double>& v);
  /// Times at which the run has an event: two rows at the same time (left and right limits).
  std::vector<double> EventTimes() const;
};

/// Rows beyond this are thinned for the page (every k-th row, event rows and the last kept).
constexpr size_t kMaxReportRows = 20000;

/// True when the build embedded uPlot (scripts/setup.sh fetched it); without it the page has
/// every table and the scene, and a note in place of the plots.
bool ReportHasPlots();

/// True when the build embedded three.js (scripts/setup.sh fetched it); without it a page with a
/// 3-D scene says so in the scene's place.
bool ReportHasThree();

/// Appends `text` as a JSON string to `*out`; `<` is written `\u003c`, so the data cannot end the
/// page's <script> element.
void JsonString(const std::string& text, std::string* out);

/// The page's HTML text.
std::string ReportHtml(const ReportData& data);

/// Writes the page's text to `path`; throws ResultWriteError naming the file when it cannot be
/// written.
void WriteReport(const std::string& path, const std::string& html);

}  // namespace momenta
