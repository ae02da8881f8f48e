// The HTML report (`momenta simulate --report`, `momenta report`): what it records for the scene,
// checked against the mechanism's own geometry, and the page rendered in a real browser —
// Debian's headless Chromium loads each report, the DOM says how many series and scene shapes the
// page drew and over how many frames, and a screenshot decoded with libpng is not blank.

#include "app/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <regex>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/result_reader.h"
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

size_t Count(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

/// The scene of a model file as simulate --report records it.
Scene SceneOf(const std::string& model) {
  LoadedModel loaded;
  loaded.with_scene = true;
  EXPECT_EQ(LoadAndBuild(SourcePath(model), std::vector<std::string>{}, &loaded), kExitOk);
  ResolveSceneColumns(loaded.model->output_names, &loaded.scene);
  return loaded.scene;
}

const SceneShape* Find(const Scene& s, const std::string& owner, const std::string& kind) {
  for (const auto& shape : s.shapes) {
    if (shape.owner == owner && shape.kind == kind) return &shape;
  }
  return nullptr;
}

const std::vector<std::string>& Field(const SceneShape& s, const std::string& key) {
  for (const auto& f : s.fields) {
    if (f.key == key) return f.columns;
  }
  static const std::vector<std::string> kNone;
  ADD_FAILURE() << "no field " << key << " in the " << s.kind << " of " << s.owner;
  return kNone;
}

TEST(ReportSceneTest, BallAndPendulumDrawsEveryPartOnceFromTheModelsOwnOutputsWherePossible) {
  const Scene s = SceneOf("models/ball_pendulum_impact.yaml");
  // Ball A (a Body: circle with its angle), the pivot (ground), the joint (pin), the cord (line)
  // and B (a PointMass: circle); the contact and nothing else draws nothing.
  ASSERT_EQ(s.shapes.size(), 5u);
  ASSERT_NE(Find(s, "A", "circle"), nullptr);
  ASSERT_NE(Find(s, "pivot", "ground"), nullptr);
  ASSERT_NE(Find(s, "joint", "pin"), nullptr);
  ASSERT_NE(Find(s, "cord", "line"), nullptr);
  ASSERT_NE(Find(s, "B", "circle"), nullptr);
  // B's centre is the model's own output B.r: read from those columns, not added again.
  EXPECT_EQ(Field(*Find(s, "B", "circle"), "at"), (std::vector<std::string>{"B.r[1]", "B.r[2]"}));
  EXPECT_EQ(s.num_model_columns, 10u);  // A.r, A.v, B.r, B.v (two each), contact.d, joint.phi
  for (const auto& added : s.added) EXPECT_NE(added, "B.r");
}

TEST(ReportSceneTest, RecordedCordKeepsItsLengthAndEndsAtTheBall) {
  // simulate --scene-columns writes the scene's quantities into the CSV: the cord's ends are
  // L = 3.5 m apart at every row, and its far end is B's centre. Both hold to the solver's
  // tolerance (rtol 1e-8 on positions of order 1 m, and the constraint is solved exactly at every
  // step): 1e-6 m leaves two orders of magnitude.
  TempDir dir;
  const std::string csv = dir.File("bp.csv");
  CliResult r = RunMomenta({"simulate", SourcePath("models/ball_pendulum_impact.yaml"), "-o", csv,
                            "--scene-columns", "-q"},
                           dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Scene s = SceneOf("models/ball_pendulum_impact.yaml");
  const ResultTable t = ReadResult(csv);
  const SceneShape& cord = *Find(s, "cord", "line");
  const auto& from = Field(cord, "from");
  const auto& to = Field(cord, "to");
  ASSERT_EQ(from.size(), 2u);
  ASSERT_GT(t.time.size(), 1000u);
  double worst_length = 0, worst_end = 0;
  for (size_t i = 0; i < t.time.size(); ++i) {
    const double x0 = t.values[t.Column(from[0])][i], y0 = t.values[t.Column(from[1])][i];
    const double x1 = t.values[t.Column(to[0])][i], y1 = t.values[t.Column(to[1])][i];
    worst_length = std::max(worst_length, std::fabs(std::hypot(x1 - x0, y1 - y0) - 3.5));
    worst_end = std::max(worst_end, std::hypot(x1 - t.values[t.Column("B.r[1]")][i],
                                               y1 - t.values[t.Column("B.r[2]")][i]));
    EXPECT_DOUBLE_EQ(x0, 0.0);
    EXPECT_DOUBLE_EQ(y0, 4.0);
  }
  EXPECT_LT(worst_length, 1e-6);
  EXPECT_LT(worst_end, 1e-9);
}

TEST(ReportSceneTest, EveryMultibodySceneDrawsItsParts) {
  // Shapes per model: slider crank: the world (ground), 3 revolute joints (pins), 4 bars and the
  // prismatic guide (lines), 3 bodies (circles); billiards: its 3 balls; double pendulum: the
  // world, 2 joints, 2 bars, 2 bodies.
  struct Case {
    const char* model;
    size_t shapes, circles;
  } cases[] = {{"models/slider_crank.yaml", 12, 3},
               {"models/billiards.yaml", 3, 3},
               {"models/double_pendulum.yaml", 7, 2}};
  for (const auto& c : cases) {
    const Scene s = SceneOf(c.model);
    size_t circles = 0;
    for (const auto& shape : s.shapes) circles += shape.kind == "circle";
    EXPECT_EQ(s.shapes.size(), c.shapes) << c.model;
    EXPECT_EQ(circles, c.circles) << c.model;
  }
}

TEST(ReportSceneTest, AnimationDeclarationsAreCheckedWhereTheyAreWritten) {
  auto error = [](const std::string& shape) {
    return testing::BuildError(R"(
model: M
define:
  Dot:
    variables: {x: {start: 0}}
    equations: [der(x) = 1]
    animation:
      - )" + shape + R"(
components:
  d: {type: Dot}
)");
  };
  EXPECT_TRUE(Contains(error("{shape: blob, at: [x, 0]}"),
                       "unknown shape 'blob' in the animation of Dot (valid shapes: box, beam, "
                       "circle, cone, cylinder, frame, gearwheel, ground, line, line3d, pin, pipe, "
                       "sphere, spring, wall)"))
      << error("{shape: blob, at: [x, 0]}");
  EXPECT_TRUE(Contains(error("{shape: circle, at: [x, 0]}"),
                       "circle in the animation of Dot needs 'radius'"));
  EXPECT_TRUE(Contains(error("{shape: line, from: [x, 0], to: [0, 0], colour: red}"),
                       "unknown key 'colour' in line in the animation of Dot"));
  EXPECT_EQ(error("{shape: pin, at: [x, 0]}"), "");
  EXPECT_TRUE(
      Contains(error("{shape: line, from: [x, 0], to: [0, 0], colour: red}"), "test.yaml:8:"));
}

TEST(ReportPageTest, UserTextCannotEndTheDataScript) {
  ReportData d;
  d.model_name = "M";
  d.doc = "a doc with </script><b>bold</b> and \"quotes\"";
  d.columns = {"x"};
  d.num_plotted = 1;
  d.Row(0, {1});
  const std::string html = ReportHtml(d);
  // The page's own four scripts end; the doc's text is written \u003c/script>.
  EXPECT_EQ(Count(html, "</script>"), 4u);
  EXPECT_TRUE(Contains(
      html, "\"doc\":\"a doc with \\u003c/script>\\u003cb>bold\\u003c/b> and \\\"quotes\\\"\""))
      << html.substr(html.find("\"doc\""), 120);
}

TEST(ReportPageTest, UserTextInEveryFieldStaysText) {
  // Every text field a model, a file name or the solver fills, holding a script end and an element
  // with an event handler: the page's own four scripts end, no element is made from the text, and
  // every "onerror" is inside an escaped string (JSON's \u003c or HTML's &lt;).
  const std::string evil = "</script><img src=x onerror=alert(1)>";
  ReportData d;
  d.model_name = d.model_file = d.doc = d.result_file = evil;
  d.parameters = {{evil, evil, evil, 1}};
  d.build = {{evil, evil}};
  d.solver = {{evil, evil}};
  d.columns = {evil};
  d.units = {evil};
  d.notes = {evil};
  d.num_plotted = 1;
  d.Row(0, {1});
  const std::string html = ReportHtml(d);
  EXPECT_EQ(Count(html, "</script>"), 4u);
  EXPECT_EQ(Count(html, "<img"), 0u);
  const size_t escaped = Count(html, "\\u003cimg src=x onerror") + Count(html, "&lt;img src=x onerror");
  EXPECT_EQ(Count(html, "onerror"), escaped);
  EXPECT_GE(escaped, 14u);  // each of the 14 strings above appears at least once
}

TEST(ReportPageTest, LongRunsAreThinnedKeepingEveryEventRow) {
  // 50 001 rows with an event at t = 30001 (two rows): at most kMaxReportRows rows plus the
  // event rows and the last reach the page, and the event's two rows are among them.
  ReportData d;
  d.model_name = "M";
  d.columns = {"x"};
  d.num_plotted = 1;
  for (int i = 0; i < 50000; ++i) {
    d.Row(i, {double(i)});
    if (i == 30001) d.Row(i, {-1.0});
  }
  const std::string html = ReportHtml(d);
  EXPECT_TRUE(Contains(html, "\"events\":[30001]"));
  EXPECT_TRUE(Contains(html, "\"rows\":50001,"));
  const size_t begin = html.find("\"data\":[[") + 9, end = html.find(']', begin);
  const std::string times = html.substr(begin, end - begin);
  EXPECT_LE(Count(times, ",") + 1, kMaxReportRows + 3);
  EXPECT_GE(Count(times, ",") + 1, kMaxReportRows / 2);
  EXPECT_TRUE(Contains(times, ",30001,30001,"));
  EXPECT_TRUE(Contains(times, ",49999"));
}

TEST(ReportSceneTest, AFieldNamingWhatTheComponentLacksIsReportedAtTheField) {
  // The names a field uses are resolved when a report is made (a plain simulate never reads them).
  TempDir dir;
  const std::string model = dir.Write("bad.yaml", R"(model: M
define:
  Dot:
    variables: {x: {start: 0, fixed: true}}
    equations: [der(x) = 1]
    animation:
      - {shape: pin, at: [x, nosuch]}
components:
  d: {type: Dot}
experiment: {stop: 0.1}
)");
  CliResult r = RunMomenta({"simulate", model, "--report", dir.File("bad.html")}, dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, model + ":7:30: d (Dot) has no variable or parameter 'nosuch' (valid names: x)")) << r.err;
  EXPECT_EQ(RunMomenta({"simulate", model, "-q", "-o", dir.File("bad.csv")}, dir.path()).exit_code, 0);
}

// ---- In a real browser ------------------------------------------------------------------------

bool HaveChromium() { return std::system("command -v chromium >/dev/null 2>&1") == 0; }

/// Runs headless Chromium on `html` with `mode` (--dump-dom and --screenshot=FILE) and returns its
/// standard output (the DOM). Virtual time lets the page's scripts finish before the DOM is taken.
std::string Chromium(const TempDir& dir, const std::string& html, const std::string& mode) {
  const std::string out = dir.File("chromium.out");
  const std::string cmd =
      "cd '" + dir.path() + "' && timeout 120 chromium --headless --no-sandbox --disable-gpu " +
      "--user-data-dir='" + dir.File("profile") + "' --virtual-time-budget=5000 " +
      "--window-size=1000,1300 --hide-scrollbars " + mode + " 'file://" + html + "' >'" + out +
      "' 2>'" + dir.File("chromium.err") + "'";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << cmd << "\n" << ReadText(dir.File("chromium.err"));
  return ReadText(out);
}

/// The value of `data-<name>` on the page's <body> as Chromium left it; -1 when absent.
long DataAttribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex("<body[^>]* data-" + name + "=\"([0-9]+)\"")))
    return -1;
  return std::stol(m[1]);
}

struct Rendered {
  std::string dom;
  testing::PngImage shot;
  size_t rows = 0;  ///< rows of the run's CSV
};

/// Simulates `model` with --report and loads the page once in Chromium, which dumps its DOM and
/// takes a screenshot in the same run (each Chromium start costs seconds).
Rendered RenderReport(const TempDir& dir, const std::string& model) {
  Rendered r;
  const std::string html = dir.File("report.html"), csv = dir.File("run.csv");
  CliResult sim =
      RunMomenta({"simulate", SourcePath(model), "-o", csv, "--report", html}, dir.path());
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_TRUE(Contains(sim.out, "report: " + html)) << sim.out;
  r.rows = ReadResult(csv).time.size();
  r.dom = Chromium(dir, html, "--dump-dom --screenshot='" + dir.File("shot.png") + "'");
  r.shot = testing::ReadPng(dir.File("shot.png"));
  return r;
}

/// A screenshot that shows a page with plots or a scene: decoded, of the window's size, with
/// many colours (antialiased curves in several colours) and a fair share of drawn pixels.
void ExpectDrawn(const testing::PngImage& shot) {
  ASSERT_TRUE(shot.ok) << shot.error;
  EXPECT_EQ(shot.width, 1000u);
  EXPECT_EQ(shot.height, 1300u);
  EXPECT_GT(shot.CountColours(), 64u);
  EXPECT_GT(shot.CountNotBackground(), shot.width * shot.height / 100);
}

class ReportBrowserTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!HaveChromium())
      GTEST_SKIP()
          << "chromium is not installed (Debian package chromium; scripts/setup.sh installs it)";
    if (!ReportHasPlots())
      GTEST_SKIP() << "this build has no uPlot (run scripts/setup.sh, then configure again)";
  }
  TempDir dir_;
};

TEST_F(ReportBrowserTest, CarrierCollisionPlotsEveryOutput) {
  const Rendered r = RenderReport(dir_, "models/carrier_collision.yaml");
  // Ten outputs, one chart per unit: the velocities (m/s), the positions (m) and the Collision
  // blocks' velocities, which declare no unit; no scene (1-D parts only).
  EXPECT_EQ(DataAttribute(r.dom, "series"), 10) << r.dom.substr(0, 2000);
  EXPECT_EQ(DataAttribute(r.dom, "plots"), 3);
  EXPECT_EQ(DataAttribute(r.dom, "scene-shapes"), -1);
  EXPECT_TRUE(Contains(r.dom, "CarrierCollision"));
  ExpectDrawn(r.shot);
}

TEST_F(ReportBrowserTest, BallAndPendulumAnimatesItsFiveParts) {
  const Rendered r = RenderReport(dir_, "models/ball_pendulum_impact.yaml");
  EXPECT_EQ(DataAttribute(r.dom, "series"), 10) << r.dom.substr(0, 2000);
  EXPECT_EQ(DataAttribute(r.dom, "scene-shapes"), 5);
  EXPECT_EQ(DataAttribute(r.dom, "scene-drawn"), 5);
  EXPECT_EQ(DataAttribute(r.dom, "scene-frames"), static_cast<long>(r.rows));
  ExpectDrawn(r.shot);
}

TEST_F(ReportBrowserTest, SliderCrankAnimatesItsTwelveParts) {
  const Rendered r = RenderReport(dir_, "models/slider_crank.yaml");
  EXPECT_EQ(DataAttribute(r.dom, "scene-shapes"), 12) << r.dom.substr(0, 2000);
  EXPECT_EQ(DataAttribute(r.dom, "scene-drawn"), 12);
  EXPECT_EQ(DataAttribute(r.dom, "scene-frames"), static_cast<long>(r.rows));
  EXPECT_EQ(DataAttribute(r.dom, "series"), 16);  // 11 outputs, five of them vectors
  ExpectDrawn(r.shot);
}

// ---- momenta report from a result written before ----------------------------------------------

TEST(ReportCommandTest, ReportOfAResultWithSceneColumnsHasTheScene) {
  TempDir dir;
  const std::string csv = dir.File("bp.csv"), html = dir.File("bp.html");
  const std::string model = SourcePath("models/ball_pendulum_impact.yaml");
  ASSERT_EQ(
      RunMomenta({"simulate", model, "-o", csv, "--scene-columns", "-q"}, dir.path()).exit_code, 0);
  CliResult r = RunMomenta({"report", csv, "--model", model, "-o", html}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = ReadText(html);
  EXPECT_EQ(Count(page, "{\"kind\":"), 5u);
  EXPECT_TRUE(Contains(page, "\"plotted\":10,"));
  EXPECT_TRUE(Contains(page, "not recorded in a result file"));
}

TEST(ReportCommandTest, ReportOfAPlainResultSaysWhatTheSceneLacks) {
  TempDir dir;
  const std::string csv = dir.File("bp.csv");
  const std::string model = SourcePath("models/ball_pendulum_impact.yaml");
  ASSERT_EQ(RunMomenta({"simulate", model, "-o", csv, "-q"}, dir.path()).exit_code, 0);
  CliResult r = RunMomenta({"report", csv, "-m", model}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = ReadText(dir.File("bp.html"));
  // The outputs hold the balls' centres (A.r, B.r) but not their radii, nor the cord's ends: no
  // shape is complete, and the page says so.
  EXPECT_TRUE(Contains(
      page,
      "the result holds the positions of 0 of the scene's 5 shapes (simulate with --scene-columns"))
      << page.substr(0, 3000);
  EXPECT_EQ(Count(page, "{\"kind\":"), 0u);
}

TEST(ReportCommandTest, ErrorsNameTheFile) {
  TempDir dir;
  const std::string model = SourcePath("models/ball_pendulum_impact.yaml");
  CliResult r = RunMomenta({"report", dir.File("none.csv"), "-m", model}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, "cannot read the result " + dir.File("none.csv"))) << r.err;
  const std::string bad = dir.Write("bad.csv", "t,x\n0,1\n");
  r = RunMomenta({"report", bad, "-m", model}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(r.err, bad + ":1: not a momenta result")) << r.err;
  const std::string broken = dir.Write("broken.csv", "time,x\n0,1\n0.1,abc\n");
  r = RunMomenta({"report", broken, "-m", model}, dir.path());
  EXPECT_TRUE(Contains(r.err, broken + ":3: 'abc' in column x is not a number")) << r.err;
  r = RunMomenta(
      {"simulate", model, "-o", dir.File("x.csv"), "--report", "/nonexistent/dir/r.html"},
      dir.path());
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(Contains(r.err, "cannot write the report /nonexistent/dir/r.html")) << r.err;
}

}  // namespace
}  // namespace momenta
