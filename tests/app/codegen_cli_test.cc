// `momenta simulate --codegen`: native code gives the interpreter's file byte for byte, the summary
// says what ran, and without a compiler the run goes on interpreted after a one-line note.
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

class CodegenCliTest : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("MOMENTA_CACHE_DIR", dir_.File("cache").c_str(), 1); }
  void TearDown() override {
    ::unsetenv("MOMENTA_CACHE_DIR");
    ::unsetenv("MOMENTA_CC");
  }
  testing::CliResult Simulate(const std::string& codegen, const std::string& out) {
    return testing::RunMomenta({"simulate", testing::SourcePath("models/spring_damper_chain.yaml"), "-p", "n=3",
                                "--codegen", codegen, "-o", out},
                               dir_.path());
  }
  testing::TempDir dir_;
};

TEST_F(CodegenCliTest, NativeWritesTheInterpretersResults) {
  testing::CliResult interp = Simulate("interp", "interp.csv");
  ASSERT_EQ(interp.exit_code, 0) << interp.err;
  EXPECT_NE(interp.out.find("code: interpreter"), std::string::npos) << interp.out;
  testing::CliResult native = Simulate("native", "native.csv");
  ASSERT_EQ(native.exit_code, 0) << native.err;
  EXPECT_NE(native.out.find("code: native code"), std::string::npos) << native.out;
  EXPECT_NE(native.out.find("compiled in"), std::string::npos) << native.out;
  EXPECT_EQ(testing::ReadText(dir_.File("native.csv")), testing::ReadText(dir_.File("interp.csv")));
  // Again: from the cache.
  testing::CliResult again = Simulate("native", "again.csv");
  EXPECT_NE(again.out.find("cached"), std::string::npos) << again.out;
}

TEST_F(CodegenCliTest, WithoutCompilerFallsBackWithANote) {
  ::setenv("MOMENTA_CC", "/nonexistent", 1);
  testing::CliResult r = Simulate("native", "out.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: no C compiler (/nonexistent) found: the model runs interpreted\n"), std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("code: interpreter"), std::string::npos) << r.out;
}

TEST_F(CodegenCliTest, RejectsAnUnknownChoice) {
  testing::CliResult r = Simulate("jit", "out.csv");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--codegen"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace momenta
