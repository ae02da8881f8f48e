// reroll_bench: how much of a model's compiled programs loop rerolling (core/compile/reroll.h) covers,
// how long the detection takes, and what evaluating the rolled form costs against the
// straight-line interpreter (Program::Run) on the residual and the Jacobian.
//
// usage: reroll_bench --model FILE [-p NAME=VALUE]... [--evals K] [--dump PROGRAM]
//   prints one line per compiled program: instructions, share inside loops (count >= 4),
//   segments, loops, rolled size (instructions kept), detection time; then per evaluation
//   times (CPU time; medians over 9 alternating pairs of batches of K evaluations) of
//   Program::Run and RolledProgram::Run for the residual and the Jacobian, and the median ratio,
//   after checking that both give bitwise the same values.
//   --dump PROGRAM prints that program's instructions and its segments (to see irregularities).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/build.h"
#include "core/lang/component_type.h"
#include "core/base/error.h"
#include "core/lang/model_spec.h"
#include "core/compile/reroll.h"
#include "core/lang/yaml_loader.h"
#include "core/lang/builtin_library.h"

namespace {

using momenta_bench::CpuSeconds;

struct Named {
  const char* name;
  const momenta::Program* program;
};

std::vector<Named> Programs(const momenta::CompiledModel& m) {
  return {{"residual", &m.residual},           {"jacobian", &m.jacobian},
          {"outputs", &m.outputs},             {"zero_crossings", &m.zero_crossings},
          {"zero_crossing_rates", &m.zero_crossing_rates}, {"init_residual", &m.init_residual},
          {"init_jacobian", &m.init_jacobian}, {"start_values", &m.start_values},
          {"start_guesses", &m.start_guesses}, {"parameters", &m.parameters}};
}

/// A register's region in the layout, for dumps.
std::string Reg(const momenta::RegisterLayout& L, uint32_t r) {
  char buf[32];
  if (r < L.param_base) std::snprintf(buf, sizeof buf, "s%u", r);
  else if (r < L.y_base) std::snprintf(buf, sizeof buf, "p%u", r - L.param_base);
  else if (r < L.yp_base) std::snprintf(buf, sizeof buf, "y%u", r - L.y_base);
  else if (r < L.disc_base) std::snprintf(buf, sizeof buf, "yp%u", r - L.yp_base);
  else if (r < L.temp_base) std::snprintf(buf, sizeof buf, "g%u", r);
  else std::snprintf(buf, sizeof buf, "t%u", r - L.temp_base);
  return buf;
}

void Dump(const momenta::CompiledModel& m, const momenta::Program& p) {
  const auto segments = momenta::Reroll(p);
  size_t k = 0;
  for (uint32_t i = 0; i < p.size(); ++i) {
    while (k < segments.size() && segments[k].begin == i) {
      std::printf("---- segment begin=%u len=%u count=%u\n", segments[k].begin, segments[k].len, segments[k].count);
      ++k;
    }
    const momenta::Instruction& in = p.code()[i];
    std::string dst = in.op == momenta::kStore ? "out" + std::to_string(in.dst) : Reg(m.layout, in.dst);
    std::printf("%6u op%-3u %-8s %-8s %-8s %-8s\n", i, in.op, dst.c_str(), Reg(m.layout, in.a).c_str(),
                Reg(m.layout, in.b).c_str(), Reg(m.layout, in.c).c_str());
  }
}

/// CPU seconds per evaluation of `a` and of `b`, and the ratio b/a: medians over 9 pairs of
/// batches of `evals` evaluations, a's and b's batches alternating so that both see the same
/// machine (it is shared).
template <typename A, typename B>
std::array<double, 3> PerEvalPaired(A a, B b, int evals) {
  std::vector<double> ta, tb, ratio;
  for (int k = 0; k < 9; ++k) {
    const double t0 = CpuSeconds();
    for (int e = 0; e < evals; ++e) a();
    const double t1 = CpuSeconds();
    for (int e = 0; e < evals; ++e) b();
    const double t2 = CpuSeconds();
    ta.push_back((t1 - t0) / evals);
    tb.push_back((t2 - t1) / evals);
    ratio.push_back((t2 - t1) / (t1 - t0));
  }
  for (auto* v : {&ta, &tb, &ratio}) std::sort(v->begin(), v->end());
  return {ta[4], tb[4], ratio[4]};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace momenta;
  std::string model_file, dump;
  ParameterOverrides overrides;
  int evals = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--model" && i + 1 < argc) {
      model_file = argv[++i];
    } else if (a == "-p" && i + 1 < argc) {
      const std::string kv = argv[++i];
      const size_t eq = kv.find('=');
      if (eq == std::string::npos) {
        std::fprintf(stderr, "-p wants NAME=VALUE, got %s\n", kv.c_str());
        return 2;
      }
      overrides[kv.substr(0, eq)] = std::atof(kv.c_str() + eq + 1);
    } else if (a == "--evals" && i + 1 < argc) {
      evals = std::atoi(argv[++i]);
    } else if (a == "--dump" && i + 1 < argc) {
      dump = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s --model FILE [-p NAME=VALUE]... [--evals K] [--dump PROGRAM]\n", argv[0]);
      return 2;
    }
  }
  if (model_file.empty()) {
    std::fprintf(stderr, "usage: %s --model FILE [-p NAME=VALUE]... [--evals K] [--dump PROGRAM]\n", argv[0]);
    return 2;
  }
  try {
    BuildReport report;
    const double b0 = CpuSeconds();
    auto model = BuildModel(LoadModelFile(model_file), BuiltinLibrary(), overrides, &report);
    const double build_s = CpuSeconds() - b0;
    const CompiledModel& m = *model;
    std::printf("# reroll_bench model=%s unknowns=%zu load_build_cpu_s=%.3f\n", model_file.c_str(), m.num_unknowns(), build_s);
    if (!dump.empty()) {
      for (const Named& p : Programs(m)) {
        if (dump == p.name) Dump(m, *p.program);
      }
      return 0;
    }
    std::printf("%-20s %10s %8s %9s %7s %10s %9s\n", "program", "instr", "in_loops", "segments", "loops", "rolled", "reroll_s");
    for (const Named& p : Programs(m)) {
      const double t0 = CpuSeconds();
      const auto segments = Reroll(*p.program);
      const double reroll_s = CpuSeconds() - t0;
      const RerollCoverage c = Coverage(segments);
      std::printf("%-20s %10zu %7.1f%% %9zu %7zu %10zu %9.4f\n", p.name, c.instructions, 100 * c.share(), c.segments,
                  c.loops, c.rolled_size, reroll_s);
    }
    // Per evaluation: the straight-line interpreter against the rolled one, same registers.
    if (evals == 0) evals = static_cast<int>(std::max<size_t>(1, 20000000 / (m.residual.size() + m.jacobian.size() + 1)));
    std::vector<double> regs(m.layout.size, 0.0);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.5, 1.5);
    for (double& r : regs) r = u(rng);
    for (const auto& [reg, value] : m.constants) regs[reg] = value;
    m.parameters.Run(regs.data(), nullptr);
    for (const Named& p : {Named{"residual", &m.residual}, Named{"jacobian", &m.jacobian}}) {
      const RolledProgram rolled(*p.program);
      const size_t outs = std::max<size_t>(m.num_unknowns(), m.jacobian_pattern.nnz()) + 1;
      std::vector<double> out1(outs, 0.0), out2(outs, 0.0), regs1 = regs, regs2 = regs;
      p.program->Run(regs1.data(), out1.data());
      rolled.Run(regs2.data(), out2.data());
      const bool same = std::memcmp(out1.data(), out2.data(), outs * sizeof(double)) == 0 &&
                        std::memcmp(regs1.data(), regs2.data(), regs.size() * sizeof(double)) == 0;
      const auto t = PerEvalPaired([&] { p.program->Run(regs1.data(), out1.data()); },
                                   [&] { rolled.Run(regs2.data(), out2.data()); }, evals);
      std::printf("eval %-10s straight_ns=%.0f rolled_ns=%.0f ratio=%.2f identical=%d evals=%d\n", p.name,
                  t[0] * 1e9, t[1] * 1e9, t[2], same ? 1 : 0, evals);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
