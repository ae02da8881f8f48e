#include "core/compile/native_code.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "core/compile/codegen.h"
#include "core/compile/native_cache.h"
#include "core/base/error.h"

extern char** environ;

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::atomic<uint64_t> g_compilations{0};

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

/// Flags chosen by measurement (bench/RESULTS.md, "Native model code"): -O1 without the
/// alias-walking passes compiles large straight-line code several times faster than -O2 and runs
/// it as fast. A unit whose code is mostly loops is small and runs its loop bodies thousands of
/// times per evaluation: -O2 there (its redundancy elimination loads a register the body reads
/// twice once, and carries a value loaded in one repetition into the next) makes the chain's
/// residual 30 % faster (20 against 14 µs at n = 10 000) for no measurable compile time
/// (bench/RESULTS.md, "The residual per evaluation"). No contraction into fused multiply-adds
/// and no fast-math: the results must be the interpreter's to the bit.
const std::vector<std::string> kStraightLineFlags = {"-O1", "-fno-tree-dse", "-fno-tree-fre", "-fno-tree-dominator-opts",
                                                     "-fno-tree-pta"};
const std::vector<std::string> kLoopFlags = {"-O2"};
const std::vector<std::string> kRequiredFlags = {"-fPIC", "-shared", "-ffp-contract=off", "-fno-fast-math", "-w"};
/// A unit with a loop gets kLoopFlags when it holds at most this many straight-line instructions
/// (statements outside loops): -O2 takes twice -O1's time on straight-line code (0.6 against
/// 0.3 s of CPU for pendulum_chain's 1 400 statements at n = 10) and runs it no faster.
constexpr size_t kMaxStraightInLoopUnit = 500;

/// The optimisation flags: $MOMENTA_CC_FLAGS (split at spaces) for every unit, else kLoopFlags or
/// kStraightLineFlags; then the ones the loading and the bit-equality need.
std::vector<std::string> CompileFlags(bool loop_unit) {
  std::vector<std::string> flags;
  if (const std::string env = Env("MOMENTA_CC_FLAGS"); !env.empty()) {
    std::stringstream words(env);
    for (std::string w; words >> w;) flags.push_back(w);
  } else {
    flags = loop_unit ? kLoopFlags : kStraightLineFlags;
  }
  flags.insert(flags.end(), kRequiredFlags.begin(), kRequiredFlags.end());
  return flags;
}

/// Auto's cost model, with constants measured as bench/RESULTS.md ("Native model code") records:
/// compiling costs about kCompileFixed plus kCompilePerInstruction per instruction in the C (a
/// rerolled loop's body counts once); a cached object costs kCacheHit (key, dlopen); native code
/// saves about kSavedPerEvaluation per residual instruction and evaluation; a run evaluates the
/// residual about kEvaluationsPerRun times.
constexpr double kCompileFixed = 0.3;               // s
constexpr double kCompilePerInstruction = 2.3e-4;   // s
constexpr double kCacheHit = 5e-4;                  // s
constexpr double kSavedPerEvaluation = 1.1e-9;      // s per residual instruction
constexpr double kEvaluationsPerRun = 3000;
/// Straight-line code stops paying beyond this many residual instructions in the C (loops count
/// their body once, so this is the residual rerolling leaves irregular): its machine code no
/// longer fits the caches and is fetched from memory at every evaluation (bench/RESULTS.md,
/// "Native model code", has the RC ladder and chain figures this limit sits between).
constexpr size_t kMaxStraightLine = 300000;

/// The C compiler: $MOMENTA_CC (a path, or a name looked up on the PATH), else cc on the PATH.
/// Empty when there is none; `identity` then says what was looked for.
struct Compiler {
  std::string path;
  std::string identity;  ///< path, size and mtime: a new compiler makes new keys
};

bool IsExecutableFile(const std::string& path, struct stat* st) {
  return ::stat(path.c_str(), st) == 0 && S_ISREG(st->st_mode) && ::access(path.c_str(), X_OK) == 0;
}

Compiler FindCompiler() {
  std::string name = Env("MOMENTA_CC");
  if (name.empty()) name = "cc";
  std::vector<std::string> candidates;
  if (name.find('/') != std::string::npos) {
    candidates.push_back(name);
  } else {
    std::stringstream dirs(Env("PATH"));
    for (std::string dir; std::getline(dirs, dir, ':');) candidates.push_back((dir.empty() ? "." : dir) + "/" + name);
  }
  Compiler c;
  for (const std::string& path : candidates) {
    struct stat st {};
    if (!IsExecutableFile(path, &st)) continue;
    c.path = path;
    std::ostringstream id;
    id << path << ":" << st.st_size << ":" << st.st_mtim.tv_sec << "." << st.st_mtim.tv_nsec;
    c.identity = id.str();
    return c;
  }
  c.identity = name;
  return c;
}

/// Two independent 64-bit hashes of a sequence of words (128 bits: collisions are not a concern).
class KeyHash {
 public:
  /// One multiply per lane and word (the key of a large model hashes millions of words); Hex()
  /// mixes thoroughly at the end.
  void Add(uint64_t v) {
    h1_ = (h1_ ^ v) * 0x9e3779b97f4a7c15ull;
    h1_ ^= h1_ >> 29;
    h2_ = (h2_ + v) * 0xc2b2ae3d27d4eb4full;
    h2_ = (h2_ << 31) | (h2_ >> 33);
  }
  void Add(const std::string& s) {
    Add(s.size());
    for (char ch : s) Add(static_cast<unsigned char>(ch));
  }
  std::string Hex() const {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(Mix(h1_)),
                  static_cast<unsigned long long>(Mix(h2_ ^ h1_)));
    return buf;
  }

 private:
  static uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  uint64_t h1_ = 0x6a09e667f3bcc908ull, h2_ = 0xbb67ae8584caa73bull;
};

std::string KeyOf(const CompiledModel& model, const NativeCodeOptions& options, const Compiler& compiler) {
  KeyHash h;
  h.Add(kCodeFormatVersion);
  h.Add(compiler.identity);
  // The flag policy: a unit's choice follows from the instructions hashed below.
  for (bool loop_unit : {false, true}) {
    for (const std::string& f : CompileFlags(loop_unit)) h.Add(f);
  }
  h.Add(kMaxStraightInLoopUnit);
  h.Add(options.max_function_len);
  h.Add(options.loops ? 1u : 0u);
  const RegisterLayout& L = model.layout;
  for (uint32_t v : {L.param_base, L.y_base, L.yp_base, L.disc_base, L.pre_base, L.cond_base, L.temp_base, L.size}) {
    h.Add(v);
  }
  for (size_t k = 0; k < kNumModelPrograms; ++k) {
    if (!IsNativeProgram(static_cast<ModelProgram>(k))) continue;
    const Program& p = ProgramOf(model, static_cast<ModelProgram>(k));
    h.Add(k);
    h.Add(p.size());
    for (const Instruction& in : p.code()) {
      h.Add(static_cast<uint64_t>(in.op) | static_cast<uint64_t>(in.dst) << 32);
      h.Add(static_cast<uint64_t>(in.a) | static_cast<uint64_t>(in.b) << 32);
      h.Add(in.c);
    }
    h.Add(p.tables().size());
    for (const TableShape& t : p.tables()) {
      h.Add(static_cast<uint64_t>(t.rows) | static_cast<uint64_t>(t.cols) << 32);
      h.Add(t.column);
    }
  }
  return h.Hex();
}

std::string Symbol(size_t k) { return "momenta_p" + std::to_string(k); }

/// The objects this process loaded, by handle: the descriptor each was loaded through and how
/// many NativeCode hold it. glibc's dlopen returns an object already loaded under the same name
/// without opening the file, so the descriptor N behind the name /proc/self/fd/N stays open (and
/// its number unused by another load) until the last holder closes the object.
struct LoadedObjects {
  std::mutex mutex;
  std::map<void*, std::pair<int, int>> by_handle;  ///< handle -> (descriptor, holders)
};

LoadedObjects& Loaded() {
  static LoadedObjects* loaded = new LoadedObjects();  // never destroyed: objects may outlive statics
  return *loaded;
}

/// dlopen of the checked object through its descriptor (/proc/self/fd/N is the very file whose
/// content was checked); the descriptor then belongs to Loaded(). nullptr and why on failure.
void* OpenChecked(CheckedObject* object, std::string* why) {
  LoadedObjects& loaded = Loaded();
  std::lock_guard<std::mutex> lock(loaded.mutex);
  const std::string path = "/proc/self/fd/" + std::to_string(object->fd.get());
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* e = ::dlerror();
    *why = e ? e : "dlopen failed";
    return nullptr;
  }
  auto [at, added] = loaded.by_handle.try_emplace(handle, object->fd.get(), 0);
  if (added) object->fd.release();  // else the object was loaded already (the same file): ours closes
  ++at->second.second;
  return handle;
}

void CloseLoaded(void* handle) {
  LoadedObjects& loaded = Loaded();
  std::lock_guard<std::mutex> lock(loaded.mutex);
  ::dlclose(handle);
  auto at = loaded.by_handle.find(handle);
  if (at != loaded.by_handle.end() && --at->second.second == 0) {
    ::close(at->second.first);
    loaded.by_handle.erase(at);
  }
}

/// Loads the checked object `object` and checks it is the object for `key`; nullptr (and why)
/// otherwise.
std::shared_ptr<const NativeCode> Load(CheckedObject* object, const std::string& key, std::string* why) {
  void* handle = OpenChecked(object, why);
  if (!handle) return nullptr;
  const char* stored = static_cast<const char*>(::dlsym(handle, "momenta_key"));
  if (!stored || key != stored) {
    *why = "it holds another model's code";
    CloseLoaded(handle);
    return nullptr;
  }
  std::array<NativeCode::Function, kNumModelPrograms> functions{};
  for (size_t k = 0; k < kNumModelPrograms; ++k) {
    if (!IsNativeProgram(static_cast<ModelProgram>(k))) continue;
    functions[k] = reinterpret_cast<NativeCode::Function>(::dlsym(handle, Symbol(k).c_str()));
    if (!functions[k]) {
      *why = "it lacks " + Symbol(k);
      CloseLoaded(handle);
      return nullptr;
    }
  }
  return std::make_shared<NativeCode>(handle, functions);
}

/// A compiler process running, and the file its messages go to.
struct CompilerJob {
  pid_t pid = -1;
  std::string log;
  int status = 0;
  bool done = false;
};

/// What Build returns when a signal stopped it.
const char kInterrupted[] = "interrupted";

/// Starts the compiler with `args` (after its path), its output into `log`; pid -1 when it cannot
/// be started. With `own_group` the job leads a process group of its own, so that stopping it
/// stops the driver and the cc1 and as it runs (and a terminal's ^C reaches momenta only).
CompilerJob StartCompiler(const Compiler& compiler, const std::vector<std::string>& args, const std::string& log,
                          bool own_group) {
  std::vector<std::string> words = {compiler.path};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (own_group) {
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
  }
  CompilerJob job{-1, log};
  if (::posix_spawn(&job.pid, compiler.path.c_str(), &actions, &attributes, argv.data(), environ) != 0) job.pid = -1;
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  return job;
}

/// Whether every job has ended (reaping those that have); `block` waits for them.
bool Reap(std::vector<CompilerJob>* jobs, bool block) {
  bool all = true;
  for (CompilerJob& job : *jobs) {
    if (job.done || job.pid < 0) continue;
    pid_t got;
    while ((got = ::waitpid(job.pid, &job.status, block ? 0 : WNOHANG)) < 0 && errno == EINTR) {
    }
    job.done = got == job.pid || got < 0;
    all = all && job.done;
  }
  return all;
}

/// Whether any process of group `pgid` is left (a zombie counts until its parent reaps it).
bool GroupLeft(pid_t pgid) { return ::kill(-pgid, 0) == 0 || errno == EPERM; }

/// Stops every running job's process group: SIGTERM (gcc then removes its own temporary files),
/// SIGKILL for what still runs a second later; then reaps them, and waits (a second at most) for
/// the rest of each group (cc1, as: the driver may be reaped before they have gone).
void StopCompilers(std::vector<CompilerJob>* jobs) {
  std::vector<pid_t> groups;
  for (const CompilerJob& job : *jobs) {
    if (!job.done && job.pid > 0) {
      ::kill(-job.pid, SIGTERM);
      groups.push_back(job.pid);
    }
  }
  for (int k = 0; k < 100 && !Reap(jobs, false); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  for (const CompilerJob& job : *jobs) {
    if (!job.done && job.pid > 0) ::kill(-job.pid, SIGKILL);
  }
  Reap(jobs, true);
  for (pid_t group : groups) {
    for (int k = 0; k < 100 && GroupLeft(group); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (GroupLeft(group)) ::kill(-group, SIGKILL);
  }
}

/// Waits for `jobs`: "" when they all succeeded, else the first failure (the first line its
/// compiler printed), or kInterrupted when `*interrupt` was raised meanwhile (the jobs are then
/// stopped). The logs are removed.
std::string FinishCompilers(const Compiler& compiler, std::vector<CompilerJob> jobs,
                            const std::atomic<bool>* interrupt) {
  // Poll every 5 ms while a signal can stop the build; otherwise block.
  while (!Reap(&jobs, interrupt == nullptr)) {
    if (interrupt->load()) {
      StopCompilers(&jobs);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::string failure;
  for (const CompilerJob& job : jobs) {
    if (interrupt && interrupt->load()) {
      failure = kInterrupted;
    } else if (job.pid < 0) {
      failure = compiler.path + " could not be started";
    } else if (failure.empty() && !(WIFEXITED(job.status) && WEXITSTATUS(job.status) == 0)) {
      std::ifstream in(job.log);
      std::string line;
      std::getline(in, line);
      failure = compiler.path + " failed" + (line.empty() ? "" : ": " + line);
    }
    std::remove(job.log.c_str());
  }
  return failure;
}

/// The instructions a program's C holds: the bodies of its segments (a loop's once).
size_t EmittedSize(const CodegenProgram& p) {
  size_t n = 0;
  for (const CodeSegment& s : p.segments) n += s.len;
  return n;
}

/// Whether a translation unit is compiled with kLoopFlags: it holds a loop and little
/// straight-line code.
bool IsLoopUnit(const std::vector<CodegenProgram>& unit) {
  size_t straight = 0;
  bool loop = false;
  for (const CodegenProgram& p : unit) {
    for (const CodeSegment& s : p.segments) {
      if (s.count > 1) {
        loop = true;
      } else {
        straight += s.len;
      }
    }
  }
  return loop && straight <= kMaxStraightInLoopUnit;
}

/// The programs in `parts` groups of about equal emitted size (largest first into the lightest
/// group), one translation unit each, so that the compiler runs on every core.
std::vector<std::vector<CodegenProgram>> Partition(std::vector<CodegenProgram> programs, size_t parts) {
  std::sort(programs.begin(), programs.end(),
            [](const CodegenProgram& x, const CodegenProgram& y) { return EmittedSize(x) > EmittedSize(y); });
  std::vector<std::vector<CodegenProgram>> groups(parts);
  std::vector<size_t> load(parts, 0);
  for (CodegenProgram& p : programs) {
    const size_t g = static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    load[g] += EmittedSize(p) + 1;
    groups[g].push_back(std::move(p));
  }
  while (groups.size() > 1 && groups.back().empty()) groups.pop_back();
  return groups;
}

/// The native programs of `model` with their segments: loops where rerolling finds them
/// (options.loops), straight-line code otherwise.
std::vector<CodegenProgram> NativePrograms(const CompiledModel& model, const NativeCodeOptions& options) {
  std::vector<CodegenProgram> programs;
  for (size_t k = 0; k < kNumModelPrograms; ++k) {
    if (!IsNativeProgram(static_cast<ModelProgram>(k))) continue;
    const Program& p = ProgramOf(model, static_cast<ModelProgram>(k));
    programs.push_back({Symbol(k), &p,
                        options.loops ? LoopSegments(p, options.max_function_len)
                                      : StraightSegments(p, options.max_function_len)});
  }
  return programs;
}

/// A name no other process or thread picks for its temporary files in `dir`.
std::string TemporaryStem(const std::string& dir, const std::string& key) {
  static std::atomic<uint64_t> counter{0};
  std::random_device rd;
  std::ostringstream s;
  s << dir << "/tmp-" << key << "-" << ::getpid() << "-" << counter.fetch_add(1) << "-" << rd();
  return s.str();
}

/// A private directory for one build's sources, objects and logs, removed with them. Inside it
/// the files have fixed names (the key and the unit): the compiler records the source file's name
/// in the object, so the same code then gives the same bytes in every process.
class BuildDirectory {
 public:
  BuildDirectory(const std::string& cache_dir, const std::string& key)
      : path_(TemporaryStem(cache_dir, key)), made_(::mkdir(path_.c_str(), 0700) == 0) {}
  ~BuildDirectory() {
    std::error_code ignored;
    if (made_) std::filesystem::remove_all(path_, ignored);
  }
  BuildDirectory(const BuildDirectory&) = delete;
  BuildDirectory& operator=(const BuildDirectory&) = delete;

  bool made() const { return made_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  bool made_;
};

/// Compiles the units' `sources` into `object`: one unit directly, several at once (then linked);
/// "" on success, else why not (kInterrupted when a signal stopped it). `stem` names the logs
/// and the units' objects.
std::string Compile(const Compiler& compiler, const std::vector<std::vector<CodegenProgram>>& units,
                    const std::vector<std::string>& sources, const std::string& stem, const std::string& object,
                    const std::atomic<bool>* interrupt) {
  const bool own_group = interrupt != nullptr;
  g_compilations.fetch_add(1);
  if (sources.size() == 1) {
    std::vector<std::string> args = CompileFlags(IsLoopUnit(units[0]));
    args.insert(args.end(), {"-o", object, sources[0], "-lm"});
    return FinishCompilers(compiler, {StartCompiler(compiler, args, stem + ".log", own_group)}, interrupt);
  }
  std::vector<CompilerJob> jobs;
  std::vector<std::string> objects;
  for (size_t u = 0; u < sources.size(); ++u) {
    objects.push_back(stem + "-" + std::to_string(u) + ".o");
    std::vector<std::string> args = CompileFlags(IsLoopUnit(units[u]));
    args.insert(args.end(), {"-c", "-o", objects.back(), sources[u]});
    jobs.push_back(StartCompiler(compiler, args, stem + "-" + std::to_string(u) + ".log", own_group));
  }
  std::string failure = FinishCompilers(compiler, std::move(jobs), interrupt);
  if (failure.empty()) {
    std::vector<std::string> args = CompileFlags(false);
    args.insert(args.end(), {"-o", object});
    args.insert(args.end(), objects.begin(), objects.end());
    args.push_back("-lm");
    failure = FinishCompilers(compiler, {StartCompiler(compiler, args, stem + ".log", own_group)}, interrupt);
  }
  for (const std::string& o : objects) std::remove(o.c_str());
  return failure;
}

/// Emits, compiles and stores the object as `cache`'s entry `key` (into `*object`, checked and
/// open for loading); "" on success, else why not. A large model's programs are split over
/// several translation units compiled at once (one per core, each of at least
/// kInstructionsPerUnit), then linked.
constexpr size_t kInstructionsPerUnit = 10000;

std::string Build(const CompiledModel& model, std::vector<CodegenProgram> programs, const NativeCodeOptions& options,
                  const Compiler& compiler, const std::string& key, const NativeCache& cache, NativeCodeReport* report,
                  CheckedObject* object) {
  // The C files, in a private directory of this build.
  auto t0 = Clock::now();
  size_t instructions = 0;
  for (const CodegenProgram& p : programs) instructions += EmittedSize(p);
  const size_t cores = std::max(1u, std::thread::hardware_concurrency());
  const auto units = Partition(std::move(programs), std::min(cores, 1 + instructions / kInstructionsPerUnit));
  const BuildDirectory dir(cache.path(), key);
  if (!dir.made()) return "cannot make a directory for the compiler's files: " + dir.path();
  const std::string stem = dir.path() + "/" + key;
  std::vector<std::string> sources;
  std::string failure;
  for (size_t u = 0; u < units.size() && failure.empty(); ++u) {
    CodegenOptions copt;
    copt.max_function_len = options.max_function_len;
    copt.key = u == 0 ? key : "";
    copt.comment = (model.flat ? model.flat->model_name : std::string()) + ", part " + std::to_string(u + 1);
    sources.push_back(stem + "-" + std::to_string(u) + ".c");
    std::ofstream f(sources.back(), std::ios::binary);
    f << EmitC(units[u], model.layout, copt);
    f.close();
    if (!f) failure = "cannot write " + sources.back();
  }
  report->codegen_seconds += Since(t0);
  // Compile, unless a signal came meanwhile.
  auto t1 = Clock::now();
  if (failure.empty() && options.interrupt && options.interrupt->load()) failure = kInterrupted;
  if (failure.empty()) failure = Compile(compiler, units, sources, stem, stem + ".so", options.interrupt);
  report->compile_seconds = Since(t1);
  // MOMENTA_KEEP_C=1 keeps the C next to the object (to read it, or to time compilers on it).
  for (size_t u = 0; u < sources.size(); ++u) {
    if (Env("MOMENTA_KEEP_C") == "1") {
      std::rename(sources[u].c_str(), (cache.path() + "/" + key + "-" + std::to_string(u) + ".c").c_str());
    }
    std::remove(sources[u].c_str());
  }
  // The object and its digest into the cache in one step each.
  if (failure.empty()) *object = cache.Store(key, stem + ".so", &failure);
  return failure;
}

/// Auto's choice: whether native code is expected to save more than it costs in
/// `options.expected_runs` runs; `why` says what was weighed. `residual_emitted` and `emitted` are
/// the instructions the C holds (a loop's body once) for the residual and for all native programs:
/// what costs compile time and instruction cache, where the saving grows with the instructions
/// run (the residual's size).
bool NativePays(const CompiledModel& model, size_t residual_emitted, size_t emitted, bool cached,
                const NativeCodeOptions& options, std::string* why) {
  if (residual_emitted > kMaxStraightLine) {
    *why = "auto: a residual of " + std::to_string(residual_emitted) +
           " straight-line instructions runs slower native than interpreted (the instruction cache)";
    return false;
  }
  const double saved = options.expected_runs * kEvaluationsPerRun * kSavedPerEvaluation *
                       static_cast<double>(model.residual.size());
  const double cost = cached ? kCacheHit : kCompileFixed + kCompilePerInstruction * static_cast<double>(emitted);
  std::ostringstream s;
  s.precision(2);
  s << "auto: " << (cached ? "loading the cached code" : "compiling") << " costs about " << cost
    << " s and saves about " << saved << " s";
  if (!cached && saved < cost) s << "; --codegen native compiles it once for later runs";
  *why = s.str();
  return saved > cost;
}

void AddNote(NativeCodeReport* r, const std::string& note) {
  r->note += (r->note.empty() ? "" : "; ") + note;
}

/// Compiles the model's code into `dir` (created 0700 when missing), or into a private temporary
/// directory when `dir` may not be used (core/compile/native_cache.h), and loads it. `why`: why a
/// cached object was not used ("" when there was none).
std::shared_ptr<const NativeCode> CompileAndLoad(const CompiledModel& model, std::vector<CodegenProgram> programs,
                                                 const NativeCodeOptions& options, const Compiler& compiler,
                                                 const std::string& key, const std::string& dir, std::string why,
                                                 NativeCodeReport* r) {
  if (dir.empty()) {
    AddNote(r, "no cache directory for native code (set MOMENTA_CACHE_DIR): the model runs interpreted");
    return nullptr;
  }
  std::optional<PrivateBuildDir> private_dir;  // outlives the cache that may point into it
  std::optional<NativeCache> cache;
  cache.emplace(dir, true);
  if (!cache->usable()) {
    AddNote(r, cache->refusal() + ": not used; the model's code is compiled in a private temporary directory " +
                   "and not kept");
    private_dir.emplace();
    if (private_dir->path().empty()) {
      AddNote(r, "no temporary directory could be made: the model runs interpreted");
      return nullptr;
    }
    cache.emplace(private_dir->path(), false);
    r->library = private_dir->path() + "/" + key + ".so";
  }
  CheckedObject object;
  if (std::string failure = Build(model, std::move(programs), options, compiler, key, *cache, r, &object);
      !failure.empty()) {
    if (failure == kInterrupted) {
      r->interrupted = true;
    } else {
      AddNote(r, "native code failed (" + failure + "): the model runs interpreted");
    }
    return nullptr;
  }
  auto t2 = Clock::now();
  auto code = Load(&object, key, &why);
  r->load_seconds = Since(t2);
  if (!code) AddNote(r, "native code failed to load (" + why + "): the model runs interpreted");
  if (!why.empty() && code) r->reason += "; " + why;
  return code;
}

}  // namespace

NativeCode::~NativeCode() {
  if (handle_) CloseLoaded(handle_);
}

bool ParseCodegenMode(const std::string& text, CodegenMode* mode) {
  if (text == "auto") {
    *mode = CodegenMode::kAuto;
  } else if (text == "native") {
    *mode = CodegenMode::kNative;
  } else if (text == "interp") {
    *mode = CodegenMode::kInterp;
  } else {
    return false;
  }
  return true;
}

const Program& ProgramOf(const CompiledModel& m, ModelProgram which) {
  switch (which) {
    case ModelProgram::kParameters: return m.parameters;
    case ModelProgram::kGuardValues: return m.guard_values;
    case ModelProgram::kResidual: return m.residual;
    case ModelProgram::kJacobian: return m.jacobian;
    case ModelProgram::kOutputs: return m.outputs;
    case ModelProgram::kStartValues: return m.start_values;
    case ModelProgram::kStartGuesses: return m.start_guesses;
    case ModelProgram::kInitResidual: return m.init_residual;
    case ModelProgram::kInitJacobian: return m.init_jacobian;
    case ModelProgram::kRedundantResidual: return m.redundant_residual;
    case ModelProgram::kDiscreteStarts: return m.discrete_starts;
    case ModelProgram::kDiscreteUpdate: return m.discrete_update;
    case ModelProgram::kZeroCrossings: return m.zero_crossings;
    case ModelProgram::kZeroCrossingRates: return m.zero_crossing_rates;
    case ModelProgram::kWhenConditions: return m.when_conditions;
    case ModelProgram::kWhenValues: return m.when_values;
    case ModelProgram::kImpactValues: return m.impact_values;
  }
  MOMENTA_CHECK(false);
  return m.residual;
}

bool IsNativeProgram(ModelProgram which) {
  switch (which) {
    case ModelProgram::kResidual:
    case ModelProgram::kJacobian:
    case ModelProgram::kOutputs:
    case ModelProgram::kZeroCrossings:
    case ModelProgram::kZeroCrossingRates:
    case ModelProgram::kDiscreteUpdate:
    case ModelProgram::kWhenConditions:
    case ModelProgram::kWhenValues:
    case ModelProgram::kImpactValues:
      return true;
    default:
      return false;
  }
}

std::string NativeCodeReport::Summary() const {
  std::ostringstream s;
  s.precision(3);
  if (native) {
    s << "native code, " << instructions << " instructions";
    if (emitted) s << " (" << emitted << " in the C)";
    s << ", ";
    if (cache_hit) {
      s << "cached (loaded in " << load_seconds * 1e3 << " ms)";
    } else {
      s << "compiled in " << compile_seconds << " s (C " << codegen_seconds * 1e3 << " ms)";
    }
  } else {
    s << "interpreter, " << instructions << " instructions";
  }
  if (!reason.empty()) s << " (" << reason << ")";
  return s.str();
}

std::string NativeCacheDir() {
  if (std::string d = Env("MOMENTA_CACHE_DIR"); !d.empty()) return d;
  if (std::string d = Env("XDG_CACHE_HOME"); !d.empty()) return d + "/momenta";
  if (std::string d = Env("HOME"); !d.empty()) return d + "/.cache/momenta";
  return "";
}

std::string NativeCodeKey(const CompiledModel& model, const NativeCodeOptions& options) {
  return KeyOf(model, options, FindCompiler());
}

uint64_t NativeCompilations() { return g_compilations.load(); }

std::shared_ptr<const NativeCode> LoadNativeCode(const CompiledModel& model, const NativeCodeOptions& options,
                                                 NativeCodeReport* report) {
  NativeCodeReport r;
  for (size_t k = 0; k < kNumModelPrograms; ++k) {
    if (IsNativeProgram(static_cast<ModelProgram>(k))) r.instructions += ProgramOf(model, static_cast<ModelProgram>(k)).size();
  }
  auto done = [&](std::shared_ptr<const NativeCode> code) {
    r.native = code != nullptr;
    if (report) *report = r;
    return code;
  };
  if (options.mode == CodegenMode::kInterp) {
    r.reason = "--codegen interp";
    return done(nullptr);
  }
  // Where the object is or would be.
  auto t0 = Clock::now();
  const Compiler compiler = FindCompiler();
  const std::string key = KeyOf(model, options, compiler);
  const std::string dir = NativeCacheDir();
  const NativeCache cache(dir, false);
  r.library = dir.empty() ? "" : dir + "/" + key + ".so";
  const bool cached = cache.Has(key);
  r.codegen_seconds = Since(t0);
  // Auto: native only where it pays.
  // The segments (rerolling: linear, 0.1 s per million instructions), needed to compile and to
  // weigh compiling or a large residual; a cached object of a small model skips them.
  std::vector<CodegenProgram> programs;
  size_t residual_emitted = model.residual.size();
  auto segment = [&] {
    programs = NativePrograms(model, options);
    r.emitted = 0;
    for (const CodegenProgram& p : programs) {
      r.emitted += EmittedSize(p);
      if (p.program == &model.residual) residual_emitted = EmittedSize(p);
    }
  };
  if (options.mode == CodegenMode::kAuto) {
    if (!cached || model.residual.size() > kMaxStraightLine) segment();
    if (!NativePays(model, residual_emitted, r.emitted, cached, options, &r.reason)) return done(nullptr);
  } else {
    r.reason = "--codegen native";
  }
  // A cached object, when it passes the checks (core/compile/native_cache.h).
  std::string why;
  if (cached) {
    auto t1 = Clock::now();
    bool refused = false;
    CheckedObject object = cache.Read(key, &why, &refused);
    if (object.fd.valid()) {
      if (auto code = Load(&object, key, &why)) {
        r.load_seconds = Since(t1);
        r.cache_hit = true;
        return done(code);
      }
    }
    if (refused) r.note = "the cached " + r.library + " was not loaded: " + why + "; the model is compiled again";
    why = "the cached " + r.library + " was rebuilt: " + why;
  }
  // Compile it.
  if (compiler.path.empty()) {
    AddNote(&r, "no C compiler (" + compiler.identity + ") found: the model runs interpreted");
    return done(nullptr);
  }
  if (programs.empty()) segment();
  return done(CompileAndLoad(model, std::move(programs), options, compiler, key, dir, why, &r));
}

std::shared_ptr<const CompiledModel> AttachNativeCode(std::shared_ptr<const CompiledModel> model,
                                                      const NativeCodeOptions& options, NativeCodeReport* report) {
  std::shared_ptr<const NativeCode> code = LoadNativeCode(*model, options, report);
  if (code == model->native) return model;
  // The only owner finishes the model in place (it was made non-const by BuildModel); a shared
  // model stays as it is and a copy gets the code.
  std::shared_ptr<CompiledModel> target = model.use_count() == 1
                                              ? std::const_pointer_cast<CompiledModel>(model)
                                              : std::make_shared<CompiledModel>(*model);
  target->native = std::move(code);
  return target;
}

}  // namespace momenta
