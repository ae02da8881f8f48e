// The report's 3-D scene (docs/FORMAT.md "Animation", MSL's Visualizers.Advanced.Shape): a model
// that defines its own 3-D types — a box turning about y (its frame's T from the angle) and a
// sphere on a circle in the x-y plane — has its shapes' fields recorded as outputs with the
// closed-form values, and headless Chromium with software GL draws it where the projection puts it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <regex>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/report.h"
#include "app/result_reader.h"
#include "tests/support/cli_runner.h"
#include "tests/support/png_image.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::ReadText;
using testing::RunMomenta;
using testing::TempDir;

// spinner: phi = w t (w = 1 rad/s), T = the rotation by phi about y (world to frame, MSL's R.T).
// ball: theta = w t (w = 2 rad/s), centre r = R [cos theta, sin theta, 0] (R = 1.5 m).
constexpr const char* kSpinning = R"(model: Spinning
define:
  Spinner:
    parameters:
      w: {value: 1, unit: rad/s}
      a: {value: 0.6, unit: m}
    variables:
      phi: {start: 0, fixed: true}
      T: {shape: [3, 3]}
    equations:
      - der(phi) = w
      - T = [[cos(phi), 0, -sin(phi)], [0, 1, 0], [sin(phi), 0, cos(phi)]]
    animation:
      - {shape: box, r: [0, 0, 0], T: T, r_shape: [-a/2, 0, 0], length: a, color: [255, 160, 0]}
      - {shape: frame, r: [0, 0, 0], T: T, length: 1.2*a}
  Orbiter:
    parameters:
      R: {value: 1.5, unit: m}
      w: {value: 2, unit: rad/s}
      d: {value: 0.4, unit: m}
    variables:
      theta: {start: 0, fixed: true}
      r: {shape: [3]}
    equations:
      - der(theta) = w
      - r = [R*cos(theta), R*sin(theta), 0]
    animation:
      - {shape: sphere, r: r, r_shape: [-d/2, 0, 0], length: d, color: [255, 0, 255]}
      - {shape: line3d, from: [0, 0, 0], to: r}
components:
  spinner: {type: Spinner}
  ball: {type: Orbiter}
outputs: [ball.theta]
experiment: {stop: 3.2, interval: 0.01}
)";

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

Scene SceneOf(const std::string& path) {
  LoadedModel loaded;
  loaded.with_scene = true;
  EXPECT_EQ(LoadAndBuild(path, std::vector<std::string>{}, &loaded), kExitOk);
  ResolveSceneColumns(loaded.model->output_names, &loaded.scene);
  return loaded.scene;
}

const std::vector<std::string>& Field(const Scene& s, const std::string& owner,
                                      const std::string& kind, const std::string& key) {
  for (const auto& shape : s.shapes) {
    if (shape.owner != owner || shape.kind != kind) continue;
    for (const auto& f : shape.fields) {
      if (f.key == key) return f.columns;
    }
  }
  static const std::vector<std::string> kNone;
  ADD_FAILURE() << "no field " << key << " in the " << kind << " of " << owner;
  return kNone;
}

TEST(ReportScene3dTest, FieldsAreRecordedWithTheirClosedFormValues) {
  TempDir dir;
  const std::string model = dir.Write("spin.yaml", kSpinning), csv = dir.File("spin.csv");
  CliResult r = RunMomenta({"simulate", model, "-o", csv, "--scene-columns", "-q"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Scene s = SceneOf(model);
  EXPECT_TRUE(s.space);
  ASSERT_EQ(s.shapes.size(), 4u);
  const auto& T = Field(s, "spinner", "box", "T");
  const auto& centre = Field(s, "ball", "sphere", "r");
  ASSERT_EQ(T.size(), 9u);
  ASSERT_EQ(centre.size(), 3u);
  EXPECT_EQ(T[2], "spinner.T[1,3]");
  EXPECT_EQ(Field(s, "spinner", "box", "r_shape").size(), 3u);
  EXPECT_EQ(Field(s, "ball", "line3d", "to"), centre);
  // Row 100 is t = 1 s: phi = 1 rad, theta = 2 rad. The angles are integrals of constants, exact
  // to IDA's tolerance (rtol 1e-6 of values of order 1): 1e-6.
  const ResultTable t = ReadResult(csv);
  ASSERT_GT(t.time.size(), 100u);
  ASSERT_DOUBLE_EQ(t.time[100], 1.0);
  const double c = std::cos(1.0), sn = std::sin(1.0);
  const double expected_T[9] = {c, 0, -sn, 0, 1, 0, sn, 0, c};
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(t.values[t.Column(T[k])][100], expected_T[k], 1e-6) << T[k];
  EXPECT_NEAR(t.values[t.Column(centre[0])][100], 1.5 * std::cos(2.0), 1e-6);
  EXPECT_NEAR(t.values[t.Column(centre[1])][100], 1.5 * std::sin(2.0), 1e-6);
  EXPECT_NEAR(t.values[t.Column(centre[2])][100], 0.0, 1e-12);
}

TEST(ReportScene3dTest, PlanarAndThreeDimensionalShapesDoNotMix) {
  TempDir dir;
  std::string yaml = kSpinning;
  yaml.replace(yaml.find("components:"), 0,
               "  Dot:\n    variables: {x: {start: 0, fixed: true}}\n    equations: [der(x) = 1]\n"
               "    animation:\n      - {shape: pin, at: [x, 0]}\n");
  yaml += "";
  yaml.replace(yaml.find("  ball: {type: Orbiter}"), 0, "  dot: {type: Dot}\n");
  const std::string model = dir.Write("mixed.yaml", yaml);
  CliResult r = RunMomenta({"simulate", model, "--report", dir.File("m.html")}, dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, model + ":34:9: dot (Dot) draws a planar pin, but spinner draws a 3-D box: "
                                      "a model's shapes are all planar or all 3-D"))
      << r.err;
}

TEST(ReportScene3dTest, ThreeDimensionalKindsAreCheckedWhereTheyAreWritten) {
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
  EXPECT_TRUE(Contains(error("{shape: sphere, r: [x, 0, 0]}"), "sphere in the animation of Dot needs 'length'"));
  EXPECT_TRUE(Contains(error("{shape: box, r: [x, 0, 0], length: 1, colour: [1, 2, 3]}"),
                       "unknown key 'colour' in box in the animation of Dot"));
  // A spring with `r` is the MSL's coil; with from/to the planar zigzag.
  EXPECT_EQ(error("{shape: spring, r: [x, 0, 0], length: 1, extra: 5}"), "");
  EXPECT_EQ(error("{shape: spring, from: [x, 0], to: [0, 0]}"), "");
  EXPECT_TRUE(Contains(error("{shape: spring, r: [x, 0, 0], to: [0, 0]}"),
                       "unknown key 'to' in spring in the animation of Dot"));
}

// A shape's `if:` (docs/FORMAT.md "Animation"): a Boolean expression in the component's scope;
// the page draws the shape only where it holds at the start, and `-p` reaches it.
constexpr const char* kConditional = R"(model: C
define:
  Dot:
    parameters: {show: {value: true, type: Boolean}, d: {value: 0.2, unit: m}}
    variables: {x: {start: 0, fixed: true}}
    equations: [der(x) = 1]
    animation:
      - {shape: sphere, if: show, r: [x, 0, 0], length: d}
      - {shape: box, if: not show, r: [x, 0, 0], length: d}
      - {shape: frame, r: [0, 0, 0], length: d}
components:
  a: {type: Dot}
  b: {type: Dot, show: false}
experiment: {stop: 1, interval: 0.5}
)";

/// The page's scene as "kind@owner" in the page's order (its JSON, app/report.cc).
std::vector<std::string> PageShapes(const std::string& html) {
  std::vector<std::string> out;
  const std::regex shape("\"kind\":\"([a-z0-9]+)\",\"owner\":\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), shape); it != std::sregex_iterator(); ++it) {
    out.push_back((*it)[1].str() + "@" + (*it)[2].str());
  }
  return out;
}

using Shapes = std::vector<std::string>;

TEST(ReportScene3dTest, AShapeIsDrawnOnlyWhereItsIfHolds) {
  TempDir dir;
  const std::string model = dir.Write("c.yaml", kConditional), html = dir.File("c.html");
  CliResult r = RunMomenta({"simulate", model, "-o", dir.File("c.csv"), "--report", html, "-q"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(PageShapes(ReadText(html)), (Shapes{"sphere@a", "frame@a", "box@b", "frame@b"}));
  r = RunMomenta({"simulate", model, "-o", dir.File("c.csv"), "--report", html, "-q", "-p", "b.show=true"}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(PageShapes(ReadText(html)), (Shapes{"sphere@a", "frame@a", "sphere@b", "frame@b"}));
  // The page's data names no `if` (the condition is decided when the page is made).
  EXPECT_FALSE(Contains(ReadText(html), "\"if\":"));
}

TEST(ReportScene3dTest, AnIfNamingWhatTheComponentLacksIsAnErrorAtTheField) {
  TempDir dir;
  std::string yaml = kConditional;
  yaml.replace(yaml.find("if: show,"), 9, "if: shw,");
  const std::string model = dir.Write("c.yaml", yaml);
  CliResult r = RunMomenta({"simulate", model, "--report", dir.File("c.html"), "-q"}, dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, model + ":8:29: a (Dot) has no variable or parameter 'shw'")) << r.err;
  // Without a report the shapes are not read.
  EXPECT_EQ(RunMomenta({"simulate", model, "-o", dir.File("c.csv"), "-q"}, dir.path()).exit_code, 0);
}

// The MSL's DoublePendulum (two Revolutes, two BodyBoxes): the World draws its axes and its gravity
// arrow (a cylinder and a cone), each Revolute its axis cylinder, each BodyBox its box; the parts
// inside a BodyBox (its Body and FixedTranslation, animation = false as in the MSL) draw nothing.
// The report changes no result: the results file is the same byte for byte without it.
constexpr const char* kDoublePendulum = "models/msl/Mechanics/MultiBody/Examples/Elementary/DoublePendulum.yaml";

TEST(ReportScene3dTest, MultiBodyPartsDrawTheMslsShapesAndAnimationFalseDrawsNothing) {
  TempDir dir;
  const std::string model = testing::SourcePath(kDoublePendulum), html = dir.File("dp.html");
  auto shapes = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"simulate", model, "-o", dir.File("dp.csv"), "--report", html, "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    CliResult r = RunMomenta(args, dir.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return PageShapes(ReadText(html));
  };
  EXPECT_EQ(shapes({}), (Shapes{"frame@world", "cylinder@world", "cone@world", "cylinder@revolute1", "box@boxBody1",
                                "cylinder@revolute2", "box@boxBody2"}));
  const std::string with_report = ReadText(dir.File("dp.csv"));
  CliResult plain = RunMomenta({"simulate", model, "-o", dir.File("plain.csv"), "-q"}, dir.path());
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(with_report, ReadText(dir.File("plain.csv")));
  EXPECT_EQ(shapes({"-p", "boxBody2.animation=false"}),
            (Shapes{"frame@world", "cylinder@world", "cone@world", "cylinder@revolute1", "box@boxBody1",
                    "cylinder@revolute2"}));
  EXPECT_EQ(shapes({"-p", "world.animateWorld=false", "-p", "world.animateGravity=false"}),
            (Shapes{"cylinder@revolute1", "box@boxBody1", "cylinder@revolute2", "box@boxBody2"}));
  // world.enableAnimation = false: nothing at all, and no 3-D scene on the page.
  EXPECT_EQ(shapes({"-p", "world.enableAnimation=false"}), Shapes{});
  EXPECT_FALSE(Contains(ReadText(html), "function momentaScene3d"));
}

// A model whose element outputs (`body1.frame_a.r_0[1]` …) are what a shape reads whole
// (`frame_a.r_0`): the scene reads those columns instead of listing the elements twice.
TEST(ReportScene3dTest, AVectorTheModelOutputsElementByElementIsReadFromThoseColumns) {
  TempDir dir;
  const std::string html = dir.File("ts.html");
  CliResult r = RunMomenta({"simulate", testing::SourcePath("models/msl/Mechanics/MultiBody/Examples/Elementary/ThreeSprings.yaml"),
                            "-o", dir.File("ts.csv"), "--report", html, "-q"},
                           dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = ReadText(html);
  EXPECT_TRUE(Contains(page, "\"r\":[\"body1.frame_a.r_0[1]\",\"body1.frame_a.r_0[2]\",\"body1.frame_a.r_0[3]\"]"));
  EXPECT_EQ(PageShapes(page).size(), 10u);
}

// ---- In a real browser ------------------------------------------------------------------------

/// Renders `html` (the page at time t) in headless Chromium with software GL: the screenshot
/// goes to shot, the DOM to dom. Empty when it ran; else the command and Chromium's errors.
std::string RenderInChromium(const TempDir& dir, const std::string& html, const std::string& t,
                             const std::string& shot, const std::string& dom) {
  const std::string cmd = "cd '" + dir.path() + "' && timeout 120 chromium --headless --no-sandbox " +
                          "--use-angle=swiftshader --enable-unsafe-swiftshader --user-data-dir='" +
                          dir.File("profile") + "' --virtual-time-budget=5000 --window-size=1000,1300 " +
                          "--hide-scrollbars --dump-dom --screenshot='" + shot + "' 'file://" + html +
                          "#t=" + t + "' >'" + dom + "' 2>'" + dir.File("chromium.err") + "'";
  if (std::system(cmd.c_str()) == 0) return "";
  return cmd + "\n" + ReadText(dir.File("chromium.err"));
}

/// The number of frames the page's 3-D scene rendered (0 when there is no 3-D canvas).
long RenderedFrames(const std::string& dom) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex("<canvas id=\"scene\"[^>]* data-scene=\"3d\" data-rendered=\"([0-9]+)\""))) {
    return 0;
  }
  return std::stol(m[1]);
}

TEST(ReportScene3dBrowserTest, ChromiumDrawsTheSphereWhereTheProjectionPutsIt) {
  if (std::system("command -v chromium >/dev/null 2>&1") != 0) GTEST_SKIP() << "chromium is not installed";
  if (!ReportHasThree()) GTEST_SKIP() << "this build has no three.js (run scripts/setup.sh, then configure again)";
  TempDir dir;
  const std::string model = dir.Write("spin.yaml", kSpinning), html = dir.File("spin.html");
  CliResult sim = RunMomenta({"simulate", model, "-o", dir.File("spin.csv"), "--report", html}, dir.path());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  // Software GL (SwiftShader); the page opens at t = 1 s (#t=1).
  const std::string shot = dir.File("shot.png"), out = dir.File("dom.html");
  ASSERT_EQ(RenderInChromium(dir, html, "1", shot, out), "");
  const std::string dom = ReadText(out);
  EXPECT_GT(RenderedFrames(dom), 0) << dom.substr(0, 3000);
  EXPECT_TRUE(Contains(dom, "data-scene-drawn=\"4\""));
  // The sphere (magenta, shaded: g well below r and b, r close to b) and the box (orange: g about
  // 0.4-0.8 of r, b small). The page opens looking along -z with y up, aimed at the scene's centre,
  // which is the origin here (a whole turn of the ball about the box), so the ball's centre
  // projects at the box's centre plus a vector along (cos theta, -sin theta) in screen pixels,
  // theta = 2 rad; the point opposite it shows the background.
  const testing::PngImage img = testing::ReadPng(shot);
  ASSERT_TRUE(img.ok) << img.error;
  double sx = 0, sy = 0, bx = 0, by = 0;
  size_t ns = 0, nb = 0;
  for (uint32_t y = 0; y < img.height; ++y) {
    for (uint32_t x = 0; x < img.width; ++x) {
      const uint8_t* p = &img.rgba[4 * (size_t(y) * img.width + x)];
      const int r = p[0], g = p[1], b = p[2];
      if (r > 60 && b > 60 && g < 0.35 * std::min(r, b) && std::abs(r - b) < 0.3 * std::max(r, b)) {
        sx += x, sy += y, ++ns;
      } else if (r > 100 && g > 0.4 * r && g < 0.8 * r && b < 0.2 * r) {
        bx += x, by += y, ++nb;
      }
    }
  }
  ASSERT_GT(ns, 200u);
  ASSERT_GT(nb, 1000u);
  sx /= ns, sy /= ns, bx /= nb, by /= nb;
  const double dx = sx - bx, dy = sy - by;
  // 3 degrees: the box's turned faces move its centroid by a few pixels at ~110 px.
  EXPECT_NEAR(std::atan2(-dy, dx), 2.0, 3 * M_PI / 180) << dx << ", " << dy;
  EXPECT_GT(std::hypot(dx, dy), 50);
  const uint8_t* opposite = &img.rgba[4 * (size_t(std::lround(by - dy)) * img.width + size_t(std::lround(bx - dx)))];
  EXPECT_EQ(int(opposite[0]), 0xfc);
  EXPECT_EQ(int(opposite[1]), 0xfc);
  EXPECT_EQ(int(opposite[2]), 0xfa);
}

// The seed's Example 1 in 3-D (models/ball_pendulum_3d_impact.yaml): the report draws its two
// balls, Parts.Body spheres of diameter 2r, where the run puts them. At t = 0.5 s, before the
// impact, A has fallen g t^2/2 from [r, 4, 0] and B hangs at [0, 4 - L, 0]: the line between
// the two spheres on the screen (looking along -z, y up) is that between the centres.
TEST(ReportScene3dBrowserTest, ChromiumDrawsTheSeedsBallAndPendulumInSpace) {
  if (std::system("command -v chromium >/dev/null 2>&1") != 0) GTEST_SKIP() << "chromium is not installed";
  if (!ReportHasThree()) GTEST_SKIP() << "this build has no three.js (run scripts/setup.sh, then configure again)";
  TempDir dir;
  const std::string html = dir.File("bp.html");
  CliResult sim = RunMomenta({"simulate", testing::SourcePath("models/ball_pendulum_3d_impact.yaml"), "-o",
                              dir.File("bp.csv"), "--report", html, "-q"},
                             dir.path());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::string shot = dir.File("shot.png"), out = dir.File("dom.html");
  ASSERT_EQ(RenderInChromium(dir, html, "0.5", shot, out), "");
  const std::string dom = ReadText(out);
  EXPECT_GT(RenderedFrames(dom), 0) << dom.substr(0, 3000);
  // The balls, and the World's axes and gravity arrow (a cylinder and a cone), the pivot's rod from
  // the origin (Parts.Fixed), the joint's axis cylinder and the cord (FixedTranslation); the
  // Bodies' cylinders to their centres of mass have length 0 (r_CM = 0) and are not drawn.
  EXPECT_TRUE(Contains(dom, "data-scene-drawn=\"8\"")) << dom.substr(0, 3000);
  // The balls' blue (the Body's [0, 128, 255], shaded) inside the scene, whose background is
  // #fcfcfa (the plots and the slider below it are blue too): the principal axis of those pixels
  // is the line between the two spheres, which are the same size on the screen (both at z = 0).
  const testing::PngImage img = testing::ReadPng(shot);
  ASSERT_TRUE(img.ok) << img.error;
  auto pixel = [&](uint32_t x, uint32_t y) { return &img.rgba[4 * (size_t(y) * img.width + x)]; };
  uint32_t x0 = img.width, x1 = 0, y0 = img.height, y1 = 0;  // the scene's background's bounds
  for (uint32_t y = 0; y < img.height; ++y) {
    for (uint32_t x = 0; x < img.width; ++x) {
      const uint8_t* p = pixel(x, y);
      if (p[0] == 0xfc && p[1] == 0xfc && p[2] == 0xfa) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    }
  }
  ASSERT_GT(x1, x0 + 400);
  ASSERT_GT(y1, y0 + 300);
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  size_t n = 0;
  for (uint32_t y = y0; y <= y1; ++y) {
    for (uint32_t x = x0; x <= x1; ++x) {
      const uint8_t* p = pixel(x, y);
      if (p[2] > 80 && p[2] > 1.4 * p[1] && p[0] < 0.3 * p[2]) {
        sx += x, sy += y, sxx += double(x) * x, syy += double(y) * y, sxy += double(x) * y, ++n;
      }
    }
  }
  ASSERT_GT(n, 2000u);
  const double mx = sx / n, my = sy / n;
  const double cxx = sxx / n - mx * mx, cyy = syy / n - my * my, cxy = sxy / n - mx * my;
  const double axis = 0.5 * std::atan2(2 * cxy, cxx - cyy);  // screen angle, y down
  const double r = 0.5, g = 9.80665, t = 0.5;
  const double expected = std::atan2((4 - g * t * t / 2) - (4 - 3.5), r - 0);  // world angle, y up
  double diff = std::fmod(std::fabs(-axis - expected), M_PI);
  diff = std::min(diff, M_PI - diff);
  // Observed 77.601 degrees against 77.600: the spheres are symmetric about their centres on the
  // screen; half a degree leaves room for the shading's rounding (0.5 degrees is 1.3 px at 150 px).
  EXPECT_LT(diff, 0.5 * M_PI / 180) << "axis " << -axis * 180 / M_PI << " deg, expected " << expected * 180 / M_PI;
  // Two separate spheres, not one: the pixels spread along the axis much more than across it.
  const double along = 0.5 * (cxx + cyy) + std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
  const double across = cxx + cyy - along;
  EXPECT_GT(along, 4 * across);
}

// The MSL's DoublePendulum in Chromium at t = 0.5 s: seven shapes drawn (data-scene-drawn). Looking
// along -z (y up), the two Revolutes' axis cylinders (red, seen end-on) are blobs at the joints:
// revolute2 is 0.5 m from revolute1 along the first box, at the angle phi1 of the run; the boxes'
// blue centroid is rev1 + 0.375 u1 + 0.125 u2 (u1 at phi1, u2 at phi1 + phi2; two 0.5 m boxes).
// With boxBody2.animation = false six shapes are drawn and the blue is about half.
TEST(ReportScene3dBrowserTest, ChromiumDrawsTheMslDoublePendulumsParts) {
  if (std::system("command -v chromium >/dev/null 2>&1") != 0) GTEST_SKIP() << "chromium is not installed";
  if (!ReportHasThree()) GTEST_SKIP() << "this build has no three.js (run scripts/setup.sh, then configure again)";
  TempDir dir;
  struct Blobs {
    std::vector<std::pair<double, double>> red;  // red pixels among red (not the 1-px axis lines)
    double bx = 0, by = 0;                       // the blue centroid
    size_t blue = 0;
  };
  auto render = [&](const std::string& name, const std::vector<std::string>& extra, std::string* dom) {
    const std::string html = dir.File(name + ".html"), shot = dir.File(name + ".png");
    std::vector<std::string> args = {"simulate", testing::SourcePath(kDoublePendulum), "-o", dir.File(name + ".csv"),
                                     "--report", html, "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    CliResult sim = RunMomenta(args, dir.path());
    EXPECT_EQ(sim.exit_code, 0) << sim.err;
    EXPECT_EQ(RenderInChromium(dir, html, "0.5", shot, dir.File(name + ".dom")), "");
    *dom = ReadText(dir.File(name + ".dom"));
    Blobs b;
    const testing::PngImage img = testing::ReadPng(shot);
    EXPECT_TRUE(img.ok) << img.error;
    if (!img.ok) return b;
    auto pixel = [&](uint32_t x, uint32_t y) { return &img.rgba[4 * (size_t(y) * img.width + x)]; };
    auto red = [&](uint32_t x, uint32_t y) {
      const uint8_t* p = pixel(x, y);
      return p[0] > 100 && p[1] < 0.35 * p[0] && p[2] < 0.35 * p[0];
    };
    // The scene is where its background (#fcfcfa) is; the slider and plots below are blue too.
    uint32_t x0 = img.width, x1 = 0, y0 = img.height, y1 = 0;
    for (uint32_t y = 0; y < img.height; ++y) {
      for (uint32_t x = 0; x < img.width; ++x) {
        const uint8_t* p = pixel(x, y);
        if (p[0] == 0xfc && p[1] == 0xfc && p[2] == 0xfa) {
          x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
      }
    }
    for (uint32_t y = y0 + 2; y + 2 <= y1; ++y) {
      for (uint32_t x = x0 + 2; x + 2 <= x1; ++x) {
        if (red(x, y) && red(x - 1, y) && red(x + 1, y) && red(x, y - 1) && red(x, y + 1)) b.red.push_back({x, y});
        const uint8_t* p = pixel(x, y);
        if (p[2] > 80 && p[2] > 1.4 * p[1] && p[0] < 0.3 * p[2]) b.bx += x, b.by += y, ++b.blue;
      }
    }
    if (b.blue) b.bx /= b.blue, b.by /= b.blue;
    return b;
  };
  std::string dom;
  const Blobs all = render("dp", {}, &dom);
  EXPECT_GT(RenderedFrames(dom), 0) << dom.substr(0, 3000);
  EXPECT_TRUE(Contains(dom, "data-scene-drawn=\"7\"")) << dom.substr(0, 3000);
  ASSERT_GT(all.red.size(), 20u);
  ASSERT_GT(all.blue, 800u);
  // Two red blobs: split the red pixels at their centroid along their principal axis; a and b are
  // their centroids.
  struct Joints {
    double ax = 0, ay = 0, bx = 0, by = 0;
    size_t na = 0, nb = 0;
  };
  auto joints = [](const Blobs& blobs) {
    double mx = 0, my = 0, cxx = 0, cyy = 0, cxy = 0;
    for (const auto& [x, y] : blobs.red) mx += x, my += y;
    mx /= blobs.red.size(), my /= blobs.red.size();
    for (const auto& [x, y] : blobs.red) cxx += (x - mx) * (x - mx), cyy += (y - my) * (y - my), cxy += (x - mx) * (y - my);
    const double axis = 0.5 * std::atan2(2 * cxy, cxx - cyy);
    Joints j;
    for (const auto& [x, y] : blobs.red) {
      if ((x - mx) * std::cos(axis) + (y - my) * std::sin(axis) < 0) j.ax += x, j.ay += y, ++j.na;
      else j.bx += x, j.by += y, ++j.nb;
    }
    if (j.na) j.ax /= j.na, j.ay /= j.na;
    if (j.nb) j.bx /= j.nb, j.by /= j.nb;
    return j;
  };
  Joints j = joints(all);
  ASSERT_GT(j.na, 5u);
  ASSERT_GT(j.nb, 5u);
  // revolute2 is the blob nearer the blue centroid (|0.125 (u2 - u1)| < |0.375 u1 + 0.125 u2|).
  if (std::hypot(j.ax - all.bx, j.ay - all.by) < std::hypot(j.bx - all.bx, j.by - all.by)) {
    std::swap(j.ax, j.bx), std::swap(j.ay, j.by);
  }
  const double ax = j.ax, ay = j.ay, bx = j.bx, by = j.by;
  const double scale = std::hypot(bx - ax, by - ay) / 0.5;  // pixels per metre in the plane z = 0
  EXPECT_GT(scale, 100);
  // The run's angles at the row the page shows (the nearest to 0.5 s; rows are 0.6 ms apart).
  const ResultTable t = ReadResult(dir.File("dp.csv"));
  size_t row = 0;
  for (size_t k = 0; k < t.time.size(); ++k) {
    if (std::fabs(t.time[k] - 0.5) < std::fabs(t.time[row] - 0.5)) row = k;
  }
  const double phi1 = t.values[t.Column("revolute1.phi")][row], phi2 = t.values[t.Column("revolute2.phi")][row];
  // Screen y is down. 2 degrees: the blobs' centroids are within a pixel at ~100 px apart.
  double diff = std::remainder(std::atan2(-(by - ay), bx - ax) - phi1, 2 * M_PI);
  EXPECT_LT(std::fabs(diff), 2 * M_PI / 180) << "rev1 -> rev2 at " << std::atan2(-(by - ay), bx - ax) << ", phi1 " << phi1;
  const double ex = ax + scale * (0.375 * std::cos(phi1) + 0.125 * std::cos(phi1 + phi2));
  const double ey = ay - scale * (0.375 * std::sin(phi1) + 0.125 * std::sin(phi1 + phi2));
  // 3% of a metre's pixels: the joints' red cylinders hide a little of the boxes' ends.
  EXPECT_NEAR(all.bx, ex, 0.03 * scale);
  EXPECT_NEAR(all.by, ey, 0.03 * scale);
  // boxBody2.animation = false: six shapes, and the blue of one box of two. The scene fits what is
  // drawn, so the blue area is compared in square metres (pixels over the square of the scale).
  const Blobs one = render("dp1", {"-p", "boxBody2.animation=false"}, &dom);
  EXPECT_TRUE(Contains(dom, "data-scene-drawn=\"6\"")) << dom.substr(0, 3000);
  const Joints j1 = joints(one);
  ASSERT_GT(j1.na, 5u);
  ASSERT_GT(j1.nb, 5u);
  const double scale1 = std::hypot(j1.bx - j1.ax, j1.by - j1.ay) / 0.5;
  const double ratio = (one.blue / (scale1 * scale1)) / (all.blue / (scale * scale));
  // A half, less what the joints' cylinders hide (box1 has both): 0.4 to 0.6.
  EXPECT_GT(ratio, 0.4);
  EXPECT_LT(ratio, 0.6);
}

}  // namespace
}  // namespace momenta
