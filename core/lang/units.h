#pragma once
/// Physical units as Modelica writes them in `unit:` strings (docs/FORMAT.md, "Units"): SI base
/// and derived units with prefixes, products `N.m` or `N*m`, quotients `m/s2` or `m/s^2`, integer
/// exponents `kg.m2`, `s-1`, `1/s`, parentheses `N.m/(rad.s)`, the dimensionless `1`, and the
/// non-SI units engineers use: `deg`, `rpm`, `min`, `h`, `bar`, `degC` (an offset unit).
///
/// A unit is a dimension (exponents of the seven SI base units; the radian and the steradian are
/// dimensionless, as in SI) with a scale and an offset to the coherent SI unit:
/// value_SI = value * factor + offset.
///
/// The loader checks every `unit:` string here and converts a value written with a unit ("40 kg")
/// to its parameter's declared unit; the dimension check of equations is core/lang/unit_check.h.

#include <array>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/base/error.h"
#include "core/lang/ast.h"

namespace momenta {

/// Exponents of m, kg, s, A, K, mol, cd. Exponents are rational in general (sqrt(m2) = m,
/// sqrt(m) = m^0.5); they are kept as doubles and compared to 1e-9.
struct Dimension {
  std::array<double, 7> exponents{};

  bool dimensionless() const;
  bool operator==(const Dimension& o) const;
  bool operator!=(const Dimension& o) const { return !(*this == o); }
  Dimension operator*(const Dimension& o) const;
  Dimension operator/(const Dimension& o) const;
  Dimension Power(double p) const;
};

/// A unit: its dimension and how a value in it converts to the coherent SI unit.
struct Unit {
  Dimension dimension;
  double factor = 1;  ///< value_SI = value * factor + offset
  double offset = 0;  ///< nonzero for degC only
};

/// A unit string that does not parse; the message says where and why.
class UnitError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Parses a unit string ("N.m/rad", "m/s2", "kN/m", "1/s", "degC"). Throws UnitError naming the
/// string and the part that does not parse, e.g. "unknown unit 'mps' in 'mps'".
Unit ParseUnit(const std::string& text);

/// The dimension in the words of its most common unit ("N", "m/s", "N.m", "1"), else in SI base
/// units ("kg.m2/s3").
std::string DimensionText(const Dimension& d);

/// A number with a unit, as a value may be written: "10kN/m", "2500 g", "-5 degC", "40 kg".
struct Quantity {
  double value = 0;
  std::string unit;  ///< as written, e.g. "kN/m"
};

/// Splits `text` into a number and a unit string when it is one (the unit must parse); nullopt
/// for a plain number or anything else (an expression such as "2*m").
std::optional<Quantity> SplitQuantity(const std::string& text);

/// The number `text` is when it is a decimal number as values are written: [sign] digits
/// [. digits] [e [sign] digits], nothing before or after (no hex, inf, nan or spaces); nullopt
/// otherwise. Throws UnitError naming the text when it is one outside double's range: above
/// 1.8e308, or below the smallest normal double 2.2e-308 but not zero (a subnormal keeps only a
/// few digits).
std::optional<double> ParseDecimal(const std::string& text);

/// `value` in unit `from` expressed in unit `to`. Throws UnitError when the dimensions differ:
/// "kN/m (N/m) cannot be converted to kg (kg)", or when the result is outside double's range.
double ConvertValue(double value, const std::string& from, const std::string& to);

/// The number `value` written in `unit` as a number in `target_unit` (docs/FORMAT.md, "Units"),
/// as an expression tree. Throws ModelError at `loc` naming `who` and both units when the
/// dimensions differ or the target declares no unit.
AstPtr ValueInUnit(double value, const std::string& unit, const std::string& target_unit,
                   const std::string& who, const SourceLoc& loc);

/// Parses `unit` and throws ModelError at `loc` when it does not parse (the loader's check of
/// every `unit:` string).
void CheckUnitString(const std::string& unit, const SourceLoc& loc, const std::string& what);

}  // namespace momenta
