#include "core/compile/reroll.h"

#include <algorithm>
#include <array>
#include <unordered_map>

#include "core/base/error.h"

/// Detection. A loop of body length L starting at `begin` with count c holds exactly when, for
/// every t in [begin + L, begin + c*L):
///   P1(t): op[t] == op[t - L]
///   P2(t) (t >= begin + 2L): code[t] - code[t - L] == code[t - L] - code[t - 2L]  (all fields)
/// so the loop from `begin` reaches the first t where P1 or P2 fails, rounded down to whole
/// repetitions. Both predicates depend on t and L only, not on where the loop starts, so the first
/// failure found from some t0 answers every later query that starts between t0 and it: a memo per
/// L makes all the scans for one L together one pass over the program.
///
/// Candidate body lengths come from the program itself: each instruction gets a shape (its op and,
/// per operand, whether it reads a computed value or an input), a window of kWindow shapes is
/// hashed, and the distances to the next few windows with the same hash are the candidates at
/// that position. The scan is greedy from the start: at each
/// position, the candidate covering most instructions with at least min_count repetitions becomes
/// a loop and the scan continues after it; otherwise the instruction joins the straight-line code.

namespace momenta {

namespace {

constexpr uint32_t kNone = 0xffffffffu;
constexpr uint32_t kWindow = 12;
constexpr int kCandidates = 16;

uint64_t Mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  return h * 0xff51afd7ed558ccdull;
}

bool IsStore(uint8_t op) { return op == kStore; }

/// The operand fields an instruction reads (registers), by op: a and b for most; c for kIf. The
/// fields it does not read are compared too (they must match for an exact description) but say
/// nothing about shape.
int RegisterOperands(uint8_t op) {
  if (op == kStore || op == kStoreRegister) return 1;
  if (op == static_cast<uint8_t>(Op::kIf)) return 3;
  return 2;
}

/// Per instruction, a hash of its shape: op and, per operand, whether the program wrote that
/// register before (a computed value) or not (an input: time, parameters, y, y'). Both stay the
/// same along a loop, whatever the loop's strides.
std::vector<uint64_t> Shapes(const std::vector<Instruction>& code) {
  uint32_t max_reg = 0;
  for (const Instruction& in : code) {
    if (!IsStore(in.op)) max_reg = std::max(max_reg, in.dst);
  }
  std::vector<bool> written(static_cast<size_t>(max_reg) + 1, false);
  std::vector<uint64_t> shape(code.size());
  for (uint32_t k = 0; k < code.size(); ++k) {
    const Instruction& in = code[k];
    uint64_t h = in.op;
    const uint32_t operands[3] = {in.a, in.b, in.c};
    for (int f = 0; f < RegisterOperands(in.op); ++f) {
      const uint32_t r = operands[f];
      h = 2 * h + (r <= max_reg && written[r] ? 1 : 0);
    }
    shape[k] = Mix(0, h);
    if (!IsStore(in.op)) written[in.dst] = true;
  }
  return shape;
}

/// next[k]: the next position whose window of kWindow shapes hashes like k's (kNone if none).
std::vector<uint32_t> NextSameWindow(const std::vector<uint64_t>& shape) {
  const size_t n = shape.size();
  std::vector<uint32_t> next(n, kNone);
  if (n < kWindow) return next;
  const size_t windows = n - kWindow + 1;
  // Open addressing: (hash, position) with position kNone for empty slots.
  size_t capacity = 16;
  while (capacity < 2 * windows) capacity *= 2;
  std::vector<uint64_t> keys(capacity);
  std::vector<uint32_t> last(capacity, kNone);
  for (size_t k = windows; k-- > 0;) {
    uint64_t h = 0;
    for (uint32_t j = 0; j < kWindow; ++j) h = Mix(h, shape[k + j]);
    size_t slot = (h ^ (h >> 29)) & (capacity - 1);
    while (last[slot] != kNone && keys[slot] != h) slot = (slot + 1) & (capacity - 1);
    next[k] = last[slot];
    keys[slot] = h;
    last[slot] = static_cast<uint32_t>(k);
  }
  return next;
}

bool SameDifference(const Instruction& x2, const Instruction& x1, const Instruction& x0) {
  return x2.dst - x1.dst == x1.dst - x0.dst && x2.a - x1.a == x1.a - x0.a &&
         x2.b - x1.b == x1.b - x0.b && x2.c - x1.c == x1.c - x0.c;
}

/// The first failures of P1 and P2 (see the top) for each body length tried, remembered.
class PeriodChecker {
 public:
  explicit PeriodChecker(const std::vector<Instruction>& code) : code_(code) {}

  /// Whole repetitions of the body code[begin, begin + len) from begin.
  uint32_t Count(uint32_t begin, uint32_t len) {
    const uint32_t n = static_cast<uint32_t>(code_.size());
    if (begin + len >= n) return 1;
    Memo& memo = memo_[len];
    const uint32_t f1 = FirstFailure(&memo.op, begin + len, [&](uint32_t t) {
      return code_[t].op == code_[t - len].op;
    });
    uint32_t end = f1;
    if (begin + 2 * len < f1) {
      const uint32_t f2 = FirstFailure(&memo.step, begin + 2 * len, [&](uint32_t t) {
        return SameDifference(code_[t], code_[t - len], code_[t - 2 * len]);
      });
      end = std::min(end, f2);
    }
    return (end - begin) / len;
  }

 private:
  struct Scan {
    uint32_t from = kNone, failure = 0;  ///< the predicate holds on [from, failure)
  };
  struct Memo {
    Scan op, step;
  };

  /// The first t >= start where `holds` fails, from the memo when an earlier scan covers start.
  template <typename Holds>
  uint32_t FirstFailure(Scan* scan, uint32_t start, Holds holds) {
    const uint32_t n = static_cast<uint32_t>(code_.size());
    if (scan->from != kNone && scan->from <= start && start <= scan->failure) return scan->failure;
    uint32_t t = start;
    while (t < n && holds(t)) ++t;
    scan->from = start;
    scan->failure = t;
    return t;
  }

  const std::vector<Instruction>& code_;
  std::unordered_map<uint32_t, Memo> memo_;
};

LoopSegment MakeSegment(const std::vector<Instruction>& code, uint32_t begin, uint32_t len, uint32_t count) {
  LoopSegment s;
  s.begin = begin;
  s.len = len;
  s.count = count;
  s.stride.assign(len, Instruction{0, 0, 0, 0, 0});
  if (count > 1) {
    for (uint32_t j = 0; j < len; ++j) {
      const Instruction& x0 = code[begin + j];
      const Instruction& x1 = code[begin + len + j];
      s.stride[j] = {0, x1.dst - x0.dst, x1.a - x0.a, x1.b - x0.b, x1.c - x0.c};
    }
  }
  return s;
}

}  // namespace

std::vector<LoopSegment> Reroll(const Program& program, const RerollOptions& options) {
  const std::vector<Instruction>& code = program.code();
  const uint32_t n = static_cast<uint32_t>(code.size());
  MOMENTA_CHECK(code.size() < kNone);
  const uint32_t min_count = std::max<uint32_t>(options.min_count, 2);
  const std::vector<uint32_t> next = NextSameWindow(Shapes(code));
  PeriodChecker checker(code);
  std::vector<LoopSegment> segments;
  uint32_t straight = 0;  // start of the straight-line code not yet emitted
  for (uint32_t pos = 0; pos < n;) {
    // The candidate body lengths at pos: distances to the next windows shaped alike.
    uint32_t best_len = 0, best_count = 0;
    uint32_t at = pos < next.size() ? next[pos] : kNone;
    for (int k = 0; k < kCandidates && at != kNone; ++k, at = next[at]) {
      const uint32_t len = at - pos;
      if (len > options.max_len) break;
      const uint32_t count = checker.Count(pos, len);
      if (count >= min_count && static_cast<uint64_t>(len) * count > static_cast<uint64_t>(best_len) * best_count) {
        best_len = len;
        best_count = count;
      }
    }
    if (best_count == 0) {
      ++pos;
      continue;
    }
    // A loop: the straight-line code before it, then the loop.
    if (straight < pos) segments.push_back(MakeSegment(code, straight, pos - straight, 1));
    segments.push_back(MakeSegment(code, pos, best_len, best_count));
    pos += best_len * best_count;
    straight = pos;
  }
  if (straight < n) segments.push_back(MakeSegment(code, straight, n - straight, 1));
  return segments;
}

std::vector<Instruction> Expand(const std::vector<Instruction>& code, const std::vector<LoopSegment>& segments) {
  std::vector<Instruction> out;
  for (const LoopSegment& s : segments) {
    for (uint32_t i = 0; i < s.count; ++i) {
      for (uint32_t j = 0; j < s.len; ++j) {
        const Instruction& x = code[s.begin + j];
        const Instruction& d = s.stride[j];
        out.push_back({x.op, x.dst + i * d.dst, x.a + i * d.a, x.b + i * d.b, x.c + i * d.c});
      }
    }
  }
  return out;
}

RerollCoverage Coverage(const std::vector<LoopSegment>& segments, uint32_t min_count) {
  RerollCoverage c;
  c.segments = segments.size();
  for (const LoopSegment& s : segments) {
    const size_t size = static_cast<size_t>(s.len) * s.count;
    c.instructions += size;
    c.rolled_size += s.len;
    if (s.count >= min_count) {
      c.in_loops += size;
      ++c.loops;
    }
  }
  return c;
}

RolledProgram::RolledProgram(const Program& program, const RerollOptions& options)
    : segments_(Reroll(program, options)), tables_(program.tables()) {
  for (const LoopSegment& s : segments_) {
    body_begin_.push_back(static_cast<uint32_t>(bodies_.size()));
    bodies_.insert(bodies_.end(), program.code().begin() + s.begin, program.code().begin() + s.begin + s.len);
    if (s.count > 1) max_len_ = std::max(max_len_, s.len);
  }
}

size_t RolledProgram::size() const {
  size_t size = 0;
  for (const LoopSegment& s : segments_) size += static_cast<size_t>(s.len) * s.count;
  return size;
}

void RolledProgram::Run(double* regs, double* out) const {
  // A loop runs its body from a copy whose registers step by the strides after each repetition.
  constexpr uint32_t kOnStack = 512;
  std::array<Instruction, kOnStack> small;
  std::vector<Instruction> large;
  Instruction* body = small.data();
  if (max_len_ > kOnStack) {
    large.resize(max_len_);
    body = large.data();
  }
  for (size_t k = 0; k < segments_.size(); ++k) {
    const LoopSegment& s = segments_[k];
    const Instruction* first = bodies_.data() + body_begin_[k];
    if (s.count == 1) {
      RunInstructions(first, s.len, tables_.data(), regs, out);
      continue;
    }
    std::copy(first, first + s.len, body);
    for (uint32_t i = 0;;) {
      RunInstructions(body, s.len, tables_.data(), regs, out);
      if (++i == s.count) break;
      for (uint32_t j = 0; j < s.len; ++j) {
        const Instruction& d = s.stride[j];
        body[j].dst += d.dst;
        body[j].a += d.a;
        body[j].b += d.b;
        body[j].c += d.c;
      }
    }
  }
}

}  // namespace momenta
