#pragma once
/// Connection sets (Modelica 3.5, section 9.2): connectors joined by connections into sets, and
/// the equations each set stands for. In a set of physical connectors the potentials are equal
/// and the flows sum to zero; a connector connected to nothing has its flows zero; in a set of
/// signals every other member equals the one driver. The connections inside a composite type
/// (inner_connections.h, templates over its local variables) and the model's
/// (model_connections.h, expressions over flat variables) share this, and each writes the
/// equations in its own form and names the connectors in its own words (a ConnectionWriter).

#include <concepts>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/base/graph.h"
#include "core/lang/component_type.h"

namespace momenta::flatten_internal {

/// Two connectors may be joined when they are of one type, or both signals of one value type.
bool Compatible(const ConnectorType* a, const ConnectorType* b);

/// Throws when connectors `a` and `b` (written `a_text`, `b_text`) cannot be joined; `where`
/// ends the message (" in Cell" for a connection inside a type).
void CheckCompatible(const ConnectorType* a, const std::string& a_text, const ConnectorType* b,
                     const std::string& b_text, const SourceLoc& loc, const std::string& where = "");

/// How the connection sets of one scope are written as equations (ConnectionSets::WriteEquations
/// calls it set by set, in the order the equations are made). A slot is a connector; a variable
/// index `k` counts its connector's variables (potentials, then flows; a signal has one).
template <class Writer>
concept ConnectionWriter = requires(Writer writer, const Writer& const_writer, uint32_t slot,
                                    const std::vector<uint32_t>& set, const SourceLoc& loc) {
  /// The connector type of `slot`.
  { const_writer.TypeOf(slot) } -> std::same_as<const ConnectorType&>;
  /// A connector in a set of its own: connected to nothing.
  writer.Unconnected(slot);
  /// The one driver of a signal set of two or more, first connected at `loc`; throws when there
  /// is none, or more than one.
  { writer.Driver(set, loc) } -> std::same_as<uint32_t>;
  /// Variable `k` of `slot` equals variable `k` of `to`: writer.Equal(slot, to, k, loc).
  writer.Equal(slot, slot, slot, loc);
  /// Flow `flow` (0 for the connector type's first flow) summed over `set` is zero:
  /// writer.FlowSum(set, flow, loc).
  writer.FlowSum(set, slot, loc);
};

/// Connector slots 0 … n-1 joined by connections.
class ConnectionSets {
 public:
  explicit ConnectionSets(size_t num_slots) : joined_(num_slots), first_loc_(num_slots) {}

  /// Notes that a connection written at `loc` names `slot`; true when it is the first to.
  bool Locate(uint32_t slot, const SourceLoc& loc);
  void Join(uint32_t x, uint32_t y) { joined_.Join(x, y); }
  /// The sets, each in slot order, ordered by their first slot.
  std::vector<std::vector<uint32_t>> Sets() { return joined_.Sets(); }
  /// Writes the equations of `sets` (Sets()) with `writer`.
  template <ConnectionWriter Writer>
  void WriteEquations(const std::vector<std::vector<uint32_t>>& sets, Writer* writer) const;

 private:
  /// Where the set's first located slot (in slot order) was connected; unknown when none was.
  SourceLoc Location(const std::vector<uint32_t>& set) const;

  DisjointSets joined_;
  std::vector<SourceLoc> first_loc_;  ///< by slot: the first connection naming it
};

template <ConnectionWriter Writer>
void ConnectionSets::WriteEquations(const std::vector<std::vector<uint32_t>>& sets, Writer* writer) const {
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
