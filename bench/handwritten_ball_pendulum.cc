// Hand-written IDA program of models/ball_pendulum.yaml and models/ball_pendulum_impact.yaml (no
// momenta), the baseline of the whole-process time to a first result (bench/first_result.py).
//
// Ball A (mass mA, radius r) falls freely from rest at (r, 4); pendulum B (a point mass mB of the
// same radius) hangs on a massless cord of length L from a fixed pivot at (0, 4), at angle theta
// from the vertical: B = (L sin(theta), 4 - L cos(theta)). States xA, yA, vxA, vyA, theta, w, in
// the coordinates a hand-written program would pick (the cord's constraint solved by hand, so no
// algebraic unknowns); gravity 9.81 m/s^2. The distance d = |A - B| is watched as a root function,
// d - 2r:
//   penalty (default; models/ball_pendulum.yaml): while d <= 2r a force of F = 10 000 N pushes the
//     centres apart along n = (A - B)/d; IDA is restarted when the contact begins and ends.
//   --impact (models/ball_pendulum_impact.yaml): when the balls touch while approaching, an
//     impulse P along n makes the normal relative velocity jump to -e times its value (e = 1),
//     through the cord: A's velocity by P n/mA, B's angular velocity by -P (n . dB/dtheta)/(mB L^2).
// Writes the model's outputs every 0.001 s, and two rows at each event (before and after), to the
// CSV file given as the last argument, as momenta does (to_chars, shortest round-trip);
// rtol = atol = 1e-8, the models' own tolerance.

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "handwritten_ida.h"

namespace {

constexpr double kR = 0.5, kMa = 1, kMb = 1, kL = 3.5, kF = 10000, kE = 1, kG = 9.81, kPivotY = 4;

struct Run {
  bool touching = false;  // the penalty force acts (penalty model only)
};

/// The contact's geometry at state y: n (unit, from B to A), d, and dB/dtheta.
struct Geometry {
  double d, nx, ny, tx, ty;
};

Geometry Geom(const double* y) {
  const double bx = kL * std::sin(y[4]), by = kPivotY - kL * std::cos(y[4]);
  const double rx = y[0] - bx, ry = y[1] - by, d = std::hypot(rx, ry);
  return {d, rx / d, ry / d, kL * std::cos(y[4]), kL * std::sin(y[4])};
}

int Residual(double, N_Vector yy, N_Vector yp, N_Vector rr, void* data) {
  const double* y = N_VGetArrayPointer(yy);
  const double* dy = N_VGetArrayPointer(yp);
  double* r = N_VGetArrayPointer(rr);
  const Geometry c = Geom(y);
  const double f = static_cast<Run*>(data)->touching ? kF : 0;  // pushes A away from B
  r[0] = dy[0] - y[2];
  r[1] = dy[1] - y[3];
  r[2] = kMa * dy[2] - f * c.nx;
  r[3] = kMa * dy[3] + kMa * kG - f * c.ny;
  r[4] = dy[4] - y[5];
  r[5] = kMb * kL * kL * dy[5] + kMb * kG * kL * std::sin(y[4]) + f * (c.nx * c.tx + c.ny * c.ty);
  return 0;
}

int Gap(double, N_Vector yy, N_Vector, double* g, void*) {
  g[0] = Geom(N_VGetArrayPointer(yy)).d - 2 * kR;
  return 0;
}

/// The derivatives that make the residual zero at state y (IDA's consistent start and restarts).
void Consistent(const double* y, const Run& run, double* dy) {
  const Geometry c = Geom(y);
  const double f = run.touching ? kF : 0;
  dy[0] = y[2];
  dy[1] = y[3];
  dy[2] = f * c.nx / kMa;
  dy[3] = f * c.ny / kMa - kG;
  dy[4] = y[5];
  dy[5] = (-kMb * kG * kL * std::sin(y[4]) - f * (c.nx * c.tx + c.ny * c.ty)) / (kMb * kL * kL);
}

/// The exact impact: the impulse along n that turns the normal relative velocity v_n into -e v_n.
void Impact(double* y) {
  const Geometry c = Geom(y);
  const double nt = c.nx * c.tx + c.ny * c.ty;
  const double vn = (y[2] - c.tx * y[5]) * c.nx + (y[3] - c.ty * y[5]) * c.ny;
  const double p = -(1 + kE) * vn / (1 / kMa + nt * nt / (kMb * kL * kL));
  y[2] += p * c.nx / kMa;
  y[3] += p * c.ny / kMa;
  y[5] -= p * nt / (kMb * kL * kL);
}

void Put(std::FILE* out, double x, char end) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  *r.ptr++ = end;
  std::fwrite(buf, 1, r.ptr - buf, out);
}

}  // namespace

int main(int argc, char** argv) {
  const bool impact = argc == 3 && std::strcmp(argv[1], "--impact") == 0;
  if (argc != 2 && !impact) {
    std::fprintf(stderr, "usage: handwritten_ball_pendulum [--impact] OUT.csv\n");
    return 2;
  }
  std::FILE* out = std::fopen(argv[argc - 1], "w");
  if (!out) return 1;
  std::fputs(impact ? "time,A.r[1],A.r[2],A.v[1],A.v[2],B.r[1],B.r[2],B.v[1],B.v[2],contact.d,joint.phi\n"
                    : "time,A.r[1],A.r[2],A.v[1],A.v[2],B.r[1],B.r[2],B.v[1],B.v[2],distance.y,touching.y,joint.phi\n",
             out);
  Run run;
  hw::Context ctx;
  hw::Vector y = hw::make_vector(6, ctx), yp = hw::make_vector(6, ctx);
  double* s = N_VGetArrayPointer(y.get());
  double* ds = N_VGetArrayPointer(yp.get());
  const double start[6] = {kR, kPivotY, 0, 0, 0, 0};
  for (int k = 0; k < 6; ++k) s[k] = start[k];
  Consistent(s, run, ds);
  hw::Ida ida(ctx);
  hw::check(IDAInit(ida.get(), Residual, 0.0, y.get(), yp.get()), "IDAInit");
  hw::check(IDASStolerances(ida.get(), 1e-8, 1e-8), "IDASStolerances");
  hw::check(IDASetUserData(ida.get(), &run), "IDASetUserData");
  hw::Matrix J(SUNDenseMatrix(6, 6, ctx));
  hw::LinearSolver ls(SUNLinSol_Dense(y.get(), J.get(), ctx));
  hw::check(IDASetLinearSolver(ida.get(), ls.get(), J.get()), "IDASetLinearSolver");
  hw::check(IDARootInit(ida.get(), 1, Gap), "IDARootInit");
  const double stop = 1, dt = 0.001;
  auto row = [&](double t) {
    const double bx = kL * std::sin(s[4]), by = kPivotY - kL * std::cos(s[4]);
    Put(out, t, ',');
    for (int k = 0; k < 4; ++k) Put(out, s[k], ',');
    Put(out, bx, ',');
    Put(out, by, ',');
    Put(out, kL * std::cos(s[4]) * s[5], ',');
    Put(out, kL * std::sin(s[4]) * s[5], ',');
    Put(out, Geom(s).d, ',');
    if (!impact) Put(out, run.touching ? 1 : 0, ',');
    Put(out, s[4], '\n');
  };
  row(0.0);
  double t = 0;
  for (long k = 1; k * dt <= stop + 1e-12; ++k) {
    const double tout = k * dt;
    while (tout - t > 1e-12) {
      const int flag = IDASolve(ida.get(), tout, &t, y.get(), yp.get(), IDA_NORMAL);
      hw::check(flag, "IDASolve");
      if (flag != IDA_ROOT_RETURN) break;
      int found = 0;
      hw::check(IDAGetRootInfo(ida.get(), &found), "IDAGetRootInfo");
      if (impact && found > 0) continue;  // the balls part after the impact: no event
      row(t);  // before the event
      if (impact)
        Impact(s);
      else
        run.touching = found < 0;
      row(t);  // after
      Consistent(s, run, ds);
      hw::check(IDAReInit(ida.get(), t, y.get(), yp.get()), "IDAReInit");
    }
    row(tout);
  }
  return std::fclose(out) == 0 ? 0 : 1;
}
