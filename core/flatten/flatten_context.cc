// The shared record of flattening: its start (the model's own types collected, each once) and
// the look-ups every job makes.

#include "core/flatten/flatten_context.h"

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/flatten/deferred_aliases.h"

namespace momenta::flatten_internal {

FlattenContext::FlattenContext(const ModelSpec& spec, const Library& library,
                               const ParameterOverrides& overrides, bool defer_equations)
    : spec(spec), library(library), overrides(overrides) {
  flat.pool = std::make_shared<ExprPool>();
  if (defer_equations) deferred = std::make_shared<DeferredAliases>(flat.pool);
  flat.model_name = spec.name;
  flat.file = spec.file;
  flat.experiment = spec.experiment;
  for (const auto& defined : spec.defines) {
    if (library.HasComponent(defined.name)) {
      throw ModelError(defined.loc, "type " + defined.name +
                                  " has the name of a library component; choose another name");
    }
    if (const ComponentType* other = defines->FindComponent(defined.name)) {
      throw ModelError(defined.loc, "type " + defined.name + " is defined twice (also at " + other->loc.ToString() + ")");
    }
    defines->AddComponent(defined);
  }
}

const ComponentType* FlattenContext::FindType(const std::string& name) const {
  // A full name first, the model's own types before the library's; a short name only then, so
  // that a model's own OpAmpCircuits.Feedback leaves `Feedback` to the library's (FORMAT.md: a
  // short name finds a qualified type when no unqualified type has that name).
  if (defines->HasComponent(name)) return defines->FindComponent(name);
  if (library.HasComponent(name)) return library.FindComponent(name);
  if (const ComponentType* t = defines->FindComponent(name)) return t;
  return library.FindComponent(name);
}

void FlattenContext::UnknownType(const ComponentSpec& c) const {
  std::vector<std::string> names = library.ComponentNames();
  for (const auto& defined : spec.defines) names.push_back(defined.name);
  auto close = ClosestNames(c.type, names);
  throw ModelError(c.type_loc, "unknown component type '" + c.type + "' for " + c.name +
                                   (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") +
                                   " (valid types: " + JoinNames(names, 80) + ")");
}

const MemoryBudget& FlattenContext::Budget() {
  if (!budget_) budget_ = BuildMemoryBudget();
  return *budget_;
}

}  // namespace momenta::flatten_internal
