// The subset reader (core/lang/yaml_fast.h): one pass of recursive descent over the block
// structure, refusing at the first thing outside the subset.

#include "core/lang/yaml_fast.h"

#include <array>
#include <string_view>

namespace momenta {
namespace {

/// Thrown where the text leaves the subset (or is not YAML); ParseYamlSubset answers null.
struct Refusal {};

[[noreturn]] void Refuse() { throw Refusal{}; }

/// As the libyaml path: deeper nesting is left to yaml-cpp, whose depth limit gives the error.
constexpr int kMaxDepth = 100;
/// YAML limits an implicit key to 1024 characters; longer keys are left to yaml-cpp.
constexpr size_t kMaxKeyLength = 1000;

/// The bytes the reader accepts in text: printable ASCII, space and newline, and bytes from 0x80
/// on (yaml-cpp passes UTF-8 through as bytes and counts columns in bytes, as this reader does;
/// it gives no meaning to NEL, LS, PS or a byte-order mark after the start). A tab, a carriage
/// return, a NUL, other control bytes and DEL are refused.
constexpr std::array<bool, 256> AcceptedBytes() {
  std::array<bool, 256> ok{};
  for (int c = 0x20; c < 0x7F; ++c) ok[c] = true;
  for (int c = 0x80; c < 0x100; ++c) ok[c] = true;
  ok['\n'] = true;
  return ok;
}
constexpr std::array<bool, 256> kAccepted = AcceptedBytes();

/// Accepted bytes that simply continue a plain scalar, except `special`: the scanning loops
/// skip runs of them with one table look-up per byte.
constexpr std::array<bool, 256> OrdinaryBytes(std::string_view special) {
  std::array<bool, 256> ok = AcceptedBytes();
  ok[' '] = ok['\n'] = false;
  for (char c : special) ok[static_cast<unsigned char>(c)] = false;
  return ok;
}
constexpr std::array<bool, 256> kOrdinaryInBlock = OrdinaryBytes(":");
constexpr std::array<bool, 256> kOrdinaryInFlow = OrdinaryBytes(",[]{}:#?");

bool IsOrdinary(const std::array<bool, 256>& table, char c) {
  return table[static_cast<unsigned char>(c)];
}

bool IsBlankOrEnd(char c) { return c == ' ' || c == '\n' || c == '\0'; }

bool IsNullText(std::string_view s) {
  return s.empty() || s == "~" || s == "null" || s == "Null" || s == "NULL";
}

/// A scalar as read: where it starts, its text (a view of the input, or of the reader's scratch
/// buffer for a scalar with escapes or folded lines, valid until the next such scalar) and whether
/// it was plain.
struct Scalar {
  YamlMark mark;
  std::string_view text;
  bool plain = true;
};

/// One pass over the text, recursive descent over the block structure. The text is a
/// std::string, so the byte past its end is '\0': a sentinel, and a NUL inside it is refused.
class SubsetReader {
 public:
  SubsetReader(const std::string& text, YamlDoc* doc)
      : begin_(text.data()), end_(text.data() + text.size()), p_(begin_), line_start_(begin_),
        doc_(doc) {}

  void Document() {
    // A text that starts with other than ASCII may be read by yaml-cpp as UTF-16 or UTF-32, or
    // start with a byte-order mark, which is not part of the text.
    if (static_cast<unsigned char>(*p_) >= 0x80) Refuse();
    SkipBlankLines();
    // An empty text, or one of comments only: yaml-cpp says what that is.
    if (indent_ < 0) Refuse();
    BlockNode(-1);
    // Whatever follows the root is less indented than it: an error.
    if (indent_ >= 0) Refuse();
  }

 private:
  // ---- position -----------------------------------------------------------------------------

  YamlMark Here() const { return {line_, static_cast<int>(p_ - line_start_)}; }
  int Column() const { return static_cast<int>(p_ - line_start_); }
  bool AtLineEnd() const {
    if (*p_ == '\n') return true;
    if (*p_ == '\0') {
      if (p_ != end_) Refuse();
      return true;
    }
    return false;
  }
  void SkipSpaces() {
    while (*p_ == ' ') ++p_;
  }
  /// A block sequence's entry: '-' followed by a space or the end of the line.
  bool AtSequenceEntry() const { return *p_ == '-' && IsBlankOrEnd(p_[1]); }

  /// Ends the line a value ended on (spaces, then a comment after a space, then the line break)
  /// and moves to the first character of the next line that holds more than a comment.
  void NextLine() {
    const char* before = p_;
    SkipSpaces();
    if (*p_ == '#') {
      // A comment needs a space before it: `'a'#b` is an error.
      if (p_ == before && p_[-1] != ' ') Refuse();
      SkipComment();
    }
    if (!AtLineEnd()) Refuse();
    SkipBlankLines();
  }

  void SkipComment() {
    while (*p_ != '\n' && *p_ != '\0') {
      if (!kAccepted[static_cast<unsigned char>(*p_)]) Refuse();
      ++p_;
    }
  }

  /// From the end of a line (or the start of the text): past blank and comment lines to the
  /// first character of the next line with content, whose indentation goes to indent_ (-1 at
  /// the end of the text).
  void SkipBlankLines() {
    for (;;) {
      if (*p_ == '\n') {
        ++p_;
        ++line_;
        line_start_ = p_;
      }
      SkipSpaces();
      if (*p_ == '\n') continue;
      if (*p_ == '#') {
        SkipComment();
        continue;
      }
      if (*p_ == '\0') {
        if (p_ != end_) Refuse();
        indent_ = -1;
        return;
      }
      indent_ = Column();
      // Document markers and directives start a line.
      if (indent_ == 0 && (*p_ == '%' || ((p_[0] == '-' || p_[0] == '.') && p_[1] == p_[0] &&
                                          p_[2] == p_[0] && IsBlankOrEnd(p_[3])))) {
        Refuse();
      }
      return;
    }
  }

  // ---- block structure ----------------------------------------------------------------------

  /// A node that starts at p_, more indented than `parent` (a sequence's '-' may sit at its
  /// key's indentation: the caller sees to that). Returns at the next line with content.
  void BlockNode(int parent) {
    if (++depth_ > kMaxDepth) Refuse();
    const int column = Column();
    if (column <= parent) Refuse();
    if (AtSequenceEntry()) {
      BlockSequence(column);
    } else if (*p_ == '[' || *p_ == '{') {
      FlowCollection(parent);
      NextLine();
    } else if (*p_ == '|' || *p_ == '>') {
      // A text at the root is left to yaml-cpp.
      if (parent < 0) Refuse();
      BlockText(parent);
    } else {
      const Scalar head = BlockScalar();
      if (AtMappingColon()) {
        BlockMapping(column, head);
      } else {
        Emit(head);
        NextLine();
      }
    }
    --depth_;
  }

  /// After a scalar: spaces, then ':' and a space or the end of the line, makes it a key.
  bool AtMappingColon() {
    SkipSpaces();
    return *p_ == ':' && IsBlankOrEnd(p_[1]);
  }

  /// A block mapping whose first key, already read, starts at column `indent`; p_ is at the ':'
  /// after it.
  void BlockMapping(int indent, Scalar key) {
    doc_->Open(YamlDoc::Kind::kMap, key.mark, YamlDoc::kUntagged);
    for (;;) {
      if (key.text.size() > kMaxKeyLength) Refuse();
      Emit(key);
      ++p_;  // the ':'
      SkipSpaces();
      if (*p_ == '#' || AtLineEnd()) {
        // The value starts on a later line: more indented, or a sequence at the key's
        // indentation. Otherwise it is empty (a null where the next key starts).
        NextLine();
        if (indent_ > indent) {
          BlockNode(indent);
        } else if (indent_ == indent && AtSequenceEntry()) {
          BlockNode(indent - 1);
        } else {
          EmptyValue(indent);
        }
      } else {
        InlineValue(indent);
      }
      // A more indented line here would continue a plain scalar or be an error.
      if (indent_ > indent) Refuse();
      if (indent_ < indent) break;
      if (AtSequenceEntry() || *p_ == '[' || *p_ == '{') Refuse();
      key = BlockScalar();
      if (!AtMappingColon()) Refuse();
    }
    doc_->Close();
  }

  /// A value after `key: ` on the same line, in a mapping at column `indent`: a scalar, a flow
  /// collection or a block scalar.
  void InlineValue(int indent) {
    if (++depth_ > kMaxDepth) Refuse();
    if (*p_ == '|' || *p_ == '>') {
      BlockText(indent);
      --depth_;
      return;
    }
    if (*p_ == '[' || *p_ == '{') {
      FlowCollection(indent);
    } else {
      // `key: - a` and `a: b: c` are errors.
      if (AtSequenceEntry()) Refuse();
      const Scalar value = BlockScalar();
      if (AtMappingColon()) Refuse();
      Emit(value);
    }
    NextLine();
    --depth_;
  }

  /// An empty value in a mapping at column `indent`, p_ at the next line with content. yaml-cpp
  /// marks it where the next key starts; an empty value before the end of the mapping or of the
  /// text is left to it.
  void EmptyValue(int indent) {
    if (indent_ != indent) Refuse();
    doc_->AddNull(Here());
  }

  /// A block sequence whose first '-' is at p_, in column `indent`.
  void BlockSequence(int indent) {
    doc_->Open(YamlDoc::Kind::kSequence, Here(), YamlDoc::kUntagged);
    for (;;) {
      ++p_;  // the '-'
      SkipSpaces();
      if (*p_ == '#' || AtLineEnd()) {
        // The item on the lines below; an empty item is left to yaml-cpp.
        NextLine();
        if (indent_ <= indent) Refuse();
        BlockNode(indent);
      } else {
        // `- x`, `- key: value` (a mapping at this column), `- - x`.
        BlockNode(indent);
      }
      if (indent_ > indent) Refuse();
      if (indent_ < indent || !AtSequenceEntry()) break;
    }
    doc_->Close();
  }

  // ---- scalars ------------------------------------------------------------------------------

  /// A literal (`|`) or folded (`>`) block scalar whose indicator is at p_, its lines more
  /// indented than `parent`, all at one indentation. The header is `|`, `>`, `|-` or `>-` (the
  /// text ends in one line break, or in none); more indented lines (kept as they are, not
  /// folded), lines of spaces past the indentation, leading empty lines, an empty text and a
  /// last line without a line break are refused. Returns at the next line with content.
  void BlockText(int parent) {
    Scalar s;
    s.mark = Here();
    s.plain = false;
    const bool folded = *p_ == '>';
    ++p_;
    const bool strip = *p_ == '-';
    if (strip) ++p_;
    // The header ends its line.
    const char* before = p_;
    SkipSpaces();
    if (*p_ == '#') {
      if (p_ == before) Refuse();
      SkipComment();
    }
    if (*p_ != '\n') Refuse();
    scratch_.clear();
    int indent = -1;  // the text's indentation, from its first line
    int breaks = 0;   // line breaks after the last line of text, not yet written
    for (;;) {
      ++p_;
      ++line_;
      line_start_ = p_;
      SkipSpaces();
      const int spaces = Column();
      if (*p_ == '\n') {
        if (indent < 0 || spaces > indent) Refuse();
        ++breaks;
        continue;
      }
      // Spaces before the end of the text, without a line break, are left to yaml-cpp.
      if (*p_ == '\0' && spaces > 0) Refuse();
      if (*p_ == '\0' || *p_ == '#' || spaces < indent) break;
      if (indent < 0) {
        if (spaces <= parent) Refuse();
        indent = spaces;
      } else if (spaces > indent) {
        Refuse();
      }
      // Between two lines of text: a literal keeps the line breaks; a folded text turns a
      // single one into a space and keeps all but one of several.
      if (breaks == 1 && folded) {
        scratch_ += ' ';
      } else if (breaks > 0) {
        scratch_.append(static_cast<size_t>(folded ? breaks - 1 : breaks), '\n');
      }
      const char* text = p_;
      while (*p_ != '\n') {
        if (!kAccepted[static_cast<unsigned char>(*p_)]) Refuse();
        ++p_;
      }
      scratch_.append(text, p_);
      breaks = 1;
    }
    // A '#' line as indented as the text is text; one before the text, or an empty text, is left
    // to yaml-cpp.
    if (indent < 0 || (*p_ == '#' && Column() >= indent)) Refuse();
    if (!strip) scratch_ += '\n';
    s.text = scratch_;
    Emit(s);
    // p_ is past the indentation of the line after the text (or at the end).
    p_ = line_start_;
    SkipBlankLines();
  }

  /// A scalar in block context: quoted, or plain up to ': ', ' #' or the end of the line.
  Scalar BlockScalar() {
    if (*p_ == '\'' || *p_ == '"') return Quoted();
    Scalar s;
    s.mark = Here();
    if (!CanStartPlain()) Refuse();
    const char* start = p_;
    const char* last = p_;  // one past the last character that is not a space
    for (;;) {
      const char* run = p_;
      while (IsOrdinary(kOrdinaryInBlock, *p_)) ++p_;
      if (p_ != run) last = p_;
      const char c = *p_;
      if (c == ':') {
        if (IsBlankOrEnd(p_[1])) break;
        last = ++p_;
      } else if (c == ' ') {
        if (p_[1] == '#') break;
        ++p_;
      } else if (c == '\n' || c == '\0') {
        break;
      } else {
        Refuse();
      }
    }
    s.text = std::string_view(start, static_cast<size_t>(last - start));
    return s;
  }

  /// A plain scalar starts with anything but an indicator; '-' followed by a non-space is a
  /// plain scalar (a negative number).
  bool CanStartPlain() const {
    switch (*p_) {
      case '-':
        return !IsBlankOrEnd(p_[1]) && p_[1] != ',' && p_[1] != ']' && p_[1] != '}' &&
               p_[1] != '[' && p_[1] != '{';
      case '?': case ':': case ',': case '[': case ']': case '{': case '}': case '#': case '&':
      case '*': case '!': case '|': case '>': case '\'': case '"': case '%': case '@': case '`':
      case ' ': case '\n': case '\0':
        return false;
      default:
        return kAccepted[static_cast<unsigned char>(*p_)];
    }
  }

  /// A scalar in a flow collection: quoted, or plain up to ',', ']', '}' or ': ' (the other
  /// characters that end or start flow tokens, ':' and '#' are refused inside it).
  Scalar FlowScalar() {
    if (*p_ == '\'' || *p_ == '"') return Quoted();
    Scalar s;
    s.mark = Here();
    if (!CanStartPlain()) Refuse();
    const char* start = p_;
    const char* last = p_;
    for (;;) {
      const char* run = p_;
      while (IsOrdinary(kOrdinaryInFlow, *p_)) ++p_;
      if (p_ != run) last = p_;
      const char c = *p_;
      if (c == ',' || c == ']' || c == '}' || (c == ':' && p_[1] == ' ')) break;
      if (c == ' ') {
        ++p_;
      } else if (c == '\n' && EntryEndsOnNextLine()) {
        break;
      } else {
        // '[', '{', '#', '?', ':' inside, a line break that continues the scalar, a control byte.
        Refuse();
      }
    }
    s.text = std::string_view(start, static_cast<size_t>(last - start));
    return s;
  }

  /// At the line break after a plain scalar in a flow collection: whether the next line starts
  /// with the ',', ']' or '}' after it (any other text would continue the scalar).
  bool EntryEndsOnNextLine() const {
    const char* q = p_ + 1;
    while (*q == ' ') ++q;
    return *q == ',' || *q == ']' || *q == '}';
  }

  /// A single- or double-quoted scalar that ends on its line.
  Scalar Quoted() {
    Scalar s;
    s.mark = Here();
    s.plain = false;
    const char quote = *p_++;
    const char* start = p_;
    // Without an escape the text is a view of the input; with one it is built in scratch_.
    bool copied = false;
    for (;;) {
      const char c = *p_;
      if (c == quote) {
        if (quote == '\'' && p_[1] == '\'') {
          Copy(start, p_ + 1, &copied);
          p_ += 2;
          start = p_;
          continue;
        }
        break;
      }
      if (c == '\\' && quote == '"') {
        Copy(start, p_, &copied);
        scratch_ += Escaped(p_[1]);
        p_ += 2;
        start = p_;
        continue;
      }
      if (c == '\n' || !kAccepted[static_cast<unsigned char>(c)]) Refuse();
      ++p_;
    }
    if (copied) {
      scratch_.append(start, p_);
      s.text = scratch_;
    } else {
      s.text = std::string_view(start, static_cast<size_t>(p_ - start));
    }
    ++p_;  // the closing quote
    return s;
  }

  void Copy(const char* from, const char* to, bool* copied) {
    if (!*copied) scratch_.clear();
    *copied = true;
    scratch_.append(from, to);
  }

  /// The character a double-quoted escape stands for; escapes of other characters (\x, \u,
  /// line continuations, ...) are refused.
  static char Escaped(char c) {
    switch (c) {
      case '\\': return '\\';
      case '"': return '"';
      case '/': return '/';
      case 'n': return '\n';
      case 't': return '\t';
      case 'r': return '\r';
      case '0': return '\0';
      case 'a': return '\a';
      case 'b': return '\b';
      case 'v': return '\v';
      case 'f': return '\f';
      case 'e': return '\x1b';
      case ' ': return ' ';
      default: Refuse();
    }
  }

  // ---- flow collections ---------------------------------------------------------------------

  /// A flow collection in a block node more indented than `parent`: its lines after the first
  /// must be more indented than that too.
  void FlowCollection(int parent) {
    flow_parent_ = parent;
    if (*p_ == '[') {
      FlowSequence();
    } else {
      FlowMapping();
    }
  }

  void FlowNode() {
    if (++depth_ > kMaxDepth) Refuse();
    if (*p_ == '[') {
      FlowSequence();
    } else if (*p_ == '{') {
      FlowMapping();
    } else {
      Emit(FlowScalar());
    }
    --depth_;
  }

  /// `[a, b, ...]`; a trailing comma, an empty entry or a pair (`[a: b]`) is refused.
  void FlowSequence() {
    doc_->Open(YamlDoc::Kind::kSequence, Here(), YamlDoc::kUntagged);
    ++p_;
    FlowSpace();
    if (*p_ != ']') {
      for (;;) {
        FlowNode();
        FlowSpace();
        if (*p_ == ']') break;
        if (*p_ != ',') Refuse();
        ++p_;
        FlowSpace();
      }
    }
    ++p_;
    doc_->Close();
  }

  /// `{k: v, ...}`; keys are scalars, every key has a value after ': ' on its line.
  void FlowMapping() {
    doc_->Open(YamlDoc::Kind::kMap, Here(), YamlDoc::kUntagged);
    ++p_;
    FlowSpace();
    if (*p_ != '}') {
      for (;;) {
        const Scalar key = FlowScalar();
        if (key.text.size() > kMaxKeyLength) Refuse();
        Emit(key);
        SkipSpaces();
        if (*p_ != ':' || p_[1] != ' ') Refuse();
        ++p_;
        SkipSpaces();
        FlowNode();
        FlowSpace();
        if (*p_ == '}') break;
        if (*p_ != ',') Refuse();
        ++p_;
        FlowSpace();
      }
    }
    ++p_;
    doc_->Close();
  }

  /// Between the entries of a flow collection: spaces, and comments and line breaks when the
  /// next line is more indented than the block the collection is in (and than column 0).
  void FlowSpace() {
    for (;;) {
      SkipSpaces();
      if (*p_ == '#') {
        if (p_ != line_start_ && p_[-1] != ' ') Refuse();
        SkipComment();
      }
      if (*p_ != '\n') return;
      ++p_;
      ++line_;
      line_start_ = p_;
      SkipSpaces();
      if (*p_ != '\n' && *p_ != '#' && (Column() <= flow_parent_ || Column() == 0)) Refuse();
    }
  }

  // ---- output -------------------------------------------------------------------------------

  /// A scalar node as yaml-cpp reports it: an untagged plain `~`, `null`, `Null`, `NULL` is a
  /// null; a quoted scalar has the tag "!".
  void Emit(const Scalar& s) {
    if (s.plain && IsNullText(s.text)) {
      doc_->AddNull(s.mark);
    } else {
      doc_->AddScalar(s.mark, s.plain ? YamlDoc::kUntagged : YamlDoc::kNonSpecific, s.text);
    }
  }

  const char* const begin_;
  const char* const end_;
  const char* p_;
  const char* line_start_;
  int line_ = 0;
  /// The indentation of the line p_ is on after SkipBlankLines; -1 at the end of the text.
  int indent_ = -1;
  int depth_ = 0;
  /// The indentation of the block node the current flow collection is in.
  int flow_parent_ = -1;
  YamlDoc* doc_;
  std::string scratch_;
};

}  // namespace

std::unique_ptr<YamlDoc> ParseYamlSubset(const std::string& text) {
  auto doc = std::make_unique<YamlDoc>();
  doc->Reserve(text.size());
  try {
    SubsetReader(text, doc.get()).Document();
  } catch (const Refusal&) {
    return nullptr;
  }
  return doc;
}

}  // namespace momenta
