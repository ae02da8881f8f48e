// Hand-written IDA program of models/carrier_collision.yaml (no momenta), the baseline of the
// whole-process time to a first result (bench/first_result.py).
//
// Three carriers on a line (A, B: 40 kg, 1 m; the suitcase S: 15 kg, 0.4 m), free between impacts:
// states s_i, v_i with s' = v, v' = 0. Two gaps are watched as root functions: A's front against
// B's rear wall, (sB - 0.5) - (sA + 0.5), and B's rear wall against the suitcase's back,
// (sS - 0.2) - (sB - 0.5). When a gap closes while the bodies approach, their velocities jump by
// the impulse-momentum law with restitution e (eC = 0.8, eS = 0.3) and IDA is restarted. Writes
// the model's ten outputs every 0.005 s to the CSV file given as the only argument (as momenta
// does: to_chars, shortest round-trip), rtol = atol = 1e-9, the model's own tolerance.

#include <charconv>
#include <cstdio>
#include <string>

#include "handwritten_ida.h"

namespace {

constexpr double kMass[3] = {40, 40, 15};
constexpr double kEc = 0.8, kEs = 0.3, kVa0 = 5;

int Residual(double, N_Vector yy, N_Vector yp, N_Vector rr, void*) {
  const double* y = N_VGetArrayPointer(yy);
  const double* d = N_VGetArrayPointer(yp);
  double* r = N_VGetArrayPointer(rr);
  for (int k = 0; k < 3; ++k) {
    r[k] = d[k] - y[3 + k];  // s' = v
    r[3 + k] = kMass[k] * d[3 + k];  // m v' = 0 between impacts
  }
  return 0;
}

int Gaps(double, N_Vector yy, N_Vector, double* g, void*) {
  const double* y = N_VGetArrayPointer(yy);
  g[0] = (y[1] - 0.5) - (y[0] + 0.5);
  g[1] = (y[2] - 0.2) - (y[1] - 0.5);
  return 0;
}

/// Bodies j and k after a direct central impact with restitution e.
void Impact(double* v, int j, int k, double e) {
  const double p = kMass[j] * v[j] + kMass[k] * v[k], vrel = v[k] - v[j];
  v[j] = (p + kMass[k] * e * vrel) / (kMass[j] + kMass[k]);
  v[k] = v[j] - e * vrel;
}

void Put(std::FILE* out, double x, char end) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  *r.ptr++ = end;
  std::fwrite(buf, 1, r.ptr - buf, out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: handwritten_carrier OUT.csv\n");
    return 2;
  }
  std::FILE* out = std::fopen(argv[1], "w");
  if (!out) return 1;
  std::fputs("time,A.v,B.v,S.v,A.s,B.s,S.s,carriers.v_J1,carriers.v_K1,suitcase.v_J1,suitcase.v_K1\n", out);
  // The Collision blocks' algebraic cross-check, as constants of the run.
  double c[3] = {kVa0, 0, 0};
  Impact(c, 0, 1, kEc);
  double sc[2] = {c[1], 0};
  {
    const double p = kMass[1] * sc[0], vrel = -sc[0];
    sc[0] = (p + kMass[2] * kEs * vrel) / (kMass[1] + kMass[2]);
    sc[1] = sc[0] - kEs * vrel;
  }
  hw::Context ctx;
  hw::Vector y = hw::make_vector(6, ctx), yp = hw::make_vector(6, ctx);
  double* s = N_VGetArrayPointer(y.get());
  const double start[6] = {0, 2, 2, kVa0, 0, 0};
  for (int k = 0; k < 6; ++k) s[k] = start[k];
  N_VConst(0.0, yp.get());
  for (int k = 0; k < 3; ++k) N_VGetArrayPointer(yp.get())[k] = s[3 + k];
  hw::Ida ida(ctx);
  hw::check(IDAInit(ida.get(), Residual, 0.0, y.get(), yp.get()), "IDAInit");
  hw::check(IDASStolerances(ida.get(), 1e-9, 1e-9), "IDASStolerances");
  hw::Matrix J(SUNDenseMatrix(6, 6, ctx));
  hw::LinearSolver ls(SUNLinSol_Dense(y.get(), J.get(), ctx));
  hw::check(IDASetLinearSolver(ida.get(), ls.get(), J.get()), "IDASetLinearSolver");
  hw::check(IDARootInit(ida.get(), 2, Gaps), "IDARootInit");
  const double stop = 0.5, dt = 0.005;
  auto row = [&](double t) {
    Put(out, t, ',');
    for (int k = 0; k < 3; ++k) Put(out, s[3 + k], ',');
    for (int k = 0; k < 3; ++k) Put(out, s[k], ',');
    Put(out, c[0], ',');
    Put(out, c[1], ',');
    Put(out, sc[0], ',');
    Put(out, sc[1], '\n');
  };
  row(0.0);
  double t = 0;
  for (long k = 1; k * dt <= stop + 1e-12; ++k) {
    const double tout = k * dt;
    while (tout - t > 1e-12) {  // an impact can fall on an output time (A meets B at 0.2 s)
      const int flag = IDASolve(ida.get(), tout, &t, y.get(), yp.get(), IDA_NORMAL);
      hw::check(flag, "IDASolve");
      if (flag != IDA_ROOT_RETURN) break;
      int found[2] = {0, 0};
      hw::check(IDAGetRootInfo(ida.get(), found), "IDAGetRootInfo");
      if (found[0] && s[4] < s[3]) Impact(s + 3, 0, 1, kEc);
      if (found[1] && s[5] < s[4]) Impact(s + 3, 1, 2, kEs);
      for (int j = 0; j < 3; ++j) N_VGetArrayPointer(yp.get())[j] = s[3 + j];
      hw::check(IDAReInit(ida.get(), t, y.get(), yp.get()), "IDAReInit");
    }
    row(tout);
  }
  return std::fclose(out) == 0 ? 0 : 1;
}
