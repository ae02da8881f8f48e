#pragma once
/// Conditional connectors decided when a component's instances are made. The MSL's Resistor and
/// SpringDamper have a heat port that exists only when `useHeatPort` is true, false by default;
/// left to the passes (core/passes/conditional_connectors.h), every instance makes the port's
/// variables and its equations, and the build then folds `if useHeatPort`, finds the equations
/// that name the absent port and removes them: most of a million-component ladder's structural
/// parameters pass. When nothing can change the condition, it is decided once per type layout:
///   - the condition is a Boolean parameter of the type's own (not an outer one), bound to a
///     number in the type;
///   - the component entry does not modify it, and no `-p` names a parameter of that name;
///   - the connector is the type's own (not a part's), no connection inside the type and no
///     impact names it, and the type has no conditional parts;
///   - the type's equations read the condition only in if-conditions that it decides alone (the
///     passes fold whole conditions of parameters only: `useHeatPort and x` is theirs).
/// The instances then copy the type's equations with the condition as its number, folded
/// (FixLocalParameters), and without those that name the absent connector's variables, which the
/// passes would have removed: the component's own equations that hold only with the connector.
/// Which those are is read from a copy in a pool of its own, which folds as the model's pool does.
/// Whatever does not fit is left to the passes, which stay the reference. The connector's
/// variables and its record (FlatConditionalConnector::decided) are still made: the passes set
/// them to zero, refuse a connection to it and count it, as they do for the others.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/flatten/equation_template.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

/// What a layout's instances copy once some of its conditional connectors are decided.
struct DecidedConditions {
  /// By the layout's own connector: -1 left to the passes, else its decided existence (0 or 1).
  std::vector<int8_t> connector;
  /// How each equation (and initial equation) is copied.
  enum Use : uint8_t { kAsLayout, kFixed, kLeftOut };
  std::vector<Use> equation_use, initial_use;
  /// The equations' templates with the decided conditions fixed (those of kFixed only).
  std::vector<Template> equations, initial_equations;
  /// The if-expressions' conditions each instance folds (counted as the passes count them: one
  /// per distinct condition).
  uint32_t conditions = 0;
  bool Any() const { return std::any_of(connector.begin(), connector.end(), [](int8_t c) { return c >= 0; }); }
};

/// Which of the layout's own conditional connectors a component entry leaves decidable (-1 where
/// not, else the connector's existence from its condition's number): cheap, checked per entry.
/// `param_modifiers` are the entry's modifiers of the layout's parameters (null where none).
std::vector<int8_t> DecidableConnectors(const TypeLayout& layout, const std::vector<const Modifier*>& param_modifiers,
                                        const ParameterOverrides& overrides);

/// The copies of the layout's equations with the `decidable` connectors decided, less those
/// the connections inside the type or the equations' if-expressions leave to the passes;
/// `Any()` is false when none is left. Made once per layout and decision.
DecidedConditions DecideConditions(const TypeLayout& layout, std::vector<int8_t> decidable);

}  // namespace momenta::flatten_internal
