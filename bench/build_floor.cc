// build_floor: what the scalar build's form costs at least, against the whole build.
//
// Issue 30 asks for 10^6 array components in 2 s and 1 GB, and 10^5 written-out components in
// 1 s and 100 MB. This program asks how far tuning the present scalar build can go. It builds
// the model once as momenta does (the baseline, in the same process and run), reads the counts
// that build made, and then times only work that a build with one record per scalar cannot skip,
// at those counts, with nothing else in between. Two designs are measured:
//
// The present one (a hash-consed ExprPool, the present flat records):
//   intern   one hash-consing ExprPool call per node, for as many nodes as the whole build leaves
//            in its pool (the passes add to it), the table reserved beforehand as the build
//            reserves it; chains of products of a component's parameters and variables, each
//            chain from a constant of its own, so that every node is new, as the build's are
//   records  FlatVariable, FlatParameter and FlatEquation records at flattening's counts, in
//            reserved vectors
// A lean scalar one, for comparison (what a redesign of the scalar core could reach):
//   append   as many 16-byte nodes as flattening makes, appended to a reserved array with no
//            hashing (instantiating a type's template by copying it with its ids offset)
//   lean     records of 8, 16 and 8 bytes (variable, parameter, equation) at the same counts,
//            the per-type data (names, units, bounds, nominal, locations) held once per type
// Both:
//   walk     one pass reading each equation's variables once (CollectLeaves, one reused buffer),
//            over as many equations as flattening makes: the least a structural pass does (on
//            the present pool's nodes, for both designs)
// Times are CPU seconds and include first-touch page faults (a build pays them too). Memory is
// computed as count × size (nodes, the pool's table at 4/3 slots of 8 bytes per node, records);
// the intern floor's growth of the resident set is printed beside it (the pool also keeps an
// index of leaves and a nursery). The pool's arrays are on huge pages (madvise), as in a build;
// the records and the lean design's arrays are on the C library's default allocator (4 KB pages),
// whereas `momenta check` restarts itself with malloc on huge pages for a large model (README).
//
// usage: build_floor --model FILE [-p NAME=VALUE]... [--repeat K]
// Prints one key=value line per run and a "median" line, then a summary against the targets.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <string>
#include <stdexcept>
#include <unistd.h>
#include <vector>

#include "bench_util.h"
#include "core/base/error.h"
#include "core/build.h"
#include "core/expr/expr.h"
#include "core/expr/expr_leaves.h"
#include "core/flatten/flat_system.h"
#include "core/flatten/flatten.h"
#include "core/lang/builtin_library.h"
#include "core/lang/model_spec.h"
#include "core/lang/yaml_loader.h"

namespace {

using namespace momenta;

using momenta_bench::CpuSeconds;
using momenta_bench::Median;

/// The resident set in MB (/proc/self/statm), 0 where it cannot be read.
double ResidentMb() {
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return 0;
  long size = 0, resident = 0;
  const int read = std::fscanf(f, "%ld %ld", &size, &resident);
  std::fclose(f);
  return read == 2 ? static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1e6 : 0;
}

/// Tells the compiler that `p`'s memory is read here, so that the stores that filled it are made
/// before the clock is read again (the ClobberMemory idiom of benchmark libraries).
void Escape(const void* p) { asm volatile("" : : "r"(p) : "memory"); }

struct Counts {
  size_t components = 0;
  size_t nodes = 0;       ///< in the pool after the whole build
  size_t flat_nodes = 0;  ///< in the pool after flattening
  size_t variables = 0, parameters = 0, equations = 0;  ///< made by flattening
  size_t unknowns_after_aliases = 0;
};

struct Fields {
  std::vector<std::pair<std::string, double>> values;
  void Add(const std::string& key, double v) { values.emplace_back(key, v); }
};

// The baseline: load and build as `momenta check` does, CPU seconds; then flattening alone, for
// its counts (not timed).
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
  Counts n;
  for (const PassReport& p : report.passes) {
    if (p.name == "flatten") {
      out->Add("pass_flatten_cpu_s", p.cpu_seconds);
      n.variables = p.variables;
      n.equations = p.equations;
    }
    if (p.name == "alias elimination") n.unknowns_after_aliases = p.variables;
  }
  n.components = report.num_components;
  n.nodes = model->pool->size();
  n.parameters = report.num_parameters;
  model.reset();
  n.flat_nodes = Flatten(spec, BuiltinLibrary(), overrides, /*defer_equations=*/true).pool->size();
  return n;
}

size_t PerComponent(size_t count, const Counts& n) {
  return std::max<size_t>(1, count / std::max<size_t>(1, n.components));
}

// The present design's pool: n.nodes new nodes, hash-consed, in n.equations chains. Returns the
// chains' roots for the walk.
std::vector<ExprId> Intern(const Counts& n, ExprPool* pool, Fields* out) {
  const size_t vars = PerComponent(n.variables, n), params = PerComponent(n.parameters, n);
  const size_t components = std::max<size_t>(1, n.components);
  std::vector<ExprId> roots;
  roots.reserve(n.equations + components);
  const double rss0 = ResidentMb();
  const double c0 = CpuSeconds();
  pool->Reserve(n.nodes);
  for (size_t c = 0; c < components; ++c) {
    const size_t v0 = c * vars, p0 = c * params;
    // Running goals, so that the totals are the build's (not rounded per component).
    const size_t goal = (c + 1) * n.nodes / components;
    const size_t equations = (c + 1) * n.equations / components - c * n.equations / components;
    // The component's chains end at evenly spaced pool sizes (an iteration makes at most four
    // nodes, fewer than a chain's share), so that there are as many as it has equations.
    const size_t start = pool->size(), budget = goal > start ? goal - start : 0;
    // Each chain starts from a constant of its own, so that every node after it is new (while the
    // pairs parameter × variable do not repeat: for lcm(parameters, variables) iterations, 24 on
    // the RC ladder, which makes about 11 per chain).
    ExprId acc = pool->Const(static_cast<double>(roots.size()) + 0.5);
    size_t made = 0;
    for (size_t j = 0; pool->size() < goal; ++j) {
      const size_t before = pool->size();
      ExprId term = pool->Mul(pool->Param(ParamId(static_cast<uint32_t>(p0 + j % params))),
                              pool->Var(VarId(static_cast<uint32_t>(v0 + j % vars))));
      acc = pool->Sub(term, acc);
      while (made + 1 < equations && pool->size() - start >= (made + 1) * budget / equations) {
        roots.push_back(acc);
        ++made;
        acc = pool->Const(static_cast<double>(roots.size()) + 0.5);
      }
      if (pool->size() == before) break;  // nothing new (cannot happen with the constants above)
    }
    roots.push_back(acc);
  }
  out->Add("intern_cpu_s", CpuSeconds() - c0);
  out->Add("intern_nodes", static_cast<double>(pool->size()));
  out->Add("intern_rss_mb", ResidentMb() - rss0);
  return roots;
}

// A design's flat records, reserved at flattening's counts.
template <typename Variable, typename Parameter, typename Equation>
struct RecordSet {
  std::vector<Variable> variables;
  std::vector<Parameter> parameters;
  std::vector<Equation> equations;

  explicit RecordSet(const Counts& n) {
    variables.reserve(n.variables);
    parameters.reserve(n.parameters);
    equations.reserve(n.equations);
  }
  /// Count × size, in MB.
  double Mb() const {
    return static_cast<double>(variables.size() * sizeof(Variable) + parameters.size() * sizeof(Parameter) +
                               equations.size() * sizeof(Equation)) / 1e6;
  }
};

// The present design's records, at flattening's counts.
double Records(const Counts& n, Fields* out) {
  const size_t components = std::max<size_t>(1, n.components);
  const double c0 = CpuSeconds();
  RecordSet<FlatVariable, FlatParameter, FlatEquation> records(n);
  auto& [variables, parameters, equations] = records;
  for (size_t i = 0; i < n.variables; ++i) {
    FlatVariable& v = variables.emplace_back();
    v.instance = InstanceId(static_cast<uint32_t>(i * components / n.variables));
    v.name = TextRef{TextRef::kType, v.instance.value(), static_cast<uint32_t>(i % 8)};
  }
  for (size_t i = 0; i < n.parameters; ++i) {
    FlatParameter& p = parameters.emplace_back();
    p.instance = InstanceId(static_cast<uint32_t>(i * components / n.parameters));
    p.name = TextRef{TextRef::kType, p.instance.value(), static_cast<uint32_t>(i % 3)};
  }
  for (size_t i = 0; i < n.equations; ++i) {
    FlatEquation& e = equations.emplace_back();
    e.residual = ExprId(static_cast<uint32_t>(i));
    e.instance = InstanceId(static_cast<uint32_t>(i * components / n.equations));
  }
  Escape(variables.data());
  Escape(parameters.data());
  Escape(equations.data());
  out->Add("records_cpu_s", CpuSeconds() - c0);
  const double mb = records.Mb();
  out->Add("records_mb", mb);
  return mb;
}

// A lean scalar design: flattening's nodes appended without hashing, and records of 8/16/8 bytes.
double Lean(const Counts& n, Fields* out) {
  const size_t components = std::max<size_t>(1, n.components);
  const size_t vars = PerComponent(n.variables, n), params = PerComponent(n.parameters, n);
  const double c0 = CpuSeconds();
  std::vector<Node> nodes;
  nodes.reserve(n.flat_nodes);
  for (size_t c = 0; c < components; ++c) {
    const size_t goal = (c + 1) * n.flat_nodes / components;
    uint32_t acc = 0;
    for (size_t k = 0; nodes.size() < goal; ++k) {
      Node node;
      if (k % 3 == 0) {
        node.op = Op::kMul;
        node.a = static_cast<uint32_t>(c * params + k % params);
        node.b = static_cast<uint32_t>(c * vars + k % vars);
      } else {
        node.op = Op::kSub;
        node.a = static_cast<uint32_t>(nodes.size() - 1);
        node.b = acc;
      }
      acc = static_cast<uint32_t>(nodes.size());
      nodes.push_back(node);
    }
  }
  Escape(nodes.data());
  const double c1 = CpuSeconds();
  struct LeanVariable { uint32_t instance; uint16_t slot, flags; };
  struct LeanParameter { double value; uint32_t instance, binding; };
  struct LeanEquation { uint32_t residual, instance; };
  RecordSet<LeanVariable, LeanParameter, LeanEquation> records(n);
  auto& [variables, parameters, equations] = records;
  for (size_t i = 0; i < n.variables; ++i) {
    variables.push_back({static_cast<uint32_t>(i * components / n.variables), static_cast<uint16_t>(i % vars), 0});
  }
  for (size_t i = 0; i < n.parameters; ++i) {
    parameters.push_back({1.0, static_cast<uint32_t>(i * components / n.parameters), 0});
  }
  for (size_t i = 0; i < n.equations; ++i) {
    equations.push_back({static_cast<uint32_t>(i), static_cast<uint32_t>(i * components / n.equations)});
  }
  Escape(variables.data());
  Escape(parameters.data());
  Escape(equations.data());
  const double c2 = CpuSeconds();
  out->Add("append_cpu_s", c1 - c0);
  out->Add("lean_records_cpu_s", c2 - c1);
  const double nodes_mb = static_cast<double>(nodes.size() * sizeof(Node)) / 1e6;
  const double records_mb = records.Mb();
  out->Add("append_mb", nodes_mb);
  out->Add("lean_records_mb", records_mb);
  return nodes_mb + records_mb;
}

// One pass reading every equation's variables.
void Walk(const ExprPool& pool, const std::vector<ExprId>& roots, Fields* out) {
  const double c0 = CpuSeconds();
  std::vector<ExprId> leaves;
  size_t total = 0;
  for (ExprId root : roots) {
    CollectLeaves(pool, root, kHasVar, &leaves);
    total += leaves.size();
  }
  out->Add("walk_cpu_s", CpuSeconds() - c0);
  out->Add("walk_equations", static_cast<double>(roots.size()));
  out->Add("walk_leaves", static_cast<double>(total));
}

// The medians against each other: the build, the present design's floors, the lean design's.
// n and pool_mb are the last run's: every run makes the same counts.
void PrintSummary(const Counts& n, const std::map<std::string, std::vector<double>>& all, double pool_mb) {
  auto m = [&all](const char* key) { return Median(all.at(key)); };
  const double build = m("load_cpu_s") + m("build_cpu_s");
  const double present = m("intern_cpu_s") + m("records_cpu_s") + m("walk_cpu_s");
  const double lean = m("append_cpu_s") + m("lean_records_cpu_s") + m("walk_cpu_s");
  const double c = static_cast<double>(std::max<size_t>(1, n.components));
  std::printf("\n%zu components; per component: %.1f nodes after the build, %.1f after flattening; "
              "%.2f variables, %.2f parameters, %.2f equations made by flattening; %.2f unknowns "
              "after alias elimination\n",
              n.components, static_cast<double>(n.nodes) / c, static_cast<double>(n.flat_nodes) / c,
              static_cast<double>(n.variables) / c, static_cast<double>(n.parameters) / c,
              static_cast<double>(n.equations) / c, static_cast<double>(n.unknowns_after_aliases) / c);
  std::printf("load + build (CPU)               %8.3f s\n", build);
  std::printf("present design: intern           %8.3f s  %8.1f MB computed (resident set grew %.1f MB)\n",
              m("intern_cpu_s"), pool_mb, m("intern_rss_mb"));
  std::printf("present design: records          %8.3f s  %8.1f MB\n", m("records_cpu_s"), m("records_mb"));
  std::printf("one walk over the equations      %8.3f s\n", m("walk_cpu_s"));
  std::printf("present design's floors          %8.3f s  %8.1f MB   (the build takes %.1f times the time)\n",
              present, pool_mb + m("records_mb"), build / std::max(1e-9, present));
  std::printf("lean design: append              %8.3f s  %8.1f MB\n", m("append_cpu_s"), m("append_mb"));
  std::printf("lean design: records             %8.3f s  %8.1f MB\n", m("lean_records_cpu_s"),
              m("lean_records_mb"));
  std::printf("lean design's floors             %8.3f s  %8.1f MB\n", lean,
              m("append_mb") + m("lean_records_mb"));
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
      char* end = nullptr;
      const double value = std::strtod(kv.c_str() + eq + 1, &end);
      if (eq == 0 || end == kv.c_str() + eq + 1 || *end != '\0') return Usage();
      overrides[kv.substr(0, eq)] = value;
    } else if (a == "--repeat" && i + 1 < argc) {
      char* end = nullptr;
      const long k = std::strtol(argv[++i], &end, 10);
      if (end == argv[i] || *end != '\0' || k < 1 || k > 1000) return Usage();
      repeat = static_cast<int>(k);
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
    double pool_mb = 0;
    for (int k = 0; k < repeat; ++k) {
      Fields f;
      n = BuildOnce(file, overrides, &f);
      if (n.variables == 0 || n.equations == 0 || n.parameters == 0) {
        throw std::runtime_error("the model has no variables, equations or parameters to count");
      }
      {
        ExprPool pool;
        const std::vector<ExprId> roots = Intern(n, &pool, &f);
        if (roots.size() != n.equations) {
          std::fprintf(stderr, "build_floor: the walk reads %zu equations, flattening made %zu\n",
                       roots.size(), n.equations);
        }
        Walk(pool, roots, &f);
        pool_mb = (static_cast<double>(pool.size()) * sizeof(Node) +
                   static_cast<double>(pool.size()) * 4.0 / 3.0 * 8.0) / 1e6;
      }
      Records(n, &f);
      Lean(n, &f);
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
    PrintSummary(n, all, pool_mb);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "build_floor: %s\n", e.what());
    return 1;
  }
  return 0;
}
