#include "app/sweep_cluster.h"

#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "core/base/error.h"

#if MOMENTA_HAVE_MPI
// The C interface only (OpenMPI's and MPICH's headers would otherwise pull in the C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace momenta {

namespace {

/// A whole number from the environment, or 0.
int EnvInt(const char* name) {
  const char* text = std::getenv(name);
  return text ? std::atoi(text) : 0;
}

/// Fixed-size values and byte strings appended to a message.
class Packer {
 public:
  template <typename T>
  void Put(const T& value) {
    const char* p = reinterpret_cast<const char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void PutText(const std::string& text) {
    Put<uint64_t>(text.size());
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  std::vector<char> bytes() && { return std::move(bytes_); }

 private:
  std::vector<char> bytes_;
};

/// Reads what Packer wrote, checking every length against the message's size.
class Unpacker {
 public:
  explicit Unpacker(const std::vector<char>& bytes) : bytes_(bytes) {}
  template <typename T>
  T Get() {
    Need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::string GetText() {
    const uint64_t n = Get<uint64_t>();
    Need(n);
    std::string text(bytes_.data() + at_, n);
    at_ += n;
    return text;
  }
  bool finished() const { return at_ == bytes_.size(); }

 private:
  void Need(uint64_t n) const {
    if (n > bytes_.size() - at_) throw std::runtime_error("a sweep result message is cut short");
  }
  const std::vector<char>& bytes_;
  size_t at_ = 0;
};

#if MOMENTA_HAVE_MPI
constexpr int kTagAsk = 1, kTagAnswer = 2;
#endif

}  // namespace

std::vector<char> PackRunResult(int64_t run, const SweepRunResult& r) {
  Packer p;
  p.Put<int64_t>(run);
  p.Put<int64_t>(r.done);
  p.Put<int64_t>(r.steps);
  p.Put<int64_t>(r.events);
  p.Put<int64_t>(r.status);
  p.Put<int64_t>(r.signal);
  p.Put<uint64_t>(r.finals.size());
  for (double v : r.finals) p.Put<double>(v);
  p.PutText(r.message);
  p.PutText(r.trajectory);
  return std::move(p).bytes();
}

SweepRunResult UnpackRunResult(const std::vector<char>& bytes, int64_t* run) {
  Unpacker u(bytes);
  SweepRunResult r;
  *run = u.Get<int64_t>();
  r.done = u.Get<int64_t>() != 0;
  r.steps = u.Get<int64_t>();
  r.events = u.Get<int64_t>();
  r.status = static_cast<int>(u.Get<int64_t>());
  r.signal = static_cast<int>(u.Get<int64_t>());
  const uint64_t n = u.Get<uint64_t>();
  if (n > bytes.size() / sizeof(double)) throw std::runtime_error("a sweep result message is cut short");
  r.finals.resize(n);
  for (double& v : r.finals) v = u.Get<double>();
  r.message = u.GetText();
  r.trajectory = u.GetText();
  if (!u.finished()) throw std::runtime_error("a sweep result message has bytes left over");
  return r;
}

int MpirunWorldSize() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (int n = EnvInt(name); n > 0) return n;
  }
  return 1;
}

int MpirunLocalSize() {
  const int n = EnvInt("OMPI_COMM_WORLD_LOCAL_SIZE");
  return n > 0 ? n : 1;
}

#if MOMENTA_HAVE_MPI

bool HaveMpi() { return true; }

SweepCluster::SweepCluster() {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") && !std::getenv("PMIX_RANK")) return;
  // Only the main thread calls MPI.
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  joined_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

SweepCluster::~SweepCluster() {
  if (joined_) MPI_Finalize();
}

std::vector<int64_t> SweepCluster::AllGather(int64_t value) const {
  std::vector<int64_t> all(size_, value);
  if (joined_) MPI_Allgather(&value, 1, MPI_INT64_T, all.data(), 1, MPI_INT64_T, MPI_COMM_WORLD);
  return all;
}

bool SweepCluster::PollAsk(int* from, int64_t* run, SweepRunResult* result) const {
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, kTagAsk, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return false;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::vector<char> bytes(count);
  MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, kTagAsk, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  *from = status.MPI_SOURCE;
  *result = UnpackRunResult(bytes, run);
  return true;
}

void SweepCluster::Answer(int to, int64_t run) const {
  MPI_Send(&run, 1, MPI_INT64_T, to, kTagAnswer, MPI_COMM_WORLD);
}

void SweepCluster::Ask(int64_t run, const SweepRunResult& result) const {
  std::vector<char> bytes = PackRunResult(run, result);
  if (bytes.size() > static_cast<size_t>(INT32_MAX)) {
    // A trajectory of more than 2 GB: sent without it, the run marked as failed.
    SweepRunResult small = result;
    small.trajectory.clear();
    small.status = 3;
    small.message = "the trajectory is too large to send to rank 0 (" + std::to_string(bytes.size()) + " bytes)";
    bytes = PackRunResult(run, small);
  }
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, 0, kTagAsk, MPI_COMM_WORLD);
}

bool SweepCluster::PollAnswer(int64_t* run) const {
  int flag = 0;
  MPI_Iprobe(0, kTagAnswer, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
  if (!flag) return false;
  MPI_Recv(run, 1, MPI_INT64_T, 0, kTagAnswer, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return true;
}

#else  // built without MPI: a cluster of one, the only rank

bool HaveMpi() { return false; }

SweepCluster::SweepCluster() {
  if (const int n = MpirunWorldSize(); n > 1) {
    throw UsageError("started by mpirun on " + std::to_string(n) +
                     " ranks, but this momenta was built without MPI (install libopenmpi-dev, as "
                     "scripts/setup.sh does, and rebuild); without mpirun, a sweep runs on threads (--jobs)");
  }
}

SweepCluster::~SweepCluster() = default;

std::vector<int64_t> SweepCluster::AllGather(int64_t value) const { return {value}; }

// With one rank there is nobody to send to: reaching these is a bug in the caller.
bool SweepCluster::PollAsk(int*, int64_t*, SweepRunResult*) const {
  AbortOnInternalError("size() > 1", __FILE__, __LINE__, "PollAsk in a build without MPI");
}
void SweepCluster::Answer(int, int64_t) const {
  AbortOnInternalError("size() > 1", __FILE__, __LINE__, "Answer in a build without MPI");
}
void SweepCluster::Ask(int64_t, const SweepRunResult&) const {
  AbortOnInternalError("size() > 1", __FILE__, __LINE__, "Ask in a build without MPI");
}
bool SweepCluster::PollAnswer(int64_t*) const {
  AbortOnInternalError("size() > 1", __FILE__, __LINE__, "PollAnswer in a build without MPI");
}

#endif

}  // namespace momenta
