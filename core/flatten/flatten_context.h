#pragma once
/// The record that the jobs of flattening share, as SUNDIALS' IDAMemRec is for IDA's files: the
/// model and library being flattened, the flat system under construction, and the instances and
/// connector slots made so far, which the model's expressions and connections look up. Each job
/// is a class of its own over it (type_layout.h, instances.h, model_scope.h,
/// model_connections.h); what only one job needs stays that job's.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/base/memory_budget.h"
#include "core/flatten/component_index.h"
#include "core/flatten/flat_system.h"
#include "core/lang/model_spec.h"

namespace momenta::flatten_internal {

struct TypeLayout;
class DeferredAliases;

/// No connector slot: a composite's part, which the model's connections cannot reach.
constexpr uint32_t kNoSlot = UINT32_MAX;

/// Where an instance's records start: its variables, parameters and connector slots, numbered
/// as its layout numbers them locally.
struct InstanceData {
  const TypeLayout* layout;
  VarId first_var;
  ParamId first_param;
  uint32_t first_slot;  ///< kNoSlot for a composite's part
};

struct FlattenContext {
  /// Starts an empty flat system for `spec` and collects the model's own types (define:),
  /// refusing one that has a library component's name or is defined twice.
  FlattenContext(const ModelSpec& spec, const Library& library, const ParameterOverrides& overrides,
                 bool defer_equations);

  ExprPool& pool() { return *flat.pool; }
  /// A type of the model's own, else of the library; null when there is none.
  const ComponentType* FindType(const std::string& name) const;
  /// Throws the error for component `c`'s unknown type, with the closest names.
  [[noreturn]] void UnknownType(const ComponentSpec& c) const;
  /// The memory budget (core/base/memory_budget.h), read when the first size is checked.
  const MemoryBudget& Budget();

  const ModelSpec& spec;
  const Library& library;
  const ParameterOverrides& overrides;
  std::shared_ptr<Library> defines = std::make_shared<Library>();
  FlatSystem flat;
  std::shared_ptr<DeferredAliases> deferred;  ///< with defer_equations
  ComponentIndex components;  ///< the model's components by name (spec's names)
  std::vector<InstanceData> instance_data;  ///< by instance
  std::vector<uint32_t> slot_instance;      ///< connector slot -> instance
  /// The model's conditional connector slots -> their FlatSystem::conditional_connectors entry.
  std::unordered_map<uint32_t, size_t> conditional_slot;
  /// Parameters a component entry leaves free (`c: {fixed: false}`; free_parameters.h).
  std::vector<ParamId> free_parameters;
  double planned_bytes = 0;  ///< estimated memory of the components so far

 private:
  std::optional<MemoryBudget> budget_;
};

}  // namespace momenta::flatten_internal
