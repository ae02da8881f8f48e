// `momenta fmu`: the FMU it writes, run by an importer written here (tests/support/fmu_importer.h)
// in both kinds and compared with closed forms and with `momenta simulate`; its description
// against the FMI 2.0 schema; its binary's dynamic dependencies; the command's errors.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "app/plugin.h"
#include "tests/support/cli_runner.h"
#include "tests/support/fmu_importer.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::FmuImporter;
using testing::FmuRunResult;
using testing::ReadCsv;
using testing::ReadText;
using testing::RunMomenta;
using testing::SourcePath;
using testing::TempDir;

/// The FMU runtime is left out of sanitizer builds (fmu/CMakeLists.txt): nothing to test there.
class FmuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (FindPlugin("momenta-fmu.so").empty())
      GTEST_SKIP() << "no FMU runtime in this build (fmu/CMakeLists.txt)";
  }
};

/// The output of a shell command.
std::string Shell(const std::string& command) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  pclose(pipe);
  return out;
}

/// Exports `model` (with `extra` arguments) into dir as model.fmu; the path, or "" after a failure.
std::string Export(const TempDir& dir, const std::string& model,
                   const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {"fmu", SourcePath(model), "-o", dir.File("model.fmu")};
  args.insert(args.end(), extra.begin(), extra.end());
  const CliResult r = RunMomenta(args, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? dir.File("model.fmu") : "";
}

/// B's velocity after both impacts of the carrier collision: A (mA, vA0) hits B at rest with
/// restitution eC, then B hits the suitcase at rest with eS (Newton's law of restitution and
/// momentum, each impact on its own).
double CarrierClosedForm(double eC, double eS = 0.3, double mA = 40, double mB = 40, double mS = 15,
                         double v = 5) {
  const double vB1 = mA * v * (1 + eC) / (mA + mB);
  return vB1 * (mB - mS * eS) / (mB + mS);
}

TEST_F(FmuTest, CarrierCollisionBothKindsEndAtTheClosedForm) {
  TempDir dir;
  const std::string fmu = Export(dir, "models/carrier_collision.yaml");
  ASSERT_FALSE(fmu.empty());
  FmuImporter importer(fmu, dir.File("unpacked"));
  ASSERT_EQ(importer.error(), "");
  ASSERT_NEAR(CarrierClosedForm(0.8), 2.9045454545454545, 1e-15);
  // Between the impacts the velocities are constant: Co-Simulation lands on the exact
  // post-impact state, and the Model Exchange run (RK4 exact on constant velocities, the impacts
  // located by bisection to about 1e-17 s) too; 1e-9 m/s leaves room for the solver's rounding.
  for (const double eC : {0.8, 0.5}) {
    const std::map<std::string, double> params = {{"eC", eC}};
    const FmuRunResult cs = importer.RunCoSimulation(params, 0.5, 0.01, {"B.v", "S.v", "A.v"});
    ASSERT_TRUE(cs.ok) << cs.log;
    EXPECT_NEAR(cs.final.at("B.v"), CarrierClosedForm(eC), 1e-9) << "eC = " << eC;
    const FmuRunResult me = importer.RunModelExchange(params, 0.5, 0.01, {"B.v", "S.v", "A.v"});
    ASSERT_TRUE(me.ok) << me.log;
    EXPECT_NEAR(me.final.at("B.v"), CarrierClosedForm(eC), 1e-9) << "eC = " << eC;
    EXPECT_NEAR(me.final.at("A.v"), 2.5 * (1 - eC), 1e-9);
    EXPECT_GE(me.events, 2);  // the two impacts
  }
}

TEST_F(FmuTest, ExportedParameterValueIsTheStartValue) {
  TempDir dir;
  const std::string fmu = Export(dir, "models/carrier_collision.yaml", {"-p", "eC=0.5"});
  ASSERT_FALSE(fmu.empty());
  FmuImporter importer(fmu, dir.File("unpacked"));
  ASSERT_EQ(importer.error(), "");
  const FmuRunResult cs = importer.RunCoSimulation({}, 0.5, 0.05, {"B.v", "eC"});
  ASSERT_TRUE(cs.ok) << cs.log;
  EXPECT_EQ(cs.final.at("eC"), 0.5);
  EXPECT_NEAR(cs.final.at("B.v"), CarrierClosedForm(0.5), 1e-9);
  EXPECT_NE(ReadText(dir.File("unpacked/modelDescription.xml")).find("<Real start=\"0.5\"/>"),
            std::string::npos);
}

/// The last row of `momenta simulate MODEL --stop STOP`.
std::map<std::string, double> SimulateEnd(const TempDir& dir, const std::string& model,
                                          double stop) {
  const CliResult r = RunMomenta({"simulate", SourcePath(model), "--stop", std::to_string(stop),
                                  "-o", dir.File("sim.csv"), "--quiet"},
                                 dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const testing::Csv csv = ReadCsv(dir.File("sim.csv"));
  std::map<std::string, double> last;
  for (size_t k = 0; k < csv.header.size(); ++k) last[csv.header[k]] = csv.rows.back()[k];
  return last;
}

/// Runs `model` in both kinds to `stop` and compares `names` with `momenta simulate` within `tol`.
/// (Co-Simulation's run stops at every step's end, so its steps are not quite the simulation's.)
void CompareWithSimulate(const std::string& model, double stop, double step,
                         const std::vector<std::string>& names, double tol) {
  TempDir dir;
  const std::string fmu = Export(dir, model);
  ASSERT_FALSE(fmu.empty());
  FmuImporter importer(fmu, dir.File("unpacked"));
  ASSERT_EQ(importer.error(), "");
  const std::map<std::string, double> sim = SimulateEnd(dir, model, stop);
  const FmuRunResult cs = importer.RunCoSimulation({}, stop, step, names);
  ASSERT_TRUE(cs.ok) << cs.log;
  const FmuRunResult me = importer.RunModelExchange({}, stop, step, names);
  ASSERT_TRUE(me.ok) << me.log;
  for (const std::string& name : names) {
    EXPECT_NEAR(cs.final.at(name), sim.at(name), tol) << "Co-Simulation, " << name;
    EXPECT_NEAR(me.final.at(name), sim.at(name), tol) << "Model Exchange, " << name;
  }
}

TEST_F(FmuTest, BouncingBallMatchesSimulate) {
  // Between the bounces the ball falls freely, which RK4 integrates exactly, and each impact is
  // located by bisection: in flight at 2.5 s the Model Exchange run is within 1e-12 of the
  // simulation (tolerance 1e-8; measured 5e-13); at 6 s, past the accumulation of the bounces at
  // 4.06 s, the contact has closed in both and the ball rests at s = 0. 1e-9 leaves room.
  CompareWithSimulate("models/bouncing_ball.yaml", 2.5, 0.01, {"ball.s", "ball.v"}, 1e-9);
  CompareWithSimulate("models/bouncing_ball.yaml", 6, 0.01, {"ball.s", "ball.v"}, 1e-9);
}

TEST_F(FmuTest, PlanarDoublePendulumMatchesSimulate) {
  // A planar multibody model: the importer integrates the states the build chose and the FMU
  // solves the algebraic part at every derivative. RK4 at 1 ms differs from the simulation
  // (tolerance 1e-10, its error test on the four states) by 1.3e-8 at most over 1 s (measured;
  // 4.3e-10 with every unknown in the simulation's error test); 5e-8 rad and rad/s.
  CompareWithSimulate("models/double_pendulum.yaml", 1.0, 0.001,
                      {"joint1.phi", "joint2.phi", "joint1.w", "joint2.w"}, 5e-8);
}

TEST_F(FmuTest, TimeEventsComeFromNextEventTime) {
  // MSL's Blocks.Examples.Filter: a step at 0.1 s (a time event: no event indicator crosses, the
  // FMU gives its time as nextEventTime) into low-pass filters of order 3.
  TempDir dir;
  const std::string model = "models/msl/Blocks/Examples/Filter.yaml";
  const std::string fmu = Export(dir, model);
  ASSERT_FALSE(fmu.empty());
  FmuImporter importer(fmu, dir.File("unpacked"));
  ASSERT_EQ(importer.error(), "");
  const std::vector<std::string> names = {"Bessel.x[1]", "Butterworth.x[3]"};
  const std::map<std::string, double> sim = SimulateEnd(dir, model, 0.3);
  const FmuRunResult me = importer.RunModelExchange({}, 0.3, 0.001, names);
  ASSERT_TRUE(me.ok) << me.log;
  EXPECT_EQ(me.events, 1);
  for (const std::string& name : names) {
    EXPECT_NEAR(me.final.at(name), sim.at(name), 1e-6) << name;
  }
}

TEST_F(FmuTest, DescriptionIsValidAgainstTheFmi2Schema) {
  TempDir dir;
  for (const char* model : {"models/carrier_collision.yaml", "models/double_pendulum.yaml"}) {
    const std::string fmu = Export(dir, model);
    ASSERT_FALSE(fmu.empty());
    FmuImporter importer(fmu, dir.File("unpacked"));
    const std::string out = Shell("xmllint --noout --schema '" +
                                  SourcePath("tests/data/fmi-schema/fmi2ModelDescription.xsd") +
                                  "' '" + dir.File("unpacked/modelDescription.xml") + "' 2>&1");
    EXPECT_NE(out.find("validates"), std::string::npos) << model << ":\n" << out;
  }
}

TEST_F(FmuTest, BinaryNeedsOnlyTheCAndCxxRuntime) {
  TempDir dir;
  const std::string fmu = Export(dir, "models/carrier_collision.yaml");
  ASSERT_FALSE(fmu.empty());
  FmuImporter importer(fmu, dir.File("unpacked"));
  const std::string ldd =
      Shell("ldd '" + dir.File("unpacked/binaries/linux64/CarrierCollision.so") + "'");
  ASSERT_NE(ldd.find("libc.so"), std::string::npos) << ldd;
  std::istringstream lines(ldd);
  for (std::string line; std::getline(lines, line);) {
    const bool allowed =
        line.find("linux-vdso") != std::string::npos || line.find("libc.so") != std::string::npos ||
        line.find("libm.so") != std::string::npos || line.find("libstdc++") != std::string::npos ||
        line.find("libgcc_s") != std::string::npos || line.find("ld-linux") != std::string::npos;
    EXPECT_TRUE(allowed) << "a dependency beyond the C and C++ runtime: " << line;
  }
  // Only the FMI functions are exported.
  const std::string symbols =
      Shell("nm -D --defined-only '" + dir.File("unpacked/binaries/linux64/CarrierCollision.so") +
            "' | awk '{print $3}' | grep -v '^fmi2' | grep -c .");
  EXPECT_EQ(std::stoi(symbols), 0) << symbols;
}

TEST_F(FmuTest, GuidChangesWithTheStructureNotWithValues) {
  TempDir dir;
  const std::string model = ReadText(SourcePath("models/carrier_collision.yaml"));
  int unpacked = 0;
  auto guid = [&](const std::string& file, const std::vector<std::string>& extra) {
    const CliResult r = RunMomenta(
        [&] {
          std::vector<std::string> a = {"fmu", file, "-o", dir.File("g.fmu")};
          a.insert(a.end(), extra.begin(), extra.end());
          return a;
        }(),
        dir.path());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    FmuImporter importer(dir.File("g.fmu"), dir.File("g" + std::to_string(++unpacked)));
    return importer.guid();
  };
  const std::string base = guid(SourcePath("models/carrier_collision.yaml"), {});
  EXPECT_EQ(guid(SourcePath("models/carrier_collision.yaml"), {"-p", "eC=0.5"}), base);
  // One output fewer: another structure.
  const size_t at = model.find("S.s, ");
  ASSERT_NE(at, std::string::npos);
  std::string fewer = model;
  fewer.erase(at, 5);
  const std::string other = guid(dir.Write("fewer.yaml", fewer), {});
  EXPECT_NE(other, base);
  EXPECT_FALSE(base.empty());
}

TEST_F(FmuTest, WrongGuidIsRefusedAndATunableParameterTakesEffectBetweenSteps) {
  TempDir dir;
  const std::string fmu = Export(dir, "models/carrier_collision.yaml");
  ASSERT_FALSE(fmu.empty());
  FmuImporter importer(fmu, dir.File("unpacked"));
  testing::TakeFmuLog();
  EXPECT_EQ(importer.Instantiate(fmi2CoSimulation, "{00000000-0000-0000-0000-000000000000}"),
            nullptr);
  EXPECT_NE(testing::TakeFmuLog().find(
                "the GUID {00000000-0000-0000-0000-000000000000} is not that of the model"),
            std::string::npos);
  // eS (the suitcase's restitution) set to 1 between two steps, at 0.22 s: after the carriers'
  // impact at 0.2 s (vB = 4.5) and before the suitcase's at 0.2667 s, which is then elastic:
  // vB = (mB - mS) vB1 / (mB + mS) = 25/55 * 4.5 (tunable; before, the FMU refused it).
  fmi2Component c = importer.Instantiate(fmi2CoSimulation, importer.guid());
  ASSERT_NE(c, nullptr);
  ASSERT_EQ(
      importer.Function<decltype(&fmi2EnterInitializationMode)>("fmi2EnterInitializationMode")(c),
      fmi2OK);
  ASSERT_EQ(
      importer.Function<decltype(&fmi2ExitInitializationMode)>("fmi2ExitInitializationMode")(c),
      fmi2OK);
  auto step = importer.Function<decltype(&fmi2DoStep)>("fmi2DoStep");
  double t = 0;
  for (; t < 0.22 - 1e-9; t += 0.01) ASSERT_EQ(step(c, t, 0.01, fmi2True), fmi2OK) << t;
  const fmi2ValueReference es = importer.ValueReference("eS");
  const double elastic = 1;
  EXPECT_EQ(importer.Function<decltype(&fmi2SetReal)>("fmi2SetReal")(c, &es, 1, &elastic), fmi2OK);
  for (; t < 0.5 - 1e-9; t += 0.01) ASSERT_EQ(step(c, t, 0.01, fmi2True), fmi2OK) << t;
  const fmi2ValueReference bv = importer.ValueReference("B.v");
  double vb = 0;
  ASSERT_EQ(importer.Function<decltype(&fmi2GetReal)>("fmi2GetReal")(c, &bv, 1, &vb), fmi2OK);
  EXPECT_NEAR(vb, 25.0 / 55.0 * 4.5, 1e-9);
  importer.Free(c);
}

TEST_F(FmuTest, CommandErrorsNameTheOption) {
  TempDir dir;
  const std::string model = SourcePath("models/carrier_collision.yaml");
  CliResult r = RunMomenta({"fmu", model, "-p", "eX=1", "-o", dir.File("a.fmu")}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("eX"), std::string::npos) << r.err;
  r = RunMomenta({"fmu", model, "--kind", "hybrid", "-o", dir.File("a.fmu")}, dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.err.find("--kind hybrid: the choices are me (Model Exchange), cs (Co-Simulation) and both"),
      std::string::npos)
      << r.err;
  r = RunMomenta({"fmu", model, "-o", dir.File("no/such/folder/a.fmu")}, dir.path());
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("cannot write " + dir.File("no/such/folder/a.fmu")), std::string::npos)
      << r.err;
  // A kind alone: the description has that element only.
  r = RunMomenta({"fmu", model, "--kind", "cs", "-o", dir.File("cs.fmu")}, dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  FmuImporter importer(dir.File("cs.fmu"), dir.File("cs"));
  const std::string xml = ReadText(dir.File("cs/modelDescription.xml"));
  EXPECT_EQ(xml.find("<ModelExchange"), std::string::npos);
  EXPECT_NE(xml.find("<CoSimulation"), std::string::npos);
}

}  // namespace
}  // namespace momenta
