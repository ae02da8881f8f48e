// Security and signal findings of tests/data/reliability/2026-11-27 (01, 02, 10, 11, 15, the plot
// slips, the generated C): no planted shared object's constructor runs, no user string leaves its
// gnuplot string, no control character reaches the terminal raw, no model text reaches the C
// source unescaped, and SIGINT/SIGTERM during a native compilation stops the compilers, removes
// their files and exits 130/143. Each case runs the real CLI.

#include <dirent.h>
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/mat_writer.h"
#include "tests/app/cli_support.h"
#include "tests/support/cli_runner.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::CliResult;
using testing::RunMomenta;
using testing::TempDir;

std::string Reproducer(const std::string& name) {
  return testing::SourcePath("tests/data/reliability/2026-11-27/" + name);
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

bool Exists(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

mode_t ModeOf(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? st.st_mode & 07777 : 0;
}

/// The names in `dir` that start with `prefix`.
std::vector<std::string> Entries(const std::string& dir, const std::string& prefix) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0) names.push_back(name);
  }
  return names;
}

/// Sets environment variables for the test's lifetime (the CLI inherits them), restoring them
/// after.
class ScopedEnv {
 public:
  void Set(const std::string& name, const std::string* value) {
    const char* old = std::getenv(name.c_str());
    saved_.push_back({name, old ? std::string(old) : std::string(), old != nullptr});
    if (value) {
      ::setenv(name.c_str(), value->c_str(), 1);
    } else {
      ::unsetenv(name.c_str());
    }
  }
  ~ScopedEnv() {
    for (auto it = saved_.rbegin(); it != saved_.rend(); ++it) {
      if (it->had) {
        ::setenv(it->name.c_str(), it->value.c_str(), 1);
      } else {
        ::unsetenv(it->name.c_str());
      }
    }
  }

 private:
  struct Saved {
    std::string name, value;
    bool had;
  };
  std::vector<Saved> saved_;
};

// ---------------------------------------------------------------------------------------------
// 01, 11: the native-code cache.

class PlantedCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v cc >/dev/null 2>&1") != 0) GTEST_SKIP() << "no C compiler";
    // The object an attacker plants: its constructor writes momenta-01-PWNED into the current
    // directory. It does run when loaded (so a test that finds no mark means it was not loaded).
    planted_ = work_.File("planted.so");
    ASSERT_EQ(std::system(("cc -shared -fPIC -o " + planted_ + " " +
                           Reproducer("01-planted-cache-object.c"))
                              .c_str()),
              0);
    const pid_t child = ::fork();
    if (child == 0) {
      if (::chdir(work_.path().c_str()) != 0 || !::dlopen(planted_.c_str(), RTLD_NOW)) ::_exit(1);
      ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(Exists(work_.File("momenta-01-PWNED")))
        << "the planted object's constructor does not run";
    std::filesystem::remove(work_.File("momenta-01-PWNED"));
    // The key: the name momenta gives the model's object, learnt from a private cache.
    env_.Set("TMPDIR", &tmp_.path());
    env_.Set("MOMENTA_CACHE_DIR", &cache_.path());
    CliResult r = Simulate();
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<std::string> objects = Entries(cache_.path(), "");
    for (const std::string& name : objects) {
      if (name.size() > 3 && name.substr(name.size() - 3) == ".so")
        key_ = name.substr(0, name.size() - 3);
    }
    ASSERT_FALSE(key_.empty());
    EXPECT_TRUE(Exists(cache_.File(key_ + ".sha256")));
    EXPECT_EQ(ModeOf(cache_.File(key_ + ".so")), 0600u);
  }

  CliResult Simulate(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {"simulate",  Reproducer("01-planted-cache-object.yaml"),
                                     "--codegen", "native",
                                     "--stop",    "0.01",
                                     "-o",        work_.File("o.csv")};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunMomenta(args, work_.path());
  }

  /// Runs the model with the planted object in place and checks it never ran and the run is right.
  void ExpectNotRun(const CliResult& r, const std::string& what) {
    EXPECT_EQ(r.exit_code, 0) << what << ": " << r.err;
    EXPECT_FALSE(Exists(work_.File("momenta-01-PWNED"))) << what << ": the planted constructor ran";
    EXPECT_TRUE(Contains(r.out, "code: native code")) << what << ": " << r.out;
    // No private build directory is left behind.
    EXPECT_TRUE(Entries(tmp_.path(), "momenta-").empty()) << what;
  }

  void Plant(const std::string& dir) {
    std::filesystem::copy_file(planted_, dir + "/" + key_ + ".so",
                               std::filesystem::copy_options::overwrite_existing);
  }

  TempDir work_, cache_, tmp_;
  ScopedEnv env_;
  std::string planted_, key_;
};

TEST_F(PlantedCacheTest, WorldWritableDirectoryIsNotUsed) {
  // 01 as the reproducer sets it up: a shared directory (1777), the object planted under the key.
  TempDir shared;
  ASSERT_EQ(::chmod(shared.path().c_str(), 01777), 0);
  Plant(shared.path());
  env_.Set("MOMENTA_CACHE_DIR", &shared.path());
  CliResult r = Simulate();
  ExpectNotRun(r, "1777 directory");
  EXPECT_TRUE(Contains(
      r.err, "note: the cache directory " + shared.path() +
                 " is writable by others (mode 1777): not used; the model's code is compiled in a "
                 "private temporary directory and not kept"))
      << r.err;
  // Nothing was written into the shared directory.
  EXPECT_EQ(Entries(shared.path(), "").size(), 1u);
  // A directory writable by its group only is refused too.
  ASSERT_EQ(::chmod(shared.path().c_str(), 0770), 0);
  r = Simulate();
  ExpectNotRun(r, "0770 directory");
  EXPECT_TRUE(Contains(r.err, "is writable by its group (mode 0770): not used")) << r.err;
}

TEST_F(PlantedCacheTest, ReplacedEntryFailsItsDigestBeforeLoading) {
  // The user's own private directory, the object replaced (same owner, same mode): the content's
  // SHA-256 is not the one recorded, so it is rebuilt without being loaded.
  Plant(cache_.path());
  ASSERT_EQ(::chmod(cache_.File(key_ + ".so").c_str(), 0600), 0);
  CliResult r = Simulate();
  ExpectNotRun(r, "replaced entry");
  EXPECT_TRUE(
      Contains(r.out,
               "was rebuilt: its content is not what momenta wrote (the SHA-256 differs from the "
               "one recorded)"))
      << r.out;
  // Rebuilt: the next run loads it from the cache.
  r = Simulate();
  EXPECT_TRUE(Contains(r.out, "cached (loaded in")) << r.out;
}

TEST_F(PlantedCacheTest, EntryWritableByOthersOrALinkIsRefusedWithANote) {
  Plant(cache_.path());
  ASSERT_EQ(::chmod(cache_.File(key_ + ".so").c_str(), 0666), 0);
  CliResult r = Simulate();
  ExpectNotRun(r, "0666 entry");
  EXPECT_TRUE(Contains(
      r.err,
      "note: the cached " + cache_.File(key_ + ".so") +
          " was not loaded: it is writable by others (mode 0666); the model is compiled again"))
      << r.err;
  // A symbolic link to the planted object.
  std::filesystem::remove(cache_.File(key_ + ".so"));
  std::filesystem::create_symlink(planted_, cache_.File(key_ + ".so"));
  r = Simulate();
  ExpectNotRun(r, "symbolic link");
  EXPECT_TRUE(Contains(r.err, "was not loaded: it is a symbolic link")) << r.err;
}

TEST_F(PlantedCacheTest, EntryOfAnotherUserIsRefusedWithANote) {
  if (::geteuid() != 0) GTEST_SKIP() << "giving a file to another user needs root";
  Plant(cache_.path());
  ASSERT_EQ(::chmod(cache_.File(key_ + ".so").c_str(), 0644), 0);
  ASSERT_EQ(::chown(cache_.File(key_ + ".so").c_str(), 65534, 65534), 0);
  CliResult r = Simulate();
  ExpectNotRun(r, "foreign entry");
  EXPECT_TRUE(Contains(r.err, "was not loaded: it belongs to another user (uid 65534)")) << r.err;
  // A directory of another user.
  TempDir theirs;
  ASSERT_EQ(::chown(theirs.path().c_str(), 65534, 65534), 0);
  Plant(theirs.path());
  env_.Set("MOMENTA_CACHE_DIR", &theirs.path());
  r = Simulate();
  ExpectNotRun(r, "foreign directory");
  EXPECT_TRUE(Contains(r.err, "the cache directory " + theirs.path() +
                                  " belongs to another user (uid 65534): not used"))
      << r.err;
}

TEST_F(PlantedCacheTest, CacheDirectoriesAreMadePrivate) {
  // 11: a new HOME, no MOMENTA_CACHE_DIR or XDG_CACHE_HOME: ~/.cache and ~/.cache/momenta are 0700.
  TempDir home;
  env_.Set("HOME", &home.path());
  env_.Set("MOMENTA_CACHE_DIR", nullptr);
  env_.Set("XDG_CACHE_HOME", nullptr);
  ::umask(022);
  CliResult r = Simulate({"-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ModeOf(home.File(".cache")), 0700u);
  EXPECT_EQ(ModeOf(home.File(".cache/momenta")), 0700u);
  EXPECT_TRUE(Exists(home.File(".cache/momenta/" + key_ + ".so")));
  // XDG_CACHE_HOME, made with its momenta folder.
  const std::string xdg = home.File("xdg/cache");
  env_.Set("XDG_CACHE_HOME", &xdg);
  r = Simulate({"-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ModeOf(home.File("xdg")), 0700u);
  EXPECT_EQ(ModeOf(xdg), 0700u);
  EXPECT_EQ(ModeOf(xdg + "/momenta"), 0700u);
  // An existing world-writable default directory is refused with a note.
  ASSERT_EQ(::chmod((xdg + "/momenta").c_str(), 0777), 0);
  r = Simulate({"-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(
      r.err, "the cache directory " + xdg + "/momenta is writable by others (mode 0777): not used"))
      << r.err;
}

// ---------------------------------------------------------------------------------------------
// 02 and the plot slips.

class PlotInjectionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0)
      GTEST_SKIP() << "gnuplot is not installed";
  }
  /// Whether gnuplot ran the injected command (it would create `marker` in the work folder).
  bool Pwned() const { return Exists(dir_.File("momenta-02-PWNED")); }
  TempDir dir_;
};

const char kInjected[] = "r\nsystem(\"touch momenta-02-PWNED\")\n";

TEST_F(PlotInjectionTest, ResultFileNameStaysInItsString) {
  // The reproducer: the name is the default title and (with .svg) the default output.
  const std::string name = dir_.File(std::string(kInjected) + ".csv");
  std::filesystem::copy_file(Reproducer("02-plot-result.csv"), name);
  CliResult r = RunMomenta({"plot", name, "-y", "mass1.s", "-o", dir_.File("p.svg")}, dir_.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Pwned());
  // The title shows the name with its line ends as visible text.
  EXPECT_TRUE(Contains(testing::ReadText(dir_.File("p.svg")),
                       "r\\x0asystem(&quot;touch momenta-02-PWNED&quot;)\\x0a.csv") ||
              Contains(testing::ReadText(dir_.File("p.svg")),
                       "r\\x0asystem(\"touch momenta-02-PWNED\")\\x0a.csv"))
      << testing::ReadText(dir_.File("p.svg")).substr(0, 2000);
  // The default output name: momenta opens it, gnuplot never sees it.
  r = RunMomenta({"plot", name, "-y", "mass1.s"}, dir_.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Pwned());
  EXPECT_TRUE(Contains(testing::ReadText(dir_.File(std::string(kInjected) + ".svg")), "</svg>"));
}

TEST_F(PlotInjectionTest, OutputTitleAndColumnNamesStayInTheirStrings) {
  const std::string csv = Reproducer("02-plot-result.csv");
  // -o
  const std::string out = dir_.File(std::string(kInjected) + "o.svg");
  CliResult r = RunMomenta({"plot", csv, "-y", "mass1.s", "-o", out}, dir_.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Pwned());
  EXPECT_TRUE(Contains(testing::ReadText(out), "</svg>"));
  // --title: a control character is refused; quotes, backquotes and macros stay text.
  r = RunMomenta({"plot", csv, "-y", "mass1.s", "-o", dir_.File("t.svg"), "--title", kInjected},
                 dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Contains(
      r.err, "momenta: --title holds a control character (\\x0a): a title is one line of text"))
      << r.err;
  const std::string title = "it's `touch momenta-02-PWNED` @x ''";
  r = RunMomenta({"plot", csv, "-y", "mass1.s", "-o", dir_.File("t.svg"), "--title", title},
                 dir_.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Pwned());
  EXPECT_TRUE(Contains(testing::ReadText(dir_.File("t.svg")), "<text>" + title + "</text>"));
  // A column name from a MAT result (a CSV header cannot hold a line end).
  const std::string mat = dir_.File("r.mat"), column = std::string(kInjected) + "'x";
  {
    MatWriter w(mat, {column}, {}, 0, 1);
    w.Row(0, {1});
    w.Row(1, {2});
    w.Close();
  }
  r = RunMomenta({"plot", mat, "-y", column, "-o", dir_.File("m.svg")}, dir_.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Pwned());
  EXPECT_TRUE(Contains(testing::ReadText(dir_.File("m.svg")), "\\x0a'x</text>"))
      << testing::ReadText(dir_.File("m.svg"));
}

TEST_F(PlotInjectionTest, ResultsGnuplotCannotDrawEndWithMomentasMessage) {
  // A header and no rows.
  const std::string empty = dir_.Write("empty.csv", "time,x\n");
  CliResult r = RunMomenta({"plot", empty, "-y", "x", "-o", dir_.File("e.svg")}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "momenta: " + empty + " holds no rows: there is nothing to plot\n");
  EXPECT_FALSE(Exists(dir_.File("e.svg")));
  // inf in a repeated time (an event's line would be drawn there).
  const std::string inf = dir_.Write("inf.csv", "time,x\n0,1\ninf,2\ninf,3\n");
  r = RunMomenta({"plot", inf, "-y", "x", "-o", dir_.File("i.svg")}, dir_.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "momenta: " + inf + ": time is inf in row 2: a plot needs finite times\n");
  // gnuplot failing: its own first line, after momenta's, and no image left.
  ScopedEnv env;
  const std::string fake =
      dir_.Write("fake-gnuplot", "#!/bin/sh\necho 'line 3: something broke' >&2\nexit 1\n");
  ASSERT_EQ(::chmod(fake.c_str(), 0755), 0);
  env.Set("MOMENTA_GNUPLOT", &fake);
  r = RunMomenta(
      {"plot", Reproducer("02-plot-result.csv"), "-y", "mass1.s", "-o", dir_.File("f.svg")},
      dir_.path());
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(Contains(r.err, "momenta: gnuplot failed writing " + dir_.File("f.svg") +
                                  " (line 3: something broke)"))
      << r.err;
  EXPECT_FALSE(Exists(dir_.File("f.svg")));
}

// ---------------------------------------------------------------------------------------------
// 15: control characters in messages.

TEST(TerminalEscapesTest, ModelTextReachesTheTerminalEscaped) {
  TempDir dir;
  CliResult r = RunMomenta({"check", Reproducer("15-terminal-escapes.yaml")}, dir.path());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  for (const std::string& text : {r.out, r.err}) {
    EXPECT_EQ(text.find('\x1b'), std::string::npos) << text;
    EXPECT_EQ(text.find('\a'), std::string::npos) << text;
  }
  // The unknown type is named, its escapes visible.
  EXPECT_TRUE(Contains(r.err, "Mass\\x1b[2J\\x1b[H")) << r.err;
  EXPECT_TRUE(Contains(r.err, "15-terminal-escapes.yaml:6:")) << r.err;
}

TEST(TerminalEscapesTest, FileNameAndModelNameAreEscapedInEveryMessage) {
  TempDir dir;
  // A file name holding an escape sequence and a bell, in an error message.
  const std::string name =
      "m\x1b]0;T\a\xc2\x9b"
      "2J.yaml";
  const std::string model = dir.Write(name, "model: x\ncomponents:\n  a: {type: Nope}\n");
  CliResult r = RunMomenta({"check", model}, dir.path());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, "m\\x1b]0;T\\x07\\u009b2J.yaml:3:")) << r.err;
  EXPECT_EQ(r.err.find('\x1b'), std::string::npos);
  EXPECT_EQ(r.err.find("\xc2\x9b"), std::string::npos);
  // The model's name in a summary; momenta's own line ends stay.
  const std::string ok =
      dir.Write("ok.yaml",
                "model: \"Esc\\e[31mRED\\e]0;TITLE\\a\"\ncomponents:\n  m: {type: Mass, m: 1}\n"
                "outputs: [m.s]\nexperiment: {stop: 0.1}\n");
  r = RunMomenta({"simulate", ok, "-o", dir.File("o.csv")}, dir.path());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "Esc\\x1b[31mRED\\x1b]0;TITLE\\x07 (")) << r.out;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  EXPECT_GT(testing::Lines(r.out).size(), 3u) << r.out;
}

// ---------------------------------------------------------------------------------------------
// The generated C: model text never reaches it unescaped.

TEST(GeneratedCodeTest, ModelTextCannotLeaveItsComment) {
  if (std::system("command -v cc >/dev/null 2>&1") != 0) GTEST_SKIP() << "no C compiler";
  TempDir dir, cache;
  ScopedEnv env;
  const std::string keep = "1";
  env.Set("MOMENTA_CACHE_DIR", &cache.path());
  env.Set("MOMENTA_KEEP_C", &keep);
  // The model's name and doc carry comment ends, quotes, backslashes, line ends and a directive
  // that would fail the compilation if any reached the code.
  const std::string hostile = R"(x */ #include \"/nonexistent.h\" \\ \n#error planted\n/* y)";
  const std::string model =
      dir.Write("c.yaml", "model: \"" + hostile + "\"\ndoc: \"" + hostile +
                              "\"\ncomponents:\n  m: {type: Mass, m: 1, s: {start: 1, fixed: "
                              "true}}\n  k: {type: Spring, c: 4}\n"
                              "  f: {type: Fixed}\nconnections:\n  - [m.flange_a, k.flange_b]\n  - "
                              "[k.flange_a, f.flange]\n"
                              "outputs: [m.s]\nexperiment: {stop: 1}\n");
  CliResult native =
      RunMomenta({"simulate", model, "--codegen", "native", "-o", dir.File("n.csv")}, dir.path());
  ASSERT_EQ(native.exit_code, 0) << native.err;
  EXPECT_TRUE(Contains(native.out, "code: native code")) << native.out << native.err;
  CliResult interp = RunMomenta(
      {"simulate", model, "--codegen", "interp", "-o", dir.File("i.csv"), "-q"}, dir.path());
  ASSERT_EQ(interp.exit_code, 0) << interp.err;
  EXPECT_EQ(testing::ReadText(dir.File("n.csv")), testing::ReadText(dir.File("i.csv")));
  // The C: one comment line holds the name, with no comment end, line end or quote from it.
  const std::vector<std::string> sources = Entries(cache.path(), "");
  std::string c;
  for (const std::string& s : sources) {
    if (s.size() > 2 && s.substr(s.size() - 2) == ".c") c += testing::ReadText(cache.File(s));
  }
  ASSERT_FALSE(c.empty());
  // Each unit's first line is one comment: it opens at its start and closes at its end only.
  size_t units = 0;
  for (const std::string& line : testing::Lines(c)) {
    if (line.rfind("/* momenta model code: ", 0) != 0) {
      EXPECT_FALSE(Contains(line, "nonexistent") || Contains(line, "#error") ||
                   Contains(line, "planted"))
          << line;
      continue;
    }
    ++units;
    EXPECT_EQ(line.find("*/"), line.size() - 2) << line;
    EXPECT_EQ(line.find("/*", 2), std::string::npos) << line;
    EXPECT_TRUE(Contains(line, "x *| #include \"|nonexistent.h\" \\ ?#error planted?|* y, part 1"))
        << line;
  }
  EXPECT_GE(units, 1u);
}

// ---------------------------------------------------------------------------------------------
// 10: SIGINT and SIGTERM during a native compilation.

/// The process ids of `root`'s descendants now (from /proc).
std::set<pid_t> Descendants(pid_t root) {
  std::map<pid_t, pid_t> parent;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = testing::ReadText("/proc/" + name + "/stat");
    const size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;
    std::stringstream rest(stat.substr(close + 2));
    std::string state;
    pid_t ppid = 0;
    rest >> state >> ppid;
    parent[std::stoi(name)] = ppid;
  }
  std::set<pid_t> found{root};
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [pid, ppid] : parent) {
      if (found.count(ppid) && found.insert(pid).second) grew = true;
    }
  }
  found.erase(root);
  return found;
}

/// Whether `pid` is a live (not zombie) process.
bool Running(pid_t pid) {
  const std::string stat = testing::ReadText("/proc/" + std::to_string(pid) + "/stat");
  const size_t close = stat.rfind(')');
  return close != std::string::npos && stat.size() > close + 2 && stat[close + 2] != 'Z';
}

void InterruptCompilation(int signal_number, int expected_exit, const char* signal_name) {
  if (std::system("command -v cc >/dev/null 2>&1") != 0) GTEST_SKIP() << "no C compiler";
  TempDir dir, cache;
  ScopedEnv env;
  env.Set("MOMENTA_CACHE_DIR", &cache.path());
  testing::MomentaProcess p(
      {"simulate", Reproducer("10-sigint-during-compile.yaml"), "-p", "n=1000", "--stop", "0.01",
       "--codegen", "native", "-o", "out.csv", "-q"},
      dir.path());
  ASSERT_TRUE(p.started());
  // Wait (at most 60 s) for the build directory and a compiler under way.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::set<pid_t> compilers;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!Entries(cache.path(), "tmp-").empty()) compilers = Descendants(p.pid());
    if (!compilers.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_FALSE(compilers.empty()) << "no compiler after 60 s: " << p.err();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (pid_t pid : Descendants(p.pid())) compilers.insert(pid);
  p.Signal(signal_number);
  const int status = p.Wait(60);
  const std::string err = p.err();
  EXPECT_EQ(status, expected_exit) << err;
  EXPECT_EQ(err, "momenta: " + Reproducer("10-sigint-during-compile.yaml") + ": interrupted by " +
                     signal_name +
                     " while compiling the model's native code: the compiler was stopped and its "
                     "temporary files "
                     "removed\n");
  EXPECT_TRUE(Entries(cache.path(), "tmp-").empty()) << "the build directory is left";
  EXPECT_TRUE(Entries(cache.path(), "").empty());
  for (pid_t pid : compilers)
    EXPECT_FALSE(Running(pid)) << "compiler process " << pid << " still runs";
  EXPECT_FALSE(Exists(dir.File("out.csv")));
}

TEST(InterruptCompilationTest, SigtermStopsTheCompilersAndExits143) {
  InterruptCompilation(SIGTERM, 143, "SIGTERM");
}

TEST(InterruptCompilationTest, SigintStopsTheCompilersAndExits130) {
  InterruptCompilation(SIGINT, 130, "SIGINT");
}

}  // namespace
}  // namespace momenta
