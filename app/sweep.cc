#include "app/sweep.h"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include "app/commands.h"
#include "app/csv_writer.h"
#include "app/interrupt.h"
#include "app/progress.h"
#include "app/sweep_cluster.h"
#include "core/base/messages.h"
#include "core/base/error.h"
#include "solver/simulator.h"

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;

/// One sweep on one rank: the plan and the built model (every rank builds its own), the runs done
/// on this rank's threads, and on rank 0 the results of all ranks written in run order.
class Sweep {
 public:
  Sweep(const SweepArgs& args, const SweepCluster& cluster) : args_(args), cluster_(cluster) {}
  ~Sweep() {
    if (out_ && out_ != stdout) std::fclose(out_);
  }
  Sweep(const Sweep&) = delete;
  Sweep& operator=(const Sweep&) = delete;

  /// Plans, builds and checks the swept names; rank 0 also opens the summary and the trajectories'
  /// directory. Returns an exit code after printing what went wrong.
  int Prepare();
  /// Runs the sweep (after every rank prepared); returns the exit code (see RunSweep).
  int Run();

 private:
  int CheckSweptNames() const;
  int OpenOutputs();
  SweepRunResult RunOne(size_t k) const;
  void WriteTrajectory(size_t k, SweepRunResult* r) const;
  void Store(size_t k, SweepRunResult r, int rank);
  void ServeAsks();
  int RunRankZero();
  void RunOtherRank();
  std::string RowText(size_t k) const;
  void Emit(const std::string& text);
  int Finish(double seconds);

  const SweepArgs& args_;
  const SweepCluster& cluster_;
  std::vector<SweepAxis> axes_;
  SweepPlan plan_;
  ParameterOverrides fixed_;
  LoadedModel loaded_;
  std::shared_ptr<const CompiledModel> model_;
  SimulationOptions opt_;
  size_t runs_ = 0;
  unsigned jobs_ = 1;  ///< this rank's threads

  // Rank 0's summary file.
  std::string out_path_;
  std::FILE* out_ = nullptr;
  std::string write_error_;

  // The runs' progress; results_ and the counters under mutex_.
  std::vector<SweepRunResult> results_;
  std::atomic<size_t> next_{0};
  std::atomic<bool> stop_{false};  ///< a summary write failed, or another rank was interrupted
  std::mutex mutex_;
  std::condition_variable wake_;  ///< the main thread: a run finished or a thread left
  size_t finished_ = 0, failed_ = 0, written_ = 0;
  std::vector<size_t> runs_by_rank_;  ///< finished runs by the rank that ran them
  unsigned active_ = 0;        ///< rank 0's threads still running
  int64_t remote_open_ = 0;    ///< other ranks' threads not yet told "no more runs"
  int remote_signal_ = 0;      ///< the signal that interrupted another rank
};

int Sweep::Prepare() {
  // The plan first: a bad SPEC is found before the model is built.
  try {
    for (const auto& p : args_.params) axes_.push_back(ParseSweepAxis(p));
    plan_ = MakeSweepPlan(axes_, args_.samples, args_.seed);
  } catch (const UsageError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  // Fixed values shape the build; swept ones are set per run.
  for (const auto& a : axes_) {
    if (!a.swept()) fixed_[a.name] = a.values[0];
  }
  try {
    loaded_.codegen.mode = ResolveCodegenMode(args_.options);
    loaded_.codegen.expected_runs = static_cast<double>(plan_.values.size());
  } catch (const UsageError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  if (int code = LoadAndBuild(args_.model, fixed_, &loaded_); code != kExitOk) return code;
  model_ = loaded_.model;
  if (int code = CheckSweptNames(); code != kExitOk) return code;
  if (int code = ResolveRunOptions(args_.model, loaded_, args_.options, &opt_); code != kExitOk) return code;
  runs_ = plan_.values.size();
  // By default the machine's cores, shared by the ranks started on it.
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  jobs_ = args_.jobs ? args_.jobs : std::max(1u, cores / static_cast<unsigned>(MpirunLocalSize()));
  jobs_ = static_cast<unsigned>(std::min<size_t>(jobs_, runs_));
  return cluster_.rank() == 0 ? OpenOutputs() : kExitOk;
}

int Sweep::CheckSweptNames() const {
  const FlatSystem& flat = *model_->flat;
  for (const auto& a : axes_) {
    if (!a.swept()) continue;
    const std::optional<ParamId> id = flat.FindParameter(a.name);
    if (!id) {
      std::vector<std::string> all;  // every name, for the suggestion only
      for (uint32_t k = 0; k < flat.parameters.size(); ++k) all.push_back(flat.ParameterName(ParamId(k)));
      auto close = ClosestNames(a.name, all);
      std::cerr << "momenta: " << args_.model << ": -p " << a.name << ": no parameter of that name in "
                << flat.model_name << (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") << "\n";
      return kExitUsage;
    }
    if (const double* built = flat.structural.Find(*id)) {
      std::cerr << "momenta: -p " << a.name << "=" << a.spec << ": " << a.name
                << " is a structural parameter (a count, a connection index or a Boolean or Integer if-condition; "
                   "the model was built with "
                << a.name << " = " << FormatDouble(*built)
                << "); a sweep builds the model once, so a structural parameter can only be given one value "
                   "(run one sweep per value)\n";
      return kExitUsage;
    }
  }
  return kExitOk;
}

int Sweep::OpenOutputs() {
  // The summary file, opened before anything runs, with its header.
  out_path_ = args_.out.empty() ? FileStem(args_.model) + "_sweep.csv" : args_.out;
  out_ = out_path_ == "-" ? stdout : std::fopen(out_path_.c_str(), "w");
  if (!out_) {
    std::cerr << "momenta: cannot write the summary file " << out_path_ << ": " << std::strerror(errno) << "\n";
    return kExitSolver;
  }
  std::string header = "run";
  const std::vector<std::string>* column_groups[] = {&plan_.names, &model_->output_names};
  for (const std::vector<std::string>* names : column_groups) {
    for (const auto& n : *names) {
      header += ',';
      header += CsvField(n);
    }
  }
  Emit(header + ",steps,events,status,message\n");
  if (!args_.trajectories.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(args_.trajectories, ec);
    if (ec) {
      std::cerr << "momenta: cannot create the trajectories directory " << args_.trajectories << ": "
                << ec.message() << "\n";
      return kExitSolver;
    }
  }
  return kExitOk;
}

SweepRunResult Sweep::RunOne(size_t k) const {
  SweepRunResult r;
  ParameterOverrides overrides = fixed_;
  for (size_t j = 0; j < plan_.names.size(); ++j) overrides[plan_.names[j]] = plan_.values[k][j];
  // A fresh state per run: nothing of one run can reach the next, whichever thread or rank runs it.
  ModelState state(model_);
  try {
    state.SetParameters(overrides);
  } catch (const ModelError& e) {
    r.status = kExitModel;
    r.message = e.what();
    return r;
  }
  // The trajectory as CSV text, written by rank 0 (a failed run's rows too).
  const bool keep = !args_.trajectories.empty();
  if (keep) r.trajectory = CsvHeader(model_->output_names);
  std::vector<double> last;
  SolverStats stats;
  try {
    Simulate(&state, opt_, [&](double t, const std::vector<double>& v) {
      if (keep) AppendCsvRow(t, v, &r.trajectory);
      last = v;
    }, &stats);
  } catch (const SolverError& e) {
    r.status = kExitSolver;
    r.message = std::string("simulation failed ") + e.what();
  } catch (const UsageError& e) {
    r.status = kExitUsage;
    r.message = e.what();
  } catch (const ModelError& e) {
    r.status = kExitModel;
    r.message = e.what();
  }
  r.steps = stats.steps;
  r.events = stats.events;
  if (stats.interrupted) {
    r.done = false;
    r.signal = InterruptSignal();
  }
  if (r.status == kExitOk) r.finals = std::move(last);
  return r;
}

void Sweep::WriteTrajectory(size_t k, SweepRunResult* r) const {
  const std::string path = args_.trajectories + "/run-" + std::to_string(k) + ".csv";
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "w");
  bool ok = f && std::fwrite(r->trajectory.data(), 1, r->trajectory.size(), f) == r->trajectory.size();
  if (f && std::fclose(f) != 0) ok = false;
  r->trajectory.clear();
  if (ok) return;
  // The run counts as failed: its trajectory was asked for.
  if (r->status == kExitOk) {
    r->status = kExitSolver;
    r->message = "cannot write the results file " + path + ": " + std::strerror(errno ? errno : EIO);
    r->finals.clear();
  }
}

void Sweep::Store(size_t k, SweepRunResult r, int rank) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (r.status != kExitOk) ++failed_;
    ++runs_by_rank_[rank];
    results_[k] = std::move(r);
    ++finished_;
  }
  wake_.notify_one();
}

void Sweep::ServeAsks() {
  int from = 0;
  int64_t run = -1;
  SweepRunResult r;
  while (cluster_.PollAsk(&from, &run, &r)) {
    // The result the ask carries, if any; an interrupted run stops the sweep.
    if (run >= 0 && !r.done) {
      remote_signal_ = r.signal;
      stop_ = true;
    } else if (run >= 0) {
      if (!r.trajectory.empty()) WriteTrajectory(static_cast<size_t>(run), &r);
      Store(static_cast<size_t>(run), std::move(r), from);
    }
    // The next run from the queue rank 0's threads share, or none.
    int64_t next = -1;
    if (!InterruptRequested().load() && !stop_.load()) {
      if (const size_t k = next_.fetch_add(1); k < runs_) next = static_cast<int64_t>(k);
    }
    cluster_.Answer(from, next);
    if (next < 0) --remote_open_;
  }
}

int Sweep::Run() {
  InstallInterruptHandler();
  opt_.interrupt = &InterruptRequested();
  // Every rank's thread count: rank 0 waits for each of the others' threads to be told "no more".
  const std::vector<int64_t> jobs = cluster_.AllGather(jobs_);
  if (cluster_.rank() != 0) {
    RunOtherRank();
    return kExitOk;
  }
  for (int r = 1; r < cluster_.size(); ++r) remote_open_ += jobs[r];
  return RunRankZero();
}

void Sweep::RunOtherRank() {
  // The threads run what rank 0 hands out; the main thread alone talks to rank 0.
  std::deque<size_t> queue;
  std::vector<std::pair<size_t, SweepRunResult>> outbox;
  bool quit = false;
  std::condition_variable work;
  std::vector<std::thread> threads;
  for (unsigned w = 0; w < jobs_; ++w) {
    threads.emplace_back([&] {
      std::unique_lock<std::mutex> lock(mutex_);
      while (true) {
        work.wait(lock, [&] { return quit || !queue.empty(); });
        if (queue.empty()) return;
        const size_t k = queue.front();
        queue.pop_front();
        lock.unlock();
        SweepRunResult r = RunOne(k);
        lock.lock();
        outbox.emplace_back(k, std::move(r));
        wake_.notify_one();
      }
    });
  }
  // One ask per thread; each finished run goes back with the next ask, until every thread's
  // chain has ended with rank 0's -1.
  for (unsigned w = 0; w < jobs_; ++w) cluster_.Ask(-1, SweepRunResult{});
  unsigned closed = 0;
  while (closed < jobs_) {
    int64_t k = -1;
    while (cluster_.PollAnswer(&k)) {
      if (k < 0) {
        ++closed;
        continue;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      queue.push_back(static_cast<size_t>(k));
      work.notify_one();
    }
    std::vector<std::pair<size_t, SweepRunResult>> ready;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      ready.swap(outbox);
    }
    for (const auto& [run, r] : ready) cluster_.Ask(static_cast<int64_t>(run), r);
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait_for(lock, std::chrono::milliseconds(1), [&] { return !outbox.empty(); });
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit = true;
  }
  work.notify_all();
  for (auto& t : threads) t.join();
}

int Sweep::RunRankZero() {
  const std::atomic<bool>& interrupted = InterruptRequested();
  results_.assign(runs_, SweepRunResult{});
  runs_by_rank_.assign(cluster_.size(), 0);
  for (SweepRunResult& r : results_) r.done = false;
  active_ = jobs_;
  const auto t0 = Clock::now();
  std::vector<std::thread> threads;
  for (unsigned w = 0; w < jobs_; ++w) {
    threads.emplace_back([&] {
      while (!interrupted.load(std::memory_order_relaxed) && !stop_.load(std::memory_order_relaxed)) {
        const size_t k = next_.fetch_add(1);
        if (k >= runs_) break;
        SweepRunResult r = RunOne(k);
        if (!r.done) break;  // interrupted in the middle: not a finished run
        if (!r.trajectory.empty()) WriteTrajectory(k, &r);
        Store(k, std::move(r), 0);
      }
      std::lock_guard<std::mutex> lock(mutex_);
      --active_;
      wake_.notify_one();
    });
  }

  // The main thread writes the rows in run order as they become ready, answers the other ranks
  // (polling every millisecond) and shows progress.
  const auto poll = std::chrono::milliseconds(cluster_.size() > 1 ? 1 : 200);
  ProgressLine progress(!args_.quiet);
  {
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
      wake_.wait_for(lock, poll, [&] {
        return (active_ == 0 && remote_open_ == 0) || (written_ < runs_ && results_[written_].done);
      });
      std::string text;
      while (written_ < runs_ && results_[written_].done) text += RowText(written_++);
      const bool local_stopped = active_ == 0;
      const size_t done = finished_, bad = failed_;
      lock.unlock();
      Emit(text);
      if (!write_error_.empty()) stop_ = true;
      if (cluster_.size() > 1) ServeAsks();
      if (progress.Due()) progress.Show(FormatSweepProgress(done, runs_, bad, progress.elapsed()));
      lock.lock();
      if (local_stopped && remote_open_ == 0) break;
    }
  }
  for (auto& t : threads) t.join();
  progress.Clear();
  return Finish(std::chrono::duration<double>(Clock::now() - t0).count());
}

std::string Sweep::RowText(size_t k) const {
  const SweepRunResult& r = results_[k];
  std::string s = std::to_string(k);
  for (double v : plan_.values[k]) {
    s += ',';
    s += FormatDouble(v);
  }
  for (size_t j = 0; j < model_->output_names.size(); ++j) {
    s += ",";
    if (j < r.finals.size()) s += FormatDouble(r.finals[j]);
  }
  std::string message = r.message;
  for (char& c : message) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  s += "," + std::to_string(r.steps) + "," + std::to_string(r.events) + "," + std::to_string(r.status) + ",\"";
  for (char c : message) s += c == '"' ? std::string("\"\"") : std::string(1, c);
  return s + "\"\n";
}

void Sweep::Emit(const std::string& text) {
  if (!write_error_.empty() || text.empty()) return;
  errno = 0;
  if (std::fwrite(text.data(), 1, text.size(), out_) != text.size() || std::fflush(out_) != 0) {
    write_error_ = "cannot write the summary file " +
                   (out_path_ == "-" ? std::string("(standard output)") : out_path_) + ": " +
                   std::strerror(errno ? errno : EIO);
  }
}

int Sweep::Finish(double seconds) {
  // After an interruption: the finished rows past the first unfinished one, still in run order.
  std::string rest;
  size_t kept = written_;
  for (size_t k = written_; k < runs_; ++k) {
    if (results_[k].done) {
      rest += RowText(k);
      ++kept;
    }
  }
  Emit(rest);
  std::FILE* out = out_;
  out_ = nullptr;
  if (out != stdout && std::fclose(out) != 0 && write_error_.empty()) {
    write_error_ = "cannot write the summary file " + out_path_ + ": " + std::strerror(errno);
  }
  if (!write_error_.empty()) {
    std::cerr << "momenta: " << write_error_ << "\n";
    return kExitSolver;
  }
  const size_t bad = failed_;
  if (InterruptRequested().load() || remote_signal_ != 0) {
    std::cerr << args_.model << ": sweep interrupted: " << kept << " of " << runs_ << " runs finished"
              << (bad ? " (" + std::to_string(bad) + " failed)" : "") << "; their rows are kept in " << out_path_
              << "\n";
    return 128 + (InterruptSignal() ? InterruptSignal() : remote_signal_);
  }
  // The first failures, so that a glance at the terminal says what went wrong.
  size_t shown = 0;
  for (size_t k = 0; k < runs_ && shown < 3; ++k) {
    if (results_[k].status == kExitOk) continue;
    std::cerr << args_.model << ": run " << k << " (";
    for (size_t j = 0; j < plan_.names.size(); ++j) {
      std::cerr << (j ? ", " : "") << plan_.names[j] << " = " << FormatDouble(plan_.values[k][j]);
    }
    std::cerr << ") failed with status " << results_[k].status << ": " << results_[k].message << "\n";
    ++shown;
  }
  if (bad > shown) std::cerr << args_.model << ": " << bad - shown << " more runs failed (see the status column)\n";
  if (!args_.quiet) {
    std::ostream& o = out_path_ == "-" ? std::cerr : std::cout;
    char rate[64];
    std::snprintf(rate, sizeof rate, "%.4g s (%.4g runs/s)", seconds, seconds > 0 ? runs_ / seconds : 0.0);
    const std::string ranks = cluster_.size() > 1 ? std::to_string(cluster_.size()) + " MPI ranks x " : "";
    o << model_->flat->model_name << " (" << args_.model << "): " << runs_ << " runs on " << ranks << jobs_
      << (jobs_ == 1 ? " thread" : " threads") << " in " << rate << ", built once in "
      << FormatDouble(std::round(loaded_.build_s * 1e4) / 10) << " ms\n";
    o << "  " << runs_ - bad << " succeeded, " << bad << " failed\n";
    if (cluster_.size() > 1) {
      o << "  runs by rank:";
      for (size_t n : runs_by_rank_) o << " " << n;
      o << "\n";
    }
    o << "  summary: " << out_path_ << " (" << runs_ << " rows)\n";
    if (!args_.trajectories.empty()) o << "  trajectories: " << args_.trajectories << "/run-<k>.csv\n";
  }
  return bad ? kExitSolver : kExitOk;
}

}  // namespace

int RunSweep(const SweepArgs& args) {
  std::unique_ptr<SweepCluster> cluster;
  try {
    cluster = std::make_unique<SweepCluster>();
  } catch (const UsageError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  const int rank = cluster->rank(), size = cluster->size();
  Sweep sweep(args, *cluster);
  // Every rank prepares the same way, so only rank 0's messages are shown; another rank's only
  // when it alone failed.
  std::ostringstream captured;
  std::streambuf* saved = rank > 0 ? std::cerr.rdbuf(captured.rdbuf()) : nullptr;
  int code = sweep.Prepare();
  if (saved) std::cerr.rdbuf(saved);
  const std::vector<int64_t> codes = cluster->AllGather(code);
  int first_failed = -1;
  for (int r = 0; r < size && first_failed < 0; ++r) {
    if (codes[r] != kExitOk) first_failed = r;
  }
  if (first_failed < 0) return sweep.Run();
  if (rank > 0) {
    if (code != kExitOk && codes[0] == kExitOk) std::cerr << "momenta: rank " << rank << ": " << captured.str();
    return code;
  }
  if (code == kExitOk) {
    std::cerr << "momenta: rank " << first_failed << " of " << size << " could not prepare the sweep (exit code "
              << codes[first_failed] << "; its message is above)\n";
    code = static_cast<int>(codes[first_failed]);
  }
  return code;
}

}  // namespace momenta
