#pragma once
/// C code for register programs (issue 12, item 1): each Program becomes a C99 function
/// `void f(double* restrict r, double* restrict out)` that does exactly what Program::Run does —
/// the same operations on the same registers in the same order — so that, compiled without
/// floating-point contraction or fast-math, its results are bit-identical to the interpreter's.
///
/// A program is emitted as a sequence of segments (CodeSegment); each becomes a function of
/// bounded size, because the time an optimising C compiler takes grows faster than linearly with
/// the size of a function. Temporaries (registers from RegisterLayout::temp_base) become local
/// variables within a segment, so the compiler keeps them in machine registers; only those a later
/// segment reads are written back to the register file.
///
/// Model names never reach the code except inside comments, and SanitizeComment makes any text
/// safe there.

#include <cstdint>
#include <string>
#include <vector>

#include "core/program.h"

namespace momenta {

/// The instructions code[begin, begin + len * count) of a program. count == 1: straight-line code
/// (len instructions). count > 1 is the shape loop rerolling (core/reroll.h) produces — count
/// copies of a body of len instructions whose operands advance by a constant stride — and is not
/// emitted as a loop yet: EmitC refuses it.
struct CodeSegment {
  uint32_t begin = 0, len = 0, count = 1;
};

/// Straight-line segments of at most `max_len` instructions covering `program` in order.
std::vector<CodeSegment> StraightSegments(const Program& program, uint32_t max_len);

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
