#pragma once
/// The model's components as instances: each one's records in the flat system (its instance,
/// and its parts' for a composite; its variables, parameters, tables, equations, when-clauses and
/// impacts), copied from its type's layout with its own offsets and the component's modifiers. A
/// `count:` array makes its elements one after the other as a block (FlatSystem::blocks).

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/flatten/decided_conditions.h"
#include "core/flatten/flatten_context.h"
#include "core/flatten/instance_tables.h"
#include "core/flatten/model_scope.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

class InstanceBuilder {
 public:
  InstanceBuilder(FlattenContext* context, TypeLayoutBuilder* layouts, ModelScope* scope)
      : context_(*context), layouts_(*layouts), scope_(*scope), tables_(context, scope) {}

  /// Makes every component of the model, in the model's order, and indexes them by name
  /// (FlattenContext::components) for the connections and the model's expressions.
  void Components();

 private:
  /// A component's modifiers, by what they set in its layout (null where none does).
  struct Modifiers {
    std::vector<const Modifier*> params, vars, tables;
  };
  /// The instance being made: its component entry, layout, id and records.
  struct NewInstance {
    const ComponentSpec& component;
    const TypeLayout& layout;
    InstanceId id;
    InstanceData data;
    const LoopIndex* index;  ///< the element index of a `count:` array, for its modifiers
    const DecidedConditions* decided;  ///< its conditional connectors decided (null: none)
    /// The instance of the layout's part `sub` (-1: the component itself).
    InstanceId InstanceOf(int32_t sub) const { return sub < 0 ? id : InstanceId(id.value() + 1 + sub); }
    SourceLoc LocOf(int32_t sub) const { return sub < 0 ? component.loc : layout.subs[sub].loc; }
  };

  void ReserveComponents();
  /// Room in the flat system's arrays for `count` instances of `layout`, made before they are
  /// added, each with about `modifier_nodes` nodes of its modifiers' values.
  void ReserveElements(const TypeLayout& layout, uint32_t count, size_t modifier_nodes);
  /// The value of `count:`: a whole number of at least 1 whose components fit, with the rest of
  /// the model, in the memory budget (and in momenta's 32-bit indices) — checked before any of
  /// them is made, so an impossible count is refused at once.
  uint32_t ArrayCount(const ComponentSpec& c, const TypeLayout& layout);
  Modifiers SortModifiers(const ComponentSpec& c, const TypeLayout& layout) const;
  /// The record of a count: array (FlatSystem::blocks), begun before its first element is made;
  /// its strides are set by EndBlock.
  int32_t BeginBlock(const ComponentSpec& c, const TypeLayout& layout);
  /// A block's count and strides, from what its elements added (every element adds as many).
  void EndBlock(FlatBlock* b);
  /// The names of a layout's variables, parameters, equations and when-clauses
  /// (FlatSystem::type_names), made once: every instance's are made from them on demand.
  int32_t NamesOf(const TypeLayout& layout);
  /// For each equation of a layout, the DeferredAliases shape of its copies, or kNotSure when
  /// they are made; read once per layout.
  const std::vector<uint32_t>& SureAliasShapes(const TypeLayout& layout);
  /// Makes the nodes below the root of an equation that is not made.
  void MakeBelowRoot(const Template& t, VarId first_var, ParamId first_param);
  /// Holds a text in the flat system (FlatSystem::texts) and returns its index.
  uint32_t HeldText(std::string text);

  /// The conditional connectors of `layout` that component entry `modifiers` leaves to be
  /// decided now (decided_conditions.h), made once per layout and decision; null for none.
  const DecidedConditions* Decided(const TypeLayout& layout, const Modifiers& modifiers);
  /// Makes one instance of `layout`: an element of `block` (its `index`), or the component alone
  /// (block -1); `names` are the layout's (NamesOf).
  void AddInstance(const ComponentSpec& c, const TypeLayout& layout, int32_t block, int32_t names,
                   const Modifiers& modifiers, const LoopIndex* index, const DecidedConditions* decided);
  /// The instance records (the component's, then its parts'), its InstanceData and its slots.
  NewInstance AddRecords(const ComponentSpec& c, const TypeLayout& layout, int32_t block, int32_t names,
                         const LoopIndex* index, const DecidedConditions* decided);
  void AddConditionalConnectors(const NewInstance& instance);
  void AddParameters(const NewInstance& instance, const std::vector<const Modifier*>& modifiers);
  void AddVariables(const NewInstance& instance, const std::vector<const Modifier*>& modifiers);
  /// Copies `templates` (with their `info`; their texts from the type's `first_text`) to `out`;
  /// those with a shape in `shapes` (when given) are deferred, not made. With decided
  /// conditions, an equation is copied as `use` says (its fixed template from `fixed`).
  void AddEquations(const NewInstance& instance, const std::vector<Template>& templates,
                    const std::vector<PartInfo>& info, uint32_t first_text, const std::vector<uint32_t>* shapes,
                    const std::vector<DecidedConditions::Use>* use, const std::vector<Template>* fixed,
                    std::vector<FlatEquation>* out);
  void AddWhens(const NewInstance& instance);
  /// The impacts, each with its contact law as an equation.
  void AddImpacts(const NewInstance& instance);
  ExprId Instantiate(const NewInstance& instance, const Template& t, const std::string& text, const SourceLoc& loc) {
    return tables_.Instantiate(t, instance.data.first_var, instance.data.first_param, instance.id, text, loc);
  }

  FlattenContext& context_;
  TypeLayoutBuilder& layouts_;
  ModelScope& scope_;
  InstanceTables tables_;
  std::unordered_map<const TypeLayout*, int32_t> names_of_;  ///< index in FlatSystem::type_names
  /// SureAliasShapes, by layout.
  std::unordered_map<const TypeLayout*, std::vector<uint32_t>> sure_shapes_;
  /// Decided, by layout: each decision made for it.
  std::unordered_map<const TypeLayout*, std::vector<std::pair<std::vector<int8_t>, std::unique_ptr<DecidedConditions>>>>
      decided_;
  std::vector<ExprId> scratch_;
};

}  // namespace momenta::flatten_internal
