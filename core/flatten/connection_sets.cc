#include "core/flatten/connection_sets.h"

namespace momenta::flatten_internal {

bool Compatible(const ConnectorType* a, const ConnectorType* b) {
  return a == b || (a->is_signal && b->is_signal && a->signal_type == b->signal_type);
}

void CheckCompatible(const ConnectorType* a, const std::string& a_text, const ConnectorType* b,
                     const std::string& b_text, const SourceLoc& loc, const std::string& where) {
  if (Compatible(a, b)) return;
  auto last = [](const std::string& n) { return n.substr(n.rfind('.') + 1); };
  std::string hint;
  if (last(a->name) == last(b->name)) {
    hint = " (flanges of two domains: a library type written without its package, such as Spring or "
           "Fixed, is the translational one; write the package for another domain's, such as "
           "Rotational.Spring)";
  }
  throw ModelError(loc, "cannot connect " + a_text + " (" + a->name + ") to " + b_text + " (" + b->name +
                            ")" + where + ": connectors of different kinds" + hint);
}

bool ConnectionSets::Locate(uint32_t slot, const SourceLoc& loc) {
  if (first_loc_[slot].known()) return false;
  first_loc_[slot] = loc;
  return true;
}

SourceLoc ConnectionSets::Location(const std::vector<uint32_t>& set) const {
  for (uint32_t s : set) {
    if (first_loc_[s].known()) return first_loc_[s];
  }
  return SourceLoc();
}

void ConnectionSets::WriteEquations(const std::vector<std::vector<uint32_t>>& sets, ConnectionWriter* writer) const {
  for (const auto& set : sets) {
    const ConnectorType& type = writer->TypeOf(set[0]);
    if (set.size() == 1) {
      writer->Unconnected(set[0]);
      continue;
    }
    const SourceLoc loc = Location(set);
    if (type.is_signal) {
      // Every member but the driver equals it.
      const uint32_t driver = writer->Driver(set, loc);
      for (uint32_t s : set) {
        if (s != driver) writer->Equal(s, driver, 0, loc);
      }
      continue;
    }
    // Each potential equal to the first member's, then one sum per flow.
    const auto num_potentials = static_cast<uint32_t>(type.potentials.size());
    for (uint32_t k = 0; k < num_potentials; ++k) {
      for (size_t j = 1; j < set.size(); ++j) writer->Equal(set[j], set[0], k, loc);
    }
    for (uint32_t k = 0; k < type.flows.size(); ++k) writer->FlowSum(set, k, loc);
  }
}

}  // namespace momenta::flatten_internal
