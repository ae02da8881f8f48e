#pragma once
/// Distinct index types (in the manner of Drake's TypeSafeIndex): a VarId cannot be passed where
/// an EquationId is wanted.

#include <cstdint>
#include <functional>
#include <limits>

namespace momenta {

template <class Tag>
class TypedIndex {
 public:
  static constexpr uint32_t kInvalid = std::numeric_limits<uint32_t>::max();
  constexpr TypedIndex() = default;
  constexpr explicit TypedIndex(uint32_t value) : value_(value) {}
  constexpr explicit TypedIndex(size_t value) : value_(static_cast<uint32_t>(value)) {}
  constexpr explicit TypedIndex(int value) : value_(static_cast<uint32_t>(value)) {}
  constexpr uint32_t value() const { return value_; }
  constexpr bool valid() const { return value_ != kInvalid; }
  constexpr bool operator==(TypedIndex o) const { return value_ == o.value_; }
  constexpr bool operator!=(TypedIndex o) const { return value_ != o.value_; }
  constexpr bool operator<(TypedIndex o) const { return value_ < o.value_; }

 private:
  uint32_t value_ = kInvalid;
};

struct VarTag {};
struct ParamTag {};
struct EquationTag {};
struct ExprTag {};
struct InstanceTag {};

/// A variable of the flat system (a Real or discrete unknown of the model).
using VarId = TypedIndex<VarTag>;
/// A parameter: a value fixed during a run, overridable with -p without rebuilding.
using ParamId = TypedIndex<ParamTag>;
/// An equation of the flat system.
using EquationId = TypedIndex<EquationTag>;
/// A node of the expression pool.
using ExprId = TypedIndex<ExprTag>;
/// A component instance of the flattened model (arrays give one instance per element).
using InstanceId = TypedIndex<InstanceTag>;

}  // namespace momenta

namespace std {
template <class Tag>
struct hash<momenta::TypedIndex<Tag>> {
  size_t operator()(momenta::TypedIndex<Tag> i) const { return std::hash<uint32_t>()(i.value()); }
};
}  // namespace std
