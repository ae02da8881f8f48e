// The MPI plugin (app/mpi_plugin.h): the only code of momenta that links MPI.

#include "app/mpi_plugin.h"

#include "app/plugin.h"

// The C interface only (OpenMPI's and MPICH's headers would otherwise pull in the C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

namespace {

void Join(int* rank, int* size) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, rank);
  MPI_Comm_size(MPI_COMM_WORLD, size);
}

void Leave() { MPI_Finalize(); }

void AllGather(int64_t value, int64_t* all) {
  MPI_Allgather(&value, 1, MPI_INT64_T, all, 1, MPI_INT64_T, MPI_COMM_WORLD);
}

int Probe(int source, int tag, int* from, int* bytes) {
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, tag, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return 0;
  *from = status.MPI_SOURCE;
  MPI_Get_count(&status, MPI_BYTE, bytes);
  return 1;
}

void Receive(void* buffer, int bytes, int from, int tag) {
  MPI_Recv(buffer, bytes, MPI_BYTE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

void Send(const void* buffer, int bytes, int to, int tag) {
  MPI_Send(buffer, bytes, MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

constexpr momenta::MpiPluginTable kTable = {momenta::kPluginAbi, Join, Leave, AllGather, Probe, Receive, Send};

}  // namespace

extern "C" __attribute__((visibility("default"))) const void* momenta_mpi_plugin() {
  return &kTable;
}
