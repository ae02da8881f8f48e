// Unit strings (Modelica's syntax, as MSL uses it) parsed into a dimension and a conversion to SI.
//
// Grammar, after the Modelica specification's unit expressions, with the spellings engineers also
// write (`*` for `.`, `^` before an exponent, a chain of `/`):
//   unit     := "1" | product { "/" product }          a/b/c = a/(b.c)
//   product  := factor { ("." | "*") factor }
//   factor   := ( symbol | "(" unit ")" | "1" ) [ ["^"] ["+" | "-"] digits ]
//   symbol   := [prefix] name                           a whole name wins: "min", "cd", "Pa"
// A value converts as value_SI = value * factor + offset; only degC has an offset, and it may not
// be combined with other units (K.m is fine, degC.m has no meaning).

#include "core/lang/units.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <utility>
#include <vector>

#include "core/base/limits.h"
#include "core/base/messages.h"
#include "core/lang/parser.h"

namespace momenta {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kExponentTolerance = 1e-9;
constexpr const char* kDoubleRangeText =
    "magnitudes from 2.2e-308, the smallest normal double, to 1.8e308; a subnormal keeps only a "
    "few digits";

enum Base { kMetre, kKilogram, kSecond, kAmpere, kKelvin, kMole, kCandela };

Dimension Dim(std::initializer_list<std::pair<Base, int>> exps) {
  Dimension d;
  for (auto [b, e] : exps) d.exponents[b] = e;
  return d;
}

struct NamedUnit {
  Unit unit;
  bool prefixable;
};

/// Every unit name a `unit:` string may use, with its dimension and factor to SI.
const std::map<std::string, NamedUnit>& UnitTable() {
  static const std::map<std::string, NamedUnit> table = [] {
    std::map<std::string, NamedUnit> t;
    auto add = [&](const char* name, Dimension d, double factor, bool prefixable,
                   double offset = 0) {
      t[name] = {Unit{d, factor, offset}, prefixable};
    };
    const Dimension none;
    // SI base units (the kilogram through the gram, which takes the prefixes).
    add("m", Dim({{kMetre, 1}}), 1, true);
    add("g", Dim({{kKilogram, 1}}), 1e-3, true);
    add("kg", Dim({{kKilogram, 1}}), 1, false);
    add("s", Dim({{kSecond, 1}}), 1, true);
    add("A", Dim({{kAmpere, 1}}), 1, true);
    add("K", Dim({{kKelvin, 1}}), 1, true);
    add("mol", Dim({{kMole, 1}}), 1, true);
    add("cd", Dim({{kCandela, 1}}), 1, true);
    // SI derived units; rad and sr are dimensionless, as in SI.
    add("rad", none, 1, true);
    add("sr", none, 1, false);
    add("Hz", Dim({{kSecond, -1}}), 1, true);
    add("N", Dim({{kKilogram, 1}, {kMetre, 1}, {kSecond, -2}}), 1, true);
    add("Pa", Dim({{kKilogram, 1}, {kMetre, -1}, {kSecond, -2}}), 1, true);
    add("J", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -2}}), 1, true);
    add("W", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -3}}), 1, true);
    add("C", Dim({{kAmpere, 1}, {kSecond, 1}}), 1, true);
    add("V", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -3}, {kAmpere, -1}}), 1, true);
    add("F", Dim({{kKilogram, -1}, {kMetre, -2}, {kSecond, 4}, {kAmpere, 2}}), 1, true);
    add("Ohm", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -3}, {kAmpere, -2}}), 1, true);
    add("ohm", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -3}, {kAmpere, -2}}), 1, true);
    add("S", Dim({{kKilogram, -1}, {kMetre, -2}, {kSecond, 3}, {kAmpere, 2}}), 1, true);
    add("Wb", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -2}, {kAmpere, -1}}), 1, true);
    add("T", Dim({{kKilogram, 1}, {kSecond, -2}, {kAmpere, -1}}), 1, true);
    add("H", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -2}, {kAmpere, -2}}), 1, true);
    add("lm", Dim({{kCandela, 1}}), 1, true);
    add("lx", Dim({{kCandela, 1}, {kMetre, -2}}), 1, true);
    add("Bq", Dim({{kSecond, -1}}), 1, true);
    add("Gy", Dim({{kMetre, 2}, {kSecond, -2}}), 1, true);
    add("Sv", Dim({{kMetre, 2}, {kSecond, -2}}), 1, true);
    add("kat", Dim({{kMole, 1}, {kSecond, -1}}), 1, true);
    // Units outside SI that Modelica libraries and engineers use.
    add("deg", none, kPi / 180, false);
    add("rev", none, 2 * kPi, false);
    add("rpm", Dim({{kSecond, -1}}), 2 * kPi / 60, false);
    add("min", Dim({{kSecond, 1}}), 60, false);
    add("h", Dim({{kSecond, 1}}), 3600, false);
    add("d", Dim({{kSecond, 1}}), 86400, false);
    add("bar", Dim({{kKilogram, 1}, {kMetre, -1}, {kSecond, -2}}), 1e5, true);
    add("l", Dim({{kMetre, 3}}), 1e-3, true);
    add("L", Dim({{kMetre, 3}}), 1e-3, true);
    add("Wh", Dim({{kKilogram, 1}, {kMetre, 2}, {kSecond, -2}}), 3600, true);
    add("degC", Dim({{kKelvin, 1}}), 1, false, 273.15);
    return t;
  }();
  return table;
}

const std::map<std::string, double>& Prefixes() {
  static const std::map<std::string, double> p = {
      {"Y", 1e24}, {"Z", 1e21},  {"E", 1e18},  {"P", 1e15},  {"T", 1e12},  {"G", 1e9},  {"M", 1e6},
      {"k", 1e3},  {"h", 1e2},   {"da", 1e1},  {"d", 1e-1},  {"c", 1e-2},  {"m", 1e-3}, {"u", 1e-6},
      {"n", 1e-9}, {"p", 1e-12}, {"f", 1e-15}, {"a", 1e-18}, {"z", 1e-21}, {"y", 1e-24}};
  return p;
}

/// Recursive-descent parser over one unit string.
class UnitParser {
 public:
  explicit UnitParser(const std::string& text) : text_(text) {}

  Unit Parse() {
    if (text_.empty()) Fail("an empty unit string (write \"1\" for a dimensionless quantity)");
    Unit u = Quotient();
    if (pos_ != text_.size()) Fail("unexpected '" + std::string(1, text_[pos_]) + "'");
    if (offset_combined_) {
      Fail("degC is an offset unit and cannot be combined with other units (use K)");
    }
    if (!std::isnormal(u.factor)) Fail("its scale to SI units is outside double's range");
    return u;
  }

 private:
  [[noreturn]] void Fail(const std::string& why) const {
    std::string at = pos_ < text_.size() ? " at character " + std::to_string(pos_ + 1) : "";
    const std::string unit = Excerpt(text_, static_cast<int>(pos_));
    throw UnitError("unit '" + unit + "' does not parse: " + why + at +
                    " (write units as Modelica does: m/s2, N.m, kg.m2, 1/s, rad/s, degC)");
  }

  bool Peek(char c) const { return pos_ < text_.size() && text_[pos_] == c; }

  Unit Quotient() {
    Unit u = Product();
    while (Peek('/')) {
      ++pos_;
      Unit d = Product();
      offset_combined_ = offset_combined_ || u.offset != 0 || d.offset != 0;
      u = {u.dimension / d.dimension, u.factor / d.factor, 0};
    }
    return u;
  }

  Unit Product() {
    Unit u = Factor();
    while (Peek('.') || Peek('*')) {
      ++pos_;
      Unit f = Factor();
      offset_combined_ = offset_combined_ || u.offset != 0 || f.offset != 0;
      u = {u.dimension * f.dimension, u.factor * f.factor, 0};
    }
    return u;
  }

  Unit Factor() {
    Unit u;
    if (Peek('(')) {
      // Parentheses are the one recursion: bounded as an expression's are.
      if (++depth_ > kMaxNestingDepth) Fail(NestedTooDeep("parentheses"));
      ++pos_;
      u = Quotient();
      if (!Peek(')')) Fail("a missing ')'");
      ++pos_;
      --depth_;
    } else if (Peek('1')) {
      ++pos_;
      return u;  // the dimensionless 1 takes no exponent
    } else {
      size_t start = pos_;
      while (pos_ < text_.size() && std::isalpha(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      if (start == pos_)
        Fail(pos_ < text_.size() ? "expected a unit name" : "a unit name is missing at the end");
      u = Symbol(text_.substr(start, pos_ - start), start);
    }
    // An exponent: m2, s-1, m^2, s^-2.
    bool caret = Peek('^');
    if (caret) ++pos_;
    int sign = 1;
    if (Peek('-') || Peek('+')) {
      sign = Peek('-') ? -1 : 1;
      ++pos_;
    }
    size_t start = pos_;
    while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    if (start == pos_) {
      if (caret || sign < 0) Fail("an exponent must be a whole number");
      return u;
    }
    int e = sign * std::stoi(text_.substr(start, std::min<size_t>(pos_ - start, 3)));
    if (u.offset != 0) offset_combined_ = true;
    return {u.dimension.Power(e), std::pow(u.factor, e), 0};
  }

  Unit Symbol(const std::string& name, size_t start) {
    const auto& table = UnitTable();
    auto whole = table.find(name);
    if (whole != table.end()) return whole->second.unit;
    for (const auto& [prefix, scale] : Prefixes()) {
      if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
      auto rest = table.find(name.substr(prefix.size()));
      if (rest != table.end() && rest->second.prefixable) {
        Unit u = rest->second.unit;
        u.factor *= scale;
        return u;
      }
    }
    pos_ = start;
    Fail("unknown unit '" + name + "'");
  }

  const std::string& text_;
  size_t pos_ = 0;
  int depth_ = 0;  ///< parentheses open at pos_
  bool offset_combined_ = false;
};

std::string ExponentText(double e) {
  std::ostringstream s;
  if (std::fabs(e - std::round(e)) < kExponentTolerance) {
    s << static_cast<long>(std::round(e));
  } else {
    s << "^" << e;
  }
  return s.str();
}

}  // namespace

bool Dimension::dimensionless() const {
  for (double e : exponents) {
    if (std::fabs(e) > kExponentTolerance) return false;
  }
  return true;
}

bool Dimension::operator==(const Dimension& o) const {
  for (size_t k = 0; k < exponents.size(); ++k) {
    if (std::fabs(exponents[k] - o.exponents[k]) > kExponentTolerance) return false;
  }
  return true;
}

Dimension Dimension::operator*(const Dimension& o) const {
  Dimension d;
  for (size_t k = 0; k < exponents.size(); ++k) d.exponents[k] = exponents[k] + o.exponents[k];
  return d;
}

Dimension Dimension::operator/(const Dimension& o) const {
  Dimension d;
  for (size_t k = 0; k < exponents.size(); ++k) d.exponents[k] = exponents[k] - o.exponents[k];
  return d;
}

Dimension Dimension::Power(double p) const {
  Dimension d;
  for (size_t k = 0; k < exponents.size(); ++k) d.exponents[k] = exponents[k] * p;
  return d;
}

Unit ParseUnit(const std::string& text) { return UnitParser(text).Parse(); }

std::string DimensionText(const Dimension& d) {
  // The names engineers read, most common first: the first whose dimension matches is shown.
  static const std::vector<std::pair<Dimension, std::string>> kNamed = [] {
    std::vector<std::pair<Dimension, std::string>> v;
    for (const char* s :
         {"1",    "m",     "kg",  "s",     "A",    "K",     "mol", "cd",  "m/s", "m/s2",
          "N",    "N.m",   "W",   "V",     "Ohm",  "F",     "H",   "C",   "Pa",  "1/s",
          "1/s2", "kg.m2", "N/m", "N.s/m", "N.s",  "N.m.s", "m2",  "m3",  "Wb",  "T",
          "S",    "kg/m3", "W/K", "J/K",   "m/s3", "N/s",   "V/s", "A/s", "K/s", "W/s"}) {
      v.emplace_back(ParseUnit(s).dimension, s);
    }
    return v;
  }();
  for (const auto& [dim, name] : kNamed) {
    if (dim == d) return name;
  }
  // SI base units: kg.m2/(s3.A).
  static const char* const kBase[] = {"m", "kg", "s", "A", "K", "mol", "cd"};
  std::vector<std::string> num, den;
  for (size_t k = 0; k < d.exponents.size(); ++k) {
    double e = d.exponents[k];
    if (std::fabs(e) < kExponentTolerance) continue;
    std::string exp = ExponentText(std::fabs(e));
    (e > 0 ? num : den).push_back(kBase[k] + (exp == "1" ? "" : exp));
  }
  auto join = [](const std::vector<std::string>& parts) {
    std::string s;
    for (const auto& p : parts) s += (s.empty() ? "" : ".") + p;
    return s;
  };
  std::string out = num.empty() ? "1" : join(num);
  if (den.size() == 1) out += "/" + den[0];
  if (den.size() > 1) out += "/(" + join(den) + ")";
  return out;
}

std::optional<Quantity> SplitQuantity(const std::string& text) {
  // The number: [sign] digits [. digits] [e [sign] digits], as a YAML or command-line value.
  size_t b = 0, e = text.size();
  while (b < e && std::isspace(static_cast<unsigned char>(text[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
  size_t k = b;
  auto digits = [&] {
    size_t from = k;
    while (k < e && std::isdigit(static_cast<unsigned char>(text[k]))) ++k;
    return k - from;
  };
  if (k < e && (text[k] == '+' || text[k] == '-')) ++k;
  size_t mantissa = digits();
  if (k < e && text[k] == '.') {
    ++k;
    mantissa += digits();
  }
  if (mantissa == 0) return std::nullopt;
  if (k + 1 < e && (text[k] == 'e' || text[k] == 'E')) {
    size_t save = k++;
    if (k < e && (text[k] == '+' || text[k] == '-')) ++k;
    if (digits() == 0) k = save;  // "5 eV" is not an exponent
  }
  const size_t number_end = k;
  while (k < e && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
  // The unit: starts with a letter (or "1/") and holds only the characters of unit strings.
  if (k == e) return std::nullopt;
  bool unit_like = std::isalpha(static_cast<unsigned char>(text[k])) ||
                   (k > number_end && text.compare(k, 2, "1/") == 0);
  for (size_t j = k; j < e && unit_like; ++j) {
    char c = text[j];
    unit_like = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '*' || c == '/' ||
                c == '^' || c == '(' || c == ')' || c == '-' || c == '+';
  }
  if (!unit_like) return std::nullopt;
  Quantity q;
  q.value = *ParseDecimal(text.substr(b, number_end - b));
  q.unit = text.substr(k, e - k);
  ParseUnit(q.unit);  // a unit that does not parse is an error, not an expression
  return q;
}

double ConvertValue(double value, const std::string& from, const std::string& to) {
  Unit f = ParseUnit(from), t = ParseUnit(to);
  if (f.dimension != t.dimension) {
    throw UnitError(from + " (" + DimensionText(f.dimension) + ") cannot be converted to " + to +
                    " (" + DimensionText(t.dimension) + ")");
  }
  const double converted = (value * f.factor + f.offset - t.offset) / t.factor;
  // Beyond the range, or below it: a subnormal, or zero from a nonzero value (not -273.15 degC).
  const bool underflow =
      converted != 0 ? !std::isnormal(converted) : value != 0 && f.offset == t.offset;
  if (!std::isfinite(converted) || underflow) {
    throw UnitError(NumberText(value) + " " + from + " is " + NumberText(converted) + " " + to +
                    ", outside double's range (" + kDoubleRangeText + ")");
  }
  return converted;
}

std::optional<double> ParseDecimal(const std::string& text) {
  // The syntax first: strtod also reads hex, inf, nan and leading spaces.
  size_t k = 0;
  auto digits = [&] {
    const size_t from = k;
    while (k < text.size() && std::isdigit(static_cast<unsigned char>(text[k]))) ++k;
    return k - from;
  };
  if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
  size_t mantissa = digits();
  if (k < text.size() && text[k] == '.') {
    ++k;
    mantissa += digits();
  }
  if (mantissa == 0) return std::nullopt;
  const size_t exponent_at = k;
  if (k < text.size() && (text[k] == 'e' || text[k] == 'E')) {
    ++k;
    if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
    if (digits() == 0) return std::nullopt;
  }
  if (k != text.size()) return std::nullopt;
  // The range: strtod sets ERANGE on overflow (inf) and on underflow (a subnormal or zero).
  errno = 0;
  const double v = std::strtod(text.c_str(), nullptr);
  const bool zero =
      text.substr(0, exponent_at).find_first_of("123456789") == std::string::npos;
  if (!zero && (errno == ERANGE || !std::isnormal(v))) {
    throw UnitError("the number " + text + " is outside double's range (" + kDoubleRangeText +
                    ")");
  }
  return v;
}

AstPtr ValueInUnit(double value, const std::string& unit, const std::string& target_unit,
                   const std::string& who, const SourceLoc& loc) {
  if (target_unit.empty()) {
    throw ModelError(loc, who + " declares no unit, so a value in " + unit +
                              " cannot be converted; give it as a plain number");
  }
  auto number = std::make_shared<Ast>();
  try {
    number->number = ConvertValue(value, unit, target_unit);
  } catch (const UnitError& e) {
    throw ModelError(loc, "the value of " + who + " is in " + unit + ", but " + who + " is in " +
                              target_unit + ": " + e.what());
  }
  return number;
}

void CheckUnitString(const std::string& unit, const SourceLoc& loc, const std::string& what) {
  try {
    ParseUnit(unit);
  } catch (const UnitError& e) {
    throw ModelError(loc, std::string(e.what()) + ", in " + what);
  }
}

}  // namespace momenta
