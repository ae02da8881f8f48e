// `momenta linearize MODEL`: build the model with its free signal inputs held as inputs and the
// outputs asked for, bring it to the time asked for (the initialisation, or a simulation), and
// write its state-space form as JSON or as a MAT file.

#include "app/linearize_command.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/mat_file.h"
#include "app/report.h"
#include "core/base/messages.h"
#include "core/lang/units.h"
#include "solver/simulator.h"

namespace momenta {

namespace {

/// -u's NAME or NAME=VALUE texts; throws UsageError naming the bad one.
std::vector<std::pair<std::string, double>> ParseInputs(const std::vector<std::string>& texts) {
  std::vector<std::pair<std::string, double>> inputs;
  for (const std::string& text : texts) {
    const size_t eq = text.find('=');
    const std::string name = text.substr(0, eq);
    if (name.empty()) throw UsageError("momenta: -u takes NAME or NAME=VALUE, found '" + text + "'");
    double value = 0;
    if (eq != std::string::npos) {
      std::optional<double> number;
      try {
        number = ParseDecimal(text.substr(eq + 1));
      } catch (const std::exception&) {
        number.reset();
      }
      if (!number) {
        throw UsageError("momenta: -u " + text + ": '" + text.substr(eq + 1) + "' is not a number");
      }
      value = *number;
    }
    inputs.emplace_back(name, value);
  }
  return inputs;
}

/// -y's names: each option may hold a comma-separated list.
std::vector<std::string> SplitNames(const std::vector<std::string>& specs) {
  std::vector<std::string> names;
  for (const std::string& spec : specs) {
    std::stringstream s(spec);
    for (std::string name; std::getline(s, name, ',');) {
      if (!name.empty()) names.push_back(name);
    }
  }
  return names;
}

void JsonNumber(double v, std::string* out) {
  if (!std::isfinite(v)) {
    *out += "null";
    return;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v + 0.0);  // -0 is written 0
  *out += buf;
}

void JsonNames(const char* key, const std::vector<std::string>& names, std::string* out) {
  *out += std::string(",\n  \"") + key + "\": [";
  for (size_t k = 0; k < names.size(); ++k) {
    if (k) *out += ", ";
    JsonString(names[k], out);
  }
  *out += "]";
}

void JsonVector(const char* key, const std::vector<double>& values, std::string* out) {
  *out += std::string(",\n  \"") + key + "\": [";
  for (size_t k = 0; k < values.size(); ++k) {
    if (k) *out += ", ";
    JsonNumber(values[k], out);
  }
  *out += "]";
}

void JsonMatrix(const char* key, const DenseMatrix& m, std::string* out) {
  *out += std::string(",\n  \"") + key + "\": [";
  for (size_t r = 0; r < m.rows; ++r) {
    *out += r ? ",\n    [" : "\n    [";
    for (size_t c = 0; c < m.cols; ++c) {
      if (c) *out += ", ";
      JsonNumber(m(r, c), out);
    }
    *out += "]";
  }
  *out += m.rows ? "\n  ]" : "]";
}

/// "-1 ± 2i, -3": the eigenvalues, a conjugate pair once.
std::string EigenvalueText(const Linearization& lin) {
  std::vector<std::string> parts;
  for (const auto& lambda : lin.eigenvalues) {
    if (lambda.imag() < 0) continue;
    char buf[80];
    if (lambda.imag() == 0) {
      std::snprintf(buf, sizeof buf, "%.6g", lambda.real());
    } else {
      std::snprintf(buf, sizeof buf, "%.6g ± %.6gi", lambda.real(), lambda.imag());
    }
    parts.push_back(buf);
  }
  return JoinNames(parts, 20);
}

/// The time to linearise at from --at and the run's options; throws UsageError when it is outside
/// the experiment's interval.
double LinearizationTime(const LinearizeArgs& args, const SimulationOptions& opt) {
  if (!args.at) return opt.start;
  const double t = *args.at;
  if (!std::isfinite(t) || t < opt.start) {
    throw UsageError("momenta: --at " + NumberText(t) + ": the time must be a finite time from the start time " +
                     NumberText(opt.start) + " s on (experiment.start)");
  }
  if (t > opt.stop) {
    throw UsageError("momenta: --at " + NumberText(t) + ": beyond the stop time " + NumberText(opt.stop) +
                     " s of the experiment (experiment.stop); linearise at a time from " + NumberText(opt.start) +
                     " to " + NumberText(opt.stop) + " s");
  }
  return t;
}

/// Writes the result where -o says; returns an exit code after printing what went wrong.
int WriteResult(const LinearizeArgs& args, const std::string& model_name, const Linearization& lin) {
  const bool mat = args.out.size() > 4 && args.out.compare(args.out.size() - 4, 4, ".mat") == 0;
  try {
    if (mat) {
      WriteLinearizationMat(args.out, lin);
    } else if (args.out.empty() || args.out == "-") {
      std::cout << LinearizationJson(model_name, lin);
    } else {
      std::ofstream f(args.out);
      f << LinearizationJson(model_name, lin);
      f.flush();
      if (!f) throw std::runtime_error("cannot write " + args.out + ": " + std::strerror(errno));
    }
  } catch (const std::runtime_error& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitSolver;
  }
  if (args.out.empty() || args.out == "-") return kExitOk;
  std::cout << model_name << " (" << args.model << "): linearised at t = " << NumberText(lin.t) << " s: "
            << Counted(lin.states.size(), "state") << ", " << Counted(lin.inputs.size(), "input") << ", "
            << Counted(lin.outputs.size(), "output") << "\n";
  if (!lin.eigenvalues.empty()) std::cout << "  eigenvalues of A: " << EigenvalueText(lin) << "\n";
  std::cout << "  written to " << args.out << "\n";
  return kExitOk;
}

}  // namespace

std::string LinearizationJson(const std::string& model_name, const Linearization& lin) {
  std::string j = "{\n  \"model\": ";
  JsonString(model_name, &j);
  j += ",\n  \"time\": ";
  JsonNumber(lin.t, &j);
  JsonNames("states", lin.states, &j);
  JsonNames("inputs", lin.inputs, &j);
  JsonNames("outputs", lin.outputs, &j);
  JsonVector("x0", lin.x, &j);
  JsonVector("u0", lin.u, &j);
  JsonVector("y0", lin.y, &j);
  JsonMatrix("A", lin.A, &j);
  JsonMatrix("B", lin.B, &j);
  JsonMatrix("C", lin.C, &j);
  JsonMatrix("D", lin.D, &j);
  j += ",\n  \"eigenvalues\": [";
  for (size_t k = 0; k < lin.eigenvalues.size(); ++k) {
    j += k ? ", [" : "[";
    JsonNumber(lin.eigenvalues[k].real(), &j);
    j += ", ";
    JsonNumber(lin.eigenvalues[k].imag(), &j);
    j += "]";
  }
  return j + "]\n}\n";
}

void WriteLinearizationMat(const std::string& path, const Linearization& lin) {
  const size_t nx = lin.states.size(), nu = lin.inputs.size(), ny = lin.outputs.size();
  // [A B; C D], column by column.
  const size_t rows = nx + ny, cols = nx + nu;
  std::vector<double> abcd(rows * cols);
  for (size_t r = 0; r < rows; ++r) {
    for (size_t c = 0; c < cols; ++c) {
      double v;
      if (r < nx) {
        v = c < nx ? lin.A(r, c) : lin.B(r, c - nx);
      } else {
        v = c < nx ? lin.C(r - nx, c) : lin.D(r - nx, c - nx);
      }
      abcd[c * rows + r] = v;
    }
  }
  // Char matrices, one text a row, NUL-padded, stored column by column.
  auto char_rows = [](const std::vector<std::string>& texts, size_t* width) {
    *width = 1;
    for (const std::string& t : texts) *width = std::max(*width, t.size());
    std::vector<char> data(texts.size() * *width, '\0');
    for (size_t r = 0; r < texts.size(); ++r) {
      for (size_t c = 0; c < texts[r].size(); ++c) data[c * texts.size() + r] = texts[r][c];
    }
    return data;
  };
  std::vector<std::string> names = lin.states;
  names.insert(names.end(), lin.inputs.begin(), lin.inputs.end());
  names.insert(names.end(), lin.outputs.begin(), lin.outputs.end());
  size_t aclass_width = 0, name_width = 0;
  const std::vector<char> aclass = char_rows({"Alinear", "1.1", "", "binNormal"}, &aclass_width);
  const std::vector<char> xuy = char_rows(names, &name_width);
  const double num_states = static_cast<double>(nx);
  const std::vector<MatMatrix> matrices = {
      {"Aclass", kMatChar, 4, aclass_width, aclass.data()},
      {"nx", kMatDouble, 1, 1, &num_states},
      {"ABCD", kMatDouble, rows, cols, abcd.data()},
      {"xuyName", kMatChar, names.size(), name_width, xuy.data()},
  };
  int error = 0;
  const int status = WriteMat4(path, matrices, &error);
  if (status != 0) {
    throw std::runtime_error("cannot write " + path + (status == 2 ? std::string(": ") + std::strerror(error) : ""));
  }
}

int RunLinearize(const LinearizeArgs& args) {
  LinearizationSpec spec;
  try {
    spec.inputs = ParseInputs(args.inputs);
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return kExitUsage;
  }
  spec.outputs = SplitNames(args.outputs);
  LoadedModel loaded;
  loaded.configure_build = [&spec](BuildOptions* options) { PrepareLinearizationBuild(spec, options); };
  if (int code = LoadAndBuild(args.model, args.params, &loaded); code != kExitOk) return code;
  SimulationOptions opt;
  if (int code = ResolveRunOptions(args.model, loaded, {}, &opt); code != kExitOk) return code;
  const std::string& model_name = loaded.model->flat->model_name;
  double t = 0;
  try {
    t = LinearizationTime(args, opt);
  } catch (const UsageError& e) {
    std::cerr << e.what() << "\n";
    return kExitUsage;
  }
  // The operating point: the initialisation, or where a run to t ends; then the linearisation.
  Linearization lin;
  try {
    SolverStats stats;
    const RunPoint point = SimulateTo(loaded.state.get(), opt, t, [](double, const std::vector<double>&) {}, &stats);
    lin = Linearize(*loaded.state, point.t, point.y, point.yp,
                    ResolveLinearizationColumns(*loaded.model, loaded.report, spec));
  } catch (const SolverError& e) {
    std::cerr << args.model << ": linearisation failed " << e.what() << "\n";
    return kExitSolver;
  } catch (const ModelError& e) {
    std::cerr << args.model << ": " << e.what() << "\n";
    return kExitModel;
  }
  return WriteResult(args, model_name, lin);
}

}  // namespace momenta
