// Hand-written IDA program for the RC ladder of the ModelingToolkit benchmark suite.
//
// A sine voltage source (amplitude 1, 10 Hz) drives n resistors R_i = 1/i in series; a capacitor
// C_i = 1/i^2 joins node i (after resistor i) to ground. Capacitor voltages start at u_i = i.
//
// y = [u_1..u_n], residual F(t, y, y') = 0, with g_i = 1/R_i = i and u_0 = sin(2 pi 10 t):
//   F_i = C_i u_i' - g_i (u_{i-1} - u_i) + [i<n] g_{i+1} (u_i - u_{i+1})
// Jacobian J = dF/dy + cj dF/dy' (tridiagonal; dense or CSC for KLU):
//   (u_{i-1}) -g_i,  (u_i) cj C_i + g_i + [i<n] g_{i+1},  (u_{i+1}) -g_{i+1}
//
// usage: handwritten_rc --n N --stop T --rtol R --atol A --linear-solver dense|klu
//                       --interval DT --repeat K
#include "handwritten_ida.h"

namespace {

constexpr double kAmplitude = 1.0;
constexpr double kFrequency = 10.0;
constexpr double kTwoPi = 6.283185307179586476925286766559;

struct RcLadder final : hw::Problem {
  explicit RcLadder(long n_) : n(n_) {}
  long n;

  static double conductance(long i) { return static_cast<double>(i); }  // 1 / R_i, R_i = 1/i
  static double capacitance(long i) { return 1.0 / (static_cast<double>(i) * static_cast<double>(i)); }
  static double source(double t) { return kAmplitude * std::sin(kTwoPi * kFrequency * t); }

  const char* name() const override { return "handwritten_rc"; }
  sunindextype size() const override { return n; }
  sunindextype jacobian_nnz() const override { return 3 * n - 2; }

  // Net current into capacitor i: through R_i minus through R_{i+1}.
  static double current(const double* u, double u0, long i, long n) {
    const double u_prev = i > 1 ? u[i - 2] : u0;
    double c = conductance(i) * (u_prev - u[i - 1]);
    if (i < n) c -= conductance(i + 1) * (u[i - 1] - u[i]);
    return c;
  }

  // y' consistent with y: u_i' = current_i / C_i.
  void initial_values(double t0, double* y, double* yp) const override {
    for (long i = 1; i <= n; ++i) y[i - 1] = static_cast<double>(i);
    const double u0 = source(t0);
    for (long i = 1; i <= n; ++i) yp[i - 1] = current(y, u0, i, n) / capacitance(i);
  }

  static int res(double t, N_Vector yy, N_Vector yyp, N_Vector rr, void* user_data) {
    const long n = static_cast<RcLadder*>(user_data)->n;
    const double* u = N_VGetArrayPointer(yy);
    const double* up = N_VGetArrayPointer(yyp);
    double* r = N_VGetArrayPointer(rr);
    const double u0 = source(t);
    for (long i = 1; i <= n; ++i) r[i - 1] = capacitance(i) * up[i - 1] - current(u, u0, i, n);
    return 0;
  }

  static int jac_dense(double /*t*/, double cj, N_Vector /*y*/, N_Vector /*yp*/, N_Vector /*r*/, SUNMatrix J,
                       void* user_data, N_Vector, N_Vector, N_Vector) {
    // IDA zeroes J before calling this; column k holds rows k-1 .. k+1.
    const long n = static_cast<RcLadder*>(user_data)->n;
    for (long k = 1; k <= n; ++k) {
      double* col = SUNDenseMatrix_Column(J, k - 1);
      if (k > 1) col[k - 2] = -conductance(k);  // dF_{k-1}/du_k
      col[k - 1] = cj * capacitance(k) + conductance(k) + (k < n ? conductance(k + 1) : 0.0);
      if (k < n) col[k] = -conductance(k + 1);  // dF_{k+1}/du_k
    }
    return 0;
  }

  static int jac_sparse(double /*t*/, double cj, N_Vector /*y*/, N_Vector /*yp*/, N_Vector /*r*/, SUNMatrix J,
                        void* user_data, N_Vector, N_Vector, N_Vector) {
    const long n = static_cast<RcLadder*>(user_data)->n;
    sunindextype* colptr = SUNSparseMatrix_IndexPointers(J);
    sunindextype* rowidx = SUNSparseMatrix_IndexValues(J);
    double* val = SUNSparseMatrix_Data(J);
    sunindextype nz = 0;
    auto put = [&](sunindextype row, double x) {
      rowidx[nz] = row;
      val[nz] = x;
      ++nz;
    };
    for (long k = 1; k <= n; ++k) {
      colptr[k - 1] = nz;
      if (k > 1) put(k - 2, -conductance(k));
      put(k - 1, cj * capacitance(k) + conductance(k) + (k < n ? conductance(k + 1) : 0.0));
      if (k < n) put(k, -conductance(k + 1));
    }
    colptr[n] = nz;
    return nz == SUNSparseMatrix_NNZ(J) ? 0 : -1;
  }

  IDAResFn residual() const override { return &RcLadder::res; }
  IDALsJacFn dense_jacobian() const override { return &RcLadder::jac_dense; }
  IDALsJacFn sparse_jacobian() const override { return &RcLadder::jac_sparse; }
  const char* final_name(int k) const override { return k == 0 ? "u_1" : "u_n"; }
  double final_value(const double* y, int k) const override { return k == 0 ? y[0] : y[n - 1]; }
};

}  // namespace

int main(int argc, char** argv) {
  hw::Options defaults;
  defaults.n = 100;
  defaults.stop = 10.0;
  const hw::Options opt = hw::parse_options(argc, argv, defaults);
  try {
    RcLadder rc(opt.n);
    hw::check_dense_size(opt, rc.size());
    return hw::run_benchmark(opt, rc);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "handwritten_rc: error: %s\n", e.what());
    return 1;
  }
}
