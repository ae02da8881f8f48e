#pragma once
/// The loader's vocabulary (core/lang/yaml_loader.h): the values a model or library file holds —
/// numbers, booleans, names, expressions, units, shapes, types — read out of the nodes of one
/// file's YAML document and checked, each error at its file:line:col with whose value it is, what
/// was expected and what was found (the valid keys for an unknown key). The readers of the
/// declarations, the types, the parts and the model (yaml_loader_*.h) are written in it.

#include <array>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/lang/ast.h"
#include "core/lang/component_type.h"
#include "core/lang/yaml_tree.h"

namespace momenta {

/// Whose value a message is about ("start of mass1.s"): its pieces, put together only when a
/// message is made. A file of 100 000 components has a few such descriptions per component and,
/// usually, no error. The pieces are views: a subject lives no longer than the call it is passed
/// to.
class MessageSubject {
 public:
  MessageSubject(const char* text) : parts_{text}, size_(1) {}         // NOLINT: as a string
  MessageSubject(const std::string& text) : parts_{text}, size_(1) {}  // NOLINT: as a string
  MessageSubject(std::initializer_list<std::string_view> parts) : size_(0) {
    for (std::string_view p : parts) Add(p);
  }
  /// This subject with `more` appended ("mass1.s" + ".fixed").
  MessageSubject Plus(std::string_view a, std::string_view b = {}) const {
    MessageSubject more = *this;
    more.Add(a);
    more.Add(b);
    return more;
  }
  std::string str() const {
    std::string s;
    for (size_t k = 0; k < size_; ++k) s += parts_[k];
    return s;
  }

 private:
  void Add(std::string_view p) {
    if (p.empty()) return;
    MOMENTA_CHECK(size_ < parts_.size());
    parts_[size_++] = p;
  }
  std::array<std::string_view, 6> parts_;
  size_t size_;
};

inline std::string operator+(const MessageSubject& a, const char* b) { return a.str() + b; }
inline std::string operator+(const std::string& a, const MessageSubject& b) { return a + b.str(); }
inline std::string operator+(const char* a, const MessageSubject& b) { return a + b.str(); }

/// Reads the values of one file's nodes. `what` arguments name the value in messages.
class ValueReader {
 public:
  explicit ValueReader(std::string file) : file_(std::move(file)) { file_loc_.set_file(file_); }

  const std::string& file() const { return file_; }

  /// Where a node starts.
  SourceLoc Loc(const YamlNode& n) const {
    SourceLoc l = file_loc_;  // the file name interned once, not at every place
    const YamlMark m = n.Mark();
    if (m.line >= 0) {
      l.line = m.line + 1;
      l.column = m.column + 1;
    }
    return l;
  }

  /// Where the text of a scalar starts (after the opening quote of a quoted scalar).
  SourceLoc TextLoc(const YamlNode& n) const {
    SourceLoc l = Loc(n);
    if (n.Tag() == "!") l.column += 1;
    return l;
  }

  [[noreturn]] void Fail(const YamlNode& n, const std::string& msg) const;

  void ExpectMap(const YamlNode& n, const MessageSubject& what) const {
    if (!n.IsMap()) Fail(n, what + " must be a mapping of keys to values");
  }

  /// Every key of mapping `n` is one of `allowed`; an unknown key is an error listing them.
  void CheckKeys(const YamlNode& n, const MessageSubject& what,
                 std::initializer_list<std::string_view> allowed) const {
    CheckKeys(n, what, allowed.begin(), allowed.end());
  }
  void CheckKeys(const YamlNode& n, const MessageSubject& what,
                 const std::vector<std::string>& allowed) const {
    CheckKeys(n, what, allowed.begin(), allowed.end());
  }
  template <typename It>
  void CheckKeys(const YamlNode& n, const MessageSubject& what, It begin, It end) const {
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string_view key = it->first.AsText();
      bool ok = false;
      for (It a = begin; a != end && !ok; ++a) ok = *a == key;
      if (!ok) {
        Fail(it->first, "unknown key '" + std::string(key) + "' in " + what + " (valid keys: " +
                            JoinNames(std::vector<std::string>(begin, end)) + ")");
      }
    }
  }

  /// The text of a scalar, a view into the document.
  std::string_view ScalarText(const YamlNode& n, const MessageSubject& what) const {
    if (!n.IsScalar()) Fail(n, what + " must be a single value, not a list or mapping");
    return n.Scalar();
  }
  std::string Scalar(const YamlNode& n, const MessageSubject& what) const {
    return std::string(ScalarText(n, what));
  }

  /// A finite number.
  double Number(const YamlNode& n, const MessageSubject& what) const;
  /// The number of `map[key]`, or nullopt when the key is not there.
  std::optional<double> OptionalNumber(const YamlNode& map, const char* key,
                                       const MessageSubject& what) const;
  /// `true` or `false`.
  bool Bool(const YamlNode& n, const MessageSubject& what) const;
  /// `Real`, `Integer` or `Boolean`.
  ValueType Type(const YamlNode& n, const MessageSubject& what) const;
  /// `stateSelect:` (MSL's StateSelect) as a priority: never -2, avoid -1, default 0, prefer 1,
  /// always 2.
  int StateSelect(const YamlNode& n, const MessageSubject& what) const;

  /// The text of a value: a scalar as written, a list (`[0.5, 4]`, a matrix as a list of rows)
  /// as the array literal it stands for.
  std::string ValueText(const YamlNode& n, const MessageSubject& what) const;

  /// `shape: [2]` or `shape: [3, 3]`: one or two whole numbers of at least 1. With `open`, a
  /// size may be ":" (kOpenSize): the parameter's value gives it (`shape: [":", 2]`).
  Shape ReadShape(const YamlNode& n, const MessageSubject& what, bool open = false) const;

  /// The expression of a value.
  AstPtr Expression(const YamlNode& n, const MessageSubject& what) const {
    return Expression(n, ValueText(n, what), what);
  }
  /// The expression of a value whose text (ValueText) is `s`.
  AstPtr Expression(const YamlNode& n, const std::string& s, const MessageSubject& what) const;

  /// A value as an expression, from its text (ValueText); a number written with a unit ("40 kg",
  /// "10kN/m") is the number, and `*unit` receives the unit for the caller to convert
  /// (core/lang/units.h).
  AstPtr ValueExpression(const YamlNode& n, const std::string& text, const MessageSubject& what,
                         std::string* unit) const;

  /// A `unit:` string, checked to parse (an error at its place otherwise).
  std::string UnitString(const YamlNode& n, const std::string& what) const;

  /// The key of a component, parameter or variable the model's expressions refer to: a name as
  /// the expression parser reads it (ASCII letters, digits and '_', not starting with a digit).
  std::string Name(const YamlNode& key, const MessageSubject& what) const;

 private:
  /// A number that is not finite (`.nan`, `.inf`, …) is an error.
  void CheckFinite(const YamlNode& n, std::string_view s, const MessageSubject& what) const;

  std::string file_;
  SourceLoc file_loc_;  ///< no place yet: the file
};

}  // namespace momenta
