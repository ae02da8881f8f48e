#pragma once
/// A model ready to simulate: the DAE F(t, y, y') = 0 for IDA, its sparse Jacobian, the
/// initialisation system, the outputs, all as compiled programs over one register layout. It is
/// immutable after building; everything that changes during a run (time, y, y', parameter values)
/// lives in a ModelState.

#include <memory>
#include <string>
#include <vector>

#include "core/passes/equation_system.h"
#include "core/flatten/flat_system.h"
#include "core/compile/program.h"

namespace momenta {

class NativeCode;

/// A sparse matrix pattern in compressed-column form (what KLU takes).
struct SparsePattern {
  int32_t rows = 0, cols = 0;
  std::vector<int32_t> col_start{0};
  std::vector<int32_t> row_index;
  size_t nnz() const { return row_index.size(); }
};

struct CompiledModel {
  std::shared_ptr<const FlatSystem> flat;
  std::shared_ptr<ExprPool> pool;

  // The DAE: unknowns y (IDA's vector), with y' for the states.
  std::vector<VarId> unknowns;
  std::vector<bool> is_state;                ///< by y index
  std::vector<double> nominal;               ///< by y index, for absolute tolerances
  std::vector<uint32_t> state_y;             ///< y index of each state
  std::vector<ExprId> residual_exprs;        ///< F, one per y index (the matched equation)
  /// The equation behind each residual (its origin in `flat`).
  std::vector<SystemEquation> residual_equations;
  /// The user's equation behind residual `row`, in words (made when asked: a string a row would
  /// be a tenth of a large model's memory).
  std::string residual_origin(size_t row) const { return DescribeSystemEquation(*flat, residual_equations[row]); }
  size_t num_states() const { return state_y.size(); }
  size_t num_unknowns() const { return unknowns.size(); }

  // Outputs.
  std::vector<std::string> output_names;
  std::vector<ExprId> output_exprs;

  // Initialisation: unknowns z = [y; y' of the states]; equations [F; G].
  std::vector<ExprId> initial_exprs;          ///< G
  std::vector<std::string> initial_origin;
  std::vector<std::string> defaulted_starts;  ///< states whose start value was taken as fixed
  /// Initial conditions left out as redundant (initial_conditions.h), checked at the solution:
  /// each one's residual, description and what it follows from (one item a line).
  std::vector<ExprId> redundant_exprs;
  std::vector<std::string> redundant_origin, redundant_from;

  // Parameter-dependent checks: divisors that must not be zero.
  std::vector<DivisorGuard> guards;
  /// Guard k's divisor as text, made for its message only (the RC ladder made 500 000 of them).
  std::string guard_text(size_t k) const;

  // Discrete variables: constant between events, updated by event iteration.
  std::vector<VarId> discrete_vars;
  Program discrete_starts;  ///< out: their values before the first event (pre-values at start)
  Program discrete_update;  ///< stores every discrete equation's value into its register, in order
  std::vector<std::pair<VarId, ExprId>> discrete_equations;  ///< var = value, for `check -v`

  // Event conditions: each relation that may switch during integration is frozen in a register
  // between events; its zero-crossing function z (a - b of the relation a op b) is monitored.
  struct Condition {
    Op op;
    bool time_only;  ///< depends on time, parameters and discrete values only: a time event
    std::string text;
    bool has_rate = true;  ///< dz/dt is known (z contains no der(): zero_crossing_rates has it)
  };
  std::vector<Condition> conditions;
  Program zero_crossings;       ///< out: z (one per condition)
  Program zero_crossing_rates;  ///< out: dz/dt = dz/dy y' + dz/dt (0 where !has_rate)

  // When-clauses: value slots index when_values' outputs.
  struct When {
    std::string text;
    std::vector<std::pair<uint32_t, uint32_t>> assigns;  ///< discrete index, value slot
    std::vector<std::pair<uint32_t, uint32_t>> reinits;  ///< y index, value slot
  };
  std::vector<When> whens;
  Program when_conditions;  ///< out: one per when-clause
  Program when_values;      ///< out: every statement's value

  // Impacts.
  struct Impact {
    std::string name;
    /// The contact law `0 = if contact then der(velocity) else force`: in contact mode, the
    /// row of der(velocity) that carries Newton's law at an impact.
    uint32_t mode_row = 0;
    uint32_t contact = 0;  ///< discrete index of the contact mode
  };
  std::vector<Impact> impacts;
  Program impact_values;  ///< out: per impact gap, velocity, restitution, v_small, release
  /// Some gap or velocity reads an algebraic unknown or a derivative (a contact through index
  /// reduction): after an impulse y and y' are made consistent before the contacts are looked at
  /// again.
  bool impacts_read_algebraic = false;

  // Compiled programs.
  RegisterLayout layout;
  std::vector<std::pair<uint32_t, double>> constants;
  Program parameters;    ///< parameter-only subexpressions
  Program residual;      ///< out: F (n)
  Program jacobian;      ///< out: dF/dy + cj dF/dy' in `jacobian_pattern` order
  SparsePattern jacobian_pattern;
  Program outputs;       ///< out: outputs
  Program start_values;  ///< out: guesses for y (n)
  /// out: guesses for y from the equations that determine them explicitly (n): initialisation
  /// starts over from these when the start values fail
  Program start_guesses;
  Program init_residual; ///< out: [F; G]
  Program init_jacobian; ///< out: d[F; G]/dz in `init_pattern` order
  Program redundant_residual;  ///< out: the redundant initial conditions' residuals at z
  SparsePattern init_pattern;
  Program guard_values;  ///< out: the divisors

  ExperimentSpec experiment;

  /// The programs above as native code (core/compile/native_code.h), or null: the interpreter runs them.
  /// Shared by every ModelState and thread; it unloads with its last owner.
  std::shared_ptr<const NativeCode> native;
};

}  // namespace momenta
