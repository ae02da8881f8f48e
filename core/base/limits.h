#pragma once
/// The limits on what a user's files may nest, in one place, so that every recursive structure a
/// model controls stops at the same depth with the same words instead of overflowing the stack
/// (or taking minutes) on input built to be deep.

#include <cstdint>
#include <string>

namespace momenta {

/// The deepest nesting momenta follows in anything a model writes: an expression's parentheses,
/// calls, subscripts and if-expressions (core/lang/parser.h), a unit string's parentheses
/// (core/lang/units.h) and a chain of files that each name the next in `uses:`
/// (core/lang/yaml_loader.h). 256 is clang's default bracket depth (-fbracket-depth): far beyond
/// what models need, and well inside the stack of the sanitizer build, whose expression-parser
/// frames take about 10 KB per level (it overflows 8 MB near 800).
constexpr int kMaxNestingDepth = 256;

/// How often one expression may be differentiated with respect to time: by Pantelides' algorithm
/// (an equation differentiated more often means the algorithm is not converging, a structural
/// singularity the balance checks did not catch; mechanical systems need two) and by der()
/// written around anything other than a variable (each order multiplies the expression's size,
/// so the limit is checked on the written text before a derivative is built).
constexpr uint32_t kMaxDifferentiations = 12;

/// The words every nesting limit is reported in: "<what> nested deeper than 256 levels".
inline std::string NestedTooDeep(const std::string& what) {
  return what + " nested deeper than " + std::to_string(kMaxNestingDepth) + " levels";
}

}  // namespace momenta
