// The scalable suite (models/scalable/, after Casella et al.'s ScalableTestSuite) at small sizes,
// against closed forms of the same finite-dimensional equations (not of the PDEs they
// approximate, so the only error is the integrator's):
//
// - CascadedFirstOrder: N identical lags tau x_k' = x_{k-1} - x_k, x_0 = 1, x_k(0) = 0. Stage k is
//   the Erlang distribution function of shape k and rate 1/tau:
//     x_k(t) = 1 - e^{-s} sum_{j<k} s^j/j!,  s = t/tau.
// - HarmonicOscillator: N masses m, springs k between neighbours, both ends free; x(0) = N e_1,
//   v(0) = 0. The free-free chain's stiffness is k times the path Laplacian, whose modes are
//   phi_j(i) = cos(j pi (i - 1/2)/N) with omega_j^2 = (4k/m) sin^2(j pi/(2N)), j = 0..N-1, so
//     x_i(t) = 1 + sum_{j>=1} 2 cos(j pi/(2N)) phi_j(i) cos(omega_j t);
//   energy k N^2/2 and momentum 0 are conserved.
// - HeatConduction (TT, finite differences): with a = lambda/(cp rho) and M = N - 2 inner nodes,
//   the deviation from the linear steady profile decays in the discrete sine modes
//   sin(k pi m/(M+1)) at rates (4a/dx^2) sin^2(k pi/(2(M+1))), k = 1..M.
// - TransmissionLineEquations: the step travels along the line at v = 1/sqrt(ind cap); the far
//   end's response is the near end's delayed by the line's length (N-1) l over v (the original's
//   l = L/N, so the N-1 segments are (N-1)/N of L).
//
// Tolerances: each run uses rtol = 1e-8 (atol = rtol times each nominal), so the integrator's
// global error is a small multiple of 1e-8 of the solution's magnitude (IDA controls the local
// error; over a few hundred steps of a stable or conservative system it accumulates to some 10
// times that). The bounds are 1e-6 of each problem's scale: 1 for the lags, N for the
// oscillator's displacement, the 57 K between T0 and T1 for the rod (whose states are about
// 300 K, so rtol alone admits 3e-6 K). Measured: 1.2e-7, 9.4e-7 (N = 5), 5.6e-6 K, so 5-10 times
// below the bounds; a wrong coefficient, sign or index gives errors of order 1e-2 of the scale
// or more. Energy drift (BDF damps a little per period) was 6.4e-7 relative, bound 1e-5; the
// line's delay came out 0.26 % above the continuum's, bound 1 %.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/physics_checks.h"
#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;
using testing::Trajectory;

constexpr double kPi = 3.14159265358979323846;

/// The suite's model file with its outputs replaced, built for size N without warnings.
Built BuildScalable(const std::string& name, int n, const std::vector<std::string>& outputs) {
  std::ifstream in(testing::SourcePath("models/scalable/" + name + ".yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string list;
  for (const auto& o : outputs) list += (list.empty() ? "\"" : ", \"") + o + "\"";
  const std::string yaml =
      std::regex_replace(text.str(), std::regex("\noutputs:[^\n]*"), "\noutputs: [" + list + "]");
  return testing::BuildClean(yaml, {{"N", n}});
}

/// The model's own experiment at a tighter tolerance, with the size the model was built for (the
/// run evaluates the parameters again: T/N needs N's value as well as the structure).
Trajectory RunTight(const Built& b, int n) {
  SimulationOptions o = OptionsFromExperiment(b.model->experiment);
  o.rtol = 1e-8;
  return testing::Run(b, o, {{"N", n}});
}

std::vector<std::string> Indexed(const std::string& prefix, int from, int to, const std::string& suffix) {
  std::vector<std::string> names;
  for (int i = from; i <= to; ++i) names.push_back(prefix + "[" + std::to_string(i) + "]" + suffix);
  return names;
}

TEST(ScalableSuite, CascadedFirstOrderIsTheErlangDistribution) {
  const int n = 8;
  const double tau = 1.0 / n;  // T = 1
  Built b = BuildScalable("CascadedFirstOrder", n, Indexed("stage", 1, n, ".x"));
  EXPECT_EQ(b.model->num_states(), static_cast<size_t>(n));
  Trajectory tr = RunTight(b, n);
  ASSERT_DOUBLE_EQ(tr.t.back(), 2.0);
  for (int k = 1; k <= n; ++k) {
    const double err = testing::MaxError(tr, "stage[" + std::to_string(k) + "].x", [&](double t) {
      const double s = t / tau;
      double term = 1, sum = 0;
      for (int j = 0; j < k; ++j) {
        sum += term;
        term *= s / (j + 1);
      }
      return 1 - std::exp(-s) * sum;
    });
    EXPECT_LT(err, 1e-6) << "stage " << k;
  }
}

TEST(ScalableSuite, HarmonicOscillatorFollowsItsModesAndConservesEnergy) {
  const int n = 5;
  const double m = 1, k = 10;
  std::vector<std::string> outputs = Indexed("mass", 1, n, ".s");
  for (const auto& v : Indexed("mass", 1, n, ".v")) outputs.push_back(v);
  Built b = BuildScalable("HarmonicOscillator", n, outputs);
  EXPECT_EQ(b.model->num_states(), static_cast<size_t>(2 * n));
  Trajectory tr = RunTight(b, n);
  ASSERT_DOUBLE_EQ(tr.t.back(), 10.0);
  auto omega = [&](int j) { return std::sqrt(4 * k / m) * std::sin(j * kPi / (2 * n)); };
  for (int i = 1; i <= n; ++i) {
    const double err = testing::MaxError(tr, "mass[" + std::to_string(i) + "].s", [&](double t) {
      double x = 1;
      for (int j = 1; j < n; ++j)
        x += 2 * std::cos(j * kPi / (2 * n)) * std::cos(j * kPi * (i - 0.5) / n) * std::cos(omega(j) * t);
      return x;
    });
    EXPECT_LT(err, 1e-6 * n) << "mass " << i;
  }
  const double energy0 = 0.5 * k * n * n;
  double worst_energy = 0, worst_momentum = 0;
  for (size_t r = 0; r < tr.t.size(); ++r) {
    double kinetic = 0, potential = 0, momentum = 0;
    for (int i = 1; i <= n; ++i) {
      const double v = tr.values[r][tr.Index("mass[" + std::to_string(i) + "].v")];
      kinetic += 0.5 * m * v * v;
      momentum += m * v;
      if (i < n) {
        const double stretch = tr.values[r][tr.Index("mass[" + std::to_string(i + 1) + "].s")] -
                               tr.values[r][tr.Index("mass[" + std::to_string(i) + "].s")];
        potential += 0.5 * k * stretch * stretch;
      }
    }
    worst_energy = std::max(worst_energy, std::abs(kinetic + potential - energy0) / energy0);
    worst_momentum = std::max(worst_momentum, std::abs(momentum));
  }
  // Relative energy drift: a BDF method is dissipative, by about rtol per unit of phase.
  EXPECT_LT(worst_energy, 1e-5);
  EXPECT_LT(worst_momentum, 1e-6 * n);
}

TEST(ScalableSuite, HeatConductionDecaysInTheDiscreteSineModes) {
  const int n = 12;
  const double len = 0.2, t0 = 273.15, t1 = 330, tn = 300, a = 237.0 / (910.0 * 2712.0);
  const double dx = len / (n - 1);
  Built b = BuildScalable("HeatConduction", n, Indexed("node", 1, n - 2, ".T"));
  EXPECT_EQ(b.model->num_states(), static_cast<size_t>(n - 2));
  Trajectory tr = RunTight(b, n);
  ASSERT_DOUBLE_EQ(tr.t.back(), 350.0);
  const int inner = n - 2, parts = n - 1;  // node[m] is T[m+1], at x = m dx
  auto steady = [&](int m) { return t1 + (tn - t1) * m / parts; };
  std::vector<double> coefficient(inner + 1, 0.0);
  for (int q = 1; q <= inner; ++q) {
    for (int m = 1; m <= inner; ++m) coefficient[q] += (t0 - steady(m)) * std::sin(q * kPi * m / parts);
    coefficient[q] *= 2.0 / parts;
  }
  for (int m = 1; m <= inner; ++m) {
    const double err = testing::MaxError(tr, "node[" + std::to_string(m) + "].T", [&](double t) {
      double temperature = steady(m);
      for (int q = 1; q <= inner; ++q) {
        const double rate = 4 * a / (dx * dx) * std::pow(std::sin(q * kPi / (2 * parts)), 2);
        temperature += coefficient[q] * std::sin(q * kPi * m / parts) * std::exp(-rate * t);
      }
      return temperature;
    });
    EXPECT_LT(err, 1e-6 * (t1 - t0)) << "node " << m;
  }
}

/// The first time a column reaches half of the unit step, interpolated between rows.
double HalfwayTime(const Trajectory& tr, const std::string& column) {
  const size_t j = tr.Index(column);
  for (size_t r = 1; r < tr.t.size(); ++r) {
    const double y0 = tr.values[r - 1][j], y1 = tr.values[r][j];
    if (y0 < 0.5 && y1 >= 0.5) return tr.t[r - 1] + (0.5 - y0) / (y1 - y0) * (tr.t[r] - tr.t[r - 1]);
  }
  return NAN;
}

TEST(ScalableSuite, TransmissionLineDelaysTheStepByItsTravelTime) {
  const int n = 100;
  const double len = 100, cap = 101e-12, ind = 253e-9;
  Built b = BuildScalable("TransmissionLineEquations", n, {"source.vol", "seg[99].n.v", "load.p.i"});
  EXPECT_EQ(b.model->num_states(), static_cast<size_t>(2 * n));
  Trajectory tr = RunTight(b, n);
  const double travel = (n - 1) * (len / n) * std::sqrt(ind * cap);  // 5.0e-7 s
  const double delay = HalfwayTime(tr, "seg[99].n.v") - HalfwayTime(tr, "source.vol");
  // The discrete line is dispersive: its cells pass the filtered step (rise time 2/w = 4e-7 s,
  // 80 cells' delay) with a group delay a fraction of a percent above the continuum's.
  EXPECT_NEAR(delay / travel, 1.0, 0.01) << "delay " << delay << " s, travel time " << travel << " s";
  // Before the front arrives the far end is still at rest; at the end the matched load takes
  // the whole step: vol[N] = RL cur[N] = 1 (less the line's resistive drop, 5e-5 relative).
  for (size_t r = 0; r < tr.t.size() && tr.t[r] < 0.5 * travel; ++r)
    EXPECT_LT(std::abs(tr.Column("seg[99].n.v", r)), 1e-3) << "t = " << tr.t[r];
  EXPECT_NEAR(tr.Column("seg[99].n.v", tr.t.size() - 1), 1.0, 1e-3);
  EXPECT_NEAR(tr.Column("load.p.i", tr.t.size() - 1) * std::sqrt(ind / cap), 1.0, 1e-3);
}

}  // namespace
}  // namespace momenta
