// The values of a file's nodes, read and checked (core/lang/yaml_loader_values.h).

#include "core/lang/yaml_loader_values.h"

#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>

#include "core/lang/arrays.h"
#include "core/lang/parser.h"
#include "core/lang/units.h"

namespace momenta {

void ValueReader::Fail(const YamlNode& n, const std::string& msg) const {
  throw ModelError(Loc(n), msg);
}

double ValueReader::Number(const YamlNode& n, const MessageSubject& what) const {
  std::string s = Scalar(n, what);
  CheckFinite(n, s, what);
  // Decimal only, as in expressions: "0x10" is not 16 here either.
  std::optional<double> v;
  try {
    v = ParseDecimal(s);
  } catch (const UnitError& e) {
    Fail(n, what + ": " + e.what());
  }
  if (!v) Fail(n, what + " must be a decimal number, found '" + s + "'");
  return *v;
}

void ValueReader::CheckFinite(const YamlNode& n, std::string_view s,
                              const MessageSubject& what) const {
  static const std::string_view kNonFinite[] = {".nan", ".NaN",  ".NAN", ".inf", "-.inf",
                                                ".Inf", "-.Inf", "nan",  "NaN",  "inf",
                                                "-inf", "Inf",   "-Inf"};
  if (s.size() < 3 || s.size() > 5) return;  // none of them: the common case, decided at once
  for (std::string_view x : kNonFinite) {
    if (s == x) Fail(n, what + " must be a finite number, found '" + std::string(s) + "'");
  }
}

std::optional<double> ValueReader::OptionalNumber(const YamlNode& map, const char* key,
                                                  const MessageSubject& what) const {
  const YamlNode value = map[key];
  if (!value) return std::nullopt;
  return Number(value, what.Plus(".", key));
}

bool ValueReader::Bool(const YamlNode& n, const MessageSubject& what) const {
  std::string_view s = ScalarText(n, what);
  if (s == "true") return true;
  if (s == "false") return false;
  Fail(n, what + " must be true or false, found '" + std::string(s) + "'");
}

ValueType ValueReader::Type(const YamlNode& n, const MessageSubject& what) const {
  std::string_view s = ScalarText(n, what);
  if (s == "Real") return ValueType::kReal;
  if (s == "Integer") return ValueType::kInteger;
  if (s == "Boolean") return ValueType::kBoolean;
  Fail(n, "unknown type '" + std::string(s) + "' for " + what +
              " (valid types: Real, Integer, Boolean)");
}

int ValueReader::StateSelect(const YamlNode& n, const MessageSubject& what) const {
  static const char* const kChoices[] = {"never", "avoid", "default", "prefer", "always"};
  std::string_view s = ScalarText(n, what.Plus(".stateSelect"));
  for (int k = 0; k < 5; ++k) {
    if (s == kChoices[k]) return k - 2;
  }
  Fail(n, "unknown stateSelect '" + std::string(s) + "' for " + what +
              " (valid choices: never, avoid, default, prefer, always)");
}

std::string ValueReader::ValueText(const YamlNode& n, const MessageSubject& what) const {
  if (!n.IsSequence()) return Scalar(n, what);
  if (n.size() == 0) Fail(n, what + " is an empty list; an array has at least one element");
  std::string s = "[";
  for (size_t k = 0; k < n.size(); ++k) s += (k ? ", " : "") + ValueText(n[k], what);
  return s + "]";
}

Shape ValueReader::ReadShape(const YamlNode& n, const MessageSubject& what, bool open) const {
  if (!n.IsSequence() || n.size() < 1 || n.size() > 2) {
    Fail(n, "the shape of " + what +
                " is a list of one or two sizes, e.g. shape: [2] or shape: [3, 3]");
  }
  Shape shape;
  double elements = 1;
  for (const auto& d : n) {
    if (d.IsScalar() && d.Scalar() == ":") {
      if (!open)
        Fail(d, "the shape of " + what +
                    " has ':', which only a parameter of a component type may have");
      shape.push_back(kOpenSize);
      continue;
    }
    double v = Number(d, "a size in the shape of " + what);
    if (v != std::floor(v) || v < 1)
      Fail(d, "a size in the shape of " + what + " must be a whole number of at least 1");
    elements *= v;
    if (elements > static_cast<double>(kMaxArrayElements)) {
      Fail(n, "the shape of " + what + " has more than " + std::to_string(kMaxArrayElements) +
                  " elements");
    }
    shape.push_back(static_cast<int>(v));
  }
  return shape;
}

AstPtr ValueReader::Expression(const YamlNode& n, const std::string& s,
                               const MessageSubject& what) const {
  CheckFinite(n, s, what);
  if (s.empty()) Fail(n, what + " is empty");
  // (Sharing one tree among the values written the same way, "1e4" in every spring, was tried on
  // the written-out chain: it saved memory only with the flat records reserved at their size, and
  // then cost loading and flattening more CPU than it was worth; bench/RESULTS.md, "a fourth
  // session".)
  try {
    return ParseExpression(s, TextLoc(n));
  } catch (const ModelError& e) {
    // The parser names the place and the text; add whose value it is (spring.c).
    const std::string whose = what.str();
    bool phrase = whose.find(" of ") != std::string::npos;
    throw ModelError(std::string(e.what()) + " (in " + (phrase ? "the " : "") + whose + ")");
  }
}

AstPtr ValueReader::ValueExpression(const YamlNode& n, const std::string& text,
                                    const MessageSubject& what, std::string* unit) const {
  if (n.IsScalar()) {
    std::optional<Quantity> q;
    try {
      q = SplitQuantity(text);
    } catch (const UnitError& e) {
      Fail(n, std::string(e.what()) + ", in the value of " + what);
    }
    if (q) {
      *unit = q->unit;
      auto number = std::make_shared<Ast>();
      number->number = q->value;
      return number;
    }
  }
  return Expression(n, text, what);
}

std::string ValueReader::UnitString(const YamlNode& n, const std::string& what) const {
  std::string unit = Scalar(n, what);
  CheckUnitString(unit, TextLoc(n), "the unit of " + what);
  return unit;
}

std::string ValueReader::Name(const YamlNode& key, const MessageSubject& what) const {
  std::string s = Scalar(key, what);
  bool ok = !s.empty() && !std::isdigit(static_cast<unsigned char>(s[0]));
  for (char c : s) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  if (!ok) {
    Fail(key, what + " '" + s + "' is not a name: use ASCII letters, digits and '_', " +
                  "not starting with a digit");
  }
  return s;
}

}  // namespace momenta
