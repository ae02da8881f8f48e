#pragma once
/// The tokens of an expression in momenta's equation language (docs/FORMAT.md), for the parser
/// (core/lang/parser.h): numbers, names, operators and punctuation, each with its column, and the
/// characters that make names and numbers, which the parser's fast paths for a plain number or a
/// plain dotted name read without tokens.

#include <cctype>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/error.h"

namespace momenta {

enum class TokenKind {
  kEnd,
  kNumber,
  kIdent,
  kOp,
  kLParen,
  kRParen,
  kLBracket,
  kRBracket,
  kComma,
  kDot
};

struct Token {
  TokenKind kind = TokenKind::kEnd;
  std::string text;
  double number = 0;
  int column = 0;  ///< 0-based offset in the text
};

/// The tokens of `text`, the last a kEnd at its end (two-character operators as one; `!=` as
/// `<>`). Throws ModelError at `loc`, shifted to the column, for a number out of range, a
/// malformed number (`2x`) or a character the language has no use for.
std::vector<Token> Tokenize(const std::string& text, const SourceLoc& loc);

inline bool IsDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
inline bool IsNameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
inline bool IsNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// Where the decimal number starting at text[i] ends: digits, a point, digits, an exponent
/// (strtod alone would take 0x10). An 'e' without digits after it is not part of the number.
size_t DecimalEnd(std::string_view text, size_t i);

}  // namespace momenta
