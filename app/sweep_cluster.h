#pragma once
/// The ranks of a sweep run under MPI (`mpirun -n P momenta sweep …`, OpenMPI), and what they send
/// one another.
///
/// Work is handed out dynamically by rank 0, which also runs its share on its own threads: every
/// thread of every other rank asks rank 0 for a run, and with its next ask sends the result of the
/// one it finished (final values, statistics, status, message and, when asked for, the
/// trajectory's CSV text, which rank 0 writes). Rank 0 answers each ask with a run index, or with
/// -1 when no run is left (or the sweep is stopping), which ends that thread's chain: every thread
/// gets exactly one -1, so rank 0 knows when all the results are in. A static split (run k on
/// rank k mod P) would leave ranks idle when runs differ in cost (a run that fails at once next to
/// one that integrates a stiff stretch, a grid whose cost grows along an axis); asking costs one
/// small message per run, negligible next to a run of milliseconds.
///
/// Only each rank's main thread calls MPI (MPI_THREAD_FUNNELED), and it polls (MPI_Iprobe, then a
/// short sleep) instead of blocking in MPI, so that a rank waiting for messages does not spin a
/// core that its own threads need (OpenMPI's blocking calls busy-wait).
///
/// A plain run (not started by mpirun) is a cluster of one rank and does not even load MPI, whose
/// calls are in a plugin (momenta-mpi.so, app/mpi_plugin.h) loaded only under mpirun. mpirun is recognised by the variables it puts in each rank's environment:
/// OMPI_COMM_WORLD_SIZE (OpenMPI), PMI_SIZE (MPICH's Hydra) or PMIX_RANK.

#include <cstdint>
#include <string>
#include <vector>

namespace momenta {

/// What one run of a sweep gave.
struct SweepRunResult {
  bool done = true;            ///< finished (false: interrupted in the middle, or not run)
  std::vector<double> finals;  ///< the outputs' last values (empty when the run failed)
  long steps = 0, events = 0;
  int status = 0;              ///< 0, or the exit code the run alone would have had
  std::string message;
  std::string trajectory;  ///< the run's CSV text, when the run is on a rank other than 0
  int signal = 0;          ///< the signal that interrupted it (when !done)
};

/// A result as bytes, and back (throws std::runtime_error on a malformed message).
std::vector<char> PackRunResult(int64_t run, const SweepRunResult& result);
SweepRunResult UnpackRunResult(const std::vector<char>& bytes, int64_t* run);

/// The number of processes mpirun started, from the environment (1 when not under mpirun).
int MpirunWorldSize();
/// The number of those on this machine (OMPI_COMM_WORLD_LOCAL_SIZE; 1 when not known).
int MpirunLocalSize();

/// True when momenta's MPI plugin loads (momenta was built with MPI and the plugin is installed).
bool HaveMpi();

struct MpiPluginTable;

class SweepCluster {
 public:
  /// Joins the MPI job when started by mpirun (loading the MPI plugin); otherwise a cluster of one.
  /// Throws UsageError when started by mpirun on several ranks but the plugin cannot be loaded.
  SweepCluster();
  /// Leaves the MPI job (MPI_Finalize).
  ~SweepCluster();
  SweepCluster(const SweepCluster&) = delete;
  SweepCluster& operator=(const SweepCluster&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  /// Every rank's `value`, in rank order (a collective: every rank calls it).
  std::vector<int64_t> AllGather(int64_t value) const;

  // ---- rank 0 ----
  /// An ask that has arrived from another rank, if any (does not wait): its rank, and the run it
  /// finished (`*run` = -1 for a first ask, which carries no result).
  bool PollAsk(int* from, int64_t* run, SweepRunResult* result) const;
  /// Answers an ask: the run to do next, or -1 for none.
  void Answer(int to, int64_t run) const;

  // ---- the other ranks ----
  /// Asks rank 0 for a run, giving the result of `run` (-1: none).
  void Ask(int64_t run, const SweepRunResult& result) const;
  /// Rank 0's answer to one of this rank's asks, if any has arrived (does not wait).
  bool PollAnswer(int64_t* run) const;

 private:
  /// The plugin's table; reaching a call that needs it without it is a bug in the caller.
  const MpiPluginTable& Joined(const char* what) const;

  int rank_ = 0, size_ = 1;
  const MpiPluginTable* mpi_ = nullptr;  ///< set when this process joined an MPI job
};

}  // namespace momenta
