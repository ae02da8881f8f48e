#include "app/sweep_cluster.h"

#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "core/base/error.h"

#include "app/mpi_plugin.h"
#include "app/plugin.h"

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

constexpr int kTagAsk = 1, kTagAnswer = 2;

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

namespace {

/// The MPI plugin's table, loaded on first use; nullptr (with the reason) when it is not there.
const MpiPluginTable* Mpi(std::string* why = nullptr) {
#if MOMENTA_HAVE_MPI
  return static_cast<const MpiPluginTable*>(LoadPlugin("momenta-mpi.so", "momenta_mpi_plugin", true, why));
#else
  if (why) *why = "this momenta was built without MPI (install libopenmpi-dev, as scripts/setup.sh does, and rebuild)";
  return nullptr;
#endif
}

}  // namespace

bool HaveMpi() { return Mpi() != nullptr; }

SweepCluster::SweepCluster() {
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_SIZE") && !std::getenv("PMIX_RANK")) return;
  std::string why;
  mpi_ = Mpi(&why);
  if (!mpi_) {
    if (const int n = MpirunWorldSize(); n > 1) {
      throw UsageError("started by mpirun on " + std::to_string(n) + " ranks, but " + why +
                       "; without mpirun, a sweep runs on threads (--jobs)");
    }
    return;
  }
  // Only the main thread calls MPI.
  mpi_->join(&rank_, &size_);
}

SweepCluster::~SweepCluster() {
  if (mpi_) mpi_->leave();
}

std::vector<int64_t> SweepCluster::AllGather(int64_t value) const {
  std::vector<int64_t> all(size_, value);
  if (mpi_) mpi_->all_gather(value, all.data());
  return all;
}

// With one rank there is nobody to send to: reaching these without MPI is a bug in the caller.
const MpiPluginTable& SweepCluster::Joined(const char* what) const {
  if (!mpi_) AbortOnInternalError("size() > 1", __FILE__, __LINE__, what);
  return *mpi_;
}

bool SweepCluster::PollAsk(int* from, int64_t* run, SweepRunResult* result) const {
  const MpiPluginTable& mpi = Joined("PollAsk without MPI");
  int bytes = 0;
  if (!mpi.probe(-1, kTagAsk, from, &bytes)) return false;
  std::vector<char> message(bytes);
  mpi.receive(message.data(), bytes, *from, kTagAsk);
  *result = UnpackRunResult(message, run);
  return true;
}

void SweepCluster::Answer(int to, int64_t run) const {
  Joined("Answer without MPI").send(&run, sizeof run, to, kTagAnswer);
}

void SweepCluster::Ask(int64_t run, const SweepRunResult& result) const {
  const MpiPluginTable& mpi = Joined("Ask without MPI");
  std::vector<char> bytes = PackRunResult(run, result);
  if (bytes.size() > static_cast<size_t>(INT32_MAX)) {
    // A trajectory of more than 2 GB: sent without it, the run marked as failed.
    SweepRunResult small = result;
    small.trajectory.clear();
    small.status = 3;
    small.message = "the trajectory is too large to send to rank 0 (" + std::to_string(bytes.size()) + " bytes)";
    bytes = PackRunResult(run, small);
  }
  mpi.send(bytes.data(), static_cast<int>(bytes.size()), 0, kTagAsk);
}

bool SweepCluster::PollAnswer(int64_t* run) const {
  const MpiPluginTable& mpi = Joined("PollAnswer without MPI");
  int from = 0, bytes = 0;
  if (!mpi.probe(0, kTagAnswer, &from, &bytes)) return false;
  mpi.receive(run, sizeof *run, 0, kTagAnswer);
  return true;
}

}  // namespace momenta
