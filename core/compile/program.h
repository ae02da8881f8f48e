#pragma once
/// Compiled evaluation: a straight-line register program, run without walking expression trees.
/// One register file holds time, cj, constants, parameters, parameter-only subexpressions
/// (computed once per parameter set: parameter folding), y, y', pre-values and temporaries; each
/// compiled function (residual, Jacobian, outputs, initialisation) is a sequence of instructions
/// that read registers and store results into an output array. Temporaries are reused as soon as
/// their last reader has run, so a program's working set stays small however large the model.

#include <cstdint>
#include <functional>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

struct Instruction {
  uint8_t op;  ///< an Op, or kStore
  uint32_t dst, a, b, c;
};

/// out[dst] = regs[a]
constexpr uint8_t kStore = 255;
/// regs[dst] = regs[a] (results that later instructions read, e.g. discrete values in order)
constexpr uint8_t kStoreRegister = 254;

/// The shape of a table an interpolation reads (Op::kTable): its instruction's c indexes these.
struct TableShape {
  uint32_t rows, cols, column;
};

/// Runs `n` instructions from `code` on the registers (what Program::Run does for its code):
/// for evaluators that hold instructions elsewhere (rerolled loops, core/compile/reroll.h).
void RunInstructions(const Instruction* code, size_t n, const TableShape* tables, double* regs, double* out);

class Program {
 public:
  void Run(double* regs, double* out) const;
  /// Registers the shape of the kTable leaf `table` for an interpolation instruction's c.
  uint32_t AddTable(const Node& table);
  size_t size() const { return code_.size(); }
  std::vector<Instruction>& code() { return code_; }
  const std::vector<Instruction>& code() const { return code_; }
  /// The table shapes interpolation instructions index by their c.
  const std::vector<TableShape>& tables() const { return tables_; }

 private:
  std::vector<Instruction> code_;
  std::vector<TableShape> tables_;
};

/// Registers every compiled function of a model shares: time, cj, the initialisation flag,
/// parameters, y, y', discrete values, pre-values (of y, then of the discrete values), event
/// conditions, constants and parameter-only subexpressions, then temporaries.
struct RegisterLayout {
  static constexpr uint32_t kTime = 0, kCj = 1, kInitial = 2;
  uint32_t param_base = 0, y_base = 0, yp_base = 0, disc_base = 0, pre_base = 0, cond_base = 0;
  uint32_t temp_base = 0, size = 0;
  uint32_t num_params = 0, num_unknowns = 0, num_discrete = 0, num_conditions = 0;
};

/// A zero-filled array of 32-bit values by expression node id, for the few per-node arrays sized
/// to a pool of millions of nodes: it is mapped on its own, so a new element is zero without a
/// write (the kernel gives zeroed pages, only those an id reaches), and growing it with the pool
/// moves page tables (mremap) instead of copying, so the old and the new array never both take
/// memory.
class NodeArray {
 public:
  NodeArray() = default;
  NodeArray(const NodeArray&) = delete;
  NodeArray& operator=(const NodeArray&) = delete;
  ~NodeArray();
  /// Room for ids below `n`; new elements are 0.
  void Grow(size_t n);
  /// Unmaps the array; it is empty afterwards.
  void Release();
  size_t size() const { return size_; }
  uint32_t& operator[](size_t k) { return data_[k]; }
  uint32_t operator[](size_t k) const { return data_[k]; }

 private:
  uint32_t* data_ = nullptr;
  size_t size_ = 0;  ///< elements mapped
};

/// Turns expression DAGs into Programs. Leaves map to fixed registers: kVar(v) -> y or the
/// discrete values, kDer(v) -> y', kPre(v) -> pre, kCond(r) -> conditions, through `y_index` and
/// `disc_index` (flat variable -> position, or -1).
class ProgramCompiler {
 public:
  ProgramCompiler(const ExprPool& pool, uint32_t num_params, std::vector<int32_t> y_index,
                  std::vector<int32_t> disc_index, uint32_t num_conditions);

  /// A program that stores roots[k] into out[k] in its turn, right after the code for roots[k]
  /// (a value several roots share is computed once and stored in each one's turn), or, with
  /// `registers`, into regs[registers[k]] as soon as it is computed (so later roots read it).
  /// Temporaries are taken lowest free first and the operands of + and * are ordered by kind
  /// and age, not by node id, so that runs of like components give like instruction blocks
  /// (core/compile/reroll.h).
  Program Compile(const std::vector<ExprId>& roots, const std::vector<uint32_t>* registers = nullptr);
  /// Finalises the layout (after every Compile): temporaries go after the global registers.
  /// Gives back Compile's scratch first (no Compile may follow), which holds a few bytes per
  /// pool node at the build's memory peak.
  void Finish(std::vector<Program*> programs);

  const RegisterLayout& layout() const { return layout_; }
  Program& parameter_program() { return params_; }
  /// (register, value) of every constant.
  const std::vector<std::pair<uint32_t, double>>& constants() const { return constants_; }

 private:
  uint32_t Global();
  /// The register of node `id`, or 0 when it has none yet.
  uint32_t Global(uint32_t id) const;
  uint32_t LeafRegister(ExprId e);
  uint32_t ParamOnlyRegister(ExprId e);
  void GrowNodeSlots();
  /// Whether the programs compute node `id` (not a leaf, constant or parameter-only value,
  /// which have registers of their own).
  bool Computed(uint32_t id) const;
  void EmitParamOnly(ExprId root);

  const ExprPool& pool_;
  std::vector<int32_t> y_index_, disc_index_;
  RegisterLayout layout_;
  uint32_t next_global_;
  std::vector<std::pair<uint32_t, double>> constants_;
  Program params_;
  std::vector<uint32_t> param_stack_;  ///< EmitParamOnly's scratch
  uint32_t max_temps_ = 0;
  /// Compile()'s number of the computed node `id` in this call, visiting it if new (see Compile).
  uint32_t Visit(uint32_t id);
  /// Compile()'s first step: the nodes the program computes, children first, into order_, each
  /// with its count of readers; after each root a marker (its index with kTempFlag).
  void OrderNodes(const std::vector<ExprId>& roots);
  /// Compile()'s second step, node by node in order_ (program.cc).
  struct Emission;
  /// The register an operand is read from: a temporary for a computed value, else its global
  /// register (a parameter-only value emitted into the parameter program first).
  uint32_t OperandRegister(uint32_t child);
  /// One reader of `child` has run: its temporary is freed after the last.
  void Release(uint32_t child, Emission* emission);
  /// The instruction of the computed node numbered `q`, into the lowest free temporary.
  void EmitNode(uint32_t q, Emission* emission);
  /// The end of root k's turn: its value stored.
  void EndRootTurn(uint32_t k, const std::vector<ExprId>& roots, Emission* emission);
  // Compile()'s scratch, reused across calls (see Compile).
  struct Local {
    uint32_t uses;   ///< readers not yet emitted
    uint32_t reg;    ///< temporary holding the value
    uint8_t state;   ///< 0 unvisited, 1 children pushed, 2 ordered
  };
  /// By node id: for a node the programs compute, its number in this Compile() call if visited_
  /// agrees; for any other, its global register (0: none yet). One array for both, where two
  /// took 4 bytes per pool node each at the build's memory peak.
  NodeArray node_slot_;
  std::vector<uint32_t> visited_;   ///< by number: node id
  std::vector<Local> local_;        ///< by number
  std::vector<uint32_t> order_, stack_;  ///< Compile's walk: reused, so grown once
};

/// The flag marking a temporary register before Finish() places them.
constexpr uint32_t kTempFlag = 0x80000000u;

}  // namespace momenta
