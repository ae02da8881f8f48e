// The tests' FMI 2.0 importer (fmu_importer.h).

#include "tests/support/fmu_importer.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

namespace momenta::testing {

namespace {

std::string& LogText() {
  static std::string text;
  return text;
}

void Logger(fmi2ComponentEnvironment, fmi2String instance, fmi2Status status, fmi2String category,
            fmi2String message, ...) {
  char buf[4096];
  va_list args;
  va_start(args, message);
  std::vsnprintf(buf, sizeof buf, message, args);
  va_end(args);
  LogText() += std::string(instance ? instance : "") + " [" + (category ? category : "") +
               ", status " + std::to_string(static_cast<int>(status)) + "] " + buf + "\n";
}

const fmi2CallbackFunctions kCallbacks = {Logger, std::calloc, std::free, nullptr, nullptr};

std::string Attribute(const std::string& xml, const std::string& name) {
  std::smatch m;
  if (std::regex_search(xml, m, std::regex("\\b" + name + "=\"([^\"]*)\""))) return m[1];
  return "";
}

}  // namespace

std::string TakeFmuLog() {
  std::string text;
  text.swap(LogText());
  return text;
}

FmuImporter::FmuImporter(const std::string& fmu, const std::string& dir) : dir_(dir) {
  const std::string unzip = "unzip -q -o '" + fmu + "' -d '" + dir + "'";
  if (std::system(unzip.c_str()) != 0) {
    error_ = "cannot unpack " + fmu;
    return;
  }
  std::ifstream in(dir + "/modelDescription.xml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  guid_ = Attribute(xml, "guid");
  id_ = Attribute(xml, "modelIdentifier");
  num_indicators_ = std::strtoul(Attribute(xml, "numberOfEventIndicators").c_str(), nullptr, 10);
  const std::regex variable("<ScalarVariable name=\"([^\"]*)\" valueReference=\"([0-9]+)\"");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), variable);
       it != std::sregex_iterator(); ++it) {
    refs_[(*it)[1]] = static_cast<unsigned>(std::stoul((*it)[2]));
  }
  const size_t derivatives = xml.find("<Derivatives>"), end = xml.find("</Derivatives>");
  if (derivatives != std::string::npos) {
    const std::string part = xml.substr(derivatives, end - derivatives);
    num_states_ =
        static_cast<size_t>(std::count(part.begin(), part.end(), 'U'));  // one <Unknown per state
  }
  resources_uri_ = "file://" + dir + "/resources";
  const std::string binary = dir + "/binaries/linux64/" + id_ + ".so";
  handle_ = dlopen(binary.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle_ == nullptr) error_ = std::string("dlopen: ") + dlerror();
}

FmuImporter::~FmuImporter() {
  if (handle_) dlclose(handle_);
}

unsigned FmuImporter::ValueReference(const std::string& name) const {
  auto it = refs_.find(name);
  return it == refs_.end() ? UINT32_MAX : it->second;
}

void* FmuImporter::Symbol(const char* name) const {
  void* f = handle_ ? dlsym(handle_, name) : nullptr;
  if (f == nullptr) {
    std::fprintf(stderr, "the FMU has no function %s\n", name);
    std::abort();
  }
  return f;
}

fmi2Component FmuImporter::Instantiate(fmi2Type type, const std::string& guid) {
  auto instantiate = Function<decltype(&fmi2Instantiate)>("fmi2Instantiate");
  return instantiate("test", type, guid.c_str(), resources_uri_.c_str(), &kCallbacks, fmi2False,
                     fmi2False);
}

void FmuImporter::Free(fmi2Component c) {
  if (c) Function<decltype(&fmi2FreeInstance)>("fmi2FreeInstance")(c);
}

bool FmuImporter::Start(fmi2Component c, const std::map<std::string, double>& params, double stop,
                        std::string* log) {
  if (Function<decltype(&fmi2SetupExperiment)>("fmi2SetupExperiment")(c, fmi2False, 0, 0, fmi2True,
                                                                      stop) != fmi2OK) {
    *log += "fmi2SetupExperiment failed\n";
    return false;
  }
  auto set = Function<decltype(&fmi2SetReal)>("fmi2SetReal");
  for (const auto& [name, value] : params) {
    const fmi2ValueReference vr = ValueReference(name);
    if (set(c, &vr, 1, &value) != fmi2OK) {
      *log += "fmi2SetReal " + name + " failed\n";
      return false;
    }
  }
  if (Function<decltype(&fmi2EnterInitializationMode)>("fmi2EnterInitializationMode")(c) !=
          fmi2OK ||
      Function<decltype(&fmi2ExitInitializationMode)>("fmi2ExitInitializationMode")(c) != fmi2OK) {
    *log += "the initialisation failed\n";
    return false;
  }
  return true;
}

void FmuImporter::Finish(fmi2Component c, const std::vector<std::string>& names, bool ok, FmuRunResult* r) {
  auto get = Function<decltype(&fmi2GetReal)>("fmi2GetReal");
  for (const std::string& name : names) {
    const fmi2ValueReference vr = ValueReference(name);
    double v = NAN;
    ok = ok && get(c, &vr, 1, &v) == fmi2OK;
    r->final[name] = v;
  }
  r->ok = ok;
  Free(c);
  r->log = TakeFmuLog() + r->log;
}

FmuRunResult FmuImporter::RunCoSimulation(const std::map<std::string, double>& params, double stop,
                                          double step, const std::vector<std::string>& names) {
  FmuRunResult r;
  fmi2Component c = Instantiate(fmi2CoSimulation, guid_);
  if (c == nullptr) {
    r.log = TakeFmuLog() + "fmi2Instantiate failed\n";
    return r;
  }
  bool ok = Start(c, params, stop, &r.log);
  auto do_step = Function<decltype(&fmi2DoStep)>("fmi2DoStep");
  const long n = std::lround(stop / step);
  for (long k = 0; ok && k < n; ++k) {
    const double t = k * step, h = (k + 1 == n) ? stop - t : step;
    ok = do_step(c, t, h, fmi2True) == fmi2OK;
    if (!ok) r.log += "fmi2DoStep at t = " + std::to_string(t) + " failed\n";
  }
  Finish(c, names, ok, &r);
  return r;
}

namespace {

/// The Model Exchange functions the integration uses.
struct MeFunctions {
  decltype(&fmi2SetTime) set_time;
  decltype(&fmi2SetContinuousStates) set_states;
  decltype(&fmi2GetDerivatives) derivatives;
  decltype(&fmi2GetEventIndicators) indicators;
};

/// One RK4 step of size h from (t, x); false when the FMU failed.
bool Rk4(fmi2Component c, const MeFunctions& f, double t, const std::vector<double>& x, double h,
         std::vector<double>* out) {
  const size_t n = x.size();
  std::vector<double> k1(n), k2(n), k3(n), k4(n), xs(n);
  auto eval = [&](double tt, const std::vector<double>& at, std::vector<double>* k) {
    return f.set_time(c, tt) == fmi2OK && f.set_states(c, at.data(), n) == fmi2OK &&
           f.derivatives(c, k->data(), n) == fmi2OK;
  };
  if (!eval(t, x, &k1)) return false;
  for (size_t i = 0; i < n; ++i) xs[i] = x[i] + 0.5 * h * k1[i];
  if (!eval(t + 0.5 * h, xs, &k2)) return false;
  for (size_t i = 0; i < n; ++i) xs[i] = x[i] + 0.5 * h * k2[i];
  if (!eval(t + 0.5 * h, xs, &k3)) return false;
  for (size_t i = 0; i < n; ++i) xs[i] = x[i] + h * k3[i];
  if (!eval(t + h, xs, &k4)) return false;
  out->resize(n);
  for (size_t i = 0; i < n; ++i) (*out)[i] = x[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  return true;
}

/// Whether an indicator changed sign from `before` to `after`.
bool SignChanged(const std::vector<double>& before, const std::vector<double>& after) {
  for (size_t i = 0; i < before.size(); ++i) {
    if ((before[i] > 0) != (after[i] > 0)) return true;
  }
  return false;
}

}  // namespace

FmuRunResult FmuImporter::RunModelExchange(const std::map<std::string, double>& params, double stop,
                                           double step, const std::vector<std::string>& names) {
  FmuRunResult r;
  fmi2Component c = Instantiate(fmi2ModelExchange, guid_);
  if (c == nullptr) {
    r.log = TakeFmuLog() + "fmi2Instantiate failed\n";
    return r;
  }
  const MeFunctions f{Function<decltype(&fmi2SetTime)>("fmi2SetTime"),
                      Function<decltype(&fmi2SetContinuousStates)>("fmi2SetContinuousStates"),
                      Function<decltype(&fmi2GetDerivatives)>("fmi2GetDerivatives"),
                      Function<decltype(&fmi2GetEventIndicators)>("fmi2GetEventIndicators")};
  auto new_discrete = Function<decltype(&fmi2NewDiscreteStates)>("fmi2NewDiscreteStates");
  auto enter_event = Function<decltype(&fmi2EnterEventMode)>("fmi2EnterEventMode");
  auto enter_continuous =
      Function<decltype(&fmi2EnterContinuousTimeMode)>("fmi2EnterContinuousTimeMode");
  auto get_states = Function<decltype(&fmi2GetContinuousStates)>("fmi2GetContinuousStates");
  auto completed = Function<decltype(&fmi2CompletedIntegratorStep)>("fmi2CompletedIntegratorStep");
  const size_t n = num_states_, nz = num_indicators_;
  std::vector<double> x(n), z(nz), z_new(nz), x_new(n);
  fmi2EventInfo info{};
  // The event iteration at the current time; reads the states back if it changed them.
  auto event_iteration = [&]() {
    info.newDiscreteStatesNeeded = fmi2True;
    bool changed = false;
    while (info.newDiscreteStatesNeeded) {
      if (new_discrete(c, &info) != fmi2OK) return false;
      changed = changed || info.valuesOfContinuousStatesChanged;
    }
    return enter_continuous(c) == fmi2OK && (!changed || get_states(c, x.data(), n) == fmi2OK);
  };
  bool ok = Start(c, params, stop, &r.log) && event_iteration() &&
            get_states(c, x.data(), n) == fmi2OK && f.indicators(c, z.data(), nz) == fmi2OK;
  double t = 0;
  while (ok && t < stop - 1e-12) {
    double h = std::min(step, stop - t);
    const bool time_event_ahead = info.nextEventTimeDefined && info.nextEventTime <= t + h;
    if (time_event_ahead) h = std::max(info.nextEventTime - t, 0.0);
    ok = Rk4(c, f, t, x, h, &x_new) && f.indicators(c, z_new.data(), nz) == fmi2OK;
    bool state_event = ok && SignChanged(z, z_new);
    if (state_event) {
      // Bisection of the step: hi ends past the crossing, lo before it.
      double lo = 0, hi = h;
      for (int it = 0; it < 60 && ok; ++it) {
        const double mid = 0.5 * (lo + hi);
        ok = Rk4(c, f, t, x, mid, &x_new) && f.indicators(c, z_new.data(), nz) == fmi2OK;
        (SignChanged(z, z_new) ? hi : lo) = mid;
      }
      h = hi;
      ok = ok && Rk4(c, f, t, x, h, &x_new);
    }
    if (!ok) break;
    t += h;
    x = x_new;
    fmi2Boolean enter = fmi2False, terminate = fmi2False;
    ok = f.set_time(c, t) == fmi2OK && f.set_states(c, x.data(), n) == fmi2OK &&
         completed(c, fmi2True, &enter, &terminate) == fmi2OK;
    const bool time_event = info.nextEventTimeDefined && t >= info.nextEventTime;
    if (ok && (state_event || time_event || enter)) {
      ++r.events;
      ok = enter_event(c) == fmi2OK && event_iteration();
    }
    ok = ok && f.indicators(c, z.data(), nz) == fmi2OK;
  }
  if (!ok) r.log += "the Model Exchange run failed at t = " + std::to_string(t) + "\n";
  Finish(c, names, ok, &r);
  return r;
}

}  // namespace momenta::testing
