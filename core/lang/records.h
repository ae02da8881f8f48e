#pragma once
/// Records, conditional equation blocks and the connection graph's predicates in a type's
/// scalar form (docs/FORMAT.md, "Records, functions and the connection graph"). Run by
/// ScalarForm (core/lang/arrays.h) before the arrays are expanded:
///
/// - a connector potential or a variable of a record type stands for its fields (`R.T`, `R.w`);
///   a record equation (`frame_b.R = absoluteRotation(frame_a.R, R_rel)`) becomes one equation
///   per field element (core/lang/array_expression.h evaluates record values);
/// - an overdetermined record counts as its residues in the local balance: of its elements, as
///   an unknown and in a record equation, the first `residues` are counted (`counted`), the rest
///   are not (ComponentType::uncounted_equations);
/// - `isRoot(frame_a.R)` and `rooted(frame_a.R)` become hidden Boolean parameters of the type,
///   named as written, which the connection graph (core/flatten/connection_graph.h) sets;
/// - an equation of a conditional block holds under its guard; each block's branches must count
///   the same, and the balance counts one of them.

#include "core/lang/component_type.h"

namespace momenta {

/// Whether a tree calls a function that is not momenta's own: a library's (`kind: function`), or
/// an unknown name, which the array evaluator then reports.
bool CallsLibraryFunction(const AstPtr& a);

/// Whether a type uses any of the above (its scalar form then runs them).
bool UsesRecordsOrBlocks(const ComponentType& type, const Library& library);

/// A connector type's record potentials replaced by their fields' elements (`R.T[1,1]` …), the
/// fields' shapes recorded in `arrays`, the record in `records`, and the elements beyond an
/// overdetermined record's residues not counted. Throws ModelError for an unknown record.
ConnectorType ExpandRecords(ConnectorType connector, const Library& library);

/// Variables of a record type replaced by their fields (shaped variables `R.T`, `R.w`), each
/// recorded in `records` (`R` → its record type). `owner` prefixes names in messages ("Body.",
/// or "" for a model's own). Throws ModelError for an unknown record.
std::vector<VariableDecl> ExpandRecordVariables(const std::vector<VariableDecl>& variables, const Library& library,
                                                const std::string& owner, std::map<std::string, std::string>* records);

/// A type's record variables replaced by their fields (shaped variables `R_rel.T`, `R_rel.w`),
/// its local record names recorded in `records` (its own and its connectors'), the graph's
/// predicates made hidden parameters. Before the arrays are expanded.
ComponentType ExpandRecordDeclarations(const ComponentType& type, const Library& library);

/// After the arrays are expanded: the record variables' elements beyond the residues not
/// counted, guarded equations written `0 = if guard then lhs - rhs else 0`, each block's branches
/// checked to count the same (ModelError at the block otherwise) and `uncounted_equations` set.
void FinishRecordsAndBlocks(ComponentType* type, const Library& library);

/// The name of the hidden parameter for a predicate call (`isRoot(frame_a.R)`).
std::string PredicateName(const std::string& predicate, const std::string& record);

}  // namespace momenta
