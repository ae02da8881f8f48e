// Start-up: a run loads only the libraries it uses (MPI and libmatio are in plugins, app/plugin.h),
// and the built-in library reads a component type when a model first names it
// (core/lang/builtin_library.cc) with the same result as reading its whole file.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <set>

#include "app/commands.h"
#include "app/sweep_cluster.h"
#include "core/lang/builtin_library.h"
#include "core/lang/yaml_loader.h"
#include "tests/support/cli_runner.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::ReadText;
using testing::RunMomenta;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const char kModel[] = R"(model: Drop
parameters:
  mass: {value: 2, unit: kg}
components:
  m: {type: Mass, m: mass, v: {start: 3, fixed: true}, s: {start: 0, fixed: true}}
experiment: {stop: 1, interval: 0.5}
outputs: [m.s]
)";

/// `momenta simulate` with the dynamic loader naming every library it loads (LD_DEBUG=files).
CliResult SimulateLoggingLibraries(const TempDir& dir, const std::string& output) {
  setenv("LD_DEBUG", "files", 1);
  CliResult r = RunMomenta({"simulate", dir.Write("drop.yaml", kModel), "-o", dir.File(output)}, dir.path());
  unsetenv("LD_DEBUG");
  return r;
}

TEST(StartupTest, ACsvRunLoadsNeitherMpiNorMatio) {
  TempDir dir;
  CliResult r = SimulateLoggingLibraries(dir, "drop.csv");
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  // The log is there (so the absences below mean something): the C library is always loaded.
  EXPECT_TRUE(Contains(r.err, "file=libc.so")) << r.err.substr(0, 2000);
  EXPECT_FALSE(Contains(r.err, "file=libmpi")) << "MPI loaded for a run that writes a CSV file";
  EXPECT_FALSE(Contains(r.err, "file=libmatio")) << "libmatio loaded for a run that writes a CSV file";
  EXPECT_FALSE(Contains(r.err, "file=libhdf5"));
  EXPECT_FALSE(Contains(r.err, "momenta-mat.so"));
}

/// The libraries the dynamic loader loaded, as LD_DEBUG=files names them ("file=libc.so.6 …").
std::set<std::string> LoadedLibraries(const std::string& log) {
  std::set<std::string> files;
  for (size_t at = log.find("file="); at != std::string::npos; at = log.find("file=", at + 1)) {
    const size_t end = log.find_first_of(" \t\n", at);
    files.insert(log.substr(at + 5, end == std::string::npos ? std::string::npos : end - at - 5));
  }
  return files;
}

TEST(StartupTest, ACsvRunLoadsOnlyTheCAndMathLibraries) {
#if !MOMENTA_LEAN_LINK
  GTEST_SKIP() << "built with MOMENTA_LEAN_LINK off, with the sanitizers, or without a library's static "
                  "archive: some of momenta's libraries are shared";
#endif
  // The binary holds the C++ runtime, yaml-cpp and SuiteSparse (cmake/Dependencies.cmake,
  // momenta_lean_link): their symbol lookups were a fifth of a small model's whole run.
  TempDir dir;
  CliResult r = SimulateLoggingLibraries(dir, "drop.csv");
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_EQ(LoadedLibraries(r.err), (std::set<std::string>{"libc.so.6", "libm.so.6"})) << r.err.substr(0, 2000);
}

TEST(StartupTest, AMatRunLoadsTheMatPlugin) {
  TempDir dir;
  CliResult r = SimulateLoggingLibraries(dir, "drop.mat");
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_TRUE(Contains(r.err, "lib/momenta/momenta-mat.so")) << r.err.substr(0, 2000);
  EXPECT_TRUE(Contains(r.err, "file=libmatio")) << r.err.substr(0, 2000);
  EXPECT_FALSE(Contains(r.err, "file=libmpi"));
  // The six matrices were written (their contents: tests/app/mat_test.cc).
  const std::string mat = ReadText(dir.File("drop.mat"));
  for (const char* matrix : {"Aclass", "name", "description", "dataInfo", "data_1", "data_2"}) {
    EXPECT_TRUE(Contains(mat, std::string(matrix) + '\0')) << matrix;
  }
}

TEST(StartupTest, VersionSaysWhichPluginsAreAvailable) {
  CliResult r = RunMomenta({"--version"}, ".");
  ASSERT_EQ(r.exit_code, kExitOk) << r.err;
  EXPECT_TRUE(Contains(r.out, "MAT result files: yes (")) << r.out;
  EXPECT_TRUE(Contains(r.out, HaveMpi() ? "sweeps under mpirun: yes (" : "sweeps under mpirun: no")) << r.out;
}

/// Runs `binary args` in `dir`, output captured.
CliResult RunBinary(const std::string& binary, const std::string& args, const TempDir& dir) {
  const std::string command = "cd '" + dir.path() + "' && '" + binary + "' " + args + " >out.txt 2>err.txt";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadText(dir.File("out.txt")), ReadText(dir.File("err.txt"))};
}

TEST(StartupTest, WithoutItsPluginsMomentaSaysWhatIsMissing) {
  // momenta alone in a folder: no lib/momenta/ beside it.
  TempDir dir;
  const std::string binary = dir.File("momenta");
  std::filesystem::copy_file(MOMENTA_BINARY, binary);
  dir.Write("drop.yaml", kModel);
  CliResult version = RunBinary(binary, "--version", dir);
  EXPECT_EQ(version.exit_code, kExitOk) << version.err;
  EXPECT_TRUE(Contains(version.out, "MAT result files: no")) << version.out;
  EXPECT_TRUE(Contains(version.out, "sweeps under mpirun: no")) << version.out;

  // A CSV run needs no plugin.
  CliResult csv = RunBinary(binary, "simulate drop.yaml -o drop.csv", dir);
  EXPECT_EQ(csv.exit_code, kExitOk) << csv.err;

  // A MAT file is refused before the run, naming the file and the missing plugin.
  CliResult mat = RunBinary(binary, "simulate drop.yaml -o drop.mat", dir);
  EXPECT_NE(mat.exit_code, kExitOk);
  EXPECT_TRUE(Contains(mat.err, "cannot write the results file drop.mat: MAT files need libmatio, but the plugin "
                                "momenta-mat.so is not installed (looked in " + dir.path()))
      << mat.err;

  // Under mpirun on several ranks, a usage error naming the missing plugin.
  CliResult sweep = RunBinary(binary, "sweep drop.yaml -p mass=1,2 -o s.csv", dir);
  ASSERT_EQ(sweep.exit_code, kExitOk) << sweep.err;  // not under mpirun: threads
  setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  CliResult mpi = RunBinary(binary, "sweep drop.yaml -p mass=1,2 -o s.csv", dir);
  unsetenv("OMPI_COMM_WORLD_SIZE");
  EXPECT_EQ(mpi.exit_code, kExitUsage) << mpi.err;
  EXPECT_TRUE(Contains(mpi.err, "started by mpirun on 2 ranks, but ")) << mpi.err;
  EXPECT_TRUE(Contains(mpi.err, HaveMpi() ? "momenta-mpi.so is not installed" : "built without MPI")) << mpi.err;
}

/// The library read a file at a time, as before types were read on first use.
Library WholeFiles() {
  Library lib;
  const std::string dir = std::string(MOMENTA_SOURCE_DIR) + "/components/";
  LoadLibraryString(ReadText(dir + "connectors.yaml"), "components/connectors.yaml", &lib);
  std::set<std::string> files;
  for (const auto& f : std::filesystem::directory_iterator(dir)) files.insert(f.path().filename().string());
  for (const std::string& f : files) {
    if (f != "connectors.yaml" && f.size() > 5 && f.substr(f.size() - 5) == ".yaml") {
      LoadLibraryString(ReadText(dir + f), "components/" + f, &lib);
    }
  }
  return lib;
}

TEST(StartupTest, TypesReadOnFirstUseAreThoseOfTheWholeFiles) {
  const Library whole = WholeFiles();
  const Library& builtin = BuiltinLibrary();
  // The short-name rule holds before the types are read (when this test runs alone, nothing has
  // read them yet): with Planar.Fixed read, `Fixed` is still the unqualified (translational) type,
  // not Planar.Fixed abbreviated; `Body` is Planar.Body, the only type of that last part.
  ASSERT_NE(builtin.FindComponent("Planar.Fixed"), nullptr);
  ASSERT_NE(builtin.FindComponent("Fixed"), nullptr);
  EXPECT_EQ(builtin.FindComponent("Fixed")->name, "Fixed");
  ASSERT_NE(builtin.FindComponent("Body"), nullptr);
  EXPECT_EQ(builtin.FindComponent("Body")->name, whole.FindComponent("Body")->name);
  EXPECT_EQ(builtin.FindComponent("Body")->name, "Planar.Body");
  const std::vector<std::string> names = whole.ComponentNames();
  ASSERT_EQ(builtin.ComponentNames(), names);
  ASSERT_GT(names.size(), 100u);
  for (const std::string& name : names) {
    const ComponentType& a = *whole.FindComponent(name);
    const ComponentType& b = *builtin.FindComponent(name);
    SCOPED_TRACE(name);
    // Locations (file:line:col) and the scalar forms' contents.
    EXPECT_EQ(a.loc.ToString(), b.loc.ToString());
    ASSERT_EQ(a.equations.size(), b.equations.size());
    for (size_t k = 0; k < a.equations.size(); ++k) {
      EXPECT_EQ(a.equations[k].text, b.equations[k].text);
      EXPECT_EQ(a.equations[k].loc.ToString(), b.equations[k].loc.ToString());
    }
    ASSERT_EQ(a.parameters.size(), b.parameters.size());
    for (size_t k = 0; k < a.parameters.size(); ++k) EXPECT_EQ(a.parameters[k].name, b.parameters[k].name);
    ASSERT_EQ(a.variables.size(), b.variables.size());
    for (size_t k = 0; k < a.variables.size(); ++k) EXPECT_EQ(a.variables[k].name, b.variables[k].name);
    EXPECT_EQ(a.connectors.size(), b.connectors.size());
    EXPECT_EQ(a.components.size(), b.components.size());
    EXPECT_EQ(a.whens.size(), b.whens.size());
  }
  EXPECT_EQ(builtin.ConnectorNames(), whole.ConnectorNames());
}

/// A source that reads one small type per name, once (as the built-in library's source: loading a
/// type asks the library for its name again), counting what it reads.
class CountingTypes : public LazyTypes {
 public:
  mutable int reads = 0;
  mutable std::set<std::string> asked;
  void Read(const std::string& name, Library* library) const override {
    if ((name != "Alpha" && name != "Beta") || !asked.insert(name).second) return;
    ++reads;
    LoadLibraryString(name + ":\n  parameters: {k: 1}\n", "counting.yaml", library);
  }
  void ReadAll(Library* library) const override {
    for (const char* name : {"Alpha", "Beta"}) {
      if (!library->HasComponent(name)) Read(name, library);
    }
  }
};

TEST(StartupTest, ACopiedLibraryHoldsEveryTypeAndTheOriginalKeepsItsSource) {
  auto source = std::make_shared<CountingTypes>();
  Library original;
  original.SetLazyTypes(source);
  ASSERT_NE(original.FindComponent("Alpha"), nullptr);
  // The copy reads whatever the original had not read yet into the original, then copies it: a
  // type the copy holds is never missing from the original afterwards, and each type is read once.
  Library copy = original;
  EXPECT_EQ(source->reads, 2);
  EXPECT_NE(copy.FindComponent("Beta"), nullptr);
  EXPECT_NE(original.FindComponent("Beta"), nullptr);
  EXPECT_EQ(source->reads, 2);
  // The copy's additions stay its own.
  LoadLibraryString("Gamma:\n  parameters: {k: 2}\n", "copy.yaml", &copy);
  EXPECT_NE(copy.FindComponent("Gamma"), nullptr);
  EXPECT_EQ(original.FindComponent("Gamma"), nullptr);
  Library assigned;
  assigned = original;
  EXPECT_EQ(assigned.ComponentNames(), (std::vector<std::string>{"Alpha", "Beta"}));
}

}  // namespace
}  // namespace momenta
