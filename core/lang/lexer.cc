// The tokens of an expression (core/lang/lexer.h).

#include "core/lang/lexer.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace momenta {

size_t DecimalEnd(std::string_view text, size_t i) {
  size_t j = i;
  auto digits = [&] {
    while (j < text.size() && IsDigit(text[j])) ++j;
  };
  digits();
  if (j < text.size() && text[j] == '.') {
    ++j;
    digits();
  }
  if (j < text.size() && (text[j] == 'e' || text[j] == 'E')) {
    size_t k = j + 1;
    if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
    if (k < text.size() && IsDigit(text[k])) {
      j = k;
      digits();
    }
  }
  return j;
}

namespace {

/// The character starting at text[at] for a message: 'c', a whole UTF-8 sequence as 'ü' (U+00FC),
/// or a byte that starts none as byte 0xC3.
std::string QuotedCharacter(const std::string& text, size_t at) {
  const auto lead = static_cast<unsigned char>(text[at]);
  if (lead < 0x80) return std::string("'") + text[at] + "'";
  size_t len = lead >= 0xF0 && lead < 0xF5 ? 4 : lead >= 0xE0 ? 3 : lead >= 0xC2 ? 2 : 0;
  uint32_t code = len == 2 ? lead & 0x1F : len == 3 ? lead & 0x0F : lead & 0x07;
  bool ok = len > 0 && lead < 0xF5 && at + len <= text.size();
  for (size_t k = 1; ok && k < len; ++k) {
    const auto cont = static_cast<unsigned char>(text[at + k]);
    ok = (cont & 0xC0) == 0x80;
    code = (code << 6) | (cont & 0x3F);
  }
  char hex[16];
  if (!ok) {
    std::snprintf(hex, sizeof hex, "0x%02X", lead);
    return std::string("byte ") + hex + " (not UTF-8 text)";
  }
  std::snprintf(hex, sizeof hex, "U+%04X", code);
  return "'" + text.substr(at, len) + "' (" + hex + ")";
}

/// The one-character tokens other than operators' and names' characters.
TokenKind PunctuationKind(char c) {
  switch (c) {
    case '(':
      return TokenKind::kLParen;
    case ')':
      return TokenKind::kRParen;
    case '[':
      return TokenKind::kLBracket;
    case ']':
      return TokenKind::kRBracket;
    case ',':
      return TokenKind::kComma;
    case '.':
      return TokenKind::kDot;
    default:
      return TokenKind::kEnd;
  }
}

class Lexer {
 public:
  Lexer(const std::string& text, const SourceLoc& loc) : text_(text), loc_(loc) {}

  std::vector<Token> Run() {
    std::vector<Token> out;
    size_t i = 0;
    while (true) {
      while (i < text_.size() && std::isspace(static_cast<unsigned char>(text_[i]))) ++i;
      Token t;
      t.column = static_cast<int>(i);
      if (i >= text_.size()) {
        out.push_back(t);
        return out;
      }
      char c = text_[i];
      if (std::isdigit(static_cast<unsigned char>(c)) ||
          (c == '.' && i + 1 < text_.size() &&
           std::isdigit(static_cast<unsigned char>(text_[i + 1])))) {
        i = Number(i, &t);
      } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
        size_t j = i;
        while (j < text_.size() &&
               (std::isalnum(static_cast<unsigned char>(text_[j])) || text_[j] == '_')) {
          ++j;
        }
        t.kind = TokenKind::kIdent;
        t.text = text_.substr(i, j - i);
        i = j;
      } else {
        i = Symbol(i, &t);
      }
      out.push_back(t);
    }
  }

 private:
  /// The number starting at text_[i] into `t`; where it ends.
  size_t Number(size_t i, Token* t) const {
    const size_t j = DecimalEnd(text_, i);
    t->kind = TokenKind::kNumber;
    t->text = text_.substr(i, j - i);
    t->number = std::strtod(t->text.c_str(), nullptr);
    // Beyond double's range, or a subnormal (a nonzero number below 2.2e-308 that keeps only a
    // few digits): the same range as a value with a unit (core/lang/units.h, ParseDecimal).
    if (!std::isfinite(t->number) || (t->number != 0 && !std::isnormal(t->number))) {
      throw ModelError(loc_.Shifted(static_cast<int>(i)), "number out of range '" + t->text +
                                                              "' (double's range: magnitudes from "
                                                              "2.2e-308 to 1.8e308)");
    }
    i = j;
    if (i < text_.size() &&
        (std::isalpha(static_cast<unsigned char>(text_[i])) || text_[i] == '_')) {
      throw ModelError(loc_.Shifted(static_cast<int>(i)),
                       "malformed number '" + t->text + text_[i] + "'");
    }
    return i;
  }

  /// The operator or punctuation starting at text_[i] into `t`; where it ends.
  size_t Symbol(size_t i, Token* t) const {
    static const char* kTwo[] = {"<=", ">=", "==", "<>", "!="};
    std::string two = text_.substr(i, 2);
    for (const char* op : kTwo) {
      if (two == op) {
        t->kind = TokenKind::kOp;
        t->text = two == "!=" ? "<>" : two;
        return i + 2;
      }
    }
    const char c = text_[i];
    t->text = std::string(1, c);
    t->kind = PunctuationKind(c);
    if (t->kind == TokenKind::kEnd) {
      if (std::string_view("+-*/^<>=").find(c) == std::string_view::npos) {
        throw ModelError(loc_.Shifted(t->column),
                         "unexpected character " + QuotedCharacter(text_, i));
      }
      t->kind = TokenKind::kOp;
    }
    return i + 1;
  }

  const std::string& text_;
  const SourceLoc& loc_;
};

}  // namespace

std::vector<Token> Tokenize(const std::string& text, const SourceLoc& loc) {
  return Lexer(text, loc).Run();
}

}  // namespace momenta
