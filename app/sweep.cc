#include "app/sweep.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "app/commands.h"
#include "app/csv_writer.h"
#include "app/interrupt.h"
#include "core/component_type.h"
#include "core/error.h"
#include "solver/simulator.h"

namespace momenta {

namespace {

using Clock = std::chrono::steady_clock;

std::optional<double> Number(const std::string& text) {
  if (text == "true") return 1.0;
  if (text == "false") return 0.0;
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return std::nullopt;
  try {
    size_t used = 0;
    double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::vector<std::string> Split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  size_t begin = 0;
  while (true) {
    size_t end = text.find(sep, begin);
    parts.push_back(text.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return parts;
}

std::string Trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::string Stem(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  size_t dot = base.find_last_of('.');
  return dot == std::string::npos ? base : base.substr(0, dot);
}

/// A uniform number in [0, 1) from 53 bits of the engine's output.
double Unit(std::mt19937_64& engine) { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }

/// One draw of `axis` (a distribution).
double Draw(const SweepAxis& axis, std::mt19937_64& engine) {
  if (axis.kind == SweepAxis::Kind::kUniform) return axis.a + (axis.b - axis.a) * Unit(engine);
  // Box-Muller, cosine branch; u1 in (0, 1] so its logarithm is finite.
  const double u1 = 1.0 - Unit(engine), u2 = Unit(engine);
  return axis.a + axis.b * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

/// What one run gave.
struct RunResult {
  bool done = true;         ///< finished (false: interrupted in the middle, or not run)
  std::vector<double> finals;  ///< the outputs' last values (empty when the run failed)
  long steps = 0, events = 0;
  int status = kExitOk;
  std::string message;
};

}  // namespace

SweepAxis ParseSweepAxis(const std::string& text) {
  SweepAxis axis;
  size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw UsageError("-p takes NAME=SPEC (a value, a list a,b,c, a grid a:b:n or a:b:log:n, normal(mu,sigma) "
                     "or uniform(a,b)), found '" + text + "'");
  }
  axis.name = text.substr(0, eq);
  axis.spec = text.substr(eq + 1);
  const std::string& spec = axis.spec;
  auto fail = [&](const std::string& why) -> UsageError { return UsageError("-p " + text + ": " + why); };
  auto number = [&](const std::string& part, const std::string& what) {
    std::optional<double> v = Number(Trim(part));
    if (!v) throw fail(what + " '" + part + "' is not a finite number");
    return *v;
  };
  // Distributions.
  for (auto [prefix, kind] : {std::pair{"normal(", SweepAxis::Kind::kNormal}, std::pair{"uniform(", SweepAxis::Kind::kUniform}}) {
    if (spec.rfind(prefix, 0) != 0) continue;
    const std::string what = kind == SweepAxis::Kind::kNormal ? "normal(mu,sigma)" : "uniform(a,b)";
    if (spec.back() != ')') throw fail(what + " must end with ')'");
    std::vector<std::string> args = Split(spec.substr(std::strlen(prefix), spec.size() - std::strlen(prefix) - 1), ',');
    if (args.size() != 2) throw fail(what + " takes two numbers");
    axis.kind = kind;
    axis.a = number(args[0], kind == SweepAxis::Kind::kNormal ? "the mean" : "the lower bound");
    axis.b = number(args[1], kind == SweepAxis::Kind::kNormal ? "the standard deviation" : "the upper bound");
    if (kind == SweepAxis::Kind::kNormal && !(axis.b >= 0)) throw fail("the standard deviation must not be negative");
    if (kind == SweepAxis::Kind::kUniform && !(axis.b >= axis.a)) throw fail("the upper bound is below the lower bound");
    return axis;
  }
  // Grids.
  if (spec.find(':') != std::string::npos) {
    std::vector<std::string> parts = Split(spec, ':');
    const bool log = parts.size() == 4 && Trim(parts[2]) == "log";
    if (!(parts.size() == 3 || log)) throw fail("a grid is a:b:n (linear) or a:b:log:n (logarithmic)");
    const double a = number(parts[0], "the grid's start"), b = number(parts[1], "the grid's end");
    const std::string count_text = Trim(parts.back());
    std::optional<double> count = Number(count_text);
    if (!count || *count != std::floor(*count) || *count < 1 || *count > static_cast<double>(kMaxSweepRuns)) {
      throw fail("the number of grid points '" + count_text + "' is not a whole number from 1 to " +
                 std::to_string(kMaxSweepRuns));
    }
    const size_t n = static_cast<size_t>(*count);
    if (log && !(a > 0 && b > 0)) throw fail("a logarithmic grid needs a positive start and end");
    if (n == 1 && a != b) throw fail("a grid of one point from " + FormatDouble(a) + " to " + FormatDouble(b) + " is ambiguous; give the value alone");
    for (size_t k = 0; k < n; ++k) {
      // The ends exactly as given.
      if (k == 0) {
        axis.values.push_back(a);
      } else if (k + 1 == n) {
        axis.values.push_back(b);
      } else {
        const double f = static_cast<double>(k) / static_cast<double>(n - 1);
        axis.values.push_back(log ? std::exp(std::log(a) + (std::log(b) - std::log(a)) * f) : a + (b - a) * f);
      }
    }
    return axis;
  }
  // A value or a list.
  for (const std::string& part : Split(spec, ',')) axis.values.push_back(number(part, "the value"));
  return axis;
}

SweepPlan MakeSweepPlan(const std::vector<SweepAxis>& axes, size_t samples, uint64_t seed) {
  SweepPlan plan;
  std::set<std::string> seen;
  std::vector<size_t> grid, random;  // axes that are values (one or more), distributions
  for (size_t j = 0; j < axes.size(); ++j) {
    if (!seen.insert(axes[j].name).second) throw UsageError("-p " + axes[j].name + " is given twice");
    plan.names.push_back(axes[j].name);
    (axes[j].kind == SweepAxis::Kind::kValues ? grid : random).push_back(j);
  }
  if (!random.empty() && samples == 0) {
    throw UsageError("-p " + axes[random[0]].name + "=" + axes[random[0]].spec +
                     " is a distribution: give the number of draws with --samples K");
  }
  if (random.empty() && samples > 0) {
    throw UsageError("--samples " + std::to_string(samples) +
                     ": no -p is a distribution (normal(mu,sigma) or uniform(a,b)) to draw from");
  }
  const size_t draws = random.empty() ? 1 : samples;
  size_t grid_points = 1;
  for (size_t j : grid) {
    if (axes[j].values.size() > kMaxSweepRuns / grid_points) {
      throw UsageError("the sweep has more than " + std::to_string(kMaxSweepRuns) + " runs");
    }
    grid_points *= axes[j].values.size();
  }
  if (draws > kMaxSweepRuns / grid_points) {
    throw UsageError("the sweep has more than " + std::to_string(kMaxSweepRuns) + " runs (" +
                     std::to_string(grid_points) + " grid points x " + std::to_string(draws) + " samples)");
  }
  // The draws, all up front: sample s draws the distributions in -p order.
  std::mt19937_64 engine(seed);
  std::vector<std::vector<double>> drawn(draws, std::vector<double>(random.size()));
  if (!random.empty()) {
    for (size_t s = 0; s < draws; ++s) {
      for (size_t r = 0; r < random.size(); ++r) drawn[s][r] = Draw(axes[random[r]], engine);
    }
  }
  plan.values.reserve(grid_points * draws);
  for (size_t g = 0; g < grid_points; ++g) {
    std::vector<double> row(axes.size());
    // Row-major over the grid axes: the last one varies fastest.
    size_t rest = g;
    for (size_t i = grid.size(); i-- > 0;) {
      const std::vector<double>& v = axes[grid[i]].values;
      row[grid[i]] = v[rest % v.size()];
      rest /= v.size();
    }
    for (size_t s = 0; s < draws; ++s) {
      for (size_t r = 0; r < random.size(); ++r) row[random[r]] = drawn[s][r];
      plan.values.push_back(row);
    }
  }
  return plan;
}

int RunSweep(const SweepArgs& args) {
  // The plan first: a bad SPEC is found before the model is built.
  std::vector<SweepAxis> axes;
  SweepPlan plan;
  try {
    for (const auto& p : args.params) axes.push_back(ParseSweepAxis(p));
    plan = MakeSweepPlan(axes, args.samples, args.seed);
  } catch (const UsageError& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  // Fixed values shape the build; swept ones are set per run.
  ParameterOverrides fixed;
  for (const auto& a : axes) {
    if (!a.swept()) fixed[a.name] = a.values[0];
  }
  const auto t_build = Clock::now();
  LoadedModel loaded;
  if (int code = LoadAndBuild(args.model, fixed, &loaded); code != kExitOk) return code;
  const double build_s = std::chrono::duration<double>(Clock::now() - t_build).count();
  const std::shared_ptr<const CompiledModel> model = loaded.model;
  const FlatSystem& flat = *model->flat;
  {
    std::vector<std::string> all;
    for (const auto& p : flat.parameters) all.push_back(p.name);
    std::set<std::string> known(all.begin(), all.end());
    for (const auto& a : axes) {
      if (!a.swept()) continue;
      if (!known.count(a.name)) {
        auto close = ClosestNames(a.name, all);
        std::cerr << "momenta: " << args.model << ": -p " << a.name << ": no parameter of that name in "
                  << flat.model_name << (close.empty() ? "" : " (did you mean " + JoinNames(close) + "?)") << "\n";
        return kExitUsage;
      }
      if (auto it = flat.structural.find(a.name); it != flat.structural.end()) {
        std::cerr << "momenta: -p " << a.name << "=" << a.spec << ": " << a.name
                  << " is a structural parameter (a count, a connection index or a Boolean or Integer if-condition; "
                     "the model was built with "
                  << a.name << " = " << FormatDouble(it->second)
                  << "); a sweep builds the model once, so a structural parameter can only be given one value "
                     "(run one sweep per value)\n";
        return kExitUsage;
      }
    }
  }
  SimulationOptions opt;
  if (int code = ResolveRunOptions(args.model, loaded, args.options, &opt); code != kExitOk) return code;

  const size_t runs = plan.values.size();
  unsigned jobs = args.jobs ? args.jobs : std::max(1u, std::thread::hardware_concurrency());
  jobs = static_cast<unsigned>(std::min<size_t>(jobs, runs));

  // The summary file, opened before anything runs.
  const std::string out_path = args.out.empty() ? Stem(args.model) + "_sweep.csv" : args.out;
  std::FILE* out = out_path == "-" ? stdout : std::fopen(out_path.c_str(), "w");
  if (!out) {
    std::cerr << "momenta: cannot write the summary file " << out_path << ": " << std::strerror(errno) << "\n";
    return kExitSolver;
  }
  std::string write_error;
  auto emit = [&](const std::string& text) {
    if (!write_error.empty() || text.empty()) return;
    errno = 0;
    if (std::fwrite(text.data(), 1, text.size(), out) != text.size() || std::fflush(out) != 0) {
      write_error = "cannot write the summary file " + (out_path == "-" ? std::string("(standard output)") : out_path) +
                    ": " + std::strerror(errno ? errno : EIO);
    }
  };
  {
    std::string header = "run";
    const std::vector<std::string>* column_groups[] = {&plan.names, &model->output_names};
    for (const std::vector<std::string>* names : column_groups) {
      for (const auto& n : *names) {
        header += ',';
        header += CsvField(n);
      }
    }
    header += ",steps,events,status,message\n";
    emit(header);
  }
  if (!args.trajectories.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(args.trajectories, ec);
    if (ec) {
      std::cerr << "momenta: cannot create the trajectories directory " << args.trajectories << ": " << ec.message()
                << "\n";
      if (out != stdout) std::fclose(out);
      return kExitSolver;
    }
  }

  InstallInterruptHandler();
  const std::atomic<bool>& interrupted = InterruptRequested();
  opt.interrupt = &interrupted;
  std::atomic<bool> stop{false};  // a summary write failed
  std::vector<RunResult> results(runs);
  for (RunResult& r : results) r.done = false;
  std::atomic<size_t> next{0}, finished{0}, failed{0};
  std::mutex mutex;
  std::condition_variable wake;
  unsigned active = jobs;

  auto run_one = [&](size_t k) {
    RunResult r;
    ParameterOverrides overrides = fixed;
    for (size_t j = 0; j < plan.names.size(); ++j) overrides[plan.names[j]] = plan.values[k][j];
    // A fresh state per run: nothing of one run can reach the next, whichever thread runs it.
    ModelState state(model);
    try {
      state.SetParameters(overrides);
    } catch (const ModelError& e) {
      r.status = kExitModel;
      r.message = e.what();
      return r;
    }
    std::unique_ptr<CsvWriter> trajectory;
    std::vector<double> last;
    SolverStats stats;
    try {
      if (!args.trajectories.empty()) {
        trajectory = std::make_unique<CsvWriter>(args.trajectories + "/run-" + std::to_string(k) + ".csv",
                                                 model->output_names);
      }
      Simulate(&state, opt, [&](double t, const std::vector<double>& v) {
        if (trajectory) trajectory->Row(t, v);
        last = v;
      }, &stats);
      if (trajectory) trajectory->Close();
    } catch (const SolverError& e) {
      r.status = kExitSolver;
      r.message = std::string("simulation failed ") + e.what();
    } catch (const UsageError& e) {
      r.status = kExitUsage;
      r.message = e.what();
    } catch (const ModelError& e) {
      r.status = kExitModel;
      r.message = e.what();
    } catch (const std::exception& e) {  // a trajectory file that cannot be written, among others
      r.status = kExitSolver;
      r.message = e.what();
    }
    if (trajectory && r.status != kExitOk) {
      try {
        trajectory->Close();
      } catch (const std::exception&) {
      }
    }
    r.steps = stats.steps;
    r.events = stats.events;
    if (stats.interrupted) r.done = false;
    if (r.status == kExitOk) r.finals = std::move(last);
    return r;
  };

  const auto t0 = Clock::now();
  std::vector<std::thread> threads;
  for (unsigned w = 0; w < jobs; ++w) {
    threads.emplace_back([&] {
      while (!interrupted.load(std::memory_order_relaxed) && !stop.load(std::memory_order_relaxed)) {
        const size_t k = next.fetch_add(1);
        if (k >= runs) break;
        RunResult r = run_one(k);
        if (!r.done) break;  // interrupted in the middle: not a finished run
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (r.status != kExitOk) ++failed;
          results[k] = std::move(r);
          ++finished;
        }
        wake.notify_one();
      }
      std::lock_guard<std::mutex> lock(mutex);
      --active;
      wake.notify_one();
    });
  }

  auto row_text = [&](size_t k) {
    const RunResult& r = results[k];
    std::string s = std::to_string(k);
    for (double v : plan.values[k]) {
      s += ',';
      s += FormatDouble(v);
    }
    for (size_t j = 0; j < model->output_names.size(); ++j) {
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
  };

  // The main thread writes the rows in run order as they become ready and shows progress.
  const bool progress = !args.quiet && isatty(STDERR_FILENO);
  size_t written = 0;
  bool progress_shown = false;
  auto last_progress = Clock::now() - std::chrono::seconds(1);
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (true) {
      // Woken by a finished run or the last worker leaving; every 200 ms for the progress line.
      wake.wait_for(lock, std::chrono::milliseconds(200),
                    [&] { return active == 0 || (written < runs && results[written].done); });
      std::string text;
      while (written < runs && results[written].done) text += row_text(written++);
      const bool all_stopped = active == 0;
      const size_t done = finished.load(), bad = failed.load();
      lock.unlock();
      emit(text);
      if (!write_error.empty()) stop = true;
      if (progress && !all_stopped && Clock::now() - last_progress >= std::chrono::milliseconds(200)) {
        last_progress = Clock::now();
        const double s = std::chrono::duration<double>(Clock::now() - t0).count();
        char line[160];
        std::snprintf(line, sizeof line, "\rsweep: %zu/%zu runs, %zu failed, %.1f runs/s ", done, runs, bad,
                      s > 0 ? done / s : 0.0);
        std::cerr << line << std::flush;
        progress_shown = true;
      }
      lock.lock();
      if (all_stopped) break;
    }
  }
  for (auto& t : threads) t.join();
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (progress_shown) std::cerr << "\r\033[K" << std::flush;
  // After an interruption: the finished rows past the first unfinished one, still in run order.
  std::string rest;
  size_t kept = written;
  for (size_t k = written; k < runs; ++k) {
    if (results[k].done) {
      rest += row_text(k);
      ++kept;
    }
  }
  emit(rest);
  if (out != stdout && std::fclose(out) != 0 && write_error.empty()) {
    write_error = "cannot write the summary file " + out_path + ": " + std::strerror(errno);
  }
  if (!write_error.empty()) {
    std::cerr << "momenta: " << write_error << "\n";
    return kExitSolver;
  }
  const size_t bad = failed.load();
  if (interrupted.load()) {
    std::cerr << args.model << ": sweep interrupted: " << kept << " of " << runs << " runs finished"
              << (bad ? " (" + std::to_string(bad) + " failed)" : "") << "; their rows are kept in " << out_path << "\n";
    return 128 + InterruptSignal();
  }
  // The first failures, so that a glance at the terminal says what went wrong.
  size_t shown = 0;
  for (size_t k = 0; k < runs && shown < 3; ++k) {
    if (results[k].status == kExitOk) continue;
    std::cerr << args.model << ": run " << k << " (";
    for (size_t j = 0; j < plan.names.size(); ++j) std::cerr << (j ? ", " : "") << plan.names[j] << " = " << FormatDouble(plan.values[k][j]);
    std::cerr << ") failed with status " << results[k].status << ": " << results[k].message << "\n";
    ++shown;
  }
  if (bad > shown) std::cerr << args.model << ": " << bad - shown << " more runs failed (see the status column)\n";
  if (!args.quiet) {
    std::ostream& o = out_path == "-" ? std::cerr : std::cout;
    char rate[64];
    std::snprintf(rate, sizeof rate, "%.4g s (%.4g runs/s)", seconds, seconds > 0 ? runs / seconds : 0.0);
    o << flat.model_name << " (" << args.model << "): " << runs << " runs on " << jobs
      << (jobs == 1 ? " thread" : " threads") << " in " << rate << ", built once in "
      << FormatDouble(std::round(build_s * 1e4) / 10) << " ms\n";
    o << "  " << runs - bad << " succeeded, " << bad << " failed\n";
    o << "  summary: " << out_path << " (" << runs << " rows)\n";
    if (!args.trajectories.empty()) o << "  trajectories: " << args.trajectories << "/run-<k>.csv\n";
  }
  return bad ? kExitSolver : kExitOk;
}

}  // namespace momenta
