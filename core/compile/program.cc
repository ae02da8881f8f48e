#include "core/compile/program.h"

#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <unordered_map>

#include "core/base/error.h"
#include "core/expr/expr_eval.h"

namespace momenta {

void Program::Run(double* r, double* out) const {
  RunInstructions(code_.data(), code_.size(), tables_.data(), r, out);
}

void RunInstructions(const Instruction* code, size_t n, const TableShape* tables, double* r, double* out) {
  for (const Instruction* end = code + n; code != end; ++code) {
    const Instruction& in = *code;
    double v;
    switch (static_cast<Op>(in.op)) {
      case Op::kAdd: v = r[in.a] + r[in.b]; break;
      case Op::kSub: v = r[in.a] - r[in.b]; break;
      case Op::kMul: v = r[in.a] * r[in.b]; break;
      case Op::kDiv: v = r[in.a] / r[in.b]; break;
      case Op::kNeg: v = -r[in.a]; break;
      case Op::kPow: v = PowValue(r[in.a], r[in.b]); break;
      case Op::kIf: v = r[in.a] != 0 ? r[in.b] : r[in.c]; break;
      case Op::kSin: v = std::sin(r[in.a]); break;
      case Op::kCos: v = std::cos(r[in.a]); break;
      case Op::kExp: v = std::exp(r[in.a]); break;
      case Op::kSqrt: v = std::sqrt(r[in.a]); break;
      case Op::kInterp:
      case Op::kInterpSlope: {
        // b is the register of the table's element [1,1]: the parameters as they are now.
        const TableShape& t = tables[in.c];
        v = InterpolateTable(r + in.b, t.rows, t.cols, t.column, r[in.a], in.op == static_cast<uint8_t>(Op::kInterpSlope));
        break;
      }
      case Op::kAtan2:
      case Op::kMin:
      case Op::kMax:
      case Op::kLt:
      case Op::kLe:
      case Op::kGt:
      case Op::kGe:
      case Op::kEq:
      case Op::kNe:
      case Op::kAnd:
      case Op::kOr:
        v = ApplyBinary(static_cast<Op>(in.op), r[in.a], r[in.b]);
        break;
      default:
        if (in.op == kStore) {
          out[in.dst] = r[in.a];
          continue;
        }
        if (in.op == kStoreRegister) {
          r[in.dst] = r[in.a];
          continue;
        }
        v = ApplyUnary(static_cast<Op>(in.op), r[in.a]);
        break;
    }
    r[in.dst] = v;
  }
}

uint32_t Program::AddTable(const Node& table) {
  MOMENTA_CHECK(table.op == Op::kTable);
  TableShape shape{table.b, table.TableColumns(), table.TableColumn()};
  for (size_t k = 0; k < tables_.size(); ++k) {
    if (tables_[k].rows == shape.rows && tables_[k].cols == shape.cols && tables_[k].column == shape.column) {
      return static_cast<uint32_t>(k);
    }
  }
  tables_.push_back(shape);
  return static_cast<uint32_t>(tables_.size() - 1);
}

ProgramCompiler::ProgramCompiler(const ExprPool& pool, uint32_t num_params,
                                 std::vector<int32_t> y_index, std::vector<int32_t> disc_index,
                                 uint32_t num_conditions)
    : pool_(pool), y_index_(std::move(y_index)), disc_index_(std::move(disc_index)) {
  uint32_t n = 0, nd = 0;
  for (int32_t i : y_index_) n = std::max<uint32_t>(n, static_cast<uint32_t>(i + 1));
  for (int32_t i : disc_index_) nd = std::max<uint32_t>(nd, static_cast<uint32_t>(i + 1));
  layout_.num_params = num_params;
  layout_.num_unknowns = n;
  layout_.num_discrete = nd;
  layout_.num_conditions = num_conditions;
  layout_.param_base = 3;
  layout_.y_base = layout_.param_base + num_params;
  layout_.yp_base = layout_.y_base + n;
  layout_.disc_base = layout_.yp_base + n;
  layout_.pre_base = layout_.disc_base + nd;
  layout_.cond_base = layout_.pre_base + n + nd;
  next_global_ = layout_.cond_base + num_conditions;
}

uint32_t ProgramCompiler::Global() { return next_global_++; }

uint32_t ProgramCompiler::LeafRegister(ExprId e) {
  const Node& n = pool_.node(e);
  switch (n.op) {
    case Op::kTime: return RegisterLayout::kTime;
    case Op::kInitial: return RegisterLayout::kInitial;
    case Op::kCj: return RegisterLayout::kCj;
    case Op::kParam: return layout_.param_base + n.a;
    case Op::kTable: return layout_.param_base + n.a;  // its element [1,1]; the rest follow
    case Op::kCond:
      MOMENTA_CHECK(n.a < layout_.num_conditions);
      return layout_.cond_base + n.a;
    case Op::kVar:
    case Op::kDer:
    case Op::kPre: {
      int32_t i = n.a < y_index_.size() ? y_index_[n.a] : -1;
      int32_t d = n.a < disc_index_.size() ? disc_index_[n.a] : -1;
      MOMENTA_CHECK_MSG(i >= 0 || (d >= 0 && n.op != Op::kDer),
                        "a compiled expression refers to an eliminated variable");
      if (n.op == Op::kVar) return i >= 0 ? layout_.y_base + i : layout_.disc_base + d;
      if (n.op == Op::kDer) return layout_.yp_base + i;
      return i >= 0 ? layout_.pre_base + i : layout_.pre_base + layout_.num_unknowns + d;
    }
    default:
      MOMENTA_CHECK(false);
  }
  return 0;
}

NodeArray::~NodeArray() { Release(); }

void NodeArray::Release() {
  if (data_) munmap(data_, size_ * sizeof(uint32_t));
  data_ = nullptr;
  size_ = 0;
}

void NodeArray::Grow(size_t n) {
  if (n <= size_) return;
  // Whole pages, and at least an eighth more: the Jacobian adds nodes between the programs.
  constexpr size_t kPage = 4096;
  const size_t bytes = ((std::max(n, size_ + size_ / 8) * sizeof(uint32_t)) + kPage - 1) / kPage * kPage;
  void* p = data_ ? mremap(data_, size_ * sizeof(uint32_t), bytes, MREMAP_MAYMOVE)
                  : mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  data_ = static_cast<uint32_t*>(p);
  size_ = bytes / sizeof(uint32_t);
}

void ProgramCompiler::GrowNodeSlots() { node_slot_.Grow(pool_.size()); }

uint32_t ProgramCompiler::Global(uint32_t id) const { return id < node_slot_.size() ? node_slot_[id] : 0; }

bool ProgramCompiler::Computed(uint32_t id) const {
  const Node& n = pool_.node(ExprId(id));
  return !IsLeaf(n.op) && n.op != Op::kConst && !pool_.IsParamOnly(ExprId(id));
}

uint32_t ProgramCompiler::ParamOnlyRegister(ExprId e) {
  if (node_slot_.size() <= e.value()) GrowNodeSlots();
  if (node_slot_[e.value()]) return node_slot_[e.value()];
  if (pool_.IsConst(e)) {
    uint32_t r = Global();
    constants_.emplace_back(r, pool_.ConstValue(e));
    node_slot_[e.value()] = r;
    return r;
  }
  EmitParamOnly(e);
  return node_slot_[e.value()];
}

/// Parameter-only subexpressions go to the parameter program, each into its own register.
void ProgramCompiler::EmitParamOnly(ExprId root) {
  std::vector<uint32_t>& stack = param_stack_;  // scratch: one allocation for every call
  stack.assign(1, root.value());
  while (!stack.empty()) {
    uint32_t id = stack.back();
    if (node_slot_.size() <= id) GrowNodeSlots();
    if (node_slot_[id]) {
      stack.pop_back();
      continue;
    }
    const Node& n = pool_.node(ExprId(id));
    if (n.op == Op::kConst) {
      ParamOnlyRegister(ExprId(id));
      stack.pop_back();
      continue;
    }
    if (IsLeaf(n.op)) {
      node_slot_[id] = LeafRegister(ExprId(id));
      stack.pop_back();
      continue;
    }
    // The operands' registers, looked up once each; an operand without one yet is emitted first
    // (constants get theirs at once, in operand order).
    const int arity = Arity(n.op);
    const uint32_t kids[3] = {n.a, n.b, n.c};
    uint32_t regs[3] = {0, 0, 0};
    bool ready = true;
    for (int j = 0; j < arity; ++j) {
      if (pool_.IsConst(ExprId(kids[j]))) {
        regs[j] = ParamOnlyRegister(ExprId(kids[j]));
      } else if ((regs[j] = Global(kids[j])) == 0) {
        stack.push_back(kids[j]);
        ready = false;
      }
    }
    if (!ready) continue;
    stack.pop_back();
    uint32_t dst = Global();
    params_.code().push_back({static_cast<uint8_t>(n.op), dst, regs[0], regs[1], regs[2]});
    if (n.op == Op::kInterp || n.op == Op::kInterpSlope) {
      params_.code().back().c = params_.AddTable(pool_.node(ExprId(n.b)));
    }
    node_slot_[id] = dst;
  }
}

uint32_t ProgramCompiler::Visit(uint32_t id) {
  const uint32_t k = node_slot_[id];
  if (k < visited_.size() && visited_[k] == id) return k;
  node_slot_[id] = static_cast<uint32_t>(visited_.size());
  visited_.push_back(id);
  local_.push_back({0, 0, 0});
  return static_cast<uint32_t>(visited_.size() - 1);
}

/// Compile()'s second step: the program being emitted and the temporaries' bookkeeping.
struct ProgramCompiler::Emission {
  explicit Emission(const std::vector<uint32_t>* registers) : registers(registers) {}

  /// Root k's value (register `src`) stored into out[k], or into its register.
  void Store(uint32_t k, uint32_t src) {
    if (registers) {
      prog.code().push_back({kStoreRegister, (*registers)[k], src, 0, 0});
    } else {
      prog.code().push_back({kStore, k, src, 0, 0});
    }
  }
  /// A temporary whose last reader has run.
  void Free(uint32_t reg) {
    free_regs.push_back(reg);
    std::push_heap(free_regs.begin(), free_regs.end(), std::greater<uint32_t>());
  }
  /// The lowest free temporary, or a new one.
  uint32_t TakeTemporary() {
    if (free_regs.empty()) return num_temps++;
    std::pop_heap(free_regs.begin(), free_regs.end(), std::greater<uint32_t>());
    const uint32_t reg = free_regs.back();
    free_regs.pop_back();
    return reg;
  }

  Program prog;
  const std::vector<uint32_t>* registers;
  std::vector<uint32_t> free_regs;  ///< a min-heap
  uint32_t num_temps = 0;
  /// Per temporary: the instruction that wrote its value (the value a live register holds).
  std::vector<uint32_t> written_at;
  /// Into registers: the roots of each computed value, stored as soon as it is computed.
  std::unordered_map<uint32_t, std::vector<uint32_t>> root_slots;
};

Program ProgramCompiler::Compile(const std::vector<ExprId>& roots, const std::vector<uint32_t>* registers) {
  // Per-node scratch (remaining readers, temporary register, visit state) for the nodes this call
  // computes, numbered in visit order: node_slot_ (by node id, never cleared) finds a node's
  // number, which is valid when visited_ has the node at that place (a sparse set), so nothing
  // needs clearing and the scratch is as large as the program, not as the pool. The nodes the
  // program does not compute (leaves, constants, parameter-only values) are not numbered: their
  // slot holds their global register instead.
  if (node_slot_.size() < pool_.size()) GrowNodeSlots();
  visited_.clear();
  local_.clear();
  OrderNodes(roots);
  // 2. Emit, reusing a temporary as soon as its last reader has run, the lowest free one first
  //    (last-freed first would rotate the registers of values carried from one component to the
  //    next irregularly); roots are stored in their turns (into registers: when computed).
  // One instruction per computed node and one store per root: the program's size, known now,
  // reserved exactly (grown by doubling, the programs held up to twice their size at the build's
  // memory peak, and copied on the way).
  Emission emission(registers);
  emission.prog.code().reserve(order_.size());
  for (size_t k = 0; registers && k < roots.size(); ++k) {
    if (Computed(roots[k].value())) {
      emission.root_slots[roots[k].value()].push_back(static_cast<uint32_t>(k));
    }
  }
  for (uint32_t q : order_) {
    if (q & kTempFlag) {
      EndRootTurn(q & ~kTempFlag, roots, &emission);
    } else {
      EmitNode(q, &emission);
    }
  }
  max_temps_ = std::max(max_temps_, emission.num_temps);
  return std::move(emission.prog);
}

void ProgramCompiler::OrderNodes(const std::vector<ExprId>& roots) {
  // 1. The nodes this program computes, children first, and how often each is read; after each
  //    root, a marker (its index with kTempFlag): the root is stored in its turn.
  std::vector<uint32_t>& order = order_;
  order.clear();
  std::vector<uint32_t>& stack = stack_;
  stack.clear();
  for (size_t k = 0; k < roots.size(); ++k) {
    const uint32_t root = roots[k].value();
    if (Computed(root)) {
      const uint32_t r = Visit(root);
      ++local_[r].uses;
      stack.push_back(r);
    }
    while (!stack.empty()) {
      const uint32_t q = stack.back();
      if (local_[q].state == 2) {
        stack.pop_back();
        continue;
      }
      if (local_[q].state == 0) {
        local_[q].state = 1;
        const Node& n = pool_.node(ExprId(visited_[q]));
        int arity = Arity(n.op);
        uint32_t kids[3] = {n.a, n.b, n.c};
        for (int j = arity - 1; j >= 0; --j) {
          if (!Computed(kids[j])) continue;
          const uint32_t kid = Visit(kids[j]);
          ++local_[kid].uses;
          if (local_[kid].state == 0) stack.push_back(kid);
        }
        continue;
      }
      local_[q].state = 2;
      stack.pop_back();
      order.push_back(q);
    }
    order.push_back(kTempFlag | static_cast<uint32_t>(k));
  }
}

uint32_t ProgramCompiler::OperandRegister(uint32_t child) {
  if (Computed(child)) return kTempFlag | local_[Visit(child)].reg;
  const Node& n = pool_.node(ExprId(child));
  if (n.op != Op::kConst && IsLeaf(n.op)) return LeafRegister(ExprId(child));
  return ParamOnlyRegister(ExprId(child));
}

void ProgramCompiler::EndRootTurn(uint32_t k, const std::vector<ExprId>& roots,
                                  Emission* emission) {
  // A root's turn is over: it is stored here (into out), also when an earlier root computed it,
  // so that the code of like components stays alike (loop rerolling, core/compile/reroll.h).
  const uint32_t root = roots[k].value();
  if (!Computed(root)) {
    emission->Store(k, OperandRegister(root));
  } else if (!emission->registers) {
    emission->Store(k, kTempFlag | local_[Visit(root)].reg);
    Release(root, emission);
  }
}

void ProgramCompiler::Release(uint32_t child, Emission* emission) {
  if (!Computed(child)) return;
  Local& s = local_[Visit(child)];
  if (--s.uses == 0) emission->Free(s.reg);
}

void ProgramCompiler::EmitNode(uint32_t q, Emission* emission) {
  constexpr uint32_t kNotComputed = ~0u;
  const uint32_t id = visited_[q];
  const Node& n = pool_.node(ExprId(id));
  const int arity = Arity(n.op);
  // The operands' registers, in operand order (a parameter-only operand may be emitted into
  // the parameter program here), and for a computed one its number: looked up once each.
  const uint32_t kids[3] = {n.a, n.b, n.c};
  uint32_t regs[3] = {0, 0, 0};
  uint32_t kid_number[3] = {kNotComputed, kNotComputed, kNotComputed};
  for (int j = 0; j < arity; ++j) {
    if (Computed(kids[j])) {
      kid_number[j] = Visit(kids[j]);
      regs[j] = kTempFlag | local_[kid_number[j]].reg;
    } else {
      regs[j] = OperandRegister(kids[j]);
    }
  }
  Instruction in{static_cast<uint8_t>(n.op), 0, regs[0], regs[1], regs[2]};
  // Operands of + and * in an order that does not depend on node ids (which follow the order
  // the expressions were made in): inputs first by register, then computed values oldest
  // first, so that like components give like code (loop rerolling, core/compile/reroll.h). Both are
  // commutative in IEEE arithmetic: the value is the same bit for bit.
  const std::vector<uint32_t>& written_at = emission->written_at;
  auto operand_order = [&](int j) -> uint64_t {
    return kid_number[j] != kNotComputed ? (uint64_t{1} << 32) | written_at[local_[kid_number[j]].reg] : regs[j];
  };
  if ((n.op == Op::kAdd || n.op == Op::kMul) && operand_order(1) < operand_order(0)) std::swap(in.a, in.b);
  if (n.op == Op::kInterp || n.op == Op::kInterpSlope) {
    in.c = emission->prog.AddTable(pool_.node(ExprId(n.b)));
  }
  for (int j = 0; j < arity; ++j) {
    if (kid_number[j] == kNotComputed) continue;
    Local& s = local_[kid_number[j]];
    if (--s.uses == 0) emission->Free(s.reg);
  }
  const uint32_t dst = emission->TakeTemporary();
  local_[q].reg = dst;
  if (emission->written_at.size() <= dst) emission->written_at.resize(dst + 1);
  emission->written_at[dst] = static_cast<uint32_t>(emission->prog.code().size());
  in.dst = kTempFlag | dst;
  emission->prog.code().push_back(in);
  // Into registers, every root of this value is stored at once (later roots read them).
  auto slots = emission->registers ? emission->root_slots.find(id) : emission->root_slots.end();
  if (slots != emission->root_slots.end()) {
    for (uint32_t k : slots->second) {
      emission->Store(k, kTempFlag | dst);
      Release(id, emission);
    }
  }
}

void ProgramCompiler::Finish(std::vector<Program*> programs) {
  node_slot_.Release();
  std::vector<uint32_t>().swap(visited_);
  std::vector<Local>().swap(local_);
  std::vector<uint32_t>().swap(order_);
  std::vector<uint32_t>().swap(stack_);
  std::vector<uint32_t>().swap(param_stack_);
  layout_.temp_base = next_global_;
  layout_.size = next_global_ + max_temps_ + 1;
  auto place = [&](uint32_t& r) {
    if (r & kTempFlag) r = layout_.temp_base + (r & ~kTempFlag);
  };
  for (Program* p : programs) {
    for (Instruction& in : p->code()) {
      if (in.op != kStore && in.op != kStoreRegister) place(in.dst);
      place(in.a);
      place(in.b);
      place(in.c);
    }
  }
}

}  // namespace momenta
