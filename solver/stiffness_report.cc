// The fastest modes of a model where it stands (see stiffness_report.h).
//
// The maths. Linearised at (t, y, y'), the DAE F(t, y, y') = 0 reads
//     F_y dy + F_y' dy' = 0,
// and its modes dy = v e^(lambda t) are the finite eigenvalues of the pencil F_y + lambda F_y'.
// momenta's DAEs are of index 1 after index reduction, with y = [x states; z algebraic] and F
// independent of z'. The mixed matrix M = [F_x' | F_z] (mixed_jacobian.h) is then regular, and
//     [dx'; dz] = -M^-1 F_x dx,
// so the pencil's finite eigenvalues are those of the states' ODE matrix J = rows x' of
// (-M^-1 F_x): a sparse LU of M and a dense eigen-decomposition of J (n_x x n_x). This avoids the
// QZ decomposition of the singular pencil, whose infinite eigenvalues (one per algebraic
// equation) are told apart from fast finite ones only by a threshold on beta: a light mass's
// lambda = 1e6 1/s and an algebraic row's infinity differ by a few orders of magnitude of beta.
//
// The parameters that set a mode: each real parameter changed by 1 % in a copy of the state
// (every other parameter held at its value, so that the parameter a component uses is the one
// named), J again, the eigenvalue nearest the mode's, and the elasticity d ln|lambda| / d ln p.

#include "solver/stiffness_report.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "solver/mixed_jacobian.h"

namespace momenta {

namespace {

/// The sensitivities are computed while (parameters x states^3) stays below this (a few tenths
/// of a second); past it the modes are named by the states they move most.
constexpr double kSensitivityBudget = 3e8;

/// About what BDF spends on one period of an undamped oscillation at rtol 1e-6 (bench/RESULTS.md,
/// "Numerical stress suite": 67 steps a period).
constexpr double kStepsPerPeriod = 60;

/// Elasticities below this are left out of the message.
constexpr double kShownElasticity = 0.05;

/// Three significant digits: "1.59e+05" reads worse in a sentence than "1.59e5".
std::string Short(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  std::string s = text;
  const size_t e = s.find("e+");
  if (e != std::string::npos) s.erase(e + 1, 1);
  const size_t z = s.find("e0");
  if (z != std::string::npos) s.erase(z + 1, 1);
  const size_t mz = s.find("e-0");
  if (mz != std::string::npos) s.erase(mz + 2, 1);
  return s;
}

/// The y indices of the states.
std::vector<int> StateIndices(const CompiledModel& model) {
  std::vector<int> states;
  for (size_t k = 0; k < model.num_unknowns(); ++k) {
    if (model.is_state[k]) states.push_back(static_cast<int>(k));
  }
  return states;
}

/// The states' ODE matrix J = rows x' of -M^-1 F_x at (t, y, y'); nothing when M is singular.
std::optional<Eigen::MatrixXd> StateMatrix(ModelState* state, double t, const std::vector<double>& y,
                                           const std::vector<double>& yp, const std::vector<int>& states) {
  const CompiledModel& model = state->model();
  MixedJacobian jacobian(state, t, y.data(), yp.data());
  if (!jacobian.Factor()) return std::nullopt;
  const SparsePattern& pattern = model.jacobian_pattern;
  const auto n = static_cast<int>(model.num_unknowns());
  const auto ns = static_cast<int>(states.size());
  Eigen::MatrixXd j(ns, ns);
  Eigen::VectorXd column(n);
  for (int c = 0; c < ns; ++c) {
    // Column c of -F_x, then M^-1 of it: the rates (and algebraic moves) that dx_c causes.
    column.setZero();
    const int32_t x = states[c];
    for (int32_t k = pattern.col_start[x]; k < pattern.col_start[x + 1]; ++k) {
      column[pattern.row_index[k]] = -jacobian.dfdy()[k];
    }
    const Eigen::VectorXd moved = jacobian.Solve(column);
    for (int r = 0; r < ns; ++r) j(r, c) = moved[states[r]];
  }
  if (!j.allFinite()) return std::nullopt;
  return j;
}

/// The eigenvalues of J with Im >= 0 (one of each conjugate pair), the largest |lambda| first.
std::vector<std::complex<double>> UpperEigenvalues(const Eigen::MatrixXd& j, Eigen::MatrixXcd* vectors) {
  Eigen::EigenSolver<Eigen::MatrixXd> solver(j, vectors != nullptr);
  if (solver.info() != Eigen::Success) return {};
  std::vector<int> order;
  for (int k = 0; k < j.rows(); ++k) {
    if (solver.eigenvalues()[k].imag() >= 0) order.push_back(k);
  }
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::abs(solver.eigenvalues()[a]) > std::abs(solver.eigenvalues()[b]);
  });
  std::vector<std::complex<double>> values;
  Eigen::MatrixXcd sorted(j.rows(), static_cast<int>(order.size()));
  for (size_t k = 0; k < order.size(); ++k) {
    values.push_back(solver.eigenvalues()[order[k]]);
    if (vectors) sorted.col(static_cast<int>(k)) = solver.eigenvectors().col(order[k]);
  }
  if (vectors) *vectors = sorted;
  return values;
}

/// Every parameter at its current value, by name (the overrides that reproduce the state's).
ParameterOverrides CurrentParameters(const ModelState& state) {
  const FlatSystem& flat = *state.model().flat;
  ParameterOverrides values;
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    values[flat.ParameterName(ParamId(static_cast<uint32_t>(k)))] = state.parameter_values()[k];
  }
  return values;
}

/// |lambda| of the eigenvalue of the perturbed J nearest `mode`; nothing when it cannot be had.
std::optional<double> PerturbedMagnitude(const ModelState& state, const ParameterOverrides& overrides, double t,
                                         const std::vector<double>& y, const std::vector<double>& yp,
                                         const std::vector<int>& states, std::complex<double> mode) {
  ModelState perturbed = state;
  try {
    perturbed.SetParameters(overrides);
  } catch (const std::exception&) {
    return std::nullopt;  // out of its range, or structural
  }
  std::optional<Eigen::MatrixXd> j = StateMatrix(&perturbed, t, y, yp, states);
  if (!j) return std::nullopt;
  const std::vector<std::complex<double>> values = UpperEigenvalues(*j, nullptr);
  if (values.empty()) return std::nullopt;
  auto nearest = std::min_element(values.begin(), values.end(), [&](auto a, auto b) {
    return std::abs(a - mode) < std::abs(b - mode);
  });
  return std::abs(*nearest);
}

/// The real parameters whose 1 % change moves |mode| noticeably, the strongest first.
std::vector<ParameterShare> SettingParameters(const ModelState& state, double t, const std::vector<double>& y,
                                              const std::vector<double>& yp, const std::vector<int>& states,
                                              std::complex<double> mode) {
  const FlatSystem& flat = *state.model().flat;
  const ParameterOverrides current = CurrentParameters(state);
  std::vector<ParameterShare> shares;
  for (size_t k = 0; k < flat.parameters.size(); ++k) {
    const double value = state.parameter_values()[k];
    if (flat.parameters[k].type != ValueType::kReal || value == 0 || !std::isfinite(value)) continue;
    const ParamId id(static_cast<uint32_t>(k));
    ParameterOverrides overrides = current;
    overrides[flat.ParameterName(id)] = value * 1.01;
    std::optional<double> moved = PerturbedMagnitude(state, overrides, t, y, yp, states, mode);
    if (!moved) continue;
    const double elasticity = std::log(*moved / std::abs(mode)) / std::log(1.01);
    if (std::fabs(elasticity) >= kShownElasticity) {
      shares.push_back({flat.ParameterName(id), value, flat.ParameterUnit(id), elasticity});
    }
  }
  std::sort(shares.begin(), shares.end(),
            [](const auto& a, const auto& b) { return std::fabs(a.elasticity) > std::fabs(b.elasticity); });
  return shares;
}

}  // namespace

double SystemMode::magnitude() const { return std::hypot(growth, frequency); }

std::vector<SystemMode> FastestModes(const ModelState& state, double t, const std::vector<double>& y,
                                     const std::vector<double>& yp, size_t count) {
  const CompiledModel& model = state.model();
  const std::vector<int> states = StateIndices(model);
  if (states.empty() || states.size() > kModeAnalysisLimit) return {};
  ModelState work = state;
  std::optional<Eigen::MatrixXd> j = StateMatrix(&work, t, y, yp, states);
  if (!j) return {};
  const std::vector<std::complex<double>> values = UpperEigenvalues(*j, nullptr);
  const double budget = static_cast<double>(model.flat->parameters.size()) * std::pow(states.size(), 3.0);
  std::vector<SystemMode> modes;
  for (size_t k = 0; k < values.size() && modes.size() < count; ++k) {
    SystemMode mode{values[k].real(), values[k].imag(), {}};
    if (budget <= kSensitivityBudget && std::abs(values[k]) > 0) {
      mode.parameters = SettingParameters(state, t, y, yp, states, values[k]);
    }
    modes.push_back(mode);
  }
  return modes;
}

namespace {

/// "an oscillation at 1e6 rad/s (1.59e5 Hz, period 6.28e-6 s), damping ratio 0" or "a decay at
/// 1e6 1/s (time constant 1e-6 s)".
std::string DescribeMode(const SystemMode& mode) {
  std::string text;
  if (mode.frequency > 0) {
    text = "an oscillation at " + Short(mode.frequency) + " rad/s (" + Short(mode.frequency / (2 * M_PI)) +
           " Hz, period " + Short(2 * M_PI / mode.frequency) + " s), damping ratio " +
           (std::fabs(mode.growth) < 1e-9 * mode.magnitude() ? "0" : Short(-mode.growth / mode.magnitude()));
  } else if (mode.growth < 0) {
    text = "a decay at " + Short(-mode.growth) + " 1/s (time constant " + Short(-1 / mode.growth) + " s)";
  } else {
    text = "a growth at " + Short(mode.growth) + " 1/s (unstable)";
  }
  if (!mode.parameters.empty()) {
    std::vector<std::string> names;
    for (const ParameterShare& p : mode.parameters) {
      names.push_back(p.name + " = " + Short(p.value) + (p.unit.empty() || p.unit == "1" ? "" : " " + p.unit) +
                      " (|lambda| ~ " + p.name + "^" + Short(p.elasticity) + ")");
    }
    text += ", set by " + JoinNames(names, 4);
  }
  return text;
}

/// What helps against the cost of `steps` steps in one output interval when `fastest` is the
/// fastest mode; `stopped`: the run stopped at the step limit.
std::string Advice(const SystemMode& fastest, double interval, double steps, bool stopped) {
  const std::string more = stopped ? "; --max-steps raises the limit" : "";
  const double zeta = -fastest.growth / fastest.magnitude();
  // Following an oscillation takes tens of steps a period: one that needs far fewer steps than
  // were taken does not explain them.
  const double periods = interval * fastest.frequency / (2 * M_PI);
  if (kStepsPerPeriod * std::max(periods, 1.0) < 0.1 * steps) {
    return ". That mode needs about " + Short(kStepsPerPeriod * std::max(periods, 1.0)) +
           " steps per output interval, not " + Short(steps) + ", so the steps go elsewhere: look for a "
           "configuration where the constraints lose rank (a mechanism at a dead centre, links that "
           "line up), or a discontinuity the model does not declare as an event (a relation under "
           "noEvent(), abs(), a table)" + more;
  }
  // "reduce spring.c or increase mass.m": the way each parameter slows the mode down.
  std::vector<std::string> slower;
  for (const ParameterShare& p : fastest.parameters) {
    slower.push_back((p.elasticity > 0 ? "reduce " : "increase ") + p.name);
  }
  const std::string change = slower.empty() ? "a softer spring or a heavier mass" : JoinNames(slower, 4);
  if (fastest.frequency > 0 && zeta < 0.5) {
    const std::string slow_it = "make it slower (" + change + ") or damp it (BDF steps over a mode that decays, "
                                "whatever its speed)";
    if (!stopped) {
      return ". IDA follows every period of this oscillation (tens of steps each; " + Short(periods) +
             " periods per output interval" + (periods > 0.5 ? ", more than the rows resolve: a shorter --interval shows it" : "") +
             "), so a tighter tolerance makes the run dearer, not cheaper. If it does not matter, " + slow_it;
    }
    return ". IDA must follow every period of this oscillation (tens of steps each; " + Short(periods) +
           " periods per output interval), so a tighter tolerance makes the run dearer, not cheaper. "
           "If the oscillation matters, shorten the run (--stop) or allow more steps (--max-steps); if it "
           "does not, " + slow_it;
  }
  if (fastest.growth > 0) {
    return ". The fastest mode grows: the solution diverges; check the signs and values of the parameters "
           "that set it";
  }
  return ". Fast modes that decay do not hold IDA's steps back (BDF is stable over them), so the steps go "
         "elsewhere: look for a discontinuity the model does not declare as an event (a relation under "
         "noEvent(), abs(), a table), or a source that switches faster than the output interval" + more;
}

}  // namespace

std::string ExplainStepCost(const ModelState& state, double t, const std::vector<double>& y,
                            const std::vector<double>& yp, double interval, double steps, bool stopped) {
  const CompiledModel& model = state.model();
  const size_t num_states = StateIndices(model).size();
  const std::string more = stopped ? "; --max-steps raises the limit" : "";
  if (num_states > kModeAnalysisLimit) {
    return ". The model has " + Counted(num_states, "state") + ", more than the " +
           std::to_string(kModeAnalysisLimit) +
           " whose fastest modes momenta computes (a dense eigen-decomposition): look for a stiff "
           "spring on a light mass, or a discontinuity the model does not declare as an event" + more;
  }
  const std::vector<SystemMode> modes = FastestModes(state, t, y, yp, 2);
  if (modes.empty()) {
    return ". Its modes could not be computed here (no states, or a singular system): look for a "
           "discontinuity the model does not declare as an event" + more;
  }
  std::string text = ". The fastest mode at t = " + Short(t) + " s is " + DescribeMode(modes[0]);
  if (modes.size() > 1 && modes[1].magnitude() > 0) text += "; the next: " + DescribeMode(modes[1]);
  return text + Advice(modes[0], interval, steps, stopped);
}

std::string StepCostNote(const ModelState& state, double t, const std::vector<double>& y,
                         const std::vector<double>& yp, double interval, long steps, long rows) {
  const double per_row = static_cast<double>(steps) / static_cast<double>(std::max(rows, 1L));
  if (steps < kCostNoteMinSteps || per_row < kCostNoteStepsPerRow) return "";
  return Short(static_cast<double>(steps)) + " steps, " + Short(per_row) + " per output interval" +
         ExplainStepCost(state, t, y, yp, interval, per_row, /*stopped=*/false) + ".";
}

}  // namespace momenta
