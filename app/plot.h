#pragma once
/// `momenta plot RESULT -y A,B [-o plot.svg|png]`: a plot of chosen columns of a result file for
/// documents, drawn by gnuplot (Debian's gnuplot-nox): SVG through its svg terminal, PNG through
/// pngcairo; events (two rows at one time) are dashed vertical lines.

#include <string>
#include <vector>

namespace momenta {

struct PlotArgs {
  std::string result;
  std::vector<std::string> columns;  ///< -y, comma-separated names gathered
  std::string out;                   ///< empty: <result stem>.svg
  std::string title;
  int width = 900;  ///< pixels; the height is 5/9 of it
};

/// Writes the plot; returns the exit code (2 for a bad column or file name, 3 when gnuplot is
/// missing or fails) after printing what went wrong.
int RunPlot(const PlotArgs& args);

/// Runs gnuplot ($MOMENTA_GNUPLOT, else gnuplot on the PATH; no shell) on `script`, its standard
/// output into `out` (opened here: no file name reaches gnuplot), its messages kept; "" on
/// success, else what went wrong (the image is then removed).
std::string RunGnuplot(const std::string& script, const std::string& out);

/// `text` as one line of a script's text block: a control character is written as visible text
/// (`\x0a`), so the line cannot end early (user text never stands in a gnuplot command).
std::string GnuplotTextLine(const std::string& text);

/// The gnuplot program that draws `columns` of the result (exposed for tests).
std::string GnuplotScript(const PlotArgs& args, const std::string& out_path);

}  // namespace momenta
