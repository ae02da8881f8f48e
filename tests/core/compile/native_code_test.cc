// Native model code: the cache (kept across parameter changes, renewed on a structural change,
// rebuilt when corrupted or foreign), the fallback without a compiler, and every model simulated
// natively giving the interpreter's results.
#include "core/compile/native_code.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/support/cache_dir.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

class NativeCodeTest : public ::testing::Test {
 protected:
  void SetUp() override { native_.mode = CodegenMode::kNative; }
  void TearDown() override { ::unsetenv("MOMENTA_CC"); }
  testing::ScopedCacheDir cache_;
  NativeCodeOptions native_;
};

const char* kChain = "models/spring_damper_chain.yaml";

TEST_F(NativeCodeTest, ParameterChangeReusesTheCachedCode) {
  testing::Built a = testing::BuildFile(kChain, {{"n", 4}});
  NativeCodeReport first;
  ASSERT_TRUE(LoadNativeCode(*a.model, native_, &first)) << first.note;
  EXPECT_FALSE(first.cache_hit);
  EXPECT_TRUE(std::filesystem::exists(first.library));
  // Another mass: the same structure, so the same key and no compilation.
  const uint64_t compilations = NativeCompilations();
  testing::Built b = testing::BuildFile(kChain, {{"n", 4}, {"mass[2].m", 3.5}});
  EXPECT_EQ(NativeCodeKey(*a.model, native_), NativeCodeKey(*b.model, native_));
  NativeCodeReport second;
  std::shared_ptr<const CompiledModel> nb = AttachNativeCode(b.model, native_, &second);
  ASSERT_TRUE(nb->native) << second.note;
  EXPECT_TRUE(second.cache_hit);
  EXPECT_EQ(NativeCompilations(), compilations);
  // And the parameter value is the new one: same results as the interpreter with mass[2].m = 3.5.
  testing::Trajectory interp = testing::RunDefault(b);
  testing::Trajectory compiled = testing::RunDefault({nb, b.report});
  EXPECT_EQ(interp.values, compiled.values);
}

TEST_F(NativeCodeTest, StructuralChangeCompilesAgain) {
  testing::Built a = testing::BuildFile(kChain, {{"n", 4}});
  testing::Built b = testing::BuildFile(kChain, {{"n", 5}});
  EXPECT_NE(NativeCodeKey(*a.model, native_), NativeCodeKey(*b.model, native_));
  NativeCodeReport ra, rb;
  ASSERT_TRUE(LoadNativeCode(*a.model, native_, &ra)) << ra.note;
  const uint64_t compilations = NativeCompilations();
  ASSERT_TRUE(LoadNativeCode(*b.model, native_, &rb)) << rb.note;
  EXPECT_FALSE(rb.cache_hit);
  EXPECT_EQ(NativeCompilations(), compilations + 1);
  EXPECT_NE(ra.library, rb.library);
}

TEST_F(NativeCodeTest, CorruptedCacheEntryIsRebuilt) {
  testing::Built a = testing::BuildFile(kChain, {{"n", 3}});
  NativeCodeReport r;
  ASSERT_TRUE(LoadNativeCode(*a.model, native_, &r)) << r.note;  // loaded and released
  // Truncated to half.
  const auto size = std::filesystem::file_size(r.library);
  std::filesystem::resize_file(r.library, size / 2);
  const uint64_t compilations = NativeCompilations();
  NativeCodeReport again;
  std::shared_ptr<const NativeCode> code = LoadNativeCode(*a.model, native_, &again);
  ASSERT_TRUE(code) << again.note;
  EXPECT_FALSE(again.cache_hit);
  EXPECT_EQ(NativeCompilations(), compilations + 1);
  EXPECT_NE(again.reason.find("was rebuilt"), std::string::npos) << again.reason;
  EXPECT_EQ(std::filesystem::file_size(again.library), size);
}

TEST_F(NativeCodeTest, ForeignCacheEntryIsRebuilt) {
  testing::Built a = testing::BuildFile(kChain, {{"n", 3}});
  testing::Built b = testing::BuildFile(kChain, {{"n", 6}});
  NativeCodeReport ra, rb;
  ASSERT_TRUE(LoadNativeCode(*a.model, native_, &ra)) << ra.note;
  ASSERT_TRUE(LoadNativeCode(*b.model, native_, &rb)) << rb.note;
  // b's code and its digest under a's name: passes the digest, loads, but holds b's key.
  std::filesystem::copy_file(rb.library, ra.library, std::filesystem::copy_options::overwrite_existing);
  const auto digest = [](const std::string& library) { return library.substr(0, library.size() - 3) + ".sha256"; };
  std::filesystem::copy_file(digest(rb.library), digest(ra.library), std::filesystem::copy_options::overwrite_existing);
  NativeCodeReport again;
  std::shared_ptr<const CompiledModel> na = AttachNativeCode(a.model, native_, &again);
  ASSERT_TRUE(na->native) << again.note;
  EXPECT_FALSE(again.cache_hit);
  EXPECT_NE(again.reason.find("another model's code"), std::string::npos) << again.reason;
  testing::Trajectory interp = testing::RunDefault(a);
  testing::Trajectory compiled = testing::RunDefault({na, a.report});
  EXPECT_EQ(interp.values, compiled.values);
}

TEST_F(NativeCodeTest, WithoutCompilerTheInterpreterRunsWithANote) {
  ::setenv("MOMENTA_CC", "/nonexistent/cc", 1);
  testing::Built a = testing::BuildFile(kChain, {{"n", 3}});
  NativeCodeReport r;
  std::shared_ptr<const CompiledModel> m = AttachNativeCode(a.model, native_, &r);
  EXPECT_FALSE(m->native);
  EXPECT_FALSE(r.native);
  EXPECT_EQ(r.note, "no C compiler (/nonexistent/cc) found: the model runs interpreted");
  EXPECT_EQ(testing::RunDefault({m, a.report}).values, testing::RunDefault(a).values);
}

TEST_F(NativeCodeTest, AutoKeepsTheInterpreterForSmallModels) {
  testing::Built a = testing::BuildFile(kChain, {{"n", 2}});
  NativeCodeOptions options;  // auto
  NativeCodeReport r;
  const uint64_t compilations = NativeCompilations();
  EXPECT_FALSE(LoadNativeCode(*a.model, options, &r));
  EXPECT_EQ(NativeCompilations(), compilations);
  EXPECT_EQ(r.reason.rfind("auto: ", 0), 0u) << r.reason;
  EXPECT_TRUE(r.note.empty());
  NativeCodeOptions interp;
  interp.mode = CodegenMode::kInterp;
  EXPECT_FALSE(LoadNativeCode(*a.model, interp, &r));
  EXPECT_EQ(r.reason, "--codegen interp");
}

TEST_F(NativeCodeTest, AutoUsesCachedCodeWhereItPays) {
  testing::Built a = testing::BuildFile(kChain, {{"n", 50}});
  NativeCodeOptions automatic;
  NativeCodeReport r;
  // Not cached: one run does not repay the compilation.
  const uint64_t compilations = NativeCompilations();
  EXPECT_FALSE(LoadNativeCode(*a.model, automatic, &r));
  EXPECT_EQ(NativeCompilations(), compilations);
  EXPECT_NE(r.reason.find("--codegen native compiles it once"), std::string::npos) << r.reason;
  // Many runs (a sweep) do.
  automatic.expected_runs = 1e4;
  EXPECT_TRUE(LoadNativeCode(*a.model, automatic, &r)) << r.reason << r.note;
  EXPECT_EQ(NativeCompilations(), compilations + 1);
  // Cached: loading pays even for one run.
  automatic.expected_runs = 1;
  EXPECT_TRUE(LoadNativeCode(*a.model, automatic, &r)) << r.reason;
  EXPECT_TRUE(r.cache_hit);
}

/// A model of over 10 000 instructions is compiled as several translation units at once (on a
/// machine with more than one core) and linked: the same rows.
TEST_F(NativeCodeTest, LargeModelCompiledInPartsGivesTheSameRows) {
  testing::Built b = testing::BuildFile(kChain, {{"n", 500}});
  NativeCodeReport r;
  testing::Built nb{AttachNativeCode(b.model, native_, &r), b.report};
  ASSERT_TRUE(nb.model->native) << r.note;
  EXPECT_GT(r.instructions, 10000u);
  SimulationOptions options = OptionsFromExperiment(b.model->experiment);
  options.stop = 0.2;
  testing::Trajectory interp = testing::Run(b, options);
  testing::Trajectory compiled = testing::Run(nb, options);
  EXPECT_EQ(interp.values, compiled.values);
  EXPECT_EQ(interp.stats.steps, compiled.stats.steps);
}

TEST(NativeCodeModeTest, ParsesTheThreeChoices) {
  CodegenMode mode = CodegenMode::kInterp;
  EXPECT_TRUE(ParseCodegenMode("auto", &mode));
  EXPECT_EQ(mode, CodegenMode::kAuto);
  EXPECT_TRUE(ParseCodegenMode("native", &mode));
  EXPECT_EQ(mode, CodegenMode::kNative);
  EXPECT_TRUE(ParseCodegenMode("interp", &mode));
  EXPECT_EQ(mode, CodegenMode::kInterp);
  EXPECT_FALSE(ParseCodegenMode("jit", &mode));
}

/// Every model in models/ and models/msl simulated with native code gives the interpreter's
/// rows: the programs agree to the bit, so the whole run does.
TEST_F(NativeCodeTest, EveryModelSimulatesTheSameNative) {
  std::vector<std::string> files;
  for (const char* dir : {"models", "models/msl"}) {
    for (const auto& entry : std::filesystem::directory_iterator(testing::SourcePath(dir))) {
      if (entry.path().extension() == ".yaml") files.push_back(std::string(dir) + "/" + entry.path().filename().string());
    }
  }
  std::sort(files.begin(), files.end());
  ASSERT_GT(files.size(), 30u);
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    testing::Built b = testing::BuildFile(file);
    NativeCodeReport r;
    testing::Built nb{AttachNativeCode(b.model, native_, &r), b.report};
    ASSERT_TRUE(nb.model->native) << r.note;
    testing::Trajectory interp = testing::RunDefault(b);
    testing::Trajectory compiled = testing::RunDefault(nb);
    ASSERT_EQ(interp.t, compiled.t);
    EXPECT_EQ(interp.values, compiled.values);
    EXPECT_EQ(interp.stats.steps, compiled.stats.steps);
  }
}

}  // namespace
}  // namespace momenta
