#pragma once
/// Why a run costs so many steps: the fastest modes of the model linearised where it stands, the
/// parameters that set them, and advice that fits them. Read when IDA gives up for too much work
/// (ida_session.cc), so that the message names the cause instead of a tolerance.

#include <cstddef>
#include <string>
#include <vector>

#include "core/compile/model_state.h"

namespace momenta {

/// Systems with more unknowns than this are not analysed: the dense QZ decomposition of the
/// pencil costs O(n^3) time and O(n^2) memory (200 unknowns: about 0.1 s, 0.6 MB).
constexpr size_t kModeAnalysisLimit = 200;

/// How a parameter moves a mode: d ln|lambda| / d ln p (a spring constant c of a mass-spring
/// mode: 0.5; the mass: -0.5).
struct ParameterShare {
  std::string name;  ///< as the user writes it in -p: "spring.c"
  double value = 0;
  std::string unit;
  double elasticity = 0;
};

/// One eigenvalue lambda = growth + i*frequency of the linearised DAE (a conjugate pair counted
/// once), with the parameters that set it, the strongest first.
struct SystemMode {
  double growth = 0;     ///< Re(lambda) [1/s]; negative: the mode decays
  double frequency = 0;  ///< Im(lambda) >= 0 [rad/s]
  std::vector<ParameterShare> parameters;
  double magnitude() const;  ///< |lambda| [1/s]
};

/// The modes of F(t, y, y') = 0 linearised at (t, y, y'): the finite eigenvalues lambda of the
/// pencil dF/dy + lambda dF/dy' (the algebraic equations give the infinite ones, left out), the
/// fastest (largest |lambda|) first, at most `count`, each with the parameters whose 1 % change
/// moves its |lambda| by more than 0.05 %. Empty when the model has more than kModeAnalysisLimit
/// unknowns or the decomposition fails. `state` is not changed (the parameters are perturbed in
/// a copy).
std::vector<SystemMode> FastestModes(const ModelState& state, double t, const std::vector<double>& y,
                                     const std::vector<double>& yp, size_t count);

/// The sentences that explain an explosion of the step count at time t after `steps` steps since
/// the last output row (`interval` apart): the fastest modes, their periods per output interval,
/// and the advice that fits them (a fast undamped oscillation: damp it, soften it or shorten the
/// run; a fast decay, or modes too slow for that many steps: the steps go elsewhere, look for
/// constraints that lose rank or an undeclared discontinuity). Starts with ". "; says what it
/// could not analyse.
/// `stopped`: the run stopped at the step limit (the advice then mentions --max-steps).
std::string ExplainStepCost(const ModelState& state, double t, const std::vector<double>& y,
                            const std::vector<double>& yp, double interval, double steps, bool stopped);

/// A finished run is noted as dear from this many steps ...
constexpr long kCostNoteMinSteps = 100000;
/// ... when they are this many per output interval on average (a smooth solution needs tens).
constexpr double kCostNoteStepsPerRow = 1000;

/// "1e6 steps, 1e4 per output interval. The fastest mode …" for a finished run of `steps` steps
/// over `rows` output intervals that crosses both thresholds above, from its values at the end
/// (t, y, y'); otherwise "".
std::string StepCostNote(const ModelState& state, double t, const std::vector<double>& y,
                         const std::vector<double>& yp, double interval, long steps, long rows);

}  // namespace momenta
