#pragma once
/// A composite type's parts, laid out inside the layout of the type that holds them: each part's
/// names under its path ("mass.s", "links[2].phi"), then its templates rebased to the composite's
/// local indices, with the composite's modifiers in place of the part's defaults. The composite's
/// own connections come after (inner_connections.h).

#include <cstdint>
#include <string>
#include <vector>

#include "core/flatten/flatten_context.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

/// One element of a part of a composite (a component, or one element of a `count:` array).
struct PartPlan {
  const ComponentSpec* spec;
  const TypeLayout* layout;
  std::string path;      ///< relative to the composite: "mass", "links[2]"
  int32_t sub;           ///< its index in the composite's subs
  int32_t sub_base;      ///< where its own subs start in the composite's subs
  double index;          ///< 1-based element index (the modifiers' i), 0 for a single part
  uint32_t first_slot;   ///< its first connector in InnerConnections' slot list
};

/// Lays out the type of every part of `layout`'s type (with `builder`), checks that the parts fit
/// in the memory budget, appends their variables and parameters (and those of their parts) to
/// `layout` under their relative paths, and returns the parts in order.
std::vector<PartPlan> LayoutPartNames(TypeLayout* layout, TypeLayoutBuilder* builder, FlattenContext* context);

/// Appends the parts' templates to `layout`, rebased to its local indices, with the composite's
/// modifiers (expressions of its own names) in place of the parts' defaults.
void LayoutPartTemplates(TypeLayout* layout, const std::vector<PartPlan>& plans);

}  // namespace momenta::flatten_internal
