// Connection sets: the first connection that names each slot, and whether two connectors may be
// joined. The skeleton of a set's equations is a template over its writer (connection_sets.h).

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

}  // namespace momenta::flatten_internal
