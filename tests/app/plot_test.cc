// `momenta plot RESULT -y A,B -o FILE.svg|png`: the image is written through gnuplot and is valid
// (the SVG is a complete document holding each series by name and a curve per series; the PNG
// decodes with libpng to the asked size and is not blank), from a CSV and from a MAT result; bad
// column names and extensions are reported by their messages.

#include "app/plot.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/png_image.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::ReadText;
using testing::RunMomenta;
using testing::SourcePath;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class PlotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
      GTEST_SKIP()
          << "gnuplot is not installed (Debian package gnuplot-nox; scripts/setup.sh installs it)";
    }
    csv_ = dir_.File("carriers.csv");
    CliResult r = RunMomenta(
        {"simulate", SourcePath("models/carrier_collision.yaml"), "-o", csv_, "-q"}, dir_.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  TempDir dir_;
  std::string csv_;
};

TEST_F(PlotTest, SvgIsACompleteDocumentWithOneCurvePerSeries) {
  const std::string svg = dir_.File("v.svg");
  CliResult r = RunMomenta({"plot", csv_, "-y", "B.v,S.v", "-y", "A.v", "-o", svg}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = ReadText(svg);
  ASSERT_TRUE(Contains(text, "<svg")) << text.substr(0, 500);
  EXPECT_TRUE(Contains(text.substr(text.size() - 200), "</svg>"));
  // The key names each series; gnuplot draws each curve in a group of its own.
  for (const char* name : {"B.v", "S.v", "A.v"})
    EXPECT_TRUE(Contains(text, std::string("<text>") + name + "</text>")) << name;
  const std::regex curve("<g id=\"gnuplot_plot_([0-9]+)\"");
  size_t curves =
      std::distance(std::sregex_iterator(text.begin(), text.end(), curve), std::sregex_iterator());
  EXPECT_EQ(curves, 3u);
  // The carriers collide at events: dashed lines mark them.
  EXPECT_TRUE(Contains(text, "stroke-dasharray")) << "no event line";
}

TEST_F(PlotTest, PngDecodesToTheAskedSizeAndIsNotBlank) {
  const std::string png = dir_.File("v.png");
  CliResult r =
      RunMomenta({"plot", csv_, "-y", "B.v,S.v", "-o", png, "--width", "720"}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const testing::PngImage img = testing::ReadPng(png);
  ASSERT_TRUE(img.ok) << img.error;
  EXPECT_EQ(img.width, 720u);
  EXPECT_EQ(img.height, 400u);
  // Two coloured curves, axes and labels, antialiased: many colours, and well over 1 % drawn.
  EXPECT_GT(img.CountColours(), 32u);
  EXPECT_GT(img.CountNotBackground(), img.width * img.height / 100);
}

TEST_F(PlotTest, MatResultPlotsTheSameSeries) {
  const std::string mat = dir_.File("carriers.mat"), svg = dir_.File("m.svg");
  ASSERT_EQ(RunMomenta({"simulate", SourcePath("models/carrier_collision.yaml"), "-o", mat, "-q"},
                       dir_.path())
                .exit_code,
            0);
  CliResult r = RunMomenta({"plot", mat, "-y", "S.v", "-o", svg}, dir_.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(ReadText(svg), "<text>S.v</text>"));
  // The same numbers reach gnuplot from either file.
  PlotArgs a{csv_, {"S.v"}, svg, "t"}, b{mat, {"S.v"}, svg, "t"};
  EXPECT_EQ(GnuplotScript(a, svg), GnuplotScript(b, svg));
}

TEST_F(PlotTest, BadColumnsAndExtensionsAreNamed) {
  CliResult r = RunMomenta({"plot", csv_, "-y", "B.vv", "-o", dir_.File("x.svg")}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "the result has no column 'B.vv' (did you mean B.v")) << r.err;
  EXPECT_TRUE(Contains(r.err, "valid: A.v, B.v, S.v")) << r.err;
  r = RunMomenta({"plot", csv_, "-y", "B.v", "-o", dir_.File("x.pdf")}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "chosen by the extension (.svg or .png)")) << r.err;
  r = RunMomenta({"plot", dir_.File("none.csv"), "-y", "B.v"}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "cannot read the result")) << r.err;
}

}  // namespace
}  // namespace momenta
