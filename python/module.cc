// momenta's Python extension `momenta._momenta`: PythonModel (python/python_model.h) bound with
// pybind11. Runs release the GIL while they simulate and poll Python's signals, so that Ctrl-C
// stops them; their rows come back as numpy arrays. The API users call (momenta.load, Result,
// SweepResult, the exception classes) is python/momenta/__init__.py, over this module.

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/base/error.h"
#include "core/lang/compiled_types.h"
#include "python/python_model.h"

namespace py = pybind11;

namespace momenta::python {

namespace {

/// The exception classes momenta/__init__.py defines (set by _set_exceptions; owned for the
/// process's life).
PyObject* g_model_error = nullptr;
PyObject* g_usage_error = nullptr;

py::array_t<double> Array(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::dict StatsDict(const SolverStats& s) {
  py::dict d;
  d["linear_solver"] = s.linear_solver;
  d["steps"] = s.steps;
  d["residual_evals"] = s.residual_evals;
  d["jacobian_evals"] = s.jacobian_evals;
  d["error_test_failures"] = s.error_test_failures;
  d["nonlinear_failures"] = s.nonlinear_failures;
  d["init_iterations"] = s.init_iterations;
  d["events"] = s.events;
  d["time_events"] = s.time_events;
  d["impacts"] = s.impacts;
  d["restarts"] = s.restarts;
  d["init_seconds"] = s.init_seconds;
  d["integrate_seconds"] = s.integrate_seconds;
  d["final_time"] = s.final_time;
  d["cost_note"] = s.cost_note;
  return d;
}

/// A run as the Python layer takes it: time (rows), values (rows x outputs), events and impacts
/// (their times), stats, status and message.
py::dict RecordDict(const RunRecord& r, size_t width) {
  py::dict d;
  const auto rows = static_cast<py::ssize_t>(r.time.size());
  py::array_t<double> values({rows, static_cast<py::ssize_t>(width)});
  std::copy(r.values.begin(), r.values.end(), values.mutable_data());
  d["time"] = Array(r.time);
  d["values"] = std::move(values);
  d["events"] = Array(r.stats.event_times);
  d["impacts"] = Array(r.stats.impact_times);
  d["stats"] = StatsDict(r.stats);
  d["status"] = r.status;
  d["message"] = r.message;
  return d;
}

/// The run options the Python layer passes: numbers (or None) by name, linear_solver and
/// error_test.
SimulateOverrides OverridesFrom(const py::dict& options) {
  SimulateOverrides o;
  auto number = [&](const char* name, std::optional<double>* out) {
    if (options.contains(name) && !options[name].is_none()) *out = options[name].cast<double>();
  };
  number("stop", &o.stop);
  number("rtol", &o.rtol);
  number("atol", &o.atol);
  number("interval", &o.interval);
  number("max_order", &o.max_order);
  number("max_steps", &o.max_steps);
  if (options.contains("linear_solver") && !options["linear_solver"].is_none()) {
    o.linear_solver = options["linear_solver"].cast<std::string>();
  }
  if (options.contains("error_test") && !options["error_test"].is_none()) {
    o.error_test = options["error_test"].cast<std::string>();
  }
  return o;
}

/// Runs every set of overrides with the GIL released; Ctrl-C (a pending KeyboardInterrupt)
/// stops them and is raised.
py::list Run(PythonModel& model, const std::vector<ParameterOverrides>& runs, const py::dict& options,
             unsigned jobs, bool keep_rows) {
  const SimulationOptions resolved = model.ResolveOptions(OverridesFrom(options));
  const std::vector<ParameterOverrides> overrides = model.RunOverrides(runs);
  model.PrepareForRuns(runs.size());
  const std::shared_ptr<const CompiledModel> compiled = model.compiled();
  std::vector<RunRecord> records;
  {
    py::gil_scoped_release release;
    records = RunAll(compiled, model.path(), overrides, resolved, jobs, keep_rows, [] {
      py::gil_scoped_acquire acquire;
      return PyErr_CheckSignals() != 0;
    });
  }
  if (PyErr_Occurred()) throw py::error_already_set();
  py::list out;
  for (const RunRecord& r : records) out.append(RecordDict(r, compiled->output_names.size()));
  return out;
}

/// Model.linearize's answer: names, the operating point, the matrices as lists of rows and the
/// eigenvalues as complex numbers (__init__.py makes numpy arrays of them). A solver failure is a
/// ModelError here: its message says what failed and at which time.
py::dict LinearizeDict(const PythonModel& model, const ParameterOverrides& params, std::optional<double> at,
                       const std::vector<std::pair<std::string, double>>& inputs,
                       const std::vector<std::string>& outputs) {
  Linearization lin;
  {
    py::gil_scoped_release release;
    try {
      lin = model.Linearize(params, at, LinearizationSpec{inputs, outputs});
    } catch (const SolverError& e) {
      throw ModelError(model.path() + ": linearisation failed " + e.what());
    }
  }
  auto rows = [](const DenseMatrix& m) {
    py::list out;
    for (size_t r = 0; r < m.rows; ++r) {
      py::list row;
      for (size_t c = 0; c < m.cols; ++c) row.append(m(r, c));
      out.append(row);
    }
    return out;
  };
  py::dict d;
  d["time"] = lin.t;
  d["states"] = lin.states;
  d["inputs"] = lin.inputs;
  d["outputs"] = lin.outputs;
  d["x0"] = lin.x;
  d["u0"] = lin.u;
  d["y0"] = lin.y;
  d["A"] = rows(lin.A);
  d["B"] = rows(lin.B);
  d["C"] = rows(lin.C);
  d["D"] = rows(lin.D);
  d["eigenvalues"] = lin.eigenvalues;
  return d;
}

}  // namespace

}  // namespace momenta::python

PYBIND11_MODULE(_momenta, m) {
  using namespace momenta;
  using namespace momenta::python;
  m.doc() = "momenta's compiled core; use the momenta package (momenta.load) rather than this module.";
  // The library's types as the build parsed them: no library text is parsed in this process.
  UseCompiledLibraryTypes(CompiledBuiltinTypes());

  m.def("_set_exceptions", [](py::object model_error, py::object usage_error) {
    g_model_error = model_error.release().ptr();
    g_usage_error = usage_error.release().ptr();
  });
  // A model error (file:line:col first) and an argument error, as the classes __init__.py gave.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const UsageError& e) {
      PyErr_SetString(g_usage_error ? g_usage_error : PyExc_ValueError, PythonText(e.what()).c_str());
    } catch (const ModelError& e) {
      PyErr_SetString(g_model_error ? g_model_error : PyExc_RuntimeError, PythonText(e.what()).c_str());
    }
  });

  py::class_<PythonModel>(m, "Model")
      .def(py::init([](const std::string& path, const ParameterOverrides& params, const std::string& codegen) {
             py::gil_scoped_release release;
             return std::make_unique<PythonModel>(path, params, codegen);
           }),
           py::arg("path"), py::arg("params"), py::arg("codegen"))
      .def_property_readonly("path", &PythonModel::path)
      .def_property_readonly("name", &PythonModel::model_name)
      .def_property_readonly("outputs", &PythonModel::output_names)
      .def_property_readonly("units", &PythonModel::output_units)
      .def_property_readonly("warnings", &PythonModel::warnings)
      .def_property_readonly("codegen", &PythonModel::codegen_summary)
      .def("parameters",
           [](const PythonModel& model) {
             py::list out;
             for (const ParameterInfo& p : model.Parameters()) {
               out.append(py::make_tuple(p.name, p.value, p.unit, p.description, p.structural));
             }
             return out;
           })
      .def("experiment",
           [](const PythonModel& model) {
             const SimulationOptions o = model.experiment_options();
             py::dict d;
             d["start"] = o.start;
             d["stop"] = o.stop;
             d["rtol"] = o.rtol;
             d["atol"] = o.atol < 0 ? o.rtol : o.atol;
             d["interval"] = o.interval > 0 ? o.interval : (o.stop - o.start) / 500;
             return d;
           })
      .def("linearize", &LinearizeDict, py::arg("params"), py::arg("at"), py::arg("inputs"),
           py::arg("outputs"))
      .def("run", &Run, py::arg("runs"), py::arg("options"), py::arg("jobs"), py::arg("keep_rows"));
}
