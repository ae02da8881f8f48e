#pragma once
/// The stages of CompileModel (core/compile/ only), in the order it runs them: each fills its
/// part of the CompiledModel from the equation system, and the CompileContext carries what one
/// stage hands a later one (where each variable lives, the zero-crossing functions, the initial
/// Jacobian's first rows). The programs are compiled in one fixed order over one ProgramCompiler,
/// which numbers registers as it goes: the order is part of the compiled model (and of the native
/// code's cache key), so the stages keep it.
///
///   CompileUnknowns            y (declaration order, each with its matched equation), states,
///                              discrete variables apart
///   CompileInitialSystem       discrete starts, initial equations G, guards; redundant initial
///                              conditions left out, missing ones completed by start values
///   CollectConditions          event relations -> frozen conditions and crossing functions
///   CompileResidualAndJacobian F and dF/dy + cj dF/dy'
///   CompileInitialization      [F; G] and its Jacobian
///   CompileOutputs, CompileStartValues, CompileGuards
///   CompileDiscrete            discrete starts and equations
///   CompileZeroCrossings       z and dz/dt
///   CompileWhens, CompileImpacts

#include <cstdint>
#include <vector>

#include "core/compile/compiled_model.h"
#include "core/compile/program.h"
#include "core/passes/equation_system.h"
#include "core/passes/structural_analysis.h"

namespace momenta {

/// Where each flat variable lives at run time.
struct VariableSlots {
  std::vector<int32_t> y_of_var;     ///< flat variable -> y index, -1 if none
  std::vector<int32_t> disc_of_var;  ///< flat variable -> discrete index, -1 if continuous
  std::vector<int32_t> state_of_y;   ///< y index -> state slot, -1 if algebraic
};

/// One structural nonzero of a Jacobian: row, column and the partial derivative's expression.
struct JacobianEntry {
  int32_t row, col;
  ExprId value;
  /// A y' partial (cj dF/dy'): at the same (row, col) it comes after the y partial, so that the
  /// merged entry has the same form in every component (a loop body, core/compile/reroll.h).
  bool der = false;
};

/// What the stages hand each other besides the CompiledModel.
struct CompileContext {
  VariableSlots slots;
  /// The flat equation behind each residual row (SystemEquation::origin), for the impacts.
  std::vector<uint32_t> residual_source;
  /// Each discrete variable's value before the first event: its start value, or the value an
  /// initial equation `pre(d) = expr` gives it.
  std::vector<ExprId> discrete_start;
  /// Per condition: its zero-crossing function z and dz/dt (0 where it has no rate).
  std::vector<ExprId> zero_crossings, zero_crossing_rates;
  /// The initialisation Jacobian's entries of the rows F, found with the DAE's Jacobian (the same
  /// partials); CompileInitialization adds the rows G.
  std::vector<JacobianEntry> init_entries;
};

// ---- compile.cc: unknowns, initial system, residual, Jacobians, outputs, starts -----------------

void CompileUnknowns(const EquationSystem& sys, const Structure& structure, CompileContext* ctx,
                     CompiledModel* m);
void CompileInitialSystem(const EquationSystem& sys, CompileContext* ctx, CompiledModel* m);
void CompileResidualAndJacobian(CompileContext* ctx, ProgramCompiler* compiler, CompiledModel* m);
void CompileInitialization(CompileContext* ctx, ProgramCompiler* compiler, CompiledModel* m);
void CompileOutputs(ProgramCompiler* compiler, CompiledModel* m);
void CompileStartValues(const EquationSystem& sys, const CompileContext& ctx,
                        ProgramCompiler* compiler, CompiledModel* m);
void CompileGuards(ProgramCompiler* compiler, CompiledModel* m);

// ---- compile_events.cc: conditions, discrete equations, when-clauses, impacts -------------------

/// Finds the event relations in everything that is evaluated, makes each a condition of `m` with
/// its crossing function in `ctx`, and replaces the relations by their condition leaves: in
/// `m`'s expressions and in the system's discrete equations, when-clauses and impacts, which it
/// therefore rewrites (the one stage that changes `sys`).
void CollectConditions(EquationSystem* sys, CompileContext* ctx, CompiledModel* m);
void CompileDiscrete(const EquationSystem& sys, const CompileContext& ctx,
                     ProgramCompiler* compiler, CompiledModel* m);
void CompileZeroCrossings(const CompileContext& ctx, ProgramCompiler* compiler, CompiledModel* m);
void CompileWhens(const EquationSystem& sys, const CompileContext& ctx, ProgramCompiler* compiler,
                  CompiledModel* m);
void CompileImpacts(const EquationSystem& sys, const CompileContext& ctx, ProgramCompiler* compiler,
                    CompiledModel* m);

}  // namespace momenta
