// momenta_bench: times momenta's pipeline on one model, in the style of the hand-written IDA
// programs (handwritten_chain, handwritten_rc), so that run.sh can compare the two line by line.
//
// Each of --repeat K runs measures separately
//   load_s       LoadModelFile (YAML -> ModelSpec)
//   build_s      BuildModel (flatten ... compile), wall time; pass_<name>_s is each pass's own
//                time from the BuildReport, pass_<name>_cpu_s its CPU time
//   max_rss_mb   the process's peak resident memory so far (getrusage), after the build
//   pool_nodes   expression nodes in the pool after the build (24 bytes each, plus the hash table)
//   flat_variables  variables of the flat system after the build
//   state_s      ModelState construction + SetParameters
//   init_s       consistent initialisation (SolverStats::init_seconds)
//   integrate_s  IDA set-up + the IDASolve loop (SolverStats::integrate_seconds)
//   simulate_s   wall time of the whole Simulate call (init + integrate + rows); the row
//                callback does nothing
//   *_cpu_s      the same as CPU time of the process (load, build, load_build, simulate): on a
//                shared machine it leaves out the time spent waiting for a core
// and prints one "key=value" line per run, then a "median" line (each field's median over the runs
// that measured it). --build-repeat B: only the first B runs load and build; the later ones
// simulate the last compiled model again (for models that are slow to build). When a simulation
// fails, its message goes to stderr and to a "# run K: simulation failed" line, the run's line
// keeps what was measured (simulate_failed=1), no further runs are made, and the exit code is 1.
//
// usage: momenta_bench --model FILE [-p NAME=VALUE]... [--stop T] [--rtol R] [--atol A]
//                      [--interval DT] [--linear-solver auto|dense|klu] [--repeat K]
//                      [--build-only] [--unit-nominals] [--build-repeat B]
//                      [--codegen auto|native|interp] [--function-len L] [--max-order Q]
//   --max-order      IDA's highest BDF order, 1..5 (default 5, IDA's)
//   --codegen        how the programs run (default interp, as before native code existed): the
//                    code_* fields say what it cost (code_compile_s: the C compiler; code_load_s:
//                    dlopen; code_cache_hit); res_eval_ns is the residual per evaluation
//   --function-len   instructions per generated C function at most (default 2000)
//   --unit-nominals  set every unknown's nominal to 1 after building, so that the absolute
//                    tolerance is the same scalar atol for every variable, as in the hand-written
//                    programs (IDASStolerances). Without it momenta uses atol*nominal.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sys/resource.h>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/build.h"
#include "core/base/error.h"
#include "core/lang/model_spec.h"
#include "core/compile/model_state.h"
#include "core/compile/native_code.h"
#include "solver/simulator.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// CPU time used by this process so far (user + system), in seconds: on a shared machine it does
// not count the time spent waiting for a core.
using momenta_bench::CpuSeconds;
using momenta_bench::Median;

/// The residual's cost per evaluation [ns], measured as handwritten_ida.h's residual_eval_ns does:
/// the median of 5 CPU timings of enough calls to take about 20 ms each, at the start values.
double ResidualEvalNs(momenta::ModelState* state) {
  const size_t n = state->model().num_unknowns();
  std::vector<double> y(n), yp(n), out(n);
  state->StartValues(y.data());
  const long calls = std::max<long>(10, static_cast<long>(2e6 / static_cast<double>(std::max<size_t>(n, 1))));
  std::vector<double> ns;
  for (int k = 0; k < 5; ++k) {
    const double c0 = CpuSeconds();
    for (long i = 0; i < calls; ++i) state->Residual(1e-3 * static_cast<double>(i % 7), y.data(), yp.data(), out.data());
    ns.push_back((CpuSeconds() - c0) * 1e9 / static_cast<double>(calls));
  }
  std::sort(ns.begin(), ns.end());
  return ns[2];
}

struct Options {
  std::string model;
  momenta::ParameterOverrides overrides;
  double stop = -1, rtol = -1, atol = -1, interval = -1;
  std::string linear_solver;  // empty: the model's experiment (default auto)
  int max_order = 5;
  int repeat = 5;
  int build_repeat = -1;  // < 0: every run loads and builds
  bool build_only = false;
  bool unit_nominals = false;
  momenta::NativeCodeOptions codegen{momenta::CodegenMode::kInterp};  // --codegen, --function-len
};

void Usage(const char* prog) {
  std::fprintf(stderr,
               "usage: %s --model FILE [-p NAME=VALUE]... [--stop T] [--rtol R] [--atol A]\n"
               "          [--interval DT] [--linear-solver auto|dense|klu] [--repeat K] [--build-only]\n"
               "          [--unit-nominals] [--build-repeat B] [--codegen auto|native|interp] [--function-len L]\n"
               "          [--max-order Q]\n"
               "defaults: the model's experiment section; --repeat 5; every run loads and builds\n"
               "  --build-repeat B  only the first B runs load and build (B >= 1); later runs simulate\n"
               "                    the last compiled model again (for models that are slow to build)\n",
               prog);
}

Options Parse(int argc, char** argv) {
  Options o;
  auto fail = [&](const std::string& msg) {
    std::fprintf(stderr, "%s: %s\n", argv[0], msg.c_str());
    Usage(argv[0]);
    std::exit(2);
  };
  auto number = [&](const std::string& key, const std::string& v) {
    try {
      size_t used = 0;
      double x = std::stod(v, &used);
      if (used != v.size()) throw std::invalid_argument(v);
      return x;
    } catch (const std::exception&) {
      fail("bad value '" + v + "' for " + key);
    }
    return 0.0;
  };
  for (int i = 1; i < argc; ++i) {
    std::string key = argv[i], value;
    if (key == "-h" || key == "--help") {
      Usage(argv[0]);
      std::exit(0);
    }
    if (key == "--build-only") {
      o.build_only = true;
      continue;
    }
    if (key == "--unit-nominals") {
      o.unit_nominals = true;
      continue;
    }
    size_t eq = key.find('=');
    if (key.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = key.substr(eq + 1);
      key = key.substr(0, eq);
    } else {
      if (i + 1 >= argc) fail("missing value for " + key);
      value = argv[++i];
    }
    if (key == "--model") {
      o.model = value;
    } else if (key == "-p") {
      size_t e = value.find('=');
      if (e == std::string::npos || e == 0 || e + 1 == value.size()) fail("-p takes NAME=VALUE, found '" + value + "'");
      o.overrides[value.substr(0, e)] = number("-p " + value.substr(0, e), value.substr(e + 1));
    } else if (key == "--codegen") {
      if (!momenta::ParseCodegenMode(value, &o.codegen.mode)) fail("--codegen must be auto, native or interp");
    } else if (key == "--function-len") {
      o.codegen.max_function_len = static_cast<uint32_t>(number(key, value));
      if (o.codegen.max_function_len < 1) fail("--function-len must be >= 1");
    } else if (key == "--stop") {
      o.stop = number(key, value);
    } else if (key == "--rtol") {
      o.rtol = number(key, value);
    } else if (key == "--atol") {
      o.atol = number(key, value);
    } else if (key == "--interval") {
      o.interval = number(key, value);
    } else if (key == "--repeat") {
      o.repeat = static_cast<int>(number(key, value));
    } else if (key == "--build-repeat") {
      o.build_repeat = static_cast<int>(number(key, value));
    } else if (key == "--max-order") {
      o.max_order = static_cast<int>(number(key, value));
      if (o.max_order < 1 || o.max_order > 5) fail("--max-order must be in 1..5");
    } else if (key == "--linear-solver") {
      if (value != "auto" && value != "dense" && value != "klu") fail("--linear-solver must be auto, dense or klu");
      o.linear_solver = value;
    } else {
      fail("unknown option " + key);
    }
  }
  if (o.model.empty()) fail("--model is required");
  if (o.repeat < 1) fail("--repeat must be >= 1");
  if (o.build_repeat == 0 || o.build_repeat > o.repeat) fail("--build-repeat must be in 1..repeat");
  if (o.build_repeat < 0) o.build_repeat = o.repeat;
  return o;
}

// "alias elimination" -> "alias_elimination"
std::string Key(std::string s) {
  for (char& c : s) {
    if (c == ' ' || c == '-' || c == '=') c = '_';
  }
  return s;
}

struct Run {
  std::vector<std::pair<std::string, double>> fields;  // in print order
  std::vector<std::pair<std::string, double>> finals;  // output name -> final value
  double get(const std::string& k) const {
    for (const auto& [name, v] : fields) {
      if (name == k) return v;
    }
    return NAN;
  }
};

}  // namespace

int main(int argc, char** argv) {
  using namespace momenta;
  const Options opt = Parse(argc, argv);
  std::vector<Run> runs;
  std::string header;
  bool simulate_failed = false;
  try {
    // The built-in component library is parsed on first use: once per process, not per build.
    auto tl = Clock::now();
    BuiltinLibrary();
    const double library_s = Since(tl);
    std::shared_ptr<const CompiledModel> model;
    BuildReport report;
    for (int k = 0; k < opt.repeat; ++k) {
      Run r;
      double load_s = 0, build_s = 0;
      if (k < opt.build_repeat) {
        auto t0 = Clock::now();
        const double c0 = CpuSeconds();
        ModelSpec spec = LoadModelFile(opt.model);
        load_s = Since(t0);
        const double c1 = CpuSeconds();
        report = BuildReport();
        auto t1 = Clock::now();
        model = BuildModel(spec, BuiltinLibrary(), opt.overrides, &report);
        build_s = Since(t1);
        const double c2 = CpuSeconds();
        if (opt.unit_nominals) {
          auto copy = std::make_shared<CompiledModel>(*model);
          std::fill(copy->nominal.begin(), copy->nominal.end(), 1.0);
          model = copy;
        }
        r.fields.emplace_back("load_s", load_s);
        r.fields.emplace_back("build_s", build_s);
        r.fields.emplace_back("load_build_s", load_s + build_s);
        r.fields.emplace_back("load_cpu_s", c1 - c0);
        r.fields.emplace_back("build_cpu_s", c2 - c1);
        r.fields.emplace_back("load_build_cpu_s", c2 - c0);
        for (const auto& p : report.passes) {
          r.fields.emplace_back("pass_" + Key(p.name) + "_s", p.seconds);
          r.fields.emplace_back("pass_" + Key(p.name) + "_cpu_s", p.cpu_seconds);
        }
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        r.fields.emplace_back("max_rss_mb", static_cast<double>(ru.ru_maxrss) / 1024.0);
        // The expression pool only grows: every pass's rewritten expressions stay in it.
        r.fields.emplace_back("pool_nodes", static_cast<double>(model->pool->size()));
        r.fields.emplace_back("flat_variables", static_cast<double>(model->flat->variables.size()));
        // Native code (compiled now or from the cache) as --codegen says.
        NativeCodeReport code;
        auto t4 = Clock::now();
        model = AttachNativeCode(std::move(model), opt.codegen, &code);
        r.fields.emplace_back("code_s", Since(t4));
        r.fields.emplace_back("code_native", code.native ? 1 : 0);
        r.fields.emplace_back("code_cache_hit", code.cache_hit ? 1 : 0);
        r.fields.emplace_back("code_compile_s", code.compile_seconds);
        r.fields.emplace_back("code_emit_s", code.codegen_seconds);
        r.fields.emplace_back("code_load_s", code.load_seconds);
        r.fields.emplace_back("code_instr", static_cast<double>(code.instructions));
        if (!code.note.empty()) std::printf("# code: %s\n", code.note.c_str());
      }

      SimulationOptions so = OptionsFromExperiment(model->experiment);
      if (opt.stop >= 0) so.stop = opt.stop;
      if (opt.rtol > 0) so.rtol = opt.rtol;
      if (opt.atol > 0) so.atol = opt.atol;
      if (opt.interval > 0) so.interval = opt.interval;
      if (!opt.linear_solver.empty()) so.linear_solver = opt.linear_solver;
      so.max_order = opt.max_order;

      if (k == 0) {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "# momenta_bench model=%s components=%zu unknowns=%zu states=%zu jac_nnz=%zu expr_nodes=%zu "
                      "residual_instr=%zu jacobian_instr=%zu stop=%g rtol=%g atol=%g interval=%g "
                      "linear_solver=%s max_order=%d unit_nominals=%d repeat=%d build_repeat=%d",
                      opt.model.c_str(), report.num_components, model->num_unknowns(), model->num_states(),
                      model->jacobian_pattern.nnz(), model->pool ? model->pool->size() : size_t{0}, model->residual.size(), model->jacobian.size(), so.stop,
                      so.rtol, so.atol > 0 ? so.atol : so.rtol,
                      so.interval > 0 ? so.interval : (so.stop - so.start) / 500.0, so.linear_solver.c_str(),
                      so.max_order, opt.unit_nominals ? 1 : 0, opt.repeat, opt.build_repeat);
        header = buf;
        for (const auto& [name, v] : opt.overrides) {
          char pbuf[128];
          std::snprintf(pbuf, sizeof pbuf, " %s=%g", name.c_str(), v);
          header += pbuf;
        }
        const SolverBuild solver_build = SolverBuildInfo();
        std::printf("%s\n# SUNDIALS %s (%s build); built-in library parsed in library_s=%.6f (once, not timed "
                    "in load/build)\n",
                    header.c_str(), solver_build.sundials_version.c_str(),
                    solver_build.sundials_optimized ? "optimised" : "system", library_s);
        {
          // The states by kind: "mass[12].v" counts as "mass[].v" and a written-out "mass12.v"
          // as "mass#.v", so a model of 100 000 components prints a few kinds, not every name.
          std::map<std::string, size_t> kinds;
          for (const std::string& name : report.states) {
            std::string kind;
            bool in_index = false;
            for (char ch : name) {
              if (ch == '[') in_index = true;
              const bool digit = ch >= '0' && ch <= '9';
              if (in_index && ch != '[' && ch != ']') continue;
              if (!digit) {
                kind += ch;
              } else if (kind.empty() || kind.back() != '#') {
                kind += '#';
              }
              if (ch == ']') in_index = false;
            }
            ++kinds[kind];
          }
          constexpr size_t kMaxKinds = 40;
          std::printf("# states by kind:");
          size_t shown = 0;
          for (const auto& [kind, count] : kinds) {
            if (shown++ == kMaxKinds) {
              std::printf(" (%zu more kinds)", kinds.size() - kMaxKinds);
              break;
            }
            std::printf(" %s=%zu", kind.c_str(), count);
          }
          std::printf("\n");
        }
        if (!model->nominal.empty()) {
          auto [lo, hi] = std::minmax_element(model->nominal.begin(), model->nominal.end());
          std::printf("# nominals: min=%g max=%g (absolute tolerance of unknown k = atol*nominal[k])\n", *lo, *hi);
        }
      }

      if (!opt.build_only) {
        auto t2 = Clock::now();
        ModelState state(model);
        state.SetParameters(opt.overrides);
        r.fields.emplace_back("state_s", Since(t2));
        SolverStats stats;
        std::vector<double> last(model->output_names.size());
        auto t3 = Clock::now();
        const double c3 = CpuSeconds();
        try {
          Simulate(&state, so, [&](double, const std::vector<double>& v) { last = v; }, &stats);
        } catch (const std::exception& e) {
          // Keep what was measured (load, build) and report the failure; the exit code is 1.
          std::fprintf(stderr, "momenta_bench: run %d: simulation failed: %s\n", k + 1, e.what());
          std::printf("# run %d: simulation failed: %s\n", k + 1, e.what());
          simulate_failed = true;
          r.fields.emplace_back("simulate_failed", 1);
        }
        const double simulate_s = Since(t3);
        const double simulate_cpu_s = CpuSeconds() - c3;
        if (simulate_failed) {
          std::printf("run=%d", k + 1);
          for (const auto& [name, v] : r.fields) std::printf(" %s=%.6g", name.c_str(), v);
          std::printf("\n");
          runs.push_back(std::move(r));
          break;  // the same model and options fail the same way every time
        }
        r.fields.emplace_back("init_s", stats.init_seconds);
        r.fields.emplace_back("integrate_s", stats.integrate_seconds);
        r.fields.emplace_back("simulate_s", simulate_s);
        r.fields.emplace_back("simulate_cpu_s", simulate_cpu_s);
        if (k < opt.build_repeat) r.fields.emplace_back("total_s", load_s + build_s + Since(t2));
        r.fields.emplace_back("steps", static_cast<double>(stats.steps));
        r.fields.emplace_back("res_evals", static_cast<double>(stats.residual_evals));
        r.fields.emplace_back("jac_evals", static_cast<double>(stats.jacobian_evals));
        r.fields.emplace_back("err_test_fails", static_cast<double>(stats.error_test_failures));
        r.fields.emplace_back("nonlin_conv_fails", static_cast<double>(stats.nonlinear_failures));
        r.fields.emplace_back("init_iters", static_cast<double>(stats.init_iterations));
        r.fields.emplace_back("t", stats.final_time);
        for (size_t j = 0; j < last.size(); ++j) r.finals.emplace_back(model->output_names[j], last[j]);
        if (k == 0) std::printf("# linear solver used: %s\n", stats.linear_solver.c_str());
        r.fields.emplace_back("res_eval_ns", ResidualEvalNs(&state));
      }

      std::printf("run=%d", k + 1);
      for (const auto& [name, v] : r.fields) {
        if (name.size() > 2 && name.compare(name.size() - 2, 2, "_s") == 0) {
          std::printf(" %s=%.6f", name.c_str(), v);
        } else {
          std::printf(" %s=%.10g", name.c_str(), v);
        }
      }
      for (const auto& [name, v] : r.finals) std::printf(" %s=%.17g", name.c_str(), v);
      std::printf("\n");
      std::fflush(stdout);
      runs.push_back(std::move(r));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "momenta_bench: %s\n", e.what());
    return 1;
  }

  std::printf("median");
  std::vector<std::string> names;  // every field, in first-seen order
  for (const Run& r : runs) {
    for (const auto& f : r.fields) {
      if (std::find(names.begin(), names.end(), f.first) == names.end()) names.push_back(f.first);
    }
  }
  for (const std::string& name : names) {
    std::vector<double> v;
    for (const Run& r : runs) {
      double x = r.get(name);
      if (!std::isnan(x)) v.push_back(x);
    }
    const double m = Median(v);
    if (name.size() > 2 && name.compare(name.size() - 2, 2, "_s") == 0) {
      std::printf(" %s=%.6f", name.c_str(), m);
    } else {
      std::printf(" %s=%.10g", name.c_str(), m);
    }
  }
  for (size_t j = 0; j < runs[0].finals.size(); ++j) {
    std::vector<double> v;
    for (const Run& r : runs) {
      if (j < r.finals.size()) v.push_back(r.finals[j].second);
    }
    std::printf(" %s=%.17g", runs[0].finals[j].first.c_str(), Median(v));
  }
  std::printf("\n");
  return simulate_failed ? 1 : 0;
}
