#pragma once
/// An instance's tables (docs/FORMAT.md, "Tables"): each element a parameter of the instance,
/// row by row, sized by the value the component gives (or the type's default); and the copies of
/// the instance's templates, whose table reads (interpolate, timeTable, booleanTable) become
/// expressions over those parameters. Tables read with events (core/flatten/time_table.h) fix
/// their options and their jumps when the model is built.

#include <cstdint>
#include <string>
#include <vector>

#include "core/flatten/equation_template.h"
#include "core/flatten/flatten_context.h"
#include "core/flatten/lower.h"
#include "core/flatten/model_scope.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

class InstanceTables {
 public:
  InstanceTables(FlattenContext* context, ModelScope* scope) : context_(*context), scope_(*scope) {}

  /// Makes the tables of instance `inst` of component `c` (laid out as `layout`, its records from
  /// `data`), the current instance's from now on: each element a parameter `path.table[i,j]`
  /// bound to the component's value for it (`values`, by the layout's table slot; null: the
  /// type's default) or the type's default; recorded for the check of the abscissas. `index`:
  /// the element index of a `count:` array, for the values' expressions.
  void Add(const ComponentSpec& c, const TypeLayout& layout, const InstanceData& data, InstanceId inst,
           const std::vector<const Modifier*>& values, const LoopIndex* index);

  /// Copies template `t` into the pool for instance `inst` (the current one: its tables are
  /// those the template reads), written as `text` at `loc` for messages.
  ExprId Instantiate(const Template& t, VarId first_var, ParamId first_param, InstanceId inst,
                     const std::string& text, const SourceLoc& loc);

 private:
  /// Where the current instance keeps a table's elements: consecutive parameters from `first`.
  struct InstanceTable {
    ParamId first;
    uint32_t rows = 0, cols = 0;
    size_t flat_index = 0;  ///< its FlatSystem::tables entry
  };

  /// A node of a template that reads a table, for the current instance.
  ExprId TableNode(const TNode& n, const std::vector<ExprId>& made, InstanceId inst, const std::string& text,
                   const SourceLoc& loc);
  /// The value of a structural option of timeTable(): a number, or a parameter whose value is a
  /// number (recorded as structural, so -p cannot change it after the build).
  double OptionValue(ExprId e, const std::string& what, const SourceLoc& loc);
  /// timeTable(): which times repeat (a jump) shapes the sum, so the check of the parameters
  /// keeps them as built.
  ExprId TimeTableExpr(ExprId x, ExprId table, int smoothness, int extrapolation);
  /// The FlatSystem entry of the current instance's table whose element [1,1] is `first`.
  FlatTable& FlatTableAt(uint32_t first);
  /// A parameter's value as the model is built: its -p override or its constant binding (NaN
  /// when it is an expression).
  double BuildValue(ParamId id);

  FlattenContext& context_;
  ModelScope& scope_;
  std::vector<InstanceTable> current_;  ///< the current instance's tables, by slot
  std::vector<ExprId> scratch_;
};

}  // namespace momenta::flatten_internal
