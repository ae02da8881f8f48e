#pragma once
/// C code for register programs: each Program becomes a C99 function
/// `void f(double* restrict r, const double* restrict y, const double* restrict yp,
/// double* restrict out)` that does exactly what Program::Run does — the same operations on the
/// same registers in the same order — so that, compiled without floating-point contraction or
/// fast-math, its results are bit-identical to the interpreter's. The registers of the unknowns
/// and of their derivatives are read from y[k - y_base] and yp[k - yp_base] instead (programs
/// only read them), so that the caller need not copy the solver's vectors into the registers.
///
/// A program is emitted as a sequence of segments (CodeSegment); each becomes a function of
/// bounded size, because the time an optimising C compiler takes grows faster than linearly with
/// the size of a function. Temporaries (registers from RegisterLayout::temp_base) become local
/// variables within a segment, so the compiler keeps them in machine registers; only those a later
/// segment reads are written back to the register file. Inside a loop, a temporary that is the
/// same register in every repetition stays a local; one whose register moves with the repetition
/// lives in the register file for the whole segment.
///
/// Model names never reach the code except inside comments, and SanitizeComment makes any text
/// safe there.

#include <cstdint>
#include <string>
#include <vector>

#include "core/compile/program.h"

namespace momenta {

/// The instructions code[begin, begin + len * count) of a program. count == 1: straight-line code
/// (len instructions). count > 1: a loop as loop rerolling (core/compile/reroll.h) describes it — count
/// copies of a body of len instructions, code[begin + i*len + j] equal to code[begin + j] with
/// dst, a, b and c each advanced by i * stride[j] (modulo 2^32) — emitted as a C `for` loop over
/// i whose operands are affine in i.
struct CodeSegment {
  uint32_t begin = 0, len = 0, count = 1;
  std::vector<Instruction> stride;  ///< per body position (len entries) when count > 1
};

/// Straight-line segments of at most `max_len` instructions covering `program` in order.
std::vector<CodeSegment> StraightSegments(const Program& program, uint32_t max_len);

/// Segments covering `program` in order: the loops Reroll finds whose body has at most `max_len`
/// instructions, straight-line code of at most `max_len` instructions between them. A loop whose
/// interpolations change table shape from one repetition to the next stays straight-line code
/// (the shape is a constant in the code).
std::vector<CodeSegment> LoopSegments(const Program& program, uint32_t max_len);

/// One program to emit, under the C symbol `symbol` (an identifier the caller chooses).
struct CodegenProgram {
  std::string symbol;
  const Program* program = nullptr;
  std::vector<CodeSegment> segments;  ///< empty: StraightSegments(max_function_len)
};

struct CodegenOptions {
  /// Instructions per generated function at most (the compile-time measurement in
  /// bench/RESULTS.md chose it).
  uint32_t max_function_len = 2000;
  /// Becomes `const char momenta_key[]` in the code: the cache key the loader checks (none when
  /// empty: the other translation units of one object).
  std::string key;
  /// Text for the file's header comment (sanitised).
  std::string comment;
};

/// The C99 translation unit for `programs` over `layout`'s register file.
std::string EmitC(const std::vector<CodegenProgram>& programs, const RegisterLayout& layout,
                  const CodegenOptions& options);

/// `text` made safe inside a C block comment: printable ASCII only (anything else, including
/// UTF-8 bytes and control characters, becomes '?') and no "*/" or "/*".
std::string SanitizeComment(const std::string& text);

}  // namespace momenta
