#pragma once
/// The type scope: expressions written inside a component type, lowered to templates over the
/// type's local indices (equation_template.h). A name there is a local variable, parameter or
/// table of the type (a composite's parts' under their paths: mass.s, links[2].phi), time or pi,
/// or the index i in a part array's modifiers; a subscript is a whole number, fixed when the type
/// is laid out.

#include <optional>
#include <string>

#include "core/flatten/equation_template.h"
#include "core/flatten/lower.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

/// The value of an expression of numbers and the loop index (a part's count, an index inside
/// a type, a range bound inside a type); nothing when it uses any other name.
std::optional<double> ConstantValue(const Ast& a, const LoopIndex* loop);

/// `a`, written in `layout`'s type as `text` at `loc`, as a template. With `params_only` (a
/// parameter's value, a start value) it may use parameters and constants only. `loop`: the
/// element index i of a part array whose modifier it is, else null.
Template MakeTemplate(const TypeLayout& layout, const Ast& a, const std::string& text, const SourceLoc& loc,
                      bool params_only, const LoopIndex* loop = nullptr);

/// An equation of `layout`'s type as the template of its residual, lhs - rhs.
Template EquationTemplate(const TypeLayout& layout, const EquationDecl& e);

}  // namespace momenta::flatten_internal
