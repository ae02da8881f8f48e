#pragma once
/// Tables read in time with events (docs/FORMAT.md, "Tables"): the expressions behind
/// timeTable() (MSL's CombiTimeTable) and booleanTable() (MSL's BooleanTable).
///
/// Both are sums over the table's rows of relations c_r = (x >= t_r). Between events each c_r
/// keeps its value, so the sum reads one segment; a relation of time alone is a time event, so
/// the integrator stops exactly at every table point (never integrating across a kink or a jump),
/// and the left limit at a point is the old segment's value. With y_r, t_r the rows (0-based) and
/// s_r the slope of segment r:
///   LinearSegments:   y = y_0 + s_0 (x - t_0) + sum_{r=1}^{n-2} c_r (s_r - s_{r-1}) (x - t_r)
///                     (LastTwoPoints: the outer segments extend); HoldLastPoint adds the hinges
///                     at both ends that make the slope 0 outside [t_0, t_{n-1}]; a time given
///                     twice (t_r = t_{r+1}) is the jump c_{r+1} (y_{r+1} - y_r), the slope
///                     carrying on across it;
///   ConstantSegments: y = y_0 + sum_{r=1}^{n-1} c_r (y_r - y_{r-1});
///   booleanTable:     y = sum_r (-1)^r c_r: 1 after an odd number of the times, else 0.

#include <cstdint>
#include <vector>

#include "core/expr/expr.h"

namespace momenta {

/// MSL's Modelica.Blocks.Types.Smoothness and Extrapolation, as their enumeration ordinals (the
/// ones momenta implements).
constexpr int kLinearSegments = 1, kConstantSegments = 3;
constexpr int kHoldLastPoint = 1, kLastTwoPoints = 2;

/// The CombiTimeTable look-up of the column that the kTable leaf `table` reads, at x. `jumps[r]`
/// is 1 where t_r = t_{r+1} (one entry per row).
ExprId TimeTableSum(ExprPool* pool, ExprId x, ExprId table, int smoothness, int extrapolation,
                    const std::vector<uint8_t>& jumps);

/// The BooleanTable output (0 or 1) at x for the times in the vector table `table` (a kTable
/// leaf with one column), starting at 0.
ExprId BooleanTableSum(ExprPool* pool, ExprId x, ExprId table);

}  // namespace momenta
