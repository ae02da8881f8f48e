#pragma once
/// The table of the MPI plugin (momenta-mpi.so, app/mpi_plugin.cc): the few MPI calls a sweep's
/// ranks make (app/sweep_cluster.h), behind plain C functions so that only the plugin links MPI.
/// Messages are bytes; the ranks of one job run the same binary on the same architecture.

#include <cstdint>

namespace momenta {

struct MpiPluginTable {
  int abi;  ///< kPluginAbi (app/plugin.h)
  /// MPI_Init_thread (MPI_THREAD_FUNNELED), then this rank and the number of ranks.
  void (*join)(int* rank, int* size);
  /// MPI_Finalize.
  void (*leave)();
  /// Every rank's `value` into `all` (one per rank, in rank order): a collective.
  void (*all_gather)(int64_t value, int64_t* all);
  /// A message with `tag` from `source` (-1: any rank) that has arrived, if any (does not wait): 1
  /// with its sender and its size in bytes, else 0.
  int (*probe)(int source, int tag, int* from, int* bytes);
  /// Receives that message into `buffer` (`bytes` long).
  void (*receive)(void* buffer, int bytes, int from, int tag);
  /// Sends `bytes` bytes to rank `to`.
  void (*send)(const void* buffer, int bytes, int to, int tag);
};

}  // namespace momenta

/// The plugin's one exported function: its momenta::MpiPluginTable. The type is the one the loader
/// calls it through (app/plugin.h: a function called through a pointer of another type is
/// undefined behaviour, which UBSan's function check reports).
extern "C" const void* momenta_mpi_plugin();
