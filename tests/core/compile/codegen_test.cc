// The C the code generator emits: every program of every model, compiled, gives the interpreter's
// results to the bit on the same registers; names that are not C identifiers stay in comments.
#include "core/compile/codegen.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <random>

#include "core/compile/native_code.h"
#include "tests/support/cache_dir.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

/// Compiles into a cache of its own.
class CodegenTest : public ::testing::Test {
 protected:
  testing::ScopedCacheDir cache_;
};

/// How many values a program writes to `out`.
size_t OutSize(const Program& p) {
  size_t n = 0;
  for (const Instruction& in : p.code()) {
    if (in.op == kStore) n = std::max<size_t>(n, in.dst + 1);
  }
  return n;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

/// Runs every program of `model` interpreted and native on the same random register file and
/// compares the outputs and every register that is not a temporary.
void ExpectProgramsBitEqual(const CompiledModel& model, const NativeCode& native, const std::string& what) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> value(-3.0, 3.0);
  const RegisterLayout& L = model.layout;
  for (size_t k = 0; k < kNumModelPrograms; ++k) {
    if (!IsNativeProgram(static_cast<ModelProgram>(k))) {
      EXPECT_FALSE(native.function(static_cast<ModelProgram>(k)));
      continue;
    }
    const Program& p = ProgramOf(model, static_cast<ModelProgram>(k));
    std::vector<double> regs(L.size);
    for (double& r : regs) r = value(rng);
    for (const auto& [reg, v] : model.constants) regs[reg] = v;
    // Tables must have increasing abscissas: the parameters keep the model's order of values
    // only if they are sorted, so give the parameters an increasing sequence.
    for (uint32_t j = 0; j < L.num_params; ++j) regs[L.param_base + j] = 0.25 * j - 1.0;
    // Native code reads y and y' from its arguments: their registers hold NaN for it.
    std::vector<double> regs_native = regs;
    const std::vector<double> y(regs.begin() + L.y_base, regs.begin() + L.y_base + L.num_unknowns);
    const std::vector<double> yp(regs.begin() + L.yp_base, regs.begin() + L.yp_base + L.num_unknowns);
    std::fill_n(regs_native.begin() + L.y_base, L.num_unknowns, std::nan(""));
    std::fill_n(regs_native.begin() + L.yp_base, L.num_unknowns, std::nan(""));
    const size_t n = OutSize(p);
    std::vector<double> out(n + 1, -7.0), out_native(n + 1, -7.0);
    p.Run(regs.data(), out.data());
    native.function(static_cast<ModelProgram>(k))(regs_native.data(), y.data(), yp.data(), out_native.data());
    for (size_t j = 0; j < n; ++j) {
      ASSERT_TRUE(SameBits(out[j], out_native[j]))
          << what << " program " << k << " out[" << j << "]: " << out[j] << " vs " << out_native[j];
    }
    for (uint32_t r = 0; r < L.temp_base; ++r) {
      if (r - L.y_base < L.num_unknowns || r - L.yp_base < L.num_unknowns) continue;
      ASSERT_TRUE(SameBits(regs[r], regs_native[r])) << what << " program " << k << " register " << r;
    }
  }
}

std::vector<std::string> AllModelFiles() {
  std::vector<std::string> files;
  for (const char* dir : {"models", "models/msl"}) {
    for (const auto& entry : std::filesystem::directory_iterator(testing::SourcePath(dir))) {
      if (entry.path().extension() == ".yaml") files.push_back(std::string(dir) + "/" + entry.path().filename().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST_F(CodegenTest, EveryProgramOfEveryModelIsBitIdenticalNative) {
  NativeCodeOptions native;
  native.mode = CodegenMode::kNative;
  // Small functions too (on every third model, to keep the test short), so that temporaries
  // cross function boundaries.
  const std::vector<std::string> files = AllModelFiles();
  for (uint32_t max_len : {2000u, 7u}) {
    native.max_function_len = max_len;
    for (size_t f = 0; f < files.size(); f += max_len == 7 ? 3 : 1) {
      const std::string& file = files[f];
      SCOPED_TRACE(file);
      testing::Built b = testing::BuildFile(file);
      NativeCodeReport report;
      std::shared_ptr<const NativeCode> code = LoadNativeCode(*b.model, native, &report);
      ASSERT_TRUE(code) << report.note;
      ExpectProgramsBitEqual(*b.model, *code, file);
    }
  }
}

TEST(CodegenEmitTest, SplitsLongProgramsIntoBoundedFunctions) {
  Program p;
  for (uint32_t k = 0; k < 10; ++k) p.code().push_back({static_cast<uint8_t>(Op::kAdd), 100 + k % 3, 3, 4, 0});
  std::vector<CodeSegment> segments = StraightSegments(p, 4);
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[2].begin, 8u);
  EXPECT_EQ(segments[2].len, 2u);
  RegisterLayout layout;
  layout.temp_base = 100;
  layout.size = 104;
  CodegenOptions options;
  options.max_function_len = 4;
  const std::string c = EmitC({{"f", &p, {}}}, layout, options);
  EXPECT_NE(c.find("static __attribute__((noinline)) void f_2("), std::string::npos);
  EXPECT_EQ(c.find("f_3("), std::string::npos);
}

TEST(CodegenEmitTest, CommentsHoldNoCommentDelimitersOrNonAscii) {
  EXPECT_EQ(SanitizeComment("a */ b /* c"), "a *| b |* c");
  EXPECT_EQ(SanitizeComment("R\xc3\xa9sistance\n"), "R??sistance?");
  RegisterLayout layout;
  CodegenOptions options;
  options.comment = "evil */ #include <stdio.h> /*";
  const std::string c = EmitC({}, layout, options);
  EXPECT_EQ(c.find("*/ #include"), std::string::npos);
}

/// Rerolled segments become C loops: with n = 200 identical components the C of the residual and
/// the Jacobian is a small fraction of the straight-line C and holds `for` loops, and the compiled
/// loops give the interpreter's values to the bit, program by program and over a whole run.
TEST_F(CodegenTest, IdenticalComponentsBecomeLoopsWithTheSameResults) {
  for (const char* file : {"models/spring_damper_chain.yaml", "models/rc_ladder.yaml"}) {
    SCOPED_TRACE(file);
    testing::Built b = testing::BuildFile(file, {{"n", 200}});
    for (const Program* p : {&b.model->residual, &b.model->jacobian}) {
      const std::vector<CodeSegment> loops = LoopSegments(*p, 2000);
      const std::string rolled = EmitC({{"f", p, loops}}, b.model->layout, {});
      const std::string straight = EmitC({{"f", p, StraightSegments(*p, 2000)}}, b.model->layout, {});
      EXPECT_NE(rolled.find("for (ptrdiff_t i = 0; i < "), std::string::npos);
      const size_t prelude = EmitC({}, b.model->layout, {}).size();  // the helpers, in both
      EXPECT_LT((rolled.size() - prelude) * 10, straight.size() - prelude) << rolled.size() << " vs " << straight.size();
      // The segments cover the program in order.
      uint32_t next = 0;
      for (const CodeSegment& s : loops) {
        EXPECT_EQ(s.begin, next);
        next = s.begin + s.len * s.count;
      }
      EXPECT_EQ(next, p->size());
    }
    NativeCodeOptions native;
    native.mode = CodegenMode::kNative;
    NativeCodeReport report;
    testing::Built nb{AttachNativeCode(b.model, native, &report), b.report};
    ASSERT_TRUE(nb.model->native) << report.note;
    EXPECT_LT(report.emitted * 10, report.instructions);
    ExpectProgramsBitEqual(*nb.model, *nb.model->native, file);
    SimulationOptions options = OptionsFromExperiment(b.model->experiment);
    options.stop = std::min(options.stop, 0.5);
    testing::Trajectory interp = testing::Run(b, options);
    testing::Trajectory compiled = testing::Run(nb, options);
    EXPECT_EQ(interp.values, compiled.values);
    EXPECT_EQ(interp.stats.steps, compiled.stats.steps);
  }
}

/// A loop whose temporaries move with the repetition (a value carried from one repetition to the
/// next through registers t[i]) keeps them in the register file, indexed by i.
TEST(CodegenEmitTest, MovingTemporariesStayInTheRegisterFile) {
  // t[i+1] = t[i] + r[3 + i], for i < 40: temporaries 100..140.
  Program p;
  for (uint32_t i = 0; i < 40; ++i) p.code().push_back({static_cast<uint8_t>(Op::kAdd), 101 + i, 100 + i, 3 + i, 0});
  p.code().push_back({kStore, 0, 140, 0, 0});
  const std::vector<CodeSegment> segments = LoopSegments(p, 2000);
  const auto loop = std::find_if(segments.begin(), segments.end(), [](const CodeSegment& s) { return s.count > 1; });
  ASSERT_NE(loop, segments.end());
  ASSERT_EQ(loop->len, 1u);
  const Instruction& body = p.code()[loop->begin];
  RegisterLayout layout;
  layout.temp_base = 100;
  layout.size = 141;
  const std::string c = EmitC({{"f", &p, segments}}, layout, {});
  const std::string statement = "r[" + std::to_string(body.dst) + " + 1 * i] = r[" + std::to_string(body.a) +
                                " + 1 * i] + r[" + std::to_string(body.b) + " + 1 * i];";
  EXPECT_NE(c.find(statement), std::string::npos) << c;
  // The loop's temporaries are no locals of its function.
  EXPECT_EQ(c.find("double t" + std::to_string(body.dst - 100) + ";"), std::string::npos) << c;
}

/// The same program compiled as a model's residual gives the interpreter's value to the bit.
TEST_F(CodegenTest, MovingTemporariesCompileToTheInterpretersValues) {
  CompiledModel model;
  model.layout.param_base = model.layout.y_base = model.layout.yp_base = 3;
  model.layout.disc_base = model.layout.pre_base = model.layout.cond_base = 100;
  model.layout.temp_base = 100;
  model.layout.size = 141;
  for (uint32_t i = 0; i < 40; ++i) {
    model.residual.code().push_back({static_cast<uint8_t>(Op::kAdd), 101 + i, 100 + i, 3 + i, 0});
  }
  model.residual.code().push_back({kStore, 0, 140, 0, 0});
  NativeCodeOptions native;
  native.mode = CodegenMode::kNative;
  NativeCodeReport report;
  std::shared_ptr<const NativeCode> code = LoadNativeCode(model, native, &report);
  ASSERT_TRUE(code) << report.note;
  std::vector<double> regs(141), regs_native;
  for (uint32_t k = 0; k < regs.size(); ++k) regs[k] = 0.1 * k + 1.0 / (k + 3);
  regs_native = regs;
  double out = 0, out_native = 1;
  model.residual.Run(regs.data(), &out);
  code->function(ModelProgram::kResidual)(regs_native.data(), nullptr, nullptr, &out_native);
  EXPECT_TRUE(SameBits(out, out_native)) << out << " vs " << out_native;
}

/// A loop whose operand runs from the unknowns' registers through their derivatives' into the
/// rest of the register file reads each repetition's value from the right array (y, yp, r).
TEST_F(CodegenTest, LoopsReadingAcrossTheUnknownsFindEachArray) {
  // t[i+1] = t[i] * r[90] + r[first + i*step]: with first 13, step 1 and 40 repetitions the
  // operand runs through y (3..22), then yp (23..42), then the rest; with first 1, step 7 and 10
  // repetitions it steps from before y through y and yp to after them (its first and last
  // registers are both in r, some between are not).
  for (const auto [first, step, count] : {std::array<uint32_t, 3>{13, 1, 40}, std::array<uint32_t, 3>{1, 7, 10}}) {
    CompiledModel model;
    model.layout.param_base = 3;
    model.layout.y_base = 3;
    model.layout.num_unknowns = 20;
    model.layout.yp_base = 23;
    model.layout.disc_base = model.layout.pre_base = model.layout.cond_base = 43;
    model.layout.temp_base = 100;
    model.layout.size = 141;
    for (uint32_t i = 0; i < count; ++i) {
      model.residual.code().push_back({static_cast<uint8_t>(Op::kMul), 101 + i, 100 + i, 90, 0});
      model.residual.code().push_back({static_cast<uint8_t>(Op::kAdd), 101 + i, 101 + i, first + i * step, 0});
    }
    model.residual.code().push_back({kStore, 0, 100 + count, 0, 0});
    const std::vector<CodeSegment> segments = LoopSegments(model.residual, 2000);
    const std::string c = EmitC({{"f", &model.residual, segments}}, model.layout, {});
    EXPECT_NE(c.find("for (ptrdiff_t i"), std::string::npos) << c;
    EXPECT_NE(c.find("m_reg(r, y, yp, "), std::string::npos) << c;
    NativeCodeOptions native;
    native.mode = CodegenMode::kNative;
    NativeCodeReport report;
    std::shared_ptr<const NativeCode> code = LoadNativeCode(model, native, &report);
    ASSERT_TRUE(code) << report.note;
    std::vector<double> regs(141);
    for (uint32_t k = 0; k < regs.size(); ++k) regs[k] = 0.1 * k + 1.0 / (k + 3);
    std::vector<double> regs_native = regs;
    const std::vector<double> y(regs.begin() + 3, regs.begin() + 23), yp(regs.begin() + 23, regs.begin() + 43);
    std::fill(regs_native.begin() + 3, regs_native.begin() + 43, std::nan(""));
    double out = 0, out_native = 1;
    model.residual.Run(regs.data(), &out);
    code->function(ModelProgram::kResidual)(regs_native.data(), y.data(), yp.data(), &out_native);
    EXPECT_TRUE(SameBits(out, out_native)) << "step " << step << ": " << out << " vs " << out_native;
  }
}

// Component names are ASCII identifiers (the loader's rule), so unicode reaches the code only
// through the model's name; array elements and dotted paths through every variable.
TEST_F(CodegenTest, ModelWithUnicodeAndDottedNamesCompilesAndMatches) {
  testing::Built b = testing::BuildYaml(R"(
model: "Résumé */ of a chain /*"
doc: "ünïcödé */ everywhere"
components:
  masse: {type: Mass, count: 2, m: 2, s: {start: 1, fixed: true}, v: {start: 0, fixed: true}}
  ressort: {type: Spring, c: 50}
  fixed: {type: Fixed}
connections:
  - [fixed.flange, "ressort.flange_a"]
  - ["ressort.flange_b", "masse[1].flange_a"]
  - ["masse[1].flange_b", "masse[2].flange_a"]
outputs: ["masse[2].s", "masse[1].flange_b.f"]
experiment: {stop: 1, interval: 0.1}
)");
  NativeCodeOptions native;
  native.mode = CodegenMode::kNative;
  NativeCodeReport report;
  std::shared_ptr<const CompiledModel> nm = AttachNativeCode(b.model, native, &report);
  ASSERT_TRUE(nm->native) << report.note;
  testing::Trajectory interp = testing::RunDefault(b);
  testing::Trajectory compiled = testing::RunDefault({nm, b.report});
  ASSERT_EQ(interp.values.size(), compiled.values.size());
  for (size_t row = 0; row < interp.values.size(); ++row) EXPECT_EQ(interp.values[row], compiled.values[row]);
}

}  // namespace
}  // namespace momenta
