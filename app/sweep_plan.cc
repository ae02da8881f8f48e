#include "app/sweep_plan.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <random>
#include <set>

#include "app/csv_writer.h"
#include "core/base/error.h"
#include "core/lang/units.h"

namespace momenta {

namespace {

/// A decimal number (as in expressions: no hex, inf or nan), true or false; nullopt otherwise.
/// Throws UnitError naming a number outside double's range.
std::optional<double> Number(const std::string& text) {
  if (text == "true") return 1.0;
  if (text == "false") return 0.0;
  return ParseDecimal(text);
}

std::vector<std::string> Split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  size_t begin = 0;
  while (true) {
    size_t end = text.find(sep, begin);
    parts.push_back(text.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return parts;
}

std::string Trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

/// A uniform number in [0, 1) from 53 bits of the engine's output.
double Unit(std::mt19937_64& engine) { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }

/// One draw of `axis` (a distribution).
double Draw(const SweepAxis& axis, std::mt19937_64& engine) {
  if (axis.kind == SweepAxis::Kind::kUniform) {
    const double u = Unit(engine);
    // b - a overflows only when a and b have opposite signs; then the weighted sum cannot.
    if (std::isfinite(axis.b - axis.a)) return axis.a + (axis.b - axis.a) * u;
    return axis.a * (1 - u) + axis.b * u;
  }
  // Box-Muller, cosine branch; u1 in (0, 1] so its logarithm is finite.
  const double u1 = 1.0 - Unit(engine), u2 = Unit(engine);
  return axis.a + axis.b * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

SweepAxis ParseSweepAxis(const std::string& text) {
  SweepAxis axis;
  size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw UsageError("-p takes NAME=SPEC (a value, a list a,b,c, a grid a:b:n or a:b:log:n, normal(mu,sigma) "
                     "or uniform(a,b)), found '" + text + "'");
  }
  axis.name = text.substr(0, eq);
  axis.spec = text.substr(eq + 1);
  const std::string& spec = axis.spec;
  auto fail = [&](const std::string& why) -> UsageError { return UsageError("-p " + text + ": " + why); };
  auto number = [&](const std::string& part, const std::string& what) {
    std::optional<double> v;
    try {
      v = Number(Trim(part));
    } catch (const UnitError& e) {
      throw fail(std::string(e.what()) + ", in " + what);
    }
    if (!v) throw fail(what + " '" + part + "' is not a decimal number");
    return *v;
  };
  // Distributions.
  for (auto [prefix, kind] : {std::pair{"normal(", SweepAxis::Kind::kNormal}, std::pair{"uniform(", SweepAxis::Kind::kUniform}}) {
    if (spec.rfind(prefix, 0) != 0) continue;
    const std::string what = kind == SweepAxis::Kind::kNormal ? "normal(mu,sigma)" : "uniform(a,b)";
    if (spec.back() != ')') throw fail(what + " must end with ')'");
    std::vector<std::string> args = Split(spec.substr(std::strlen(prefix), spec.size() - std::strlen(prefix) - 1), ',');
    if (args.size() != 2) throw fail(what + " takes two numbers");
    axis.kind = kind;
    axis.a = number(args[0], kind == SweepAxis::Kind::kNormal ? "the mean" : "the lower bound");
    axis.b = number(args[1], kind == SweepAxis::Kind::kNormal ? "the standard deviation" : "the upper bound");
    if (kind == SweepAxis::Kind::kNormal && !(axis.b >= 0)) throw fail("the standard deviation must not be negative");
    if (kind == SweepAxis::Kind::kUniform && !(axis.b >= axis.a)) throw fail("the upper bound is below the lower bound");
    return axis;
  }
  // Grids.
  if (spec.find(':') != std::string::npos) {
    std::vector<std::string> parts = Split(spec, ':');
    const bool log = parts.size() == 4 && Trim(parts[2]) == "log";
    if (!(parts.size() == 3 || log)) throw fail("a grid is a:b:n (linear) or a:b:log:n (logarithmic)");
    const double a = number(parts[0], "the grid's start"), b = number(parts[1], "the grid's end");
    const std::string count_text = Trim(parts.back());
    std::optional<double> count;
    try {
      count = Number(count_text);
    } catch (const UnitError&) {
      // out of range: refused below as not a count
    }
    if (!count || *count != std::floor(*count) || *count < 1 || *count > static_cast<double>(kMaxSweepRuns)) {
      throw fail("the number of grid points '" + count_text + "' is not a whole number from 1 to " +
                 std::to_string(kMaxSweepRuns));
    }
    const size_t n = static_cast<size_t>(*count);
    if (log && !(a > 0 && b > 0)) throw fail("a logarithmic grid needs a positive start and end");
    if (n == 1 && a != b) throw fail("a grid of one point from " + FormatDouble(a) + " to " + FormatDouble(b) + " is ambiguous; give the value alone");
    for (size_t k = 0; k < n; ++k) {
      // The ends exactly as given.
      if (k == 0) {
        axis.values.push_back(a);
      } else if (k + 1 == n) {
        axis.values.push_back(b);
      } else {
        const double f = static_cast<double>(k) / static_cast<double>(n - 1);
        axis.values.push_back(log ? std::exp(std::log(a) + (std::log(b) - std::log(a)) * f) : a + (b - a) * f);
      }
    }
    return axis;
  }
  // A value or a list.
  for (const std::string& part : Split(spec, ',')) axis.values.push_back(number(part, "the value"));
  return axis;
}

std::string SeedProblem(const std::string& text) {
  // CLI11 would saturate 2^64 to 2^64 - 1 and read -1 as 2^64 - 1.
  bool digits = !text.empty() && text.size() <= 20;
  for (char c : text) digits = digits && std::isdigit(static_cast<unsigned char>(c));
  errno = 0;
  if (digits) std::strtoull(text.c_str(), nullptr, 10);
  if (digits && errno != ERANGE) return "";
  return "the seed '" + text + "' is not a whole number from 0 to 18446744073709551615 (2^64 - 1)";
}

std::string TrajectoriesProblem(const std::string& text) {
  if (!text.empty()) return "";
  return "the directory name is empty; give the directory for run-<k>.csv, or leave the option out";
}

SweepPlan MakeSweepPlan(const std::vector<SweepAxis>& axes, size_t samples, uint64_t seed) {
  SweepPlan plan;
  std::set<std::string> seen;
  std::vector<size_t> grid, random;  // axes that are values (one or more), distributions
  for (size_t j = 0; j < axes.size(); ++j) {
    if (!seen.insert(axes[j].name).second) throw UsageError("-p " + axes[j].name + " is given twice");
    plan.names.push_back(axes[j].name);
    (axes[j].kind == SweepAxis::Kind::kValues ? grid : random).push_back(j);
  }
  if (!random.empty() && samples == 0) {
    throw UsageError("-p " + axes[random[0]].name + "=" + axes[random[0]].spec +
                     " is a distribution: give the number of draws with --samples K");
  }
  if (random.empty() && samples > 0) {
    throw UsageError("--samples " + std::to_string(samples) +
                     ": no -p is a distribution (normal(mu,sigma) or uniform(a,b)) to draw from");
  }
  const size_t draws = random.empty() ? 1 : samples;
  size_t grid_points = 1;
  for (size_t j : grid) {
    if (axes[j].values.size() > kMaxSweepRuns / grid_points) {
      throw UsageError("the sweep has more than " + std::to_string(kMaxSweepRuns) + " runs");
    }
    grid_points *= axes[j].values.size();
  }
  if (draws > kMaxSweepRuns / grid_points) {
    throw UsageError("the sweep has more than " + std::to_string(kMaxSweepRuns) + " runs (" +
                     std::to_string(grid_points) + " grid points x " + std::to_string(draws) + " samples)");
  }
  // The draws, all up front: sample s draws the distributions in -p order.
  std::mt19937_64 engine(seed);
  std::vector<std::vector<double>> drawn(draws, std::vector<double>(random.size()));
  if (!random.empty()) {
    for (size_t s = 0; s < draws; ++s) {
      for (size_t r = 0; r < random.size(); ++r) {
        const SweepAxis& axis = axes[random[r]];
        drawn[s][r] = Draw(axis, engine);
        if (!std::isfinite(drawn[s][r])) {
          throw UsageError("-p " + axis.name + "=" + axis.spec + ": draw " + std::to_string(s + 1) +
                           " is " + FormatDouble(drawn[s][r]) +
                           ", outside double's range; give a smaller standard deviation");
        }
      }
    }
  }
  plan.values.reserve(grid_points * draws);
  for (size_t g = 0; g < grid_points; ++g) {
    std::vector<double> row(axes.size());
    // Row-major over the grid axes: the last one varies fastest.
    size_t rest = g;
    for (size_t i = grid.size(); i-- > 0;) {
      const std::vector<double>& v = axes[grid[i]].values;
      row[grid[i]] = v[rest % v.size()];
      rest /= v.size();
    }
    for (size_t s = 0; s < draws; ++s) {
      for (size_t r = 0; r < random.size(); ++r) row[random[r]] = drawn[s][r];
      plan.values.push_back(row);
    }
  }
  return plan;
}

}  // namespace momenta
