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
  EXPECT_TRUE(Contains(dom, "data-scene-drawn=\"2\"")) << dom.substr(0, 3000);
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

}  // namespace
}  // namespace momenta
