#pragma once
/// A hook for tests only: what the build decides and computes must not follow the ids of the
/// expression pool's nodes (the order in which they were made), and a test shows it by making
/// nodes of its own in every new pool before the model's.

namespace momenta {

class ExprPool;

/// When set, called at the end of every ExprPool's construction. Null otherwise; never set
/// outside tests.
extern void (*pool_made_for_testing)(ExprPool* pool);

}  // namespace momenta
