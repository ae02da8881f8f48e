"""momenta from Python: load a model file once, then simulate it as often as you like.

    import momenta
    m = momenta.load("models/carrier_collision.yaml")     # loads and builds once
    m.parameters["eC"]            # Parameter(value=0.8, unit='', description='coefficient of ...')
    r = m.simulate(params={"eC": 0.5}, stop=0.5)
    r.time, r["B.v"]              # numpy arrays
    s = m.sweep({"eC": [0.5, 0.6, 0.7], "eS": [0.2, 0.3]}, jobs=2)
    s.final("B.v")                # one value per run, the first parameter varying slowest

A run builds nothing: every run of a model shares its compiled form and has a state of its own,
so runs on several threads (a sweep's `jobs`, or your own threads) do not disturb each other;
they release the GIL while they simulate. Errors are exceptions: ModelError for the model or a
parameter value (its message starts with file:line:col where known), UsageError (also a
ValueError) for an unknown parameter name or a bad option, SimulationError when the solver fails
(its `result` holds the rows computed before).
"""

import collections
import collections.abc
import difflib
import itertools
import os

import numpy as np

from . import _momenta

__all__ = ["load", "Model", "Result", "SweepResult", "Parameter", "Error", "ModelError", "UsageError",
           "SimulationError"]


class Error(Exception):
    """Any error momenta reports."""


class ModelError(Error):
    """The model is wrong, or a parameter value it refuses; the message names the file, line and
    column where known and the user's component."""


class UsageError(ModelError, ValueError):
    """An argument momenta cannot take: an unknown parameter name (the message lists the closest
    ones), a structural parameter changed without loading again, an option out of range."""


class SimulationError(Error):
    """The solver failed; the message names the time and the variable. `result` holds the rows
    computed up to then."""

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result


_momenta._set_exceptions(ModelError, UsageError)

Parameter = collections.namedtuple("Parameter", "value unit description")
Parameter.__doc__ = "A parameter's value (in its unit, as the model was loaded), unit and description."

_OPTIONS = ("stop", "rtol", "atol", "interval", "max_order", "max_steps", "linear_solver", "error_test")


def load(path, params=None, codegen="auto"):
    """Loads and builds the model file at `path` once; `params` (name -> number) are applied
    when building, so they may be structural (a count, a Boolean if-condition). `codegen` is
    "auto", "native" or "interp" (as `momenta simulate --codegen`). Raises ModelError."""
    return Model(path, params, codegen)


def _numbers(params, what="params"):
    """`params` as {name: float}; a value that is not a number is a UsageError naming it."""
    if params is None:
        return {}
    if not isinstance(params, collections.abc.Mapping):
        raise UsageError("%s must be a mapping of parameter names to numbers, not %s" % (what, type(params).__name__))
    out = {}
    for name, value in params.items():
        if isinstance(value, (str, bytes)):
            raise UsageError("parameter %s: %r is not a number" % (name, value))
        try:
            out[str(name)] = float(value)
        except (TypeError, ValueError):
            raise UsageError("parameter %s: %r is not a number" % (name, value)) from None
    return out


def _pandas(what):
    try:
        import pandas
    except ImportError as e:
        raise ImportError("%s needs pandas, which is not installed (Debian: apt-get install python3-pandas); "
                          "without it the results are numpy arrays (time, r[name])" % what) from e
    return pandas


class Model:
    """A built model. `parameters` maps every parameter name (model parameters, and component
    parameters as `A.m`) to a Parameter; `outputs` lists the output names; `units` maps them to
    their units; `experiment` holds the model file's start, stop, rtol, atol and interval."""

    def __init__(self, path, params=None, codegen="auto"):
        self._model = _momenta.Model(os.fspath(path), _numbers(params), codegen)
        self.path = self._model.path
        self.name = self._model.name
        self.outputs = list(self._model.outputs)
        self.units = dict(zip(self.outputs, self._model.units))
        table = self._model.parameters()
        self.parameters = {name: Parameter(value, unit, doc) for name, value, unit, doc, _ in table}
        self.structural = [name for name, _, _, _, structural in table if structural]
        self.experiment = dict(self._model.experiment())
        self.warnings = list(self._model.warnings)
        if self.warnings:
            import warnings
            for w in self.warnings:
                warnings.warn(w, stacklevel=3)

    @property
    def codegen(self):
        """How the model's programs run: native code or the interpreter, and why."""
        return self._model.codegen

    def __repr__(self):
        return "<momenta.Model %s (%s): %d outputs, %d parameters>" % (
            self.name, self.path, len(self.outputs), len(self.parameters))

    def simulate(self, params=None, *, stop=None, rtol=None, atol=None, interval=None, max_order=None,
                 max_steps=None, linear_solver=None, error_test=None):
        """Runs the model once with `params` (name -> number) over the values it was loaded
        with; the options default to the model file's experiment section. Returns a Result.
        Raises ModelError for a parameter value the model refuses, UsageError for an unknown
        name or a bad option, SimulationError (with the rows so far) when the solver fails."""
        options = dict(stop=stop, rtol=rtol, atol=atol, interval=interval, max_order=max_order,
                       max_steps=max_steps, linear_solver=linear_solver, error_test=error_test)
        params = _numbers(params)
        record = self._model.run([params], options, 1, True)[0]
        result = Result(record, self, params)
        if record["status"] == 1:
            raise ModelError(record["message"])
        if record["status"] == 2:
            raise UsageError(record["message"])
        if record["status"] != 0:
            raise SimulationError(record["message"], result)
        return result

    def sweep(self, grid, *, jobs=None, trajectories=True, **options):
        """Runs the model for every combination of the values in `grid` (name -> values; the
        first name varies slowest, as `momenta sweep`), or for each dict of a list of them, on
        `jobs` threads (default: every core), without building again. `trajectories` False keeps
        each run's last row only. The options are simulate's. A run that fails does not stop the
        others: its Result says why (SweepResult.errors). Returns a SweepResult."""
        unknown = sorted(set(options) - set(_OPTIONS))
        if unknown:
            raise TypeError("sweep() got unexpected keyword arguments %s (options: %s)" %
                            (", ".join(unknown), ", ".join(_OPTIONS)))
        if isinstance(grid, collections.abc.Mapping):
            names = [str(n) for n in grid]
            axes = [[v] if np.isscalar(v) else list(v) for v in grid.values()]
            runs = [dict(zip(names, combo)) for combo in itertools.product(*axes)]
        else:
            runs = [dict(r) for r in grid]
            names = list(dict.fromkeys(n for r in runs for n in r))
        runs = [_numbers(r, "each run of grid") for r in runs]
        if jobs is None:
            jobs = os.cpu_count() or 1
        if int(jobs) < 1:
            raise UsageError("jobs=%r: the number of threads must be at least 1" % (jobs,))
        full = dict((k, options.get(k)) for k in _OPTIONS)
        records = self._model.run(runs, full, int(jobs), bool(trajectories)) if runs else []
        return SweepResult(names, [Result(rec, self, run) for rec, run in zip(records, runs)])


    def linearize(self, params=None, *, at=None, inputs=None, outputs=None):
        """The model's state-space form dx/dt = A dx + B du, dy = C dx + D du at time `at`
        (default: the start, after the initialisation; else where a run to `at` ends), as
        `momenta linearize` computes it: over the states the build chose (after index reduction),
        the free signal inputs `inputs` (names, or name -> operating value; default: all of them
        at 0) and the outputs `outputs` (variable names; default: the model's outputs). The model
        is built again for it (inputs held, outputs added), with `params` over the load's.
        Returns a Linearization. Raises UsageError for an unknown name or a time outside the
        experiment, ModelError when the model or the linearisation fails."""
        if inputs is None:
            inputs = []
        elif isinstance(inputs, collections.abc.Mapping):
            inputs = list(_numbers(inputs, "inputs").items())
        else:
            inputs = [(str(name), 0.0) for name in inputs]
        outputs = [] if outputs is None else [str(name) for name in outputs]
        d = self._model.linearize(_numbers(params), None if at is None else float(at), inputs, outputs)
        return Linearization(d)


class Linearization:
    """A linearisation (Model.linearize): `states`, `inputs`, `outputs` (names), `A`, `B`, `C`,
    `D` (numpy arrays, n x n, n x m, p x n, p x m), the operating point `x0`, `u0`, `y0`, the
    `time`, and `eigenvalues` of A (by increasing real part)."""

    def __init__(self, d):
        self.time = d["time"]
        self.states, self.inputs, self.outputs = list(d["states"]), list(d["inputs"]), list(d["outputs"])
        n, m, p = len(self.states), len(self.inputs), len(self.outputs)
        self.A = np.array(d["A"], dtype=float).reshape(n, n)
        self.B = np.array(d["B"], dtype=float).reshape(n, m)
        self.C = np.array(d["C"], dtype=float).reshape(p, n)
        self.D = np.array(d["D"], dtype=float).reshape(p, m)
        self.x0, self.u0, self.y0 = (np.array(d[k], dtype=float) for k in ("x0", "u0", "y0"))
        self.eigenvalues = np.array(d["eigenvalues"], dtype=complex)

    def __repr__(self):
        return "<momenta.Linearization at t = %g: %d states, %d inputs, %d outputs>" % (
            self.time, len(self.states), len(self.inputs), len(self.outputs))


class Result:
    """One run: `time` and `r[name]` (every output, and "time") as numpy arrays, a row per
    output time plus a left and a right limit at each event that changes an output; `names`
    the outputs; `units` their units; `events` and `impacts` the times at which they happened;
    `stats` the solver's statistics (steps, residual_evals, events, ...); `params` the
    parameter values given to this run; `error` None, or why the run stopped early."""

    def __init__(self, record, model, params):
        self.time = record["time"]
        self.values = record["values"]
        self.names = list(model.outputs)
        self.units = model.units
        self.events = record["events"]
        self.impacts = record["impacts"]
        self.stats = record["stats"]
        self.params = dict(params)
        self.status = record["status"]
        self.error = record["message"] or None
        self._index = {n: k for k, n in enumerate(self.names)}

    def __getitem__(self, name):
        if name == "time":
            return self.time
        k = self._index.get(name)
        if k is None:
            close = difflib.get_close_matches(str(name), self.names, n=3)
            raise KeyError("%r is not an output of this model%s (outputs: %s)" % (
                name, " (did you mean %s?)" % ", ".join(close) if close else "", ", ".join(self.names)))
        return self.values[:, k]

    def __contains__(self, name):
        return name == "time" or name in self._index

    def __len__(self):
        return len(self.time)

    def keys(self):
        return ["time"] + self.names

    @property
    def ok(self):
        return self.status == 0

    def final(self, name):
        """The output's last value (nan when the run computed no row)."""
        column = self[name]
        return float(column[-1]) if len(column) else float("nan")

    def to_pandas(self):
        """The rows as a pandas DataFrame: a `time` column, then every output. Needs pandas."""
        pandas = _pandas("Result.to_pandas()")
        return pandas.DataFrame({name: self[name] for name in self.keys()})

    def __repr__(self):
        state = "ok" if self.ok else "failed: " + self.error
        return "<momenta.Result %d rows x %d outputs, %s>" % (len(self.time), len(self.names), state)


class SweepResult:
    """A sweep's runs in order: `len(s)`, `s[k]` (a Result, with `params`), iteration; `names`
    the swept parameters and `values` their values (runs x names); `final(name)` an output's last
    value in every run (nan where a run failed); `ok` which runs finished; `errors` (run, message)
    of those that did not; `to_pandas()` one row per run, as `momenta sweep`'s summary."""

    def __init__(self, names, runs):
        self.names = names
        self.runs = runs
        self.values = np.array([[r.params.get(n, np.nan) for n in names] for r in runs], dtype=float).reshape(
            len(runs), len(names))
        self.ok = np.array([r.ok for r in runs], dtype=bool)
        self.errors = [(k, r.error) for k, r in enumerate(runs) if not r.ok]

    def __len__(self):
        return len(self.runs)

    def __getitem__(self, k):
        return self.runs[k]

    def __iter__(self):
        return iter(self.runs)

    def final(self, name):
        return np.array([r.final(name) if r.ok else np.nan for r in self.runs], dtype=float)

    def to_pandas(self):
        """One row per run: the swept parameters, every output's final value, steps, events,
        status and message. Needs pandas."""
        pandas = _pandas("SweepResult.to_pandas()")
        columns = {n: self.values[:, j] for j, n in enumerate(self.names)}
        outputs = self.runs[0].names if self.runs else []
        for name in outputs:
            columns[name] = self.final(name)
        columns["steps"] = [r.stats["steps"] for r in self.runs]
        columns["events"] = [r.stats["events"] for r in self.runs]
        columns["status"] = [r.status for r in self.runs]
        columns["message"] = [r.error or "" for r in self.runs]
        return pandas.DataFrame(columns)

    def __repr__(self):
        return "<momenta.SweepResult %d runs over %s, %d failed>" % (len(self.runs), ", ".join(self.names),
                                                                     len(self.errors))
