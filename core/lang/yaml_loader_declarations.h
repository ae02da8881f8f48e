#pragma once
/// The declarations of a component type or a model as the loader reads them (docs/FORMAT.md):
/// parameters, variables, equations, when-clauses, an impact and the animation's shapes, each
/// from its YAML node, in the vocabulary of core/lang/yaml_loader_values.h.

#include <string>
#include <vector>

#include "core/lang/component_type.h"
#include "core/lang/yaml_loader_values.h"

namespace momenta {

/// Parameter `name` of `owner` (a type or the model): a value, or a mapping with `value:` and
/// `unit:`, `doc:`, `min:`, `max:`, `type:`, `shape:`. A value written with a unit is converted
/// to the declared unit, or gives the parameter its unit when it declares none.
ParameterDecl ReadParameter(const ValueReader& reader, const std::string& name, const YamlNode& n,
                            const std::string& owner);

/// Variable `name` of `owner`: nothing, or a mapping of its attributes.
VariableDecl ReadVariable(const ValueReader& reader, const std::string& name, const YamlNode& n,
                          const std::string& owner);

/// A list of equations `lhs = rhs` (`what`: "equations of Mass"). A component type's list may
/// hold conditional blocks (`- if: c`, `then: [...]`, `else: [...]`), whose places go to
/// `block_locs` (null: blocks are not allowed here).
std::vector<EquationDecl> ReadEquations(const ValueReader& reader, const YamlNode& n,
                                        const std::string& what,
                                        std::vector<SourceLoc>* block_locs = nullptr);

/// `when:`: a list of {when: condition, then: [statements]}, each statement reinit(x, expr) or
/// an assignment `x = expr`.
std::vector<WhenDecl> ReadWhens(const ValueReader& reader, const YamlNode& n,
                                const std::string& what);

/// `impact:` of type `what`: its gap, velocity, force, restitution, contact, release and v_small.
ImpactDecl ReadImpact(const ValueReader& reader, const YamlNode& n, const std::string& what);

/// `animation:`: a list of shapes, each a mapping with `shape:` and that kind's fields.
std::vector<ShapeDecl> ReadAnimation(const ValueReader& reader, const YamlNode& n,
                                     const std::string& what);

}  // namespace momenta
