// The house's shape, checked on the source tree (docs/ARCHITECTURE.md): dependencies point one way
// through core's stages (base <- expr <- lang <- flatten <- passes <- compile <- the pipeline) and
// then core <- solver <- app; the app and the Python module (python/) see only core's public face;
// no yaml-cpp or SUNDIALS header is in a public header of core or of the solver; no source file is
// longer than 800 lines.
//
// A new include that runs against the pipeline fails here with the file, the line and the rule,
// before it makes two stages depend on each other in a circle.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace momenta {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = MOMENTA_SOURCE_DIR;

struct Include {
  std::string header;  ///< as written: "core/flatten/flatten.h" or "yaml-cpp/yaml.h"
  bool angled = false;
  int line = 0;
};

std::vector<Include> IncludesOf(const fs::path& file) {
  static const std::regex kInclude(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
  std::vector<Include> out;
  std::ifstream in(file);
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::smatch m;
    if (std::regex_search(text, m, kInclude)) out.push_back({m[2], m[1] == "<", line});
  }
  return out;
}

/// Every C++ source and header below `dir` (relative to the source tree).
std::vector<fs::path> SourcesUnder(const std::string& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::recursive_directory_iterator(kSource / dir)) {
    const auto ext = entry.path().extension();
    if (entry.is_regular_file() && (ext == ".h" || ext == ".cc")) out.push_back(entry.path());
  }
  return out;
}

std::string Relative(const fs::path& file) { return fs::relative(file, kSource).string(); }

/// A core file's stage by its folder; the files at core/'s top (the pipeline and its report)
/// come last.
int CoreRank(const std::string& path) {
  static const std::vector<std::string> kStages = {"base", "expr", "lang", "flatten", "passes",
                                                   "compile"};
  for (size_t i = 0; i < kStages.size(); ++i) {
    if (path.rfind("core/" + kStages[i] + "/", 0) == 0) return static_cast<int>(2 * i);
  }
  return 2 * static_cast<int>(kStages.size());
}

TEST(LayeringTest, CoreIncludesFollowThePipeline) {
  std::vector<std::string> wrong;
  for (const auto& file : SourcesUnder("core")) {
    const std::string path = Relative(file);
    for (const auto& inc : IncludesOf(file)) {
      if (inc.angled) continue;
      const std::string where = path + ":" + std::to_string(inc.line) + ": " + inc.header;
      if (inc.header.rfind("solver/", 0) == 0 || inc.header.rfind("app/", 0) == 0) {
        wrong.push_back(where + " (core includes neither solver nor app)");
      } else if (inc.header.rfind("core/", 0) == 0 && CoreRank(inc.header) > CoreRank(path)) {
        wrong.push_back(where + " (a later stage)");
      }
    }
  }
  EXPECT_TRUE(wrong.empty()) << "includes against the pipeline:\n  " << ::testing::PrintToString(wrong);
}

TEST(LayeringTest, SolverIncludesNoApp) {
  std::vector<std::string> wrong;
  for (const auto& file : SourcesUnder("solver")) {
    for (const auto& inc : IncludesOf(file)) {
      if (!inc.angled && inc.header.rfind("app/", 0) == 0) {
        wrong.push_back(Relative(file) + ":" + std::to_string(inc.line) + ": " + inc.header);
      }
    }
  }
  EXPECT_TRUE(wrong.empty()) << ::testing::PrintToString(wrong);
}

/// What the command line may include of core and of the solver: the pipeline's entry, the
/// loader, the built model and its state, and the vocabulary they are written in.
const std::set<std::string>& AppFace() {
  static const std::set<std::string> face = {
      "core/build.h",                 // BuildModel and the build's report
      "core/build_report.h",          //
      "core/lang/yaml_loader.h",      // LoadModelFile
      "core/lang/builtin_library.h",  // the library `list` shows and models are built from
      "core/lang/compiled_types.h",   // its types as the build parsed them (main)
      "core/lang/model_spec.h",       // the experiment section, outputs
      "core/lang/units.h",            // `-p k=10kN/m`
      "core/lang/instance_scope.h",   // the report's scene: a type's expressions in an instance
      "core/compile/compiled_model.h",
      "core/compile/model_state.h",
      "core/compile/native_code.h",   // --codegen
      "core/base/error.h",
      "core/base/messages.h",
      "core/base/memory_budget.h",    // a build that turns out large restarts on huge pages
      "core/base/regular_file.h",     // result files are opened as model files are (no FIFO)
      "solver/simulator.h",
      "solver/simulation_options.h",
      "solver/linearization.h",       // `momenta linearize`: the state-space form where the model stands
  };
  return face;
}

TEST(LayeringTest, AppIncludesOnlyThePublicFace) {
  std::vector<std::string> wrong;
  for (const auto& file : SourcesUnder("app")) {
    for (const auto& inc : IncludesOf(file)) {
      const bool ours = inc.header.rfind("core/", 0) == 0 || inc.header.rfind("solver/", 0) == 0;
      if (!inc.angled && ours && !AppFace().count(inc.header)) {
        wrong.push_back(Relative(file) + ":" + std::to_string(inc.line) + ": " + inc.header);
      }
    }
  }
  EXPECT_TRUE(wrong.empty()) << "app/ reaches past core's and the solver's public face:\n  "
                             << ::testing::PrintToString(wrong);
}

TEST(LayeringTest, PythonModuleIncludesOnlyThePublicFace) {
  // python/ is a front end beside the command line: the app's face, and of the app only the run
  // options a command line and a Python call both resolve from the experiment section.
  std::vector<std::string> wrong;
  for (const auto& file : SourcesUnder("python")) {
    for (const auto& inc : IncludesOf(file)) {
      const bool ours = inc.header.rfind("core/", 0) == 0 || inc.header.rfind("solver/", 0) == 0 ||
                        inc.header.rfind("app/", 0) == 0;
      if (!inc.angled && ours && !AppFace().count(inc.header) && inc.header != "app/simulate_options.h") {
        wrong.push_back(Relative(file) + ":" + std::to_string(inc.line) + ": " + inc.header);
      }
    }
  }
  EXPECT_TRUE(wrong.empty()) << "python/ reaches past the public face:\n  " << ::testing::PrintToString(wrong);
}

/// The headers a public header brings in, followed through the project's own headers.
void CollectIncludes(const std::string& header, std::set<std::string>* seen) {
  if (!seen->insert(header).second || !fs::exists(kSource / header)) return;
  for (const auto& inc : IncludesOf(kSource / header)) {
    if (inc.angled) {
      seen->insert("<" + inc.header + ">");
    } else {
      CollectIncludes(inc.header, seen);
    }
  }
}

TEST(LayeringTest, PublicHeadersHoldNoYamlCppOrSundials) {
  static const std::regex kThirdParty(
      R"(^<(yaml-cpp/|yaml\.h|sundials/|ida/|kinsol/|nvector/|sunmatrix/|sunlinsol/|sunnonlinsol/))");
  std::vector<std::string> wrong;
  for (const auto& header : AppFace()) {
    std::set<std::string> seen;
    CollectIncludes(header, &seen);
    for (const auto& inc : seen) {
      if (std::regex_search(inc, kThirdParty)) wrong.push_back(header + " brings in " + inc);
    }
  }
  // Every header of core (what any stage may include) is free of yaml-cpp and SUNDIALS too.
  for (const auto& file : SourcesUnder("core")) {
    if (file.extension() != ".h") continue;
    for (const auto& inc : IncludesOf(file)) {
      if (inc.angled && std::regex_search("<" + inc.header, kThirdParty)) {
        wrong.push_back(Relative(file) + ":" + std::to_string(inc.line) + ": <" + inc.header + ">");
      }
    }
  }
  EXPECT_TRUE(wrong.empty()) << ::testing::PrintToString(wrong);
}

TEST(LayeringTest, NoSourceFileOver800Lines) {
  std::vector<std::string> wrong;
  for (const char* dir : {"core", "solver", "app", "python"}) {
    for (const auto& file : SourcesUnder(dir)) {
      std::ifstream in(file);
      size_t lines = 0;
      for (std::string text; std::getline(in, text);) ++lines;
      if (lines > 800) wrong.push_back(Relative(file) + ": " + std::to_string(lines) + " lines");
    }
  }
  EXPECT_TRUE(wrong.empty()) << "files that hold several jobs (split them along their jobs):\n  "
                             << ::testing::PrintToString(wrong);
}

}  // namespace
}  // namespace momenta
