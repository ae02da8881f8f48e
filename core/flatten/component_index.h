#pragma once
/// The model's components by name, for the connections and expressions that name them: two
/// look-ups per connection, 200 000 on a written-out model of 100 000 components. An
/// open-addressing table of (hash, entry) pairs over names held elsewhere (the spec's, which
/// outlive it): a look-up reads one slot and the name it finds, where a node-based map walks a
/// bucket, a node and its key (bench/RESULTS.md, "Flattening reserves written-out components").

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

namespace momenta::flatten_internal {

/// A component of the model: one instance, or a `count:` array of them.
struct ComponentArray {
  size_t spec_index;        ///< its ModelSpec::components entry
  uint32_t first_instance;  ///< its (first element's) FlatSystem::instances entry
  uint32_t count;
  bool is_array;
  uint32_t stride = 1;  ///< instance records per element: the component and a composite's parts
};

class ComponentIndex {
 public:
  void Reserve(size_t n) {
    if (2 * n > slots_.size()) Rehash(2 * n);
  }
  /// The component named `name`, or null.
  const ComponentArray* Find(std::string_view name) const {
    if (slots_.empty()) return nullptr;
    const uint64_t hash = Hash(name);
    const size_t mask = slots_.size() - 1;
    for (size_t at = hash & mask;; at = (at + 1) & mask) {
      const uint64_t slot = slots_[at];
      if (slot == 0) return nullptr;
      const auto entry = static_cast<uint32_t>(slot) - 1;
      if (slot >> 32 == hash >> 32 && names_[entry] == name) return &entries_[entry];
    }
  }
  /// Adds a component whose name is not in the table yet; `name` must outlive the table.
  void Add(std::string_view name, const ComponentArray& entry) {
    if (2 * (entries_.size() + 1) > slots_.size()) Rehash(std::max<size_t>(64, 2 * slots_.size()));
    names_.push_back(name);
    entries_.push_back(entry);
    Place(Hash(name), static_cast<uint32_t>(entries_.size()));
  }

 private:
  static uint64_t Hash(std::string_view name) {
    // The high half tells names apart before they are compared; neither half is 0 for an entry.
    const uint64_t h = std::hash<std::string_view>()(name);
    return h | (uint64_t{1} << 32);
  }
  /// Stores entry number `number` (1-based: 0 is an empty slot) under `hash`.
  void Place(uint64_t hash, uint32_t number) {
    const size_t mask = slots_.size() - 1;
    size_t at = hash & mask;
    while (slots_[at] != 0) at = (at + 1) & mask;
    slots_[at] = (hash & ~uint64_t{0xffffffff}) | number;
  }
  void Rehash(size_t at_least) {
    size_t size = 64;
    while (size < at_least) size *= 2;
    slots_.assign(size, 0);
    for (uint32_t k = 0; k < entries_.size(); ++k) Place(Hash(names_[k]), k + 1);
  }

  std::vector<uint64_t> slots_;  ///< (hash's high half, entry number), 0 when empty; a power of 2
  std::vector<std::string_view> names_;
  std::vector<ComponentArray> entries_;
};

}  // namespace momenta::flatten_internal
