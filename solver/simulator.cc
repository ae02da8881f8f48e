// IDA integration with events and exact impacts. See simulator.h for the event semantics.
//
// Impact maths (ARCHITECTURE.md decision 7). Integrating the DAE F(t, y, y') = 0 over an impact
// of vanishing length, bounded terms vanish, each y' becomes the jump Δx of a state, and each
// algebraic unknown that carries the impact becomes its impulse Λ. For F linear in y' and in the
// impulsive unknowns (masses times accelerations balanced by forces) this is
//     [dF/dy' (state columns) | dF/dz (algebraic columns)] [Δx; Λ] = 0,
// the IDA Jacobian's two parts (cj = 1 minus cj = 0, and cj = 0). The contact's own law, its
// `0 = if contact then der(velocity) else force` row taken in contact mode, integrates to the
// jump of the velocity, and Newton's law sets it:
//     ∫ der(velocity) dt = Δvelocity = -(1 + e) · velocity⁻.
// This holds through index reduction: a dummy derivative (der(v) made algebraic) integrates to
// the jump of v like a state's derivative does, and the integrals of velocity-level unknowns
// come out zero, so the velocity may be any expression of the model's unknowns.
// so the impulse passes through rods (rigid: one velocity), not through springs (bounded forces:
// Λ = 0), and through closed contacts as through rods. Positions do not jump (der(s) = v gives
// Δs = 0). An approach slower than v_small closes the contact (e = 0); it then rests, with
// der(velocity) = 0, until its release condition (a pulling force) holds.

#include "solver/simulator.h"

#include <ida/ida.h>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "solver/crossing_model.h"
#include "solver/initializer.h"
#include "solver/jacobian_fill.h"
#include "solver/sundials_support.h"

namespace momenta {

namespace {

/// The absolute tolerance of unknowns left out of IDA's error test (dummy derivatives).
constexpr double kUntestedTolerance = 1e30;

struct IdaData {
  ModelState* state;
  std::vector<double> jac_values;
  std::string error;         ///< an exception caught in a callback
  std::string last_message;  ///< IDA's own last error message
};

// The SUNDIALS boundary: no exception crosses it. A non-finite residual asks IDA for a smaller
// step (positive return); an exception is stored and stops the solver (negative return).
int Residual(double t, N_Vector y, N_Vector yp, N_Vector r, void* user) {
  auto* d = static_cast<IdaData*>(user);
  try {
    d->state->Residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), N_VGetArrayPointer(r));
  } catch (const std::exception& e) {
    d->error = e.what();
    return -1;
  }
  const double* rv = N_VGetArrayPointer(r);
  for (sunindextype k = 0, n = N_VGetLength(r); k < n; ++k) {
    if (!std::isfinite(rv[k])) return 1;
  }
  return 0;
}

int Jacobian(double t, double cj, N_Vector y, N_Vector yp, N_Vector, SUNMatrix J, void* user,
             N_Vector, N_Vector, N_Vector) {
  auto* d = static_cast<IdaData*>(user);
  try {
    const SparsePattern& pattern = d->state->model().jacobian_pattern;
    d->jac_values.resize(pattern.nnz());
    d->state->Jacobian(t, cj, N_VGetArrayPointer(y), N_VGetArrayPointer(yp), d->jac_values.data());
    FillMatrix(pattern, d->jac_values, J);
  } catch (const std::exception& e) {
    d->error = e.what();
    return -1;
  }
  return 0;
}

void IdaMessage(int, const char*, const char*, char* msg, void* user) {
  static_cast<IdaData*>(user)->last_message = msg;
}

struct IdaDeleter {
  void operator()(void* mem) const { IDAFree(&mem); }
};

double Elapsed(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string FlagMeaning(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK: return "too many steps without reaching the next output time";
    case IDA_TOO_MUCH_ACC: return "the requested accuracy is finer than the solution's rounding errors";
    case IDA_ERR_FAIL: return "the error test failed repeatedly (a discontinuity or a singularity?)";
    case IDA_CONV_FAIL: return "Newton's method failed to converge repeatedly";
    case IDA_LSETUP_FAIL:
    case IDA_LSOLVE_FAIL: return "the linear solver failed (a singular Jacobian?)";
    case IDA_RES_FAIL: return "the residual could not be evaluated";
    case IDA_REP_RES_ERR: return "the residual returned non-finite values repeatedly";
    default: return "";
  }
}

/// IDA's name for a return flag (IDAGetReturnFlagName allocates; the caller frees).
std::string FlagName(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string out = name ? name : "unknown flag";
  std::free(name);
  return out;
}

/// A relation's value for its zero-crossing function z = a - b.
/// How an event relation whose zero-crossing function is at zero (within the location error)
/// is set at an event: by the value (at the start), by the side its rate leads to (the right
/// limit: the crossing that caused the event is passed), or left as it was.
enum ZeroSide { kAtValue, kRightLimit, kHoldAtZero };

bool RelationHolds(Op op, double z) {
  switch (op) {
    case Op::kLt: return z < 0;
    case Op::kLe: return z <= 0;
    case Op::kGt: return z > 0;
    case Op::kGe: return z >= 0;
    case Op::kEq: return z == 0;
    default: return z != 0;
  }
}

/// Samples of the zero-crossing functions inside each step: the end and three interior points.
constexpr int kInteriorSamples = 3;

/// Extra samples per step where the cubic models of the crossing functions point to a dip, and
/// how often an interval may be split.
constexpr int kMaxRefinements = 32, kMaxDepth = 12;

/// IDASetMaxNumSteps' meaning for runs that step one at a time: at most this many steps between
/// two output rows.
constexpr long kMaxStepsPerRow = 500000;

class EventIntegrator {
 public:
  EventIntegrator(ModelState* state, const SimulationOptions& opt, const RowCallback& row,
                  SolverStats* stats)
      : state_(state), m_(state->model()), opt_(opt), row_(row), stats_(stats) {
    n_ = m_.num_unknowns();
    nc_ = m_.conditions.size();
    interval_ = opt.interval == 0 ? (opt.stop - opt.start) / 500.0 : opt.interval;
    outputs_.resize(m_.output_names.size());
    has_events_ = nc_ > 0 || !m_.whens.empty() || !m_.impacts.empty();
    sparse_ = opt.linear_solver == "klu" || (opt.linear_solver == "auto" && n_ > kDenseLimit);
    stats_->linear_solver = sparse_ ? "klu" : "dense";
    // The grid must be finite before its size is cast (an infinite stop would never end).
    if (!(std::isfinite(opt.start) && std::isfinite(opt.stop) && opt.stop > opt.start)) {
      throw std::invalid_argument("the stop time " + Num(opt.stop) + " is not a finite time after the start time " + Num(opt.start));
    }
    if (!(interval_ > 0 && std::isfinite(interval_))) {
      throw std::invalid_argument("the output interval " + Num(interval_) + " is not a positive finite number");
    }
    if (std::string grid = OutputGridProblem(opt.start, opt.stop, interval_); !grid.empty()) {
      throw std::invalid_argument("the output interval " + Num(interval_) + ": " + grid);
    }
    if (opt.max_order < 1 || opt.max_order > 5) {
      throw std::invalid_argument("the maximum BDF order " + std::to_string(opt.max_order) + " is not one of 1 to 5");
    }
    num_intervals_ = static_cast<long>(std::ceil((opt.stop - opt.start) / interval_ - 1e-9));
    z_.resize(nc_);
    zscale_.assign(nc_, 1.0);
  }

  void Run() {
    Initialize();
    if (n_ == 0) {
      // Nothing to integrate: outputs are functions of time and of the discrete values.
      t_run_ = std::chrono::steady_clock::now();
      if (has_events_) {
        RunStateless();
      } else {
        for (long k = 1; k <= num_intervals_ && !Interrupted(GridTime(k - 1)); ++k) {
          Emit(GridTime(k), nullptr, nullptr);
        }
      }
      stats_->integrate_seconds = Elapsed(t_run_);
      return;
    }
    PolishConsistentValues(opt_.start);
    SetUpIda();
    t_ = opt_.start;
    next_grid_ = 1;
    t_run_ = std::chrono::steady_clock::now();
    if (!has_events_) {
      RunWithoutEvents();
    } else {
      RunWithEvents();
    }
    CollectStats();
    stats_->integrate_seconds = Elapsed(t_run_);
  }

 private:
  double GridTime(long k) const { return k >= num_intervals_ ? opt_.stop : opt_.start + k * interval_; }

  /// Whether the run has been asked to stop (SimulationOptions::interrupt); records where it was.
  bool Interrupted(double t) {
    if (!opt_.interrupt || !opt_.interrupt->load(std::memory_order_relaxed)) return false;
    if (!stats_->interrupted) {
      stats_->interrupted = true;
      stats_->interrupted_at = t;
    }
    return true;
  }

  void Emit(double t, const double* y, const double* yp) {
    state_->Outputs(t, y, yp, outputs_.data());
    Row(t, outputs_);
  }

  /// Gives out a row, unless the run has been interrupted (then no row follows a gap).
  void Row(double t, const std::vector<double>& values) {
    if (stats_->interrupted) return;
    row_(t, values);
    stats_->final_time = t;
  }

  // -------------------------------------------------------------------------------------------
  // Initialisation: continuous values and discrete values iterate until they agree.

  void Initialize() {
    auto t0 = std::chrono::steady_clock::now();
    state_->StartDiscrete();
    y_.assign(n_, 0.0);
    yp_.assign(n_, 0.0);
    state_->StartValues(y_.data());
    state_->SavePre(y_.data());
    // First guesses for the conditions: their values at the start values.
    SetConditions(opt_.start, y_.data(), yp_.data(), kAtValue);
    for (int iter = 0;; ++iter) {
      InitialValues init = SolveInitialization(state_, opt_.start, sparse_);
      stats_->init_iterations += init.iterations;
      y_ = init.y;
      yp_ = init.yp;
      if (!has_events_) break;
      // Discrete equations solved with the initial system see initial() = true (MSL's friction
      // elements start sliding from `initial() and v > 0`).
      state_->set_initial(true);
      bool changed = SetConditions(opt_.start, y_.data(), yp_.data(), kAtValue);
      changed = UpdateDiscrete(opt_.start) || changed;
      state_->set_initial(false);
      if (!changed) break;
      if (iter == 50) throw SolverError("at t = " + Num(opt_.start) + ": the initial discrete values do not settle (the conditions switch back and forth)");
    }
    // When-clauses at the start: a clause fires only when its condition is true because of
    // initial() (`when initial() then …`); one already true for other reasons waits for an edge.
    when_state_.resize(m_.whens.size());
    if (!m_.whens.empty()) {
      std::vector<double> now(m_.whens.size()), at_init(m_.whens.size());
      state_->WhenConditions(opt_.start, y_.data(), yp_.data(), now.data());
      state_->set_initial(true);
      state_->WhenConditions(opt_.start, y_.data(), yp_.data(), at_init.data());
      state_->set_initial(false);
      std::vector<double> values;
      for (size_t k = 0; k < now.size(); ++k) {
        when_state_[k] = now[k] != 0;
        if (at_init[k] == 0 || now[k] != 0) continue;
        state_->set_initial(true);
        RunWhen(k, opt_.start, &values);
        state_->set_initial(false);
      }
    }
    state_->SavePre(y_.data());
    CheckNoContactOverlaps(opt_.start);
    stats_->init_seconds = Elapsed(t0);
    Emit(opt_.start, y_.data(), yp_.data());
    // The initial event: with pre() now the initial values, discrete equations such as
    // edge(u) = u and not pre(u) may change at once; a second row at the start time shows it.
    if (has_events_ && Iterate(opt_.start, /*restart=*/false)) {
      if (n_ > 0) SolveAtStart();
      last_event_time_ = opt_.start;
      Emit(opt_.start, y_.data(), yp_.data());
    }
  }

  /// Consistent continuous values at the start for the current discrete values.
  void SolveAtStart() {
    InitialValues init = SolveInitialization(state_, opt_.start, sparse_);
    stats_->init_iterations += init.iterations;
    y_ = init.y;
    yp_ = init.yp;
  }

  // -------------------------------------------------------------------------------------------
  // IDA

  void SetUpIda() {
    ctx_ = MakeContext();
    y_vec_ = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
    yp_vec_ = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
    VectorPtr abstol = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
    id_ = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
    dky_ = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
    dkyp_ = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
    const double atol = opt_.atol > 0 ? opt_.atol : opt_.rtol;
    std::vector<int64_t> y_of_var(m_.flat->variables.size(), -1);
    for (size_t k = 0; k < n_; ++k) y_of_var[m_.unknowns[k].value()] = static_cast<int64_t>(k);
    for (size_t k = 0; k < n_; ++k) {
      const FlatVariable& v = m_.flat->variables[m_.unknowns[k].value()];
      if (!m_.is_state[k] && v.derivative_order == 1 && v.derivative_of.valid()) {
        const int64_t x = y_of_var[v.derivative_of.value()];
        if (x >= 0 && !m_.is_state[x]) rate_of_algebraic_.emplace_back(static_cast<uint32_t>(x), k);
      }
    }
    SetAlgebraicRates();
    bool untested = false;
    for (size_t k = 0; k < n_; ++k) {
      N_VGetArrayPointer(abstol.get())[k] = atol * m_.nominal[k];
      // Dummy derivatives (derivatives index reduction made algebraic) follow from the other
      // unknowns through the differentiated constraints; IDA's estimate of their local error is
      // poor (a pendulum's der(der(y)) makes its steps collapse), so they are left out of the
      // error test: an absolute tolerance no value reaches.
      if (!m_.is_state[k] && m_.flat->variables[m_.unknowns[k].value()].derivative_order > 0) {
        N_VGetArrayPointer(abstol.get())[k] = kUntestedTolerance;
        untested = true;
      }
      N_VGetArrayPointer(id_.get())[k] = m_.is_state[k] ? 1.0 : 0.0;
    }
    // The consistent restarts after events solve for every algebraic unknown, dummy derivatives
    // included, to the ordinary tolerance (after an impulse they are all stale).
    if (untested) {
      restart_abstol_.reset(N_VClone(abstol.get()));
      for (size_t k = 0; k < n_; ++k) N_VGetArrayPointer(restart_abstol_.get())[k] = atol * m_.nominal[k];
    }
    Load(y_, yp_);
    data_ = IdaData{state_, {}, {}, {}};
    ida_.reset(IDACreate(ctx_.get()));
    CheckNotNull(ida_.get(), "IDACreate");
    void* mem = ida_.get();
    CheckFlag(IDAInit(mem, Residual, opt_.start, y_vec_.get(), yp_vec_.get()), "IDAInit");
    CheckFlag(IDASetUserData(mem, &data_), "IDASetUserData");
    CheckFlag(IDASetErrHandlerFn(mem, IdaMessage, &data_), "IDASetErrHandlerFn");
    CheckFlag(IDASVtolerances(mem, opt_.rtol, abstol.get()), "IDASVtolerances");
    CheckFlag(IDASetId(mem, id_.get()), "IDASetId");
    ls_ = MakeLinearSystem(y_vec_.get(), static_cast<sunindextype>(n_),
                           static_cast<sunindextype>(m_.jacobian_pattern.nnz()), sparse_, ctx_.get());
    CheckFlag(IDASetLinearSolver(mem, ls_.solver.get(), ls_.matrix.get()), "IDASetLinearSolver");
    CheckFlag(IDASetJacFn(mem, Jacobian), "IDASetJacFn");
    CheckFlag(IDASetMaxNumSteps(mem, kMaxStepsPerRow), "IDASetMaxNumSteps");
    CheckFlag(IDASetMaxOrd(mem, opt_.max_order), "IDASetMaxOrd");
    CheckFlag(IDASetStopTime(mem, opt_.stop), "IDASetStopTime");
    abstol_ = std::move(abstol);
  }

  /// IDA's residual does not depend on an algebraic unknown's y', but its first predictor does
  /// (y + h y'): where index reduction made the unknown's derivative a dummy, y' := that dummy,
  /// so the first step after a start or restart is not an O(h) guess of an algebraic value.
  void SetAlgebraicRates() {
    for (auto [x, d] : rate_of_algebraic_) yp_[x] = y_[d];
  }

  void Load(const std::vector<double>& y, const std::vector<double>& yp) {
    std::copy(y.begin(), y.end(), N_VGetArrayPointer(y_vec_.get()));
    std::copy(yp.begin(), yp.end(), N_VGetArrayPointer(yp_vec_.get()));
  }

  void CollectStats() {
    void* mem = ida_.get();
    long v = 0;
    IDAGetNumSteps(mem, &v);
    stats_->steps = base_.steps + v;
    IDAGetNumResEvals(mem, &v);
    stats_->residual_evals = base_.residual_evals + v;
    IDAGetNumJacEvals(mem, &v);
    stats_->jacobian_evals = base_.jacobian_evals + v;
    IDAGetNumErrTestFails(mem, &v);
    stats_->error_test_failures = base_.error_test_failures + v;
    IDAGetNumNonlinSolvConvFails(mem, &v);
    stats_->nonlinear_failures = base_.nonlinear_failures + v;
  }

  [[noreturn]] void Fail(int flag) {
    CollectStats();
    stats_->integrate_seconds = Elapsed(t_run_);
    void* mem = ida_.get();
    double t_fail = t_;
    IDAGetCurrentTime(mem, &t_fail);
    stats_->final_time = t_fail;
    std::ostringstream msg;
    msg << "at t = " << t_fail << ": ";
    if (!data_.error.empty()) {
      msg << data_.error;
    } else if (flag == IDA_ILL_INPUT) {
      // Tolerances below double precision make IDA's step size vanish, and its own message then
      // blames the stop time: name the tolerance instead. Otherwise IDA's message says which input.
      const double atol = opt_.atol > 0 ? opt_.atol : opt_.rtol;
      msg << "IDA rejected its input (IDA_ILL_INPUT): ";
      if (!(opt_.rtol >= kMinRelTolerance)) {
        msg << "the relative tolerance " << opt_.rtol << " is below what double precision resolves (use at least 1e-15)";
      } else if (!(atol >= kMinAbsTolerance)) {
        msg << "the absolute tolerance " << atol << " is below the smallest normal double (2.2e-308)";
      } else {
        msg << (data_.last_message.empty() ? "no reason given" : data_.last_message) << " (rtol " << opt_.rtol
            << ", atol " << atol << ")";
      }
    } else {
      msg << "IDA stopped (" << FlagName(flag) << "): " << FlagMeaning(flag);
      VectorPtr ewt = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
      VectorPtr ele = MakeVector(static_cast<sunindextype>(n_), ctx_.get());
      if (IDAGetErrWeights(mem, ewt.get()) == IDA_SUCCESS && IDAGetEstLocalErrors(mem, ele.get()) == IDA_SUCCESS) {
        size_t worst = 0;
        double worst_err = -1;
        for (size_t j = 0; j < n_; ++j) {
          double e = std::fabs(N_VGetArrayPointer(ele.get())[j] * N_VGetArrayPointer(ewt.get())[j]);
          if (e > worst_err) {
            worst_err = e;
            worst = j;
          }
        }
        msg << ". The largest local error is in " << m_.flat->DescribeVariable(m_.unknowns[worst])
            << ", governed by " << m_.residual_origin(worst);
      }
      if (flag == IDA_TOO_MUCH_ACC) {
        msg << ". Loosen the tolerance (a larger --rtol or --atol): double precision cannot deliver this one.";
      } else {
        msg << ". Try a tighter tolerance (--rtol), check the parameters of that component, or "
               "look for a singularity in its equations.";
      }
    }
    throw SolverError(msg.str());
  }

  /// The `tout` for IDASolve's next step from t_ (the step itself stops at IDASetStopTime's
  /// `tstop`). IDA_ONE_STEP reads tout on the first step after a start or restart only, to size
  /// that step: 0.001 of the distance to tout, less where 0.5 / |y'| is smaller (IDA's own
  /// default). Aimed at one output interval ahead, as IDA_NORMAL aims at the first output row,
  /// the first step follows the time scale the user asked to see rather than the length of the
  /// run (a 1000 s run would otherwise start with a 1 s step, whatever the model's dynamics).
  double StepTarget(double tstop) const { return std::min(t_ + interval_, tstop); }

  /// One step at a time to the stop time (the steps IDA_NORMAL would take to each output time),
  /// the output rows interpolated within each step, so an interrupt is seen after every step.
  void RunWithoutEvents() {
    void* mem = ida_.get();
    long steps_since_row = 0;
    while (t_ < opt_.stop && !Interrupted(t_)) {
      double tret = 0;
      int flag = IDASolve(mem, StepTarget(opt_.stop), &tret, y_vec_.get(), yp_vec_.get(), IDA_ONE_STEP);
      if (flag < 0) Fail(flag);
      // IDA_NORMAL's guard: this many steps without reaching the next output time is too many.
      const long before = next_grid_;
      EmitGrid(tret, /*inclusive=*/true);
      steps_since_row = next_grid_ != before ? 0 : steps_since_row + 1;
      if (steps_since_row >= kMaxStepsPerRow) Fail(IDA_TOO_MUCH_WORK);
      t_ = tret;
    }
  }

  // -------------------------------------------------------------------------------------------
  // The event loop

  void RunWithEvents() {
    void* mem = ida_.get();
    double* yv = N_VGetArrayPointer(y_vec_.get());
    double* ypv = N_VGetArrayPointer(yp_vec_.get());
    if (TimeRelationSwitchesAtStart()) DoEvent(t_, true);
    while (t_ < opt_.stop && !Interrupted(t_)) {
      double t_event = NextTimeEvent();
      double tstop = std::min(opt_.stop, t_event);
      CheckFlag(IDASetStopTime(mem, tstop), "IDASetStopTime");
      double t_old = t_, tret = 0;
      int flag = IDASolve(mem, StepTarget(tstop), &tret, y_vec_.get(), yp_vec_.get(), IDA_ONE_STEP);
      if (flag < 0) Fail(flag);
      // A state event inside (t_old, tret]?
      double t_cross = FirstCrossing(t_old, tret);
      if (t_cross <= tret) {
        EmitGrid(t_cross, /*inclusive=*/false);
        Interpolate(t_cross);
        DoEvent(t_cross, false);
        continue;
      }
      const bool at_time_event = flag == IDA_TSTOP_RETURN && tret == t_event;
      EmitGrid(tret, !at_time_event);  // an event's own rows cover its time
      t_ = tret;
      if (at_time_event) {  // (one exactly at the stop time gives the run's last row)
        y_.assign(yv, yv + n_);
        yp_.assign(ypv, ypv + n_);
        DoEvent(tret, true);
        EmitGridAtEvent(tret);
      }
    }
  }

  /// Models without states: time advances in sub-steps of the output interval, each checked for
  /// crossings like an IDA step (everything is a function of time and the discrete values).
  void RunStateless() {
    t_ = opt_.start;
    next_grid_ = 1;
    const double h = interval_ / 8;
    if (TimeRelationSwitchesAtStart()) DoEvent(t_, true);
    while (t_ < opt_.stop && !Interrupted(t_)) {
      double t_event = NextTimeEvent();
      double t_next = std::min({opt_.stop, t_event, t_ + h});
      double t_cross = FirstCrossing(t_, t_next);
      if (t_cross <= t_next) {
        EmitGrid(t_cross, false);
        DoEvent(t_cross, false);
        continue;
      }
      bool at_time_event = t_next == t_event && t_event < HUGE_VAL;
      EmitGrid(t_next, !at_time_event);
      t_ = t_next;
      if (at_time_event) {
        DoEvent(t_next, true);
        EmitGridAtEvent(t_next);
      }
    }
  }

  /// An event at t that changed no output wrote no rows: the grid row at t, if there is one, is
  /// written now from the values after the event (at the stop time no later step would write it).
  void EmitGridAtEvent(double t) {
    if (next_grid_ > num_intervals_ || GridTime(next_grid_) != t || t <= last_event_time_) return;
    Emit(t, y_.data(), yp_.data());
    ++next_grid_;
  }

  /// Grid rows up to `t` (and at t when inclusive), interpolated within the last step.
  void EmitGrid(double t, bool inclusive) {
    while (next_grid_ <= num_intervals_ && !Interrupted(t)) {
      double tg = GridTime(next_grid_);
      if (tg > t || (!inclusive && tg >= t)) break;
      if (tg <= last_event_time_) {  // already written as an event's rows
        ++next_grid_;
        continue;
      }
      Interpolate(tg);
      Emit(tg, y_.data(), yp_.data());
      ++next_grid_;
    }
  }

  /// Condition i is a time event whose time is computed exactly (affine in time): never sampled.
  bool Scheduled(size_t i) const { return m_.conditions[i].time_only && i < affine_.size() && affine_[i]; }

  /// y_, yp_ := the interpolant at t (within the last step).
  void Interpolate(double t) {
    if (n_ == 0) return;
    void* mem = ida_.get();
    CheckFlag(IDAGetDky(mem, t, 0, dky_.get()), "IDAGetDky");
    CheckFlag(IDAGetDky(mem, t, 1, dkyp_.get()), "IDAGetDky");
    const double* a = N_VGetArrayPointer(dky_.get());
    const double* b = N_VGetArrayPointer(dkyp_.get());
    y_.assign(a, a + n_);
    yp_.assign(b, b + n_);
  }

  /// The earliest time in (t0, t1] at which a frozen condition no longer agrees with its
  /// relation (or an open contact's gap closes while approaching); +inf when none. The crossing
  /// functions are sampled at the end and interior points of the step; between two samples each is
  /// modelled by the cubic through its values and time derivatives, and where that cubic dips more
  /// than halfway to zero the function is sampled at the dip and the interval split.
  double FirstCrossing(double t0, double t1) {
    // Nothing to watch when every condition is a scheduled time event and there are no contacts.
    bool watch = !m_.impacts.empty();
    for (size_t i = 0; i < nc_ && !watch; ++i) watch = !Scheduled(i);
    if (!watch) return HUGE_VAL;
    const bool model = !modelled_.empty() || !m_.impacts.empty();
    if (model && !(sample_valid_ && sample_.t == t0)) {
      Interpolate(t0);
      state_->ZeroCrossings(t0, y_.data(), yp_.data(), z_.data());
      TakeSample(t0, &sample_);
    }
    refinements_left_ = kMaxRefinements;
    double lo = t0;
    for (int s = 1; s <= kInteriorSamples + 1; ++s) {
      double ts = t0 + (t1 - t0) * s / (kInteriorSamples + 1);
      if (s == kInteriorSamples + 1) ts = t1;
      if (Crossed(ts)) {
        sample_valid_ = false;
        return Locate(lo, ts);
      }
      if (model) {
        TakeSample(ts, &next_sample_);
        if (double tc = Excursion(sample_, next_sample_, 0); tc < HUGE_VAL) {
          sample_valid_ = false;
          return tc;
        }
        std::swap(sample_, next_sample_);
      }
      lo = ts;
    }
    sample_valid_ = model;  // the next step starts where this one ended
    return HUGE_VAL;
  }

  /// The crossing functions and their time derivatives at one time.
  struct Sample {
    double t = 0;
    std::vector<double> z, dz;
    std::vector<double> gap, rate;  ///< per impact: its gap and velocity (the gap's rate)
  };

  /// Whether condition i is watched with a cubic model: it has a time derivative, is not an
  /// equality, and is not scheduled as a time event.
  bool Modelled(size_t i) const {
    const auto& c = m_.conditions[i];
    return c.has_rate && c.op != Op::kEq && c.op != Op::kNe && !Scheduled(i);
  }

  /// *s := the sample at t, from z_ (computed at t) and y_, yp_ (interpolated at t).
  void TakeSample(double t, Sample* s) {
    s->t = t;
    s->z.assign(z_.begin(), z_.end());
    // A relation set by its rate at the last event is an ordinary one again once its function
    // has left the band around zero.
    for (size_t i = 0; i < moving_at_zero_.size(); ++i) {
      if (moving_at_zero_[i] && std::fabs(z_[i]) > 4 * Band(i)) moving_at_zero_[i] = false;
    }
    s->dz.resize(nc_);
    state_->ZeroCrossingRates(t, y_.data(), yp_.data(), s->dz.data());
    if (m_.impacts.empty()) return;
    impact_values_.resize(5 * m_.impacts.size());
    state_->ImpactValues(t, y_.data(), yp_.data(), impact_values_.data());
    s->gap.resize(m_.impacts.size());
    s->rate.resize(m_.impacts.size());
    for (size_t k = 0; k < m_.impacts.size(); ++k) {
      s->gap[k] = impact_values_[5 * k];
      s->rate[k] = impact_values_[5 * k + 1];
    }
  }

  /// A crossing between samples a and b that the cubic models of the crossing functions point to:
  /// its located time, or +inf. Where a model dips more than halfway from its nearer end to zero,
  /// the functions are sampled at the dip: crossed there, the crossing is located before it;
  /// otherwise both halves are examined the same way (at most kMaxRefinements samples per step).
  double Excursion(const Sample& a, const Sample& b, int depth) {
    const double h = b.t - a.t;
    if (depth >= kMaxDepth || refinements_left_ <= 0 || !(h > 1e-14 * std::max(1.0, std::fabs(b.t)))) return HUGE_VAL;
    const double* c = state_->conditions();
    double tau = HUGE_VAL;
    for (size_t i : modelled_) {
      // u = side * z is positive on the side the frozen condition is on; crossing makes it negative.
      const Op op = m_.conditions[i].op;
      const bool holds_when_positive = op == Op::kGt || op == Op::kGe;
      const double side = (c[i] != 0) == holds_when_positive ? 1.0 : -1.0;
      const double ua = side * a.z[i], ub = side * b.z[i], va = side * a.dz[i] * h, vb = side * b.dz[i] * h;
      const double level = 0.5 * std::max(0.0, std::min(ua, ub)) - Band(i);
      // The cubic lies above its Bezier control points ua, ua + va/3, ub - vb/3, ub: most
      // intervals are cleared by those alone.
      if (std::min(ua + va / 3, ub - vb / 3) >= level) continue;
      auto dip = HermiteInteriorMinimum(ua, va, ub, vb);
      if (dip && dip->value < level) tau = std::min(tau, dip->tau);
    }
    // Open contacts the same way: the gap, with the contact's velocity as its rate (a body that
    // passes through another inside one step).
    const double* d = state_->discrete();
    for (size_t k = 0; k < a.gap.size(); ++k) {
      if (d[m_.impacts[k].contact] != 0) continue;
      const double ua = a.gap[k], ub = b.gap[k], va = a.rate[k] * h, vb = b.rate[k] * h;
      const double level = 0.5 * std::max(0.0, std::min(ua, ub)) - kGapBand;
      if (std::min(ua + va / 3, ub - vb / 3) >= level) continue;
      auto dip = HermiteInteriorMinimum(ua, va, ub, vb);
      if (dip && dip->value < level) tau = std::min(tau, dip->tau);
    }
    if (tau == HUGE_VAL) return HUGE_VAL;
    --refinements_left_;
    const double tm = a.t + tau * h;
    // Crossed there; or a contact overlaps there, at its deepest, so it closed (approaching)
    // before: either way the crossing lies in (a.t, tm].
    if (Crossed(tm) || OverlappingContact() >= 0) return Locate(a.t, tm);
    Sample m;
    TakeSample(tm, &m);
    if (double tc = Excursion(a, m, depth + 1); tc < HUGE_VAL) return tc;
    return Excursion(m, b, depth + 1);
  }

  /// Whether, at time t (interpolated), some condition or contact has switched.
  bool Crossed(double t) {
    Interpolate(t);
    if (nc_) {
      state_->ZeroCrossings(t, y_.data(), yp_.data(), z_.data());
      const double* c = state_->conditions();
      for (size_t i = 0; i < nc_; ++i) {
        if (Scheduled(i)) continue;  // scheduled exactly
        bool now = RelationHolds(m_.conditions[i].op, z_[i]);
        // A relation the last event set by its rate (at zero, within the band the event
        // iteration counts as zero) stays set while its function creeps across zero there.
        const bool set_by_rate = i < moving_at_zero_.size() && moving_at_zero_[i];
        if (now != (c[i] != 0) && std::fabs(z_[i]) > (set_by_rate ? 4 : 1) * Band(i)) return true;
      }
    }
    return ContactCloses(t);
  }

  bool ContactCloses(double t) {
    if (m_.impacts.empty()) return false;
    impact_values_.resize(5 * m_.impacts.size());
    state_->ImpactValues(t, y_.data(), yp_.data(), impact_values_.data());
    const double* d = state_->discrete();
    for (size_t k = 0; k < m_.impacts.size(); ++k) {
      if (d[m_.impacts[k].contact] != 0) continue;
      double gap = impact_values_[5 * k], vel = impact_values_[5 * k + 1];
      if (gap < 0 && vel < -kVelocityBand) return true;
    }
    return false;
  }

  /// An open contact that starts overlapped has no impact to resolve (its gap never closes):
  /// an error naming it.
  void CheckNoContactOverlaps(double t) {
    if (m_.impacts.empty()) return;
    impact_values_.resize(5 * m_.impacts.size());
    state_->ImpactValues(t, y_.data(), yp_.data(), impact_values_.data());
    if (const int k = OverlappingContact(); k >= 0) {
      throw SolverError("at t = " + Num(t) + ": the bodies of " + m_.impacts[k].name + " start overlapped (gap " +
                        Num(impact_values_[5 * k]) + "); move them apart so that the gap is zero or positive");
    }
  }

  /// An open contact whose gap is closed in impact_values_ (as ContactCloses left them), or -1.
  int OverlappingContact() const {
    const double* d = state_->discrete();
    for (size_t k = 0; k < m_.impacts.size(); ++k) {
      if (d[m_.impacts[k].contact] == 0 && impact_values_[5 * k] < -kGapBand) return static_cast<int>(k);
    }
    return -1;
  }

  /// The rounding band of condition i's zero-crossing function: 1e-12 of the largest magnitude
  /// it has had, and at least 1e-15 (a function that has only ever been rounding noise).
  double Band(size_t i) const { return 1e-12 * std::max(zscale_[i], 1e-3); }

  /// Illinois (regula falsi) on "crossed or not", shrinking [lo, hi] until it is below the time
  /// resolution; the event is placed at hi, where the switch has happened.
  double Locate(double lo, double hi) {
    const double tol = 100 * 2.2e-16 * (std::fabs(hi) + std::fabs(hi - lo)) + 1e-15;
    for (int it = 0; it < 200 && hi - lo > tol; ++it) {
      double mid = 0.5 * (lo + hi);
      if (Crossed(mid)) {
        hi = mid;
      } else {
        lo = mid;
      }
    }
    return hi;
  }

  /// Time of the next affine time event after t_ (+inf when none). Parameters are fixed during a
  /// run, so the answer changes only when an event has been handled (or it has been reached).
  double NextTimeEvent() {
    if (!time_events_dirty_ && t_ < next_time_event_) return next_time_event_;
    time_events_dirty_ = false;
    next_time_event_ = ComputeNextTimeEvent();
    // Which conditions the crossing models watch follows from which are scheduled.
    modelled_.clear();
    for (size_t i = 0; i < nc_; ++i) {
      if (Modelled(i)) modelled_.push_back(i);
    }
    return next_time_event_;
  }

  /// A relation of time alone that is at zero at the start (`time > 0` from t = 0) took its
  /// value there; time only moves on, so it switches at once if its slope says so: an event at
  /// the start time, after the initial one (scheduling looks only past the current time).
  bool TimeRelationSwitchesAtStart() {
    if (nc_ == 0) return false;
    NextTimeEvent();  // which conditions are affine in time
    std::vector<double> z0(nc_), z1(nc_);
    state_->ZeroCrossings(t_, nullptr, nullptr, z0.data());
    state_->ZeroCrossings(t_ + 1.0, nullptr, nullptr, z1.data());
    const double* c = state_->conditions();
    for (size_t i = 0; i < nc_; ++i) {
      if (!Scheduled(i) || m_.conditions[i].op == Op::kEq || m_.conditions[i].op == Op::kNe) continue;
      const double slope = z1[i] - z0[i];
      if (slope == 0 || std::fabs(z0[i]) > 1e-15 * std::fabs(slope) * std::max(1.0, std::fabs(t_))) continue;
      if (RelationHolds(m_.conditions[i].op, slope) != (c[i] != 0)) return true;
    }
    return false;
  }

  double ComputeNextTimeEvent() {
    if (affine_.size() != nc_) affine_.assign(nc_, false);
    double best = HUGE_VAL;
    if (nc_ == 0) return best;
    std::vector<double> z0(nc_), z1(nc_), z2(nc_);
    state_->ZeroCrossings(t_, nullptr, nullptr, z0.data());
    state_->ZeroCrossings(t_ + 1.0, nullptr, nullptr, z1.data());
    state_->ZeroCrossings(t_ + 2.0, nullptr, nullptr, z2.data());
    for (size_t i = 0; i < nc_; ++i) {
      if (!m_.conditions[i].time_only) continue;
      double slope = z1[i] - z0[i];
      affine_[i] = std::fabs((z2[i] - z1[i]) - slope) <= 1e-9 * (std::fabs(slope) + std::fabs(z0[i]) + 1);
      if (!affine_[i] || slope == 0) continue;
      double te = t_ - z0[i] / slope;
      if (te > t_ * (1 + 1e-15) + 1e-300 && te < best) best = te;
    }
    return best;
  }

  // -------------------------------------------------------------------------------------------
  // One event at time t, from the left-limit values in y_, yp_.

  void DoEvent(double t, bool time_event) {
    time_events_dirty_ = true;
    sample_valid_ = false;  // the conditions and discrete values change
    ++stats_->events;
    if (time_event) ++stats_->time_events;
    CheckChattering(t);
    // The left limit is written only if the event changes an output (or every event's is asked
    // for): an event that merely flips a relation nobody sees leaves no rows.
    std::vector<double> left(outputs_.size());
    state_->Outputs(t, y_.data(), yp_.data(), left.data());
    state_->SavePre(y_.data());
    long impacts_before = stats_->impacts;
    ResolveImpacts(t);
    Iterate(t, true);
    Restart(t);
    t_ = t;
    state_->Outputs(t, y_.data(), yp_.data(), outputs_.data());
    if (outputs_ != left || stats_->impacts != impacts_before || opt_.rows_at_every_event) {
      Row(t, left);
      Row(t, outputs_);
      last_event_time_ = t;
    }
  }

  /// The event iteration: conditions, discrete equations, releases and when-clauses until nothing
  /// changes; returns whether anything did. With `restart`, the continuous values are made
  /// consistent (IDACalcIC) between rounds.
  bool Iterate(double t, bool restart) {
    bool any = false;
    for (int iter = 0;; ++iter) {
      if (iter > 0 && restart) Restart(t);
      // The first round takes each relation at zero to the side its rate leads (the crossing
      // that caused the event is passed). Later rounds follow a restart that changed the
      // continuous solution: a relation that was at rest at zero in the first round keeps its
      // value, and its crossing, if the new motion brings one, is a new event — as in Modelica,
      // where a friction element that starts to slide reports startForward at the breakaway and
      // mode = Forward an instant later. A relation that was passing through zero still follows
      // its rate, so a sliding mode (each side's motion drives the relation back) is reported
      // as chattering here rather than crept through event by event. At the initial event
      // (no restart) nothing has crossed yet: relations take their values, and one at zero that
      // moves away switches at its crossing an instant later (a brake whose normal force starts
      // at 0 and rises is free at t = 0).
      bool changed = SetConditions(t, y_.data(), yp_.data(),
                                   !restart ? kAtValue : iter == 0 ? kRightLimit : kHoldAtZero);
      changed = UpdateDiscrete(t) || changed;
      if (changed && restart) SettleMixedSystem(t);
      changed = Releases(t) || changed;
      bool fired = FireWhens(t);
      if (!changed && !fired) break;
      any = true;
      state_->SavePre(y_.data());
      if (iter == 100) {
        throw SolverError("at t = " + Num(t) + ": chattering: the event iteration does not settle, the conditions switch back and forth at one instant (a sliding mode: each branch drives the relation back); " +
                          ActiveConditions() + ". Add hysteresis, or model the sliding state explicitly");
      }
    }
    return any;
  }

  /// With the pre-values fixed, solves the continuous unknowns for the new discrete values and
  /// evaluates the discrete equations again until the two agree: Modelica's mixed
  /// continuous/discrete systems. A friction element that stops decides whether it stays stuck
  /// from the force that holds it (sa while locked), not from the force of the sliding mode it
  /// just left. Gives up after 20 rounds; the event iteration goes on from there.
  void SettleMixedSystem(double t) {
    for (int round = 0; round < 20; ++round) {
      Restart(t);
      bool again = SetConditions(t, y_.data(), yp_.data(), kHoldAtZero);
      again = UpdateDiscrete(t) || again;
      if (!again) return;
    }
  }

  /// Consistent y, y' for the current discrete values and states (IDACalcIC), and IDA restarted.
  void Restart(double t) {
    if (n_ == 0) return;
    CollectStats();
    base_.steps = stats_->steps;
    base_.residual_evals = stats_->residual_evals;
    base_.jacobian_evals = stats_->jacobian_evals;
    base_.error_test_failures = stats_->error_test_failures;
    base_.nonlinear_failures = stats_->nonlinear_failures;
    ++stats_->restarts;
    void* mem = ida_.get();
    SetAlgebraicRates();
    Load(y_, yp_);
    CheckFlag(IDAReInit(mem, t, y_vec_.get(), yp_vec_.get()), "IDAReInit");
    double tout1 = std::min(opt_.stop, t + interval_);
    if (tout1 <= t) tout1 = t + std::max(1e-6, 1e-6 * std::fabs(t));
    auto calc_ic = [&](bool line_search) {
      if (restart_abstol_) CheckFlag(IDASVtolerances(mem, opt_.rtol, restart_abstol_.get()), "IDASVtolerances");
      CheckFlag(IDASetLineSearchOffIC(mem, line_search ? SUNFALSE : SUNTRUE), "IDASetLineSearchOffIC");
      return IDACalcIC(mem, IDA_YA_YDP_INIT, tout1);
    };
    int flag = calc_ic(true);
    if (flag < 0) {
      // IDACalcIC's line search can stall on a step that the plain Newton iteration takes (after
      // an impulse, where velocities and the unknowns that follow them jump): once more without.
      Load(y_, yp_);
      CheckFlag(IDAReInit(mem, t, y_vec_.get(), yp_vec_.get()), "IDAReInit");
      flag = calc_ic(false);
    }
    if (flag < 0) {
      throw SolverError("at t = " + Num(t) + ": no consistent restart after the event (IDACalcIC: " +
                        FlagName(flag) + (data_.error.empty() ? "" : ", " + data_.error) +
                        "); the discrete values or re-initialised states contradict the equations");
    }
    CheckFlag(IDAGetConsistentIC(mem, y_vec_.get(), yp_vec_.get()), "IDAGetConsistentIC");
    const double* a = N_VGetArrayPointer(y_vec_.get());
    const double* b = N_VGetArrayPointer(yp_vec_.get());
    y_.assign(a, a + n_);
    yp_.assign(b, b + n_);
    if (restart_abstol_) {
      // Back to the integration's tolerances; IDA takes them at its next (re)initialisation.
      CheckFlag(IDASVtolerances(mem, opt_.rtol, abstol_.get()), "IDASVtolerances");
    }
    // Consistent values polished, the rates of the algebraic unknowns with them (IDACalcIC
    // leaves those as they were), then IDA from there.
    SetAlgebraicRates();
    PolishConsistentValues(t);
    Load(y_, yp_);
    CheckFlag(IDAReInit(mem, t, y_vec_.get(), yp_vec_.get()), "IDAReInit");
  }

  /// Sets every frozen condition to its right-limit value at (t, y, y'); true when one changed.
  bool SetConditions(double t, const double* y, const double* yp, ZeroSide side) {
    if (nc_ == 0) return false;
    state_->ZeroCrossings(t, y, yp, z_.data());
    std::vector<double> rate(nc_, 0.0);
    if (side != kAtValue) state_->ZeroCrossingRates(t, y, yp, rate.data());
    if (side == kRightLimit) moving_at_zero_.assign(nc_, false);
    double* c = state_->mutable_conditions();
    bool changed = false;
    for (size_t i = 0; i < nc_; ++i) {
      zscale_[i] = std::max(zscale_[i], std::fabs(z_[i]));
      double zi = z_[i];
      // Within the location error of zero (the event is placed just past the crossing) the
      // relation takes the value its derivative leads to: the right limit. Without this, h < 0
      // at h = -1e-12 after a bounce would switch back an instant later: a duplicate event.
      const double near = 4 * Band(i) + std::fabs(rate[i]) * 1e-12 * std::max(1.0, std::fabs(t));
      const bool ordered = m_.conditions[i].op != Op::kEq && m_.conditions[i].op != Op::kNe;
      if (std::fabs(zi) <= near && ordered) {
        // A rate that would not carry z out of its band in a second is rounding, not motion:
        // a mass resting at its stop (s reinitialised to smax - L/2, v = -1e-26 m/s left by
        // the solve) is not sliding back off it.
        const double moving = std::fabs(rate[i]) * std::max(1.0, std::fabs(t)) > Band(i) ? rate[i] : 0.0;
        if (side == kRightLimit) moving_at_zero_[i] = moving != 0;
        if (side == kHoldAtZero && !moving_at_zero_[i]) continue;
        // At zero up to the location error or rounding: at the start (a velocity of 1e-17 m/s
        // left by the initial Newton solve) zero itself, at an event the side the rate leads to,
        // and zero itself where nothing moves (a brake engaging on a shaft at rest, whose
        // sliding velocity is -2e-43 m/s, is stuck, not sliding backward).
        // (Only within the band a crossing is measured against: beyond it, where a step's
        // crossing test already sees the relation switched, z is taken as it is.)
        if (side == kAtValue) {
          zi = 0;
        } else if (moving != 0) {
          zi = moving;
        } else if (std::fabs(zi) <= Band(i)) {
          zi = 0;
        }
      }
      double v = RelationHolds(m_.conditions[i].op, zi) ? 1.0 : 0.0;
      if (v != c[i]) changed = true;
      c[i] = v;
    }
    return changed;
  }

  bool UpdateDiscrete(double t) {
    const size_t nd = state_->num_discrete();
    if (nd == 0) return false;
    std::vector<double> before(state_->discrete(), state_->discrete() + nd);
    state_->UpdateDiscrete(t, y_.data(), yp_.data());
    return !std::equal(before.begin(), before.end(), state_->discrete());
  }

  /// Closed contacts whose release condition holds open.
  bool Releases(double t) {
    if (m_.impacts.empty()) return false;
    impact_values_.resize(5 * m_.impacts.size());
    state_->ImpactValues(t, y_.data(), yp_.data(), impact_values_.data());
    double* d = state_->mutable_discrete();
    bool changed = false;
    for (size_t k = 0; k < m_.impacts.size(); ++k) {
      if (d[m_.impacts[k].contact] != 0 && impact_values_[5 * k + 4] != 0) {
        d[m_.impacts[k].contact] = 0;
        changed = true;
      }
    }
    return changed;
  }

  /// When-clauses whose condition has become true: assignments and reinit().
  bool FireWhens(double t) {
    if (m_.whens.empty()) return false;
    std::vector<double> cond(m_.whens.size());
    state_->WhenConditions(t, y_.data(), yp_.data(), cond.data());
    std::vector<double> values;
    bool fired = false;
    for (size_t k = 0; k < m_.whens.size(); ++k) {
      bool now = cond[k] != 0;
      bool edge = now && !when_state_[k];
      when_state_[k] = now;
      if (!edge) continue;
      RunWhen(k, t, &values);
      fired = true;
    }
    return fired;
  }

  /// Executes when-clause k: its assignments and reinit(). `values` holds every statement's value,
  /// computed at the first clause that runs in this round (all read the same pre-values).
  void RunWhen(size_t k, double t, std::vector<double>* values) {
    if (values->empty()) {
      size_t count = 0;
      for (const auto& w : m_.whens) count += w.assigns.size() + w.reinits.size();
      values->resize(count);
      state_->WhenValues(t, y_.data(), yp_.data(), values->data());
    }
    double* d = state_->mutable_discrete();
    for (const auto& [disc, slot] : m_.whens[k].assigns) d[disc] = (*values)[slot];
    for (const auto& [y, slot] : m_.whens[k].reinits) y_[y] = (*values)[slot];
  }

  // -------------------------------------------------------------------------------------------
  // Impacts

  void ResolveImpacts(double t) {
    if (m_.impacts.empty()) return;
    const size_t ni = m_.impacts.size();
    for (int round = 0;; ++round) {
      impact_values_.resize(5 * ni);
      state_->ImpactValues(t, y_.data(), yp_.data(), impact_values_.data());
      double* d = state_->mutable_discrete();
      // The open contact that approaches fastest with its gap closed.
      int which = -1;
      double fastest = 0;
      for (size_t k = 0; k < ni; ++k) {
        if (d[m_.impacts[k].contact] != 0) continue;
        double gap = impact_values_[5 * k], vel = impact_values_[5 * k + 1];
        if (gap <= kGapBand && vel < -kVelocityBand && vel < fastest) {
          fastest = vel;
          which = static_cast<int>(k);
        }
      }
      if (which < 0) return;
      if (round == 10000) throw SolverError("at t = " + Num(t) + ": the impacts do not come to an end (more than 10000 in one instant)");
      const auto& im = m_.impacts[which];
      double vel = impact_values_[5 * which + 1];
      double e = impact_values_[5 * which + 2], v_small = impact_values_[5 * which + 3];
      // A plastic impact, or one slower than v_small, leaves the bodies resting together.
      bool close = -vel < v_small || e == 0;
      double dvel = close ? -vel : -(1 + e) * vel;
      ApplyImpulse(t, im, dvel);
      if (close) d[im.contact] = 1;
      if (m_.impacts_read_algebraic) Restart(t);
      ++stats_->impacts;
      stats_->impact_times.push_back(t);
    }
  }

  /// Solves [dF/dy' | dF/dz] [Δx; Λ] = b, the DAE integrated over the impact, with the impact's
  /// contact law taken in contact mode: its row is then der(velocity), whose integral is the jump
  /// of the velocity, and b asks that jump to be `dvel` (every other row is 0). Adds Δx to the
  /// states.
  void ApplyImpulse(double t, const CompiledModel::Impact& im, double dvel) {
    std::vector<double> dfdy, dfdyp;
    double* d = state_->mutable_discrete();
    const double mode = d[im.contact];
    d[im.contact] = 1;
    JacobianParts(t, &dfdy, &dfdyp);
    d[im.contact] = mode;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<int>(n_));
    b[im.mode_row] = dvel;
    MixedLu lu;
    if (!FactorMixed(dfdy, dfdyp, &lu)) {
      throw SolverError("at t = " + Num(t) + ": the impact of " + im.name +
                        " has no unique solution (the integrated equations are singular: is a body without mass in the impulse's path?)");
    }
    const Eigen::VectorXd x = lu.solve(b);
    for (size_t c = 0; c < n_; ++c) {
      if (m_.is_state[c]) y_[c] += x[static_cast<int>(c)];
    }
  }

  /// Polishes consistent values for IDA after a start or restart. First up to two Newton steps
  /// on F(t, y, y') = 0 for the states' rates and the algebraic unknowns (the states stay):
  /// IDACalcIC stops at its own tolerance, which leaves the rates of states noisy by about
  /// tolerance/step (1e-4), enough to flip a relation that sits exactly at zero after a reinit
  /// (a mass put at its stop with v = 0 would seem to move on). Then the rates of the algebraic
  /// unknowns that agree with the equations differentiated in time,
  ///   [dF/dy over the algebraic unknowns | dF/dy' over the states] [y'_alg; y''_states]
  ///     = -(dF/dt + dF/dy over the states * y'_states),
  /// with dF/dt by a central difference. IDA predicts every unknown from its rate: a zero rate
  /// for an algebraic unknown that moves (a stuck friction element's force following a sine)
  /// makes the error test fail again and again on the first step at a tight tolerance. Leaves
  /// the values as they are where the system is singular.
  void PolishConsistentValues(double t) {
    if (n_ == 0) return;
    const bool all_states = std::all_of(m_.is_state.begin(), m_.is_state.end(), [](bool s) { return s; });
    std::vector<double> f(n_);
    state_->Residual(t, y_.data(), yp_.data(), f.data());
    const auto consistent = [&f] { return std::all_of(f.begin(), f.end(), [](double r) { return r == 0; }); };
    if (all_states && consistent()) return;
    // One factorisation serves the Newton steps (a simplified Newton: the values move by about
    // the tolerance) and the rates.
    std::vector<double> dfdy, dfdyp;
    JacobianParts(t, &dfdy, &dfdyp);
    MixedLu lu;
    if (!FactorMixed(dfdy, dfdyp, &lu)) return;
    Eigen::VectorXd b(static_cast<int>(n_));
    for (int it = 0; it < 2 && !consistent(); ++it) {
      for (size_t r = 0; r < n_; ++r) b[static_cast<int>(r)] = -f[r];
      const Eigen::VectorXd x = lu.solve(b);
      if (!x.allFinite()) return;
      for (size_t c = 0; c < n_; ++c) (m_.is_state[c] ? yp_[c] : y_[c]) += x[static_cast<int>(c)];
      state_->Residual(t, y_.data(), yp_.data(), f.data());
    }
    if (all_states) return;
    const double h = 1e-6 * std::max(1.0, std::fabs(t));
    std::vector<double> ahead(n_), behind(n_);
    state_->Residual(t + h, y_.data(), yp_.data(), ahead.data());
    state_->Residual(t - h, y_.data(), yp_.data(), behind.data());
    for (size_t r = 0; r < n_; ++r) b[static_cast<int>(r)] = -(ahead[r] - behind[r]) / (2 * h);
    const SparsePattern& pat = m_.jacobian_pattern;
    for (int32_t c = 0; c < pat.cols; ++c) {
      if (!m_.is_state[c]) continue;
      for (int32_t k = pat.col_start[c]; k < pat.col_start[c + 1]; ++k) b[pat.row_index[k]] -= dfdy[k] * yp_[c];
    }
    const Eigen::VectorXd x = lu.solve(b);
    if (!x.allFinite()) return;
    for (size_t c = 0; c < n_; ++c) {
      if (!m_.is_state[c]) yp_[c] = x[static_cast<int>(c)];
    }
  }

  void JacobianParts(double t, std::vector<double>* dfdy, std::vector<double>* dfdyp) {
    dfdy->resize(m_.jacobian_pattern.nnz());
    dfdyp->resize(m_.jacobian_pattern.nnz());
    state_->JacobianParts(t, y_.data(), yp_.data(), dfdy->data(), dfdyp->data());
  }

  using MixedLu = Eigen::SparseLU<Eigen::SparseMatrix<double>>;

  /// Factors [dF/dy' over the states | dF/dy over the algebraic unknowns] (the matrix of
  /// IDACalcIC's YA_YDP_INIT step); false when it is singular.
  bool FactorMixed(const std::vector<double>& dfdy, const std::vector<double>& dfdyp, MixedLu* lu) {
    const SparsePattern& pat = m_.jacobian_pattern;
    std::vector<Eigen::Triplet<double>> triplets;
    for (int32_t c = 0; c < pat.cols; ++c) {
      for (int32_t k = pat.col_start[c]; k < pat.col_start[c + 1]; ++k) {
        double v = m_.is_state[c] ? dfdyp[k] : dfdy[k];
        if (v != 0) triplets.emplace_back(pat.row_index[k], c, v);
      }
    }
    Eigen::SparseMatrix<double> A(static_cast<int>(n_), static_cast<int>(n_));
    A.setFromTriplets(triplets.begin(), triplets.end());
    A.makeCompressed();
    lu->compute(A);
    return lu->info() == Eigen::Success;
  }

  // -------------------------------------------------------------------------------------------

  void CheckChattering(double t) {
    if (t - last_event_time_ <= 1e-10 * std::max(1.0, std::fabs(t))) {
      if (++close_events_ > kChatterLimit) {
        throw SolverError("at t = " + Num(t) + ": chattering: more than " + std::to_string(kChatterLimit) +
                          " events within 1e-10 s of each other; " + ActiveConditions() +
                          ". Smooth the switching relation, add hysteresis, or wrap it in noEvent()");
      }
    } else {
      close_events_ = 0;
    }
  }

  std::string ActiveConditions() const {
    std::string s = "the conditions involved include";
    for (size_t i = 0; i < nc_ && i < 5; ++i) s += (i ? ", " : " ") + m_.conditions[i].text;
    for (const auto& im : m_.impacts) s += ", the impact of " + im.name;
    return s;
  }

  static std::string Num(double v) {
    std::ostringstream s;
    s.precision(12);
    s << v;
    return s.str();
  }

  static constexpr double kGapBand = 1e-10;       ///< gaps within this [m] count as closed
  static constexpr double kVelocityBand = 1e-12;  ///< approach speeds below this [m/s] are none

  ModelState* state_;
  const CompiledModel& m_;
  const SimulationOptions& opt_;
  const RowCallback& row_;
  SolverStats* stats_;
  size_t n_ = 0, nc_ = 0;
  double interval_ = 0;
  long num_intervals_ = 0, next_grid_ = 1;
  bool has_events_ = false, sparse_ = false;
  double t_ = 0, last_event_time_ = -HUGE_VAL;
  double next_time_event_ = HUGE_VAL;
  bool time_events_dirty_ = true;
  int close_events_ = 0;
  std::vector<size_t> modelled_;  ///< conditions watched with a cubic model (see Modelled)
  Sample sample_;       ///< the crossing functions at the end of the last step
  Sample next_sample_;  ///< at the next sample time (kept to reuse its storage)
  bool sample_valid_ = false;
  int refinements_left_ = 0;
  std::vector<double> y_, yp_, z_, zscale_, outputs_, impact_values_;
  /// Per condition: at zero with a nonzero rate in the first round of the last event.
  std::vector<bool> moving_at_zero_;
  /// (y index of an algebraic unknown, y index of the dummy derivative that is its rate).
  std::vector<std::pair<uint32_t, uint32_t>> rate_of_algebraic_;
  std::vector<bool> when_state_, affine_;
  SolverStats base_;
  std::chrono::steady_clock::time_point t_run_;
  ContextPtr ctx_;
  VectorPtr y_vec_, yp_vec_, id_, dky_, dkyp_, abstol_;
  VectorPtr restart_abstol_;  ///< abstol_ with dummy derivatives tested (null when none is untested)
  LinearSystem ls_;
  IdaData data_{nullptr, {}, {}, {}};
  std::unique_ptr<void, IdaDeleter> ida_;
};

}  // namespace

SimulationOptions OptionsFromExperiment(const ExperimentSpec& e) {
  SimulationOptions o;
  o.start = e.start;
  o.stop = e.stop;
  o.interval = e.interval;
  o.rtol = e.tolerance;
  o.linear_solver = e.linear_solver;
  o.max_order = e.max_order;
  return o;
}

void Simulate(ModelState* state, const SimulationOptions& options, const RowCallback& row,
              SolverStats* stats) {
  EventIntegrator(state, options, row, stats).Run();
}

}  // namespace momenta
