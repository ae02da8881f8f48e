#pragma once
/// The equations a build leaves unmade for alias elimination (FlatSystem::deferred,
/// DeferredEquations): copies of a type's sure-alias equations (equation_template.h's
/// ReadSureAlias), and connection equations between two variables. Each is x = ±y + c or x = c,
/// which alias elimination removes without its expression; one is made only if it must stay.

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/flatten/equation_template.h"
#include "core/flatten/flat_system.h"
#include "core/flatten/type_layout.h"

namespace momenta::flatten_internal {

/// No DeferredAliases shape: the equation's copies are made (InstanceBuilder::SureAliasShapes).
constexpr uint32_t kNotSure = UINT32_MAX;

class DeferredAliases final : public DeferredEquations {
 public:
  explicit DeferredAliases(std::shared_ptr<ExprPool> pool) : pool_(std::move(pool)) {}

  bool Form(uint32_t k, std::vector<std::pair<VarId, double>>* terms, double* offset) const override;
  ExprId Make(uint32_t k) const override;

  /// A sure-alias template (`form` is ReadSureAlias's) whose copies AddCopy records.
  uint32_t AddShape(const Template& t, const SureAlias& form);
  /// Flat equation k is a copy of `shape` for the instance whose first variable and parameter
  /// are given.
  void AddCopy(size_t k, uint32_t shape, VarId first_var, ParamId first_param) {
    Set(k, {kCopy, shape, first_var.value(), first_param.value()});
  }
  /// Flat equation k is x = 0 (an unconnected flow), x = y or x + y = 0 (a connection).
  void AddZero(size_t k, VarId x) { Set(k, {kZero, 0, x.value(), 0}); }
  void AddEqual(size_t k, VarId x, VarId y) { Set(k, {kEqual, 0, x.value(), y.value()}); }
  void AddSum(size_t k, VarId x, VarId y) { Set(k, {kSum, 0, x.value(), y.value()}); }
  bool empty() const { return entries_.empty(); }
  /// Makes the deferred equations that name a variable `flat` now calls discrete (a model's
  /// when-clause assigns it, found after the components): alias elimination keeps those.
  void MakeDiscrete(FlatSystem* flat);
  /// Takes the type layouts, whose templates the copies read.
  void Keep(TypeLayouts layouts) { layouts_ = std::move(layouts); }

 private:
  enum Kind : uint8_t { kMade, kCopy, kZero, kEqual, kSum };
  struct Entry {
    Kind kind = kMade;
    uint32_t shape = 0;
    uint32_t x = 0, y = 0;  ///< a copy: its first variable and parameter; else the variables
  };
  void Set(size_t k, Entry e) {
    if (entries_.size() <= k) entries_.resize(k + 1);
    entries_[k] = e;
  }
  std::shared_ptr<ExprPool> pool_;
  std::vector<Entry> entries_;  ///< by flat equation
  struct Shape {
    const Template* tmpl;
    SureAlias form;
  };
  std::vector<Shape> shapes_;
  TypeLayouts layouts_;
  mutable std::vector<ExprId> scratch_;
};

}  // namespace momenta::flatten_internal
