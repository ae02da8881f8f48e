// build_floor: what any build that keeps one record per scalar costs, against the whole build.
//
// Issue 30 asks for 10^6 array components in 2 s and 1 GB, and 10^5 written-out components in
// 1 s and 100 MB. This program answers "can the scalar build get there by tuning?" with figures
// rather than argument. It builds the model once as momenta does (the baseline, measured in the
// same run), reads how many expression nodes, flat variables, parameters and equations that build
// made, and then times only the work that a build with one record per scalar cannot avoid, at
// those counts, with nothing else in between:
//   intern   making the pool's nodes once: one hash-consing ExprPool call per node, the table
//            reserved at the right size beforehand (the build's own pool does this); the nodes are
//            chains of products of a component's parameters and variables, each chain from a
//            constant of its own, so that every node is new, as the build's are
//   records  making the flat records once: FlatVariable, FlatParameter and FlatEquation at the
//            build's counts, each written as the flattener writes it (reserved vectors)
//   walk     one pass that reads each equation's variables once (CollectLeaves into one reused
//            buffer), which is the least every structural pass does; the build has seven such
//            passes and the compiler reads each equation again to differentiate it
// The bytes are exact: sizeof × count for the records, nodes × sizeof(Node) plus the table for
// the pool. The floors are lower bounds: the real build also parses, substitutes, matches,
// differentiates and compiles.
//
// usage: build_floor --model FILE [-p NAME=VALUE]... [--repeat K]
// Prints one key=value line per run and a "median" line, then a summary against the targets.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/build.h"
#include "core/expr/expr.h"
#include "core/expr/expr_leaves.h"
#include "core/flatten/flat_system.h"
#include "core/lang/builtin_library.h"
#include "core/lang/model_spec.h"
#include "core/lang/yaml_loader.h"

namespace {

using namespace momenta;

double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Counts {
  size_t components = 0, nodes = 0, variables = 0, parameters = 0, equations = 0;
};

struct Fields {
  std::vector<std::pair<std::string, double>> values;
  void Add(const std::string& key, double v) { values.emplace_back(key, v); }
};

// The baseline: load and build as `momenta check` does, CPU seconds.
Counts BuildOnce(const std::string& file, const std::map<std::string, double>& overrides,
                 Fields* out) {
  const double c0 = CpuSeconds();
  ModelSpec spec = LoadModelFile(file);
  const double c1 = CpuSeconds();
  BuildReport report;
  auto model = BuildModel(spec, BuiltinLibrary(), overrides, &report);
  const double c2 = CpuSeconds();
  out->Add("load_cpu_s", c1 - c0);
  out->Add("build_cpu_s", c2 - c1);
  for (const PassReport& p : report.passes) {
    if (p.name == "flatten") out->Add("pass_flatten_cpu_s", p.cpu_seconds);
  }
  Counts n;
  n.components = report.num_components;
  n.nodes = model->pool->size();
  // What flattening made, before the passes removed anything: the records a scalar build holds.
  n.variables = report.passes.empty() ? 0 : report.passes.front().variables;
  n.equations = report.passes.empty() ? 0 : report.passes.front().equations;
  n.parameters = report.num_parameters;
  return n;
}

// Floor 1: the pool's nodes, made once. Returns the equation roots for the walk.
std::vector<ExprId> Intern(const Counts& n, ExprPool* pool, Fields* out) {
  const size_t per_component_vars = std::max<size_t>(1, n.variables / std::max<size_t>(1, n.components));
  const size_t per_component_params = std::max<size_t>(1, n.parameters / std::max<size_t>(1, n.components));
  const size_t nodes_per_component = std::max<size_t>(4, n.nodes / std::max<size_t>(1, n.components));
  const size_t equations_per_component =
      std::max<size_t>(1, n.equations / std::max<size_t>(1, n.components));
  std::vector<ExprId> roots;
  roots.reserve(n.components * equations_per_component);
  const double c0 = CpuSeconds();
  pool->Reserve(n.nodes);
  for (size_t c = 0; c < n.components; ++c) {
    const size_t v0 = c * per_component_vars, p0 = c * per_component_params;
    const size_t goal = pool->size() + nodes_per_component;
    const size_t chain = std::max<size_t>(2, nodes_per_component / equations_per_component);
    // Each equation starts from a constant of its own, so that every node after it is new.
    ExprId acc = pool->Const(static_cast<double>(roots.size()) + 0.5);
    for (size_t j = 0; pool->size() < goal; ++j) {
      const size_t before = pool->size();
      ExprId term = pool->Mul(pool->Param(ParamId(static_cast<uint32_t>(p0 + j % per_component_params))),
                              pool->Var(VarId(static_cast<uint32_t>(v0 + j % per_component_vars))));
      acc = pool->Sub(term, acc);
      if ((j + 1) % chain == 0) {
        roots.push_back(acc);
        acc = pool->Const(static_cast<double>(roots.size()) + 0.5);
      }
      if (pool->size() == before && j > 4 * nodes_per_component) break;  // nothing new: stop
    }
    roots.push_back(acc);
  }
  out->Add("intern_cpu_s", CpuSeconds() - c0);
  out->Add("intern_nodes", static_cast<double>(pool->size()));
  return roots;
}

// Floor 2: the flat records, made once at the build's counts.
double Records(const Counts& n, Fields* out) {
  const double c0 = CpuSeconds();
  std::vector<FlatVariable> variables;
  std::vector<FlatParameter> parameters;
  std::vector<FlatEquation> equations;
  variables.reserve(n.variables);
  parameters.reserve(n.parameters);
  equations.reserve(n.equations);
  const size_t components = std::max<size_t>(1, n.components);
  for (size_t i = 0; i < n.variables; ++i) {
    FlatVariable& v = variables.emplace_back();
    v.instance = InstanceId(static_cast<uint32_t>(i * components / std::max<size_t>(1, n.variables)));
    v.name = TextRef{TextRef::kType, v.instance.value(), static_cast<uint32_t>(i % 8)};
  }
  for (size_t i = 0; i < n.parameters; ++i) {
    FlatParameter& p = parameters.emplace_back();
    p.instance = InstanceId(static_cast<uint32_t>(i * components / std::max<size_t>(1, n.parameters)));
    p.name = TextRef{TextRef::kType, p.instance.value(), static_cast<uint32_t>(i % 3)};
  }
  for (size_t i = 0; i < n.equations; ++i) {
    FlatEquation& e = equations.emplace_back();
    e.residual = ExprId(static_cast<uint32_t>(i));
    e.instance = InstanceId(static_cast<uint32_t>(i * components / std::max<size_t>(1, n.equations)));
  }
  out->Add("records_cpu_s", CpuSeconds() - c0);
  const double bytes = static_cast<double>(variables.capacity() * sizeof(FlatVariable) +
                                           parameters.capacity() * sizeof(FlatParameter) +
                                           equations.capacity() * sizeof(FlatEquation));
  out->Add("records_mb", bytes / 1e6);
  return bytes;
}

// Floor 3: one pass reading every equation's variables.
void Walk(const ExprPool& pool, const std::vector<ExprId>& roots, Fields* out) {
  const double c0 = CpuSeconds();
  std::vector<ExprId> leaves;
  size_t total = 0;
  for (ExprId root : roots) {
    CollectLeaves(pool, root, kHasVar, &leaves);
    total += leaves.size();
  }
  out->Add("walk_cpu_s", CpuSeconds() - c0);
  out->Add("walk_leaves", static_cast<double>(total));
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

int Usage() {
  std::fprintf(stderr, "usage: build_floor --model FILE [-p NAME=VALUE]... [--repeat K]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string file;
  std::map<std::string, double> overrides;
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--model" && i + 1 < argc) {
      file = argv[++i];
    } else if (a == "-p" && i + 1 < argc) {
      const std::string kv = argv[++i];
      const size_t eq = kv.find('=');
      if (eq == std::string::npos) return Usage();
      overrides[kv.substr(0, eq)] = std::strtod(kv.c_str() + eq + 1, nullptr);
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else {
      return Usage();
    }
  }
  if (file.empty()) return Usage();
  try {
    BuiltinLibrary();  // parsed once per process, as in momenta_bench: not part of any figure
    std::map<std::string, std::vector<double>> all;
    std::vector<std::string> order;
    Counts n;
    double pool_mb = 0, records_mb = 0;
    for (int k = 0; k < repeat; ++k) {
      Fields f;
      n = BuildOnce(file, overrides, &f);
      {
        ExprPool pool;
        const std::vector<ExprId> roots = Intern(n, &pool, &f);
        Walk(pool, roots, &f);
        // Nodes and the table the pool reserves for them (Reserve: 4/3 slots of 8 bytes per node).
        pool_mb = (static_cast<double>(pool.size()) * sizeof(Node) +
                   static_cast<double>(n.nodes) * 4.0 / 3.0 * 8.0) / 1e6;
      }
      records_mb = Records(n, &f) / 1e6;
      std::printf("run=%d", k + 1);
      for (const auto& [key, v] : f.values) {
        std::printf(" %s=%.6g", key.c_str(), v);
        if (all.find(key) == all.end()) order.push_back(key);
        all[key].push_back(v);
      }
      std::printf("\n");
    }
    std::printf("median");
    for (const std::string& key : order) std::printf(" %s=%.6g", key.c_str(), Median(all[key]));
    std::printf("\n");
    const double build = Median(all["load_cpu_s"]) + Median(all["build_cpu_s"]);
    const double floor_s = Median(all["intern_cpu_s"]) + Median(all["records_cpu_s"]) +
                           Median(all["walk_cpu_s"]);
    const double per = 1e9 / static_cast<double>(std::max<size_t>(1, n.components));
    std::printf("\n%zu components: the build made %zu nodes (%.1f per component), %zu variables, "
                "%zu parameters, %zu equations\n",
                n.components, n.nodes, static_cast<double>(n.nodes) / std::max<size_t>(1, n.components),
                n.variables, n.parameters, n.equations);
    std::printf("load + build         %8.3f s CPU   (%.0f ns per component)\n", build, build * per);
    std::printf("floor: intern        %8.3f s       %8.1f MB (nodes and table)\n",
                Median(all["intern_cpu_s"]), pool_mb);
    std::printf("floor: records       %8.3f s       %8.1f MB\n", Median(all["records_cpu_s"]),
                records_mb);
    std::printf("floor: one walk      %8.3f s\n", Median(all["walk_cpu_s"]));
    std::printf("floors together      %8.3f s       %8.1f MB; the build takes %.1f times the time\n",
                floor_s, pool_mb + records_mb, build / std::max(1e-9, floor_s));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "build_floor: %s\n", e.what());
    return 1;
  }
  return 0;
}
