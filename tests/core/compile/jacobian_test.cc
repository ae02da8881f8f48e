// The compiled symbolic Jacobians (IDA's dF/dy + cj dF/dy' and the initialisation system's)
// against central finite differences of the compiled residuals, on every model in models/, at
// the start values and at a perturbed point.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "tests/support/test_models.h"

namespace momenta {
namespace {

using testing::Built;

std::vector<std::string> ModelFiles() {
  std::vector<std::string> files;
  for (const char* dir : {"models", "models/msl"}) {
    for (const auto& e : std::filesystem::directory_iterator(testing::SourcePath(dir))) {
      if (e.path().extension() == ".yaml") files.push_back(std::string(dir) + "/" + e.path().filename().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// Dense matrix from a compressed-column pattern.
std::vector<double> Dense(const SparsePattern& p, const std::vector<double>& values) {
  std::vector<double> d(static_cast<size_t>(p.rows) * p.cols, 0.0);
  for (int32_t c = 0; c < p.cols; ++c) {
    for (int32_t k = p.col_start[c]; k < p.col_start[c + 1]; ++k) d[c * p.rows + p.row_index[k]] += values[k];
  }
  return d;
}

void CheckJacobians(const std::string& file, double mode);

/// The rounding error of the central difference (f_plus - f_minus) / (2 h): four ulps of the
/// larger residual, over h.
double RoundingOfDifference(double f_plus, double f_minus, double h) {
  return 4 * std::numeric_limits<double>::epsilon() * std::max(std::fabs(f_plus), std::fabs(f_minus)) / h;
}

class JacobianTest : public ::testing::TestWithParam<std::string> {};

TEST_P(JacobianTest, MatchesFiniteDifferences) {
  // Every discrete value and event condition 0, then every one 1: both branches of each if
  // and both modes of each contact are checked.
  for (double mode : {0.0, 1.0}) {
    SCOPED_TRACE(mode == 0 ? "discrete values and conditions 0" : "discrete values and conditions 1");
    CheckJacobians(GetParam(), mode);
  }
}

void CheckJacobians(const std::string& file, double mode) {
  Built b = testing::BuildFile(file);
  const CompiledModel& m = *b.model;
  ModelState state(b.model);
  state.SetParameters({});
  std::fill(state.mutable_discrete(), state.mutable_discrete() + state.num_discrete(), mode);
  std::fill(state.mutable_conditions(), state.mutable_conditions() + state.num_conditions(), mode);
  const size_t n = m.num_unknowns();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<double> y(n), yp(n);
  state.StartValues(y.data());
  for (size_t k = 0; k < n; ++k) {
    y[k] += jitter(rng);
    yp[k] = jitter(rng);
  }
  const double t = 0.37, cj = 12.5;
  // IDA's Jacobian.
  std::vector<double> values(m.jacobian_pattern.nnz());
  state.Jacobian(t, cj, y.data(), yp.data(), values.data());
  std::vector<double> J = Dense(m.jacobian_pattern, values);
  std::vector<double> rp(n), rm(n);
  for (size_t j = 0; j < n; ++j) {
    // Perturb y_j by h and y'_j by cj*h: the directional derivative is J's column.
    const double h = 1e-6 * std::max(1.0, std::fabs(y[j]));
    std::vector<double> y1 = y, y2 = y, yp1 = yp, yp2 = yp;
    y1[j] += h;
    y2[j] -= h;
    yp1[j] += cj * h;
    yp2[j] -= cj * h;
    state.Residual(t, y1.data(), yp1.data(), rp.data());
    state.Residual(t, y2.data(), yp2.data(), rm.data());
    for (size_t i = 0; i < n; ++i) {
      double fd = (rp[i] - rm[i]) / (2 * h);
      // Central differences are accurate to O(h^2) relative to the curvature: 1e-5 relative,
      // with a floor for entries near zero, plus their rounding error: a few ulps of the
      // residuals over h (PreLoad's stiff contacts, 1e6 N/m at this jittered point, have
      // residuals of 1e7, whose ulps over h are 2e-3).
      EXPECT_NEAR(J[j * n + i], fd, 1e-5 * std::max(1.0, std::fabs(fd)) + RoundingOfDifference(rp[i], rm[i], h))
          << file << ": dF[" << i << "] (" << m.residual_origin(i) << ") / dy["
          << j << "] (" << m.flat->VariableName(VarId(m.unknowns[j].value())) << ")";
    }
  }
  // The initialisation Jacobian.
  const size_t nz = n + m.num_states();
  std::vector<double> z(nz);
  for (size_t k = 0; k < n; ++k) z[k] = y[k];
  for (size_t s = 0; s < m.num_states(); ++s) z[n + s] = yp[m.state_y[s]];
  std::vector<double> ivalues(m.init_pattern.nnz());
  state.InitJacobian(t, z.data(), ivalues.data());
  std::vector<double> JI = Dense(m.init_pattern, ivalues);
  std::vector<double> fp(nz), fm(nz);
  for (size_t j = 0; j < nz; ++j) {
    const double h = 1e-6 * std::max(1.0, std::fabs(z[j]));
    std::vector<double> z1 = z, z2 = z;
    z1[j] += h;
    z2[j] -= h;
    state.InitResidual(t, z1.data(), fp.data());
    state.InitResidual(t, z2.data(), fm.data());
    for (size_t i = 0; i < nz; ++i) {
      double fd = (fp[i] - fm[i]) / (2 * h);
      EXPECT_NEAR(JI[j * nz + i], fd, 1e-5 * std::max(1.0, std::fabs(fd)) + RoundingOfDifference(fp[i], fm[i], h))
          << file << ": initialisation row " << i << ", column " << j;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryModel, JacobianTest, ::testing::ValuesIn(ModelFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace momenta
