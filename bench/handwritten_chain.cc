// Hand-written IDA program for the spring-damper chain benchmark.
//
// n masses (m = 1) in a line. Mass i has absolute position s_i and velocity v_i. Spring-damper i
// (c = 1e4, d = 10, unstretched length 1) joins mass i-1 to mass i (mass 0 is a wall at s = 0);
// a force 10 sin(2 pi t) pulls mass n in +s. Start at rest with s_i = i.
//
// y = [s_1..s_n, v_1..v_n], residual F(t, y, y') = 0:
//   F_i     = s_i' - v_i
//   F_{n+i} = m v_i' - (f_{i+1} - f_i) - [i == n] 10 sin(2 pi t)
//   f_i     = c (s_i - s_{i-1} - 1) + d (v_i - v_{i-1}),  s_0 = v_0 = 0,  f_{n+1} = 0
// Jacobian J = dF/dy + cj dF/dy' (analytic; dense or CSC for KLU):
//   row F_i:     (s_i) cj,  (v_i) -1
//   row F_{n+i}: (s_{i-1}) -c, (s_i) c + c[i<n], (s_{i+1}) -c
//                (v_{i-1}) -d, (v_i) d + d[i<n] + cj m, (v_{i+1}) -d
//
// usage: handwritten_chain --n N --stop T --rtol R --atol A --linear-solver dense|klu
//                          --interval DT --repeat K [--params arrays]
//
// --params arrays: the residual reads c, d, the unstretched length and m of each spring-damper
// and mass from arrays (the same values), as momenta's generated code must (its parameters are
// data: `-p` never recompiles); the default keeps them compile-time constants. The same
// equations, Jacobian and steps.
#include <memory>
#include <string>
#include <vector>

#include "handwritten_ida.h"

namespace {

constexpr double kMass = 1.0;
constexpr double kStiffness = 1e4;
constexpr double kDamping = 10.0;
constexpr double kLength = 1.0;
constexpr double kForceAmplitude = 10.0;
constexpr double kTwoPi = 6.283185307179586476925286766559;

struct Chain : hw::Problem {
  explicit Chain(long n_) : n(n_) {}
  long n;

  const char* name() const override { return "handwritten_chain"; }
  sunindextype size() const override { return 2 * n; }
  // s columns: 1 (F_i) + up to 3 (F_{n+i-1..n+i+1}); v columns the same.
  sunindextype jacobian_nnz() const override { return 2 * (n + 3 * n - 2); }

  // Force in spring-damper i (1-based), i = 1..n; zero for i = n+1.
  static double force(const double* s, const double* v, long i, long n) {
    if (i > n) return 0.0;
    const double s_prev = i > 1 ? s[i - 2] : 0.0;
    const double v_prev = i > 1 ? v[i - 2] : 0.0;
    return kStiffness * (s[i - 1] - s_prev - kLength) + kDamping * (v[i - 1] - v_prev);
  }

  // y' consistent with y: s' = v, v' = (f_{i+1} - f_i + load) / m.
  void initial_values(double t0, double* y, double* yp) const override {
    double* s = y;
    double* v = y + n;
    for (long i = 1; i <= n; ++i) {
      s[i - 1] = static_cast<double>(i);
      v[i - 1] = 0.0;
    }
    for (long i = 1; i <= n; ++i) {
      const double load = i == n ? kForceAmplitude * std::sin(kTwoPi * t0) : 0.0;
      yp[i - 1] = v[i - 1];
      yp[n + i - 1] = (force(s, v, i + 1, n) - force(s, v, i, n) + load) / kMass;
    }
  }

  static int res(double t, N_Vector yy, N_Vector yyp, N_Vector rr, void* user_data) {
    const long n = static_cast<Chain*>(user_data)->n;
    const double* s = N_VGetArrayPointer(yy);
    const double* v = s + n;
    const double* sp = N_VGetArrayPointer(yyp);
    const double* vp = sp + n;
    double* r = N_VGetArrayPointer(rr);
    double f_i = force(s, v, 1, n);
    for (long i = 1; i <= n; ++i) {
      const double f_next = force(s, v, i + 1, n);
      const double load = i == n ? kForceAmplitude * std::sin(kTwoPi * t) : 0.0;
      r[i - 1] = sp[i - 1] - v[i - 1];
      r[n + i - 1] = kMass * vp[i - 1] - (f_next - f_i) - load;
      f_i = f_next;
    }
    return 0;
  }

  static int jac_dense(double /*t*/, double cj, N_Vector /*y*/, N_Vector /*yp*/, N_Vector /*r*/, SUNMatrix J,
                       void* user_data, N_Vector, N_Vector, N_Vector) {
    // IDA zeroes J before calling this; only the nonzeros are set. Column-major storage.
    const long n = static_cast<Chain*>(user_data)->n;
    for (long k = 1; k <= n; ++k) {
      double* col_s = SUNDenseMatrix_Column(J, k - 1);
      double* col_v = SUNDenseMatrix_Column(J, n + k - 1);
      const double last = k < n ? 1.0 : 0.0;
      col_s[k - 1] = cj;
      col_v[k - 1] = -1.0;
      if (k > 1) {
        col_s[n + k - 2] = -kStiffness;
        col_v[n + k - 2] = -kDamping;
      }
      col_s[n + k - 1] = kStiffness * (1.0 + last);
      col_v[n + k - 1] = kDamping * (1.0 + last) + cj * kMass;
      if (k < n) {
        col_s[n + k] = -kStiffness;
        col_v[n + k] = -kDamping;
      }
    }
    return 0;
  }

  static int jac_sparse(double /*t*/, double cj, N_Vector /*y*/, N_Vector /*yp*/, N_Vector /*r*/, SUNMatrix J,
                        void* user_data, N_Vector, N_Vector, N_Vector) {
    // CSC, rows ascending in each column. IDA zeroes J (including the index arrays) first.
    const long n = static_cast<Chain*>(user_data)->n;
    sunindextype* colptr = SUNSparseMatrix_IndexPointers(J);
    sunindextype* rowidx = SUNSparseMatrix_IndexValues(J);
    double* val = SUNSparseMatrix_Data(J);
    sunindextype nz = 0;
    auto put = [&](sunindextype row, double x) {
      rowidx[nz] = row;
      val[nz] = x;
      ++nz;
    };
    // Column of s_k and column of v_k have the same rows: k-1 and n+k-2 .. n+k.
    for (int block = 0; block < 2; ++block) {
      for (long k = 1; k <= n; ++k) {
        colptr[block * n + k - 1] = nz;
        const double last = k < n ? 1.0 : 0.0;
        const double coef = block == 0 ? kStiffness : kDamping;
        put(k - 1, block == 0 ? cj : -1.0);
        if (k > 1) put(n + k - 2, -coef);
        put(n + k - 1, coef * (1.0 + last) + (block == 1 ? cj * kMass : 0.0));
        if (k < n) put(n + k, -coef);
      }
    }
    colptr[2 * n] = nz;
    return nz == SUNSparseMatrix_NNZ(J) ? 0 : -1;
  }

  IDAResFn residual() const override { return &Chain::res; }
  IDALsJacFn dense_jacobian() const override { return &Chain::jac_dense; }
  IDALsJacFn sparse_jacobian() const override { return &Chain::jac_sparse; }
  const char* final_name(int k) const override { return k == 0 ? "s_n" : "v_n"; }
  double final_value(const double* y, int k) const override { return k == 0 ? y[n - 1] : y[2 * n - 1]; }
};

// The chain with per-instance parameters read from arrays (--params arrays).
struct ChainArrays final : Chain {
  explicit ChainArrays(long n_) : Chain(n_), c(n_, kStiffness), d(n_, kDamping), length(n_, kLength), m(n_, kMass) {}
  std::vector<double> c, d, length, m;  // of spring-damper i and mass i at [i - 1]

  const char* name() const override { return "handwritten_chain (parameters from arrays)"; }

  static int res_arrays(double t, N_Vector yy, N_Vector yyp, N_Vector rr, void* user_data) {
    const ChainArrays& p = *static_cast<ChainArrays*>(user_data);
    const long n = p.n;
    const double* s = N_VGetArrayPointer(yy);
    const double* v = s + n;
    const double* sp = N_VGetArrayPointer(yyp);
    const double* vp = sp + n;
    double* r = N_VGetArrayPointer(rr);
    auto force = [&](long i) {  // spring-damper i (1-based); zero for i = n+1
      if (i > n) return 0.0;
      const double s_prev = i > 1 ? s[i - 2] : 0.0;
      const double v_prev = i > 1 ? v[i - 2] : 0.0;
      return p.c[i - 1] * (s[i - 1] - s_prev - p.length[i - 1]) + p.d[i - 1] * (v[i - 1] - v_prev);
    };
    double f_i = force(1);
    for (long i = 1; i <= n; ++i) {
      const double f_next = force(i + 1);
      const double load = i == n ? kForceAmplitude * std::sin(kTwoPi * t) : 0.0;
      r[i - 1] = sp[i - 1] - v[i - 1];
      r[n + i - 1] = p.m[i - 1] * vp[i - 1] - (f_next - f_i) - load;
      f_i = f_next;
    }
    return 0;
  }
  IDAResFn residual() const override { return &ChainArrays::res_arrays; }
};

}  // namespace

int main(int argc, char** argv) {
  hw::Options defaults;
  defaults.n = 100;
  defaults.stop = 10.0;
  // --params arrays is this program's own option; the rest are the shared ones.
  bool arrays = false;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (i + 1 < argc && std::string(argv[i]) == "--params" && std::string(argv[i + 1]) == "arrays") {
      arrays = true;
      ++i;
    } else {
      args.push_back(argv[i]);
    }
  }
  const hw::Options opt = hw::parse_options(static_cast<int>(args.size()), args.data(), defaults);
  try {
    std::unique_ptr<Chain> chain = arrays ? std::make_unique<ChainArrays>(opt.n) : std::make_unique<Chain>(opt.n);
    hw::check_dense_size(opt, chain->size());
    return hw::run_benchmark(opt, *chain);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "handwritten_chain: error: %s\n", e.what());
    return 1;
  }
}
