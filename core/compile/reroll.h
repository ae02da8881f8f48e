#pragma once
/// Loop rerolling of compiled programs: a straight-line register program in which runs of
/// identical components produce runs of identical instruction blocks is described as a sequence
/// of segments, each a block of instructions repeated `count` times with every register (and
/// output index) advancing by a fixed stride per repetition. The description is exact and
/// lossless: expanding it gives back the program instruction for instruction. It is what native
/// code generation turns into `for` loops, so generated code stays proportional to the number of
/// distinct component types, not to the number of scalar equations.
///
/// Segment k covers code[begin, begin + len*count); for iteration i < count and body position
/// j < len,
///   code[begin + i*len + j] == body[j] + i*stride[j]   (field by field: dst, a, b, c; op equal)
/// where body[j] = code[begin + j]. Arithmetic is modulo 2^32 (uint32_t): a stride read as
/// int32_t is the signed step, so a negative step is stored in two's complement. A temporary that
/// is the same register in every repetition, a shared register (a parameter, a constant, a
/// parameter-only value several components read) and an unused field have stride 0. count == 1
/// is straight-line code (its strides are 0). Segments cover the program in order, without gaps.

#include <cstdint>
#include <vector>

#include "core/compile/program.h"

namespace momenta {

struct LoopSegment {
  uint32_t begin = 0;  ///< first instruction of the segment in the program
  uint32_t len = 0;    ///< instructions in the body (one repetition)
  uint32_t count = 0;  ///< repetitions; 1: straight-line code
  /// Per body position: the step of dst, a, b and c per repetition (op unused, 0). Always `len`
  /// entries.
  std::vector<Instruction> stride;
};

/// Tuning of the detection; the defaults suit compiled models.
struct RerollOptions {
  /// Fewest repetitions that make a loop: shorter runs stay straight-line code.
  uint32_t min_count = 4;
  /// Longest body looked for (instructions).
  uint32_t max_len = 1u << 16;
};

/// The segments of `program`: maximal loops found greedily from the start, straight-line code
/// between them. Time is the program's size times a small factor (a hash per instruction, and
/// one scan of the program per candidate body length at most; see reroll.cc); memory is linear.
std::vector<LoopSegment> Reroll(const Program& program, const RerollOptions& options = {});

/// The instruction stream the segments describe (the inverse of Reroll, for checks).
std::vector<Instruction> Expand(const std::vector<Instruction>& code, const std::vector<LoopSegment>& segments);

/// How much of a program the loops cover.
struct RerollCoverage {
  size_t instructions = 0;      ///< in the program
  size_t in_loops = 0;          ///< inside segments with count >= min_count
  size_t segments = 0;          ///< all segments
  size_t loops = 0;             ///< segments with count >= min_count
  size_t rolled_size = 0;       ///< instructions kept: the bodies of all segments
  double share() const { return instructions ? static_cast<double>(in_loops) / instructions : 0.0; }
};
RerollCoverage Coverage(const std::vector<LoopSegment>& segments, uint32_t min_count = 4);

/// A program kept as its loops: the segment bodies and strides only (no expanded code), evaluated
/// by stepping each body's registers through the repetitions. Gives bitwise the results of
/// Program::Run on the same registers.
class RolledProgram {
 public:
  RolledProgram() = default;
  explicit RolledProgram(const Program& program, const RerollOptions& options = {});

  void Run(double* regs, double* out) const;

  /// The segments; their `begin` indexes the original program, `body_begin` this object's bodies.
  const std::vector<LoopSegment>& segments() const { return segments_; }
  const std::vector<Instruction>& bodies() const { return bodies_; }
  size_t size() const;  ///< instructions of the program it stands for

 private:
  std::vector<LoopSegment> segments_;
  std::vector<uint32_t> body_begin_;  ///< per segment: its body's first instruction in bodies_
  std::vector<Instruction> bodies_;   ///< every segment's first repetition, in order
  std::vector<TableShape> tables_;
  uint32_t max_len_ = 0;
};

}  // namespace momenta
