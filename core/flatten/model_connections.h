#pragma once
/// The model's connections: each end resolved to a connector slot of an instance (a `for:`
/// connection once per index of its range), the slots joined into connection sets
/// (connection_sets.h), and each set's equations appended to the flat system as expressions
/// over flat variables. With deferred equations, those between two continuous variables are left
/// to alias elimination (deferred_aliases.h).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/flatten/connection_sets.h"
#include "core/flatten/flatten_context.h"
#include "core/flatten/model_scope.h"

namespace momenta::flatten_internal {

class ModelConnections {
 public:
  ModelConnections(FlattenContext* context, ModelScope* scope)
      : context_(*context), scope_(*scope), sets_(context->slot_instance.size()) {}

  /// Joins every connection of the model, then appends the connection sets' equations.
  void Run();

  // The model's ConnectionWriter (connection_sets.h), for ConnectionSets::WriteEquations: the
  // equations as expressions over flat variables, deferred where they are aliases.
  const ConnectorType& TypeOf(uint32_t slot) const;
  void Unconnected(uint32_t slot);
  uint32_t Driver(const std::vector<uint32_t>& set, const SourceLoc& loc);
  void Equal(uint32_t slot, uint32_t to, uint32_t k, const SourceLoc& loc);
  void FlowSum(const std::vector<uint32_t>& set, uint32_t flow, const SourceLoc& loc);

 private:
  /// One end of a connection: an instance's connector, and where the end is written.
  struct EndRef {
    uint32_t instance;
    uint32_t connector;
    SourceLoc loc;
  };

  /// "R[3].n": a connection end as messages name it (made only for a message).
  std::string EndText(const EndRef& e) const;
  EndRef ResolveEnd(const Ast& a, const std::string& text, const SourceLoc& loc, const LoopIndex* loop);
  /// The end `component.connector` of a connection held as text (ConnectionSpec::a null: a
  /// plain name) when it names a component that is not an array and one of its connectors;
  /// nothing otherwise, and ResolveEnd reads the end's tree and says what is wrong. (Without a
  /// tree per end: 200 000 ends on a written-out model.)
  std::optional<EndRef> PlainEnd(const AstPtr& tree, const std::string& text, const SourceLoc& loc) const;
  /// The number of connections `for: i in a:b` makes, b - a + 1 (none if b < a), and a. Both
  /// bounds are whole numbers, and a range makes at most as many connections as the model has
  /// connectors (a longer one could only repeat them), so 1:1e9 is refused at once.
  size_t LoopLength(const ConnectionSpec& c, double* from);
  void Join(const EndRef& x, const EndRef& y);
  /// How many equations the connection sets make: potentials equal (a signal input equals its
  /// output), one sum per flow, an unconnected physical connector's flows zero.
  size_t ConnectionEquationCount(const std::vector<std::vector<uint32_t>>& sets) const;
  /// Connected signals have one dimension when both declare a unit (a string compare first, so
  /// the cost per connection is small).
  void CheckConnectedUnits(VarId a, const std::string& a_name, VarId b, const std::string& b_name,
                           const SourceLoc& loc);

  /// Variable `k` of slot `slot`'s connector.
  VarId VarOf(uint32_t slot, uint32_t k) const;
  /// A conditional connector decided absent when its instance was made (decided_conditions.h).
  bool DecidedAbsent(uint32_t slot) const;
  /// "R[3].n": a slot as messages name it.
  std::string NameOf(uint32_t slot) const;
  /// Appends a connection equation (`residual` invalid: deferred).
  void Add(ExprId residual, TextRef text, const SourceLoc& loc);
  /// Whether a connection equation between `a` and `b` names two continuous variables: an
  /// alias, which a build with deferred equations does not make.
  bool Continuous(VarId a, VarId b) const;

  FlattenContext& context_;
  ModelScope& scope_;
  ConnectionSets sets_;
};

}  // namespace momenta::flatten_internal
