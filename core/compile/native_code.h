#pragma once
/// Native model code: a model's register programs emitted as C (core/compile/codegen.h),
/// compiled by the system's C compiler into a shared object, loaded with dlopen and run in place
/// of Program::Run.
///
/// Compiled objects are cached on disk, named by a key hashed from the structure only: every
/// program's instructions and table shapes, the register layout, the compiler (path, size, mtime)
/// and flags, and kCodeFormatVersion. Parameter values are registers filled at run time, so `-p`
/// never recompiles. The cache directory is $MOMENTA_CACHE_DIR, else $XDG_CACHE_HOME/momenta, else
/// ~/.cache/momenta, made 0700; core/compile/native_cache.h says when a directory and an entry are
/// trusted (the user's own, writable by nobody else, the content's SHA-256 what momenta recorded,
/// all checked before dlopen), and a directory that is not is replaced by a private temporary one
/// with a note. An object is written under a temporary name and renamed into place, so
/// processes building the same model at once (a threaded or MPI sweep) never see half a file; each
/// object holds its key (`momenta_key`), and one that does not load, lacks a function or holds
/// another key is rebuilt. The compiler is $MOMENTA_CC, else `cc` on the PATH; without one the
/// interpreter runs and a one-line note says so.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "core/compile/compiled_model.h"

namespace momenta {

/// Which code runs the programs: auto chooses by an estimate of cost and saving (cached code
/// when it pays; compiling only when the expected work repays it), native and interp force one.
enum class CodegenMode { kAuto, kNative, kInterp };

/// "auto", "native" or "interp" into `*mode`; false for anything else.
bool ParseCodegenMode(const std::string& text, CodegenMode* mode);

/// Every program of a CompiledModel, in one fixed order (the generated symbols are numbered by it).
enum class ModelProgram : uint8_t {
  kParameters, kGuardValues, kResidual, kJacobian, kOutputs, kStartValues, kStartGuesses,
  kInitResidual, kInitJacobian, kRedundantResidual, kDiscreteStarts, kDiscreteUpdate,
  kZeroCrossings, kZeroCrossingRates, kWhenConditions, kWhenValues, kImpactValues,
};
constexpr size_t kNumModelPrograms = 17;

const Program& ProgramOf(const CompiledModel& model, ModelProgram which);

/// The programs native code holds: those that run at every step or event (residual, Jacobian,
/// outputs, zero crossings, event programs). Those that run once per run (parameters,
/// initialisation) stay interpreted: compiling them would cost more than it saves.
bool IsNativeProgram(ModelProgram which);

/// Bumped whenever the generated code's meaning changes, so that old cache entries are not used.
constexpr uint32_t kCodeFormatVersion = 4;  // 2: loops for rerolled segments; 3: y and yp arguments; 4: a loop stepping over y and yp reads them there

/// A loaded shared object holding a model's programs as native functions. Owned through a
/// shared_ptr by the CompiledModel (and so by every ModelState and thread that uses it); the object
/// is unloaded when the last owner goes.
class NativeCode {
 public:
  /// What Program::Run does: regs is the register file, out the output array; the unknowns and
  /// their derivatives are read from y and yp (num_unknowns each), not from their registers, so a
  /// caller can pass the solver's vectors without copying them (ModelState's residual and
  /// Jacobian) or the registers themselves (regs + y_base, regs + yp_base).
  using Function = void (*)(double* regs, const double* y, const double* yp, double* out);

  NativeCode(void* handle, const std::array<Function, kNumModelPrograms>& functions)
      : handle_(handle), functions_(functions) {}
  ~NativeCode();
  NativeCode(const NativeCode&) = delete;
  NativeCode& operator=(const NativeCode&) = delete;

  /// Null for a program that is not native (IsNativeProgram).
  Function function(ModelProgram which) const { return functions_[static_cast<size_t>(which)]; }

 private:
  void* handle_;
  std::array<Function, kNumModelPrograms> functions_;
};

struct NativeCodeOptions {
  CodegenMode mode = CodegenMode::kAuto;
  /// Instructions per generated C function at most (core/compile/codegen.h).
  uint32_t max_function_len = 2000;
  /// Runs of identical instruction blocks (core/compile/reroll.h) become C loops; false: straight-line
  /// code only (to compare; part of the key).
  bool loops = true;
  /// How many runs the code will serve (a sweep's runs): auto compiles when the expected saving
  /// outweighs the compilation.
  double expected_runs = 1;
  /// Raised by a signal handler (SIGINT, SIGTERM): a compilation under way stops its compilers
  /// (each runs in a process group of its own, which is then stopped), removes its temporary
  /// files and reports `interrupted`. Null: compilation is not interruptible.
  const std::atomic<bool>* interrupt = nullptr;
};

/// What was chosen and what it cost, for `check` and `simulate -v`-style summaries.
struct NativeCodeReport {
  bool native = false;            ///< native code runs the programs
  bool cache_hit = false;         ///< it came from the cache (no compilation)
  double codegen_seconds = 0;     ///< key, C emission (on a miss)
  double compile_seconds = 0;     ///< the C compiler (on a miss)
  double load_seconds = 0;        ///< dlopen and symbol lookup
  size_t instructions = 0;        ///< of the native programs (IsNativeProgram)
  size_t emitted = 0;             ///< of them in the C (a loop's body once), when it was emitted
  std::string reason;             ///< why this choice (one phrase)
  std::string note;               ///< a fallback to the interpreter worth telling the user (one line)
  std::string library;            ///< the shared object's path
  bool interrupted = false;       ///< NativeCodeOptions::interrupt stopped the compilation
  /// One line: "native code (cache hit, 0.4 ms)", "interpreter (auto: 120 instructions …)".
  std::string Summary() const;
};

/// The key of a model's native code under the current compiler and flags (hex); for tests.
std::string NativeCodeKey(const CompiledModel& model, const NativeCodeOptions& options);

/// Native code for `model` per `options` (nullptr: the interpreter runs), from the cache or
/// compiled now. Never throws for a missing or failing compiler: the report's note says why the
/// interpreter runs instead.
std::shared_ptr<const NativeCode> LoadNativeCode(const CompiledModel& model, const NativeCodeOptions& options,
                                                 NativeCodeReport* report);

/// `model` with its native code attached (CompiledModel::native), per LoadNativeCode. The model
/// is finished in place when the caller holds its only reference (right after BuildModel);
/// otherwise a copy gets the code, so that a model others share never changes.
std::shared_ptr<const CompiledModel> AttachNativeCode(std::shared_ptr<const CompiledModel> model,
                                                      const NativeCodeOptions& options, NativeCodeReport* report);

/// How many times this process ran the C compiler (tests check that a cached model does not).
uint64_t NativeCompilations();

/// The cache directory per the environment (see above); empty when none can be named.
std::string NativeCacheDir();

}  // namespace momenta
