// An instance's tables: their elements as parameters, and the table reads in its templates made
// over those parameters.

#include "core/flatten/instance_tables.h"

#include <cmath>

#include "core/base/error.h"
#include "core/base/messages.h"
#include "core/flatten/time_table.h"
#include "core/lang/arrays.h"
#include "core/lang/parser.h"

namespace momenta::flatten_internal {

void InstanceTables::Add(const ComponentSpec& c, const TypeLayout& layout, const InstanceData& data, InstanceId inst,
                         const std::vector<const Modifier*>& values, const LoopIndex* index) {
  current_.clear();
  if (layout.tables.empty()) return;
  FlatSystem& flat = context_.flat;
  const std::string path = flat.InstancePath(inst);
  for (size_t k = 0; k < layout.tables.size(); ++k) {
    const TypeLayout::TableSlot& slot = layout.tables[k];
    const ParameterDecl& decl = *slot.decl;
    const Modifier* m = k < values.size() ? values[k] : nullptr;
    InstanceTable table{ParamId(flat.parameters.size()), slot.rows, slot.cols, flat.tables.size()};
    std::vector<AstPtr> given;
    if (m) given = TableElements(m->value, decl, m->loc, path + "." + decl.name, &table.rows, &table.cols);
    const Shape shape = decl.shape.size() == 1 ? Shape{static_cast<int>(table.rows)}
                                            : Shape{static_cast<int>(table.rows), static_cast<int>(table.cols)};
    const TextRef unit = flat.Own(decl.unit), doc = flat.Own(decl.doc);  // one for all elements
    for (size_t e = 0; e < static_cast<size_t>(table.rows) * table.cols; ++e) {
      FlatParameter fp;
      fp.name = flat.Own(path + "." + ElementName(decl.name, shape, e));
      fp.unit = unit;
      fp.doc = doc;
      if (decl.min) fp.min = *decl.min;  // every element: a table of friction forces has min: 0
      if (decl.max) fp.max = *decl.max;
      fp.instance = inst;
      if (m) {
        fp.binding = scope_.Expr(*given[e], m->value_text, m->loc, index, false);
        fp.loc = m->loc;
      } else {
        fp.binding = Instantiate(slot.defaults[e], data.first_var, data.first_param, inst, decl.value_text, decl.loc);
        fp.loc = c.loc;
      }
      flat.parameters.push_back(std::move(fp));
    }
    flat.tables.push_back({path + "." + decl.name, table.first, table.rows, table.cols, inst, m ? m->loc : c.loc, {}});
    current_.push_back(table);
  }
}

ExprId InstanceTables::Instantiate(const Template& t, VarId first_var, ParamId first_param, InstanceId inst,
                                   const std::string& text, const SourceLoc& loc) {
  return CopyTemplate(&context_.pool(), t, first_var, first_param, &scratch_,
                      [&](const TNode& n, const std::vector<ExprId>& made) { return TableNode(n, made, inst, text, loc); });
}

ExprId InstanceTables::TableNode(const TNode& n, const std::vector<ExprId>& made, InstanceId inst,
                                 const std::string& text, const SourceLoc& loc) {
  ExprPool& pool = context_.pool();
  switch (n.kind) {
    case TNode::kTable: {
      const InstanceTable& table = current_.at(n.local);
      const auto column = static_cast<uint32_t>(n.c >= 0 ? OptionValue(made[n.c], "column", loc) : n.value);
      if (table.cols > kMaxTableColumns) {
        throw ModelError(loc, context_.flat.InstancePath(inst) + ": interpolate() reads a table with " + std::to_string(table.cols) +
                                  " columns, more than the " + std::to_string(kMaxTableColumns) + " a table may have, in '" +
                                  Excerpt(text, 0) + "'");
      }
      if (column < 1 || column > table.cols) {
        throw ModelError(loc, context_.flat.InstancePath(inst) + ": interpolate() reads column " + std::to_string(column) + " of a table with " +
                                  std::to_string(table.cols) + " columns, in '" + Excerpt(text, 0) + "'");
      }
      return pool.Table(table.first, table.rows, table.cols, column);
    }
    case TNode::kTimeTable:
      return TimeTableExpr(made[n.a], made[n.b], static_cast<int>(OptionValue(made[n.c], "smoothness", loc)),
                           static_cast<int>(OptionValue(made[n.local], "extrapolation", loc)));
    case TNode::kBooleanTable:
      return BooleanTableSum(&pool, made[n.a], made[n.b]);
    default:
      MOMENTA_CHECK_MSG(false, "only table nodes are made here");
      return ExprId();
  }
}

double InstanceTables::OptionValue(ExprId e, const std::string& what, const SourceLoc& loc) {
  ExprPool& pool = context_.pool();
  double v = 0;
  if (pool.IsConst(e)) {
    v = pool.ConstValue(e);
  } else if (pool.op(e) == Op::kParam) {
    const ParamId id(pool.node(e).a);
    const FlatParameter& fp = context_.flat.parameters[id.value()];
    const std::string name = context_.flat.ParameterName(id);
    auto ov = context_.overrides.find(name);
    if (ov != context_.overrides.end()) {
      v = ov->second;
    } else if (pool.IsConst(fp.binding)) {
      v = pool.ConstValue(fp.binding);
    } else {
      throw ModelError(fp.loc, name + " sets the " + what + " of a table, which shapes the equations: give it a number");
    }
    context_.flat.structural.Set(id, v);
  } else {
    throw ModelError(loc, "the " + what + " of a table must be a number or a parameter");
  }
  if (what == "column") {
    if (v != std::floor(v)) throw ModelError(loc, "the column of a table must be a whole number, found " + NumberText(v));
    return v;
  }
  const bool ok = what == "smoothness" ? (v == kLinearSegments || v == kConstantSegments)
                                       : (v == kHoldLastPoint || v == kLastTwoPoints);
  if (!ok) {
    throw ModelError(loc, "the " + what + " of a table is " + NumberText(v) + "; valid: " +
                              (what == "smoothness" ? "1 (LinearSegments), 3 (ConstantSegments)"
                                                    : "1 (HoldLastPoint), 2 (LastTwoPoints)"));
  }
  return v;
}

ExprId InstanceTables::TimeTableExpr(ExprId x, ExprId table, int smoothness, int extrapolation) {
  const Node t = context_.pool().node(table);
  FlatTable& flat_table = FlatTableAt(t.a);
  flat_table.jumps.assign(t.b, 0);
  for (uint32_t r = 0; r + 1 < t.b; ++r) {
    flat_table.jumps[r] = BuildValue(ParamId(t.a + r * t.TableColumns())) == BuildValue(ParamId(t.a + (r + 1) * t.TableColumns()));
  }
  return TimeTableSum(&context_.pool(), x, table, smoothness, extrapolation, flat_table.jumps);
}

FlatTable& InstanceTables::FlatTableAt(uint32_t first) {
  for (const InstanceTable& it : current_) {
    if (it.first.value() == first) return context_.flat.tables[it.flat_index];
  }
  MOMENTA_CHECK_MSG(false, "a table read belongs to its instance");
  return context_.flat.tables.front();
}

double InstanceTables::BuildValue(ParamId id) {
  const FlatParameter& fp = context_.flat.parameters[id.value()];
  auto ov = context_.overrides.find(context_.flat.ParameterName(id));
  if (ov != context_.overrides.end()) return ov->second;
  return context_.pool().IsConst(fp.binding) ? context_.pool().ConstValue(fp.binding) : std::nan("");
}

}  // namespace momenta::flatten_internal
