"""Errors are exceptions carrying momenta's messages: file:line:col, the user's names, the
closest valid names."""

import re

import pytest

import momenta
from conftest import CARRIER

RICCATI = """model: Riccati
parameters:
  k: {value: 0.25, max: 2, doc: x' = k x^2 blows up at t = 1/k}
define:
  Blow:
    parameters:
      k: {value: 1}
    variables:
      x: {start: 1, fixed: true}
    equations:
      - der(x) = k*x^2
components:
  b: {type: Blow, k: k}
experiment: {stop: 2, interval: 0.1}
outputs: [b.x]
"""


def test_the_exception_classes():
    assert issubclass(momenta.ModelError, momenta.Error) and issubclass(momenta.Error, Exception)
    assert issubclass(momenta.UsageError, momenta.ModelError) and issubclass(momenta.UsageError, ValueError)
    assert issubclass(momenta.SimulationError, momenta.Error)


def test_a_model_error_names_the_file_line_and_column(write_model):
    path = write_model("broken.yaml", "model: Broken\ncomponents:\n  A: {type: Masss, m: 1}\n")
    with pytest.raises(momenta.ModelError) as e:
        momenta.load(path)
    assert re.match(re.escape(path) + r":3:\d+: ", str(e.value)), str(e.value)
    assert "Masss" in str(e.value) and "Mass" in str(e.value).replace("Masss", "")


def test_a_missing_file(tmp_path):
    path = str(tmp_path / "nothing.yaml")
    with pytest.raises(momenta.ModelError, match=re.escape(path)):
        momenta.load(path)


def test_an_unknown_parameter_name_lists_the_closest(carrier):
    with pytest.raises(momenta.UsageError) as e:
        carrier.simulate(params={"eD": 0.5})
    text = str(e.value)
    assert text.startswith(CARRIER + ": parameter eD: no parameter of that name in CarrierCollision"), text
    assert "did you mean" in text and "eC" in text
    with pytest.raises(momenta.UsageError, match="parameter eD: no parameter of that name"):
        carrier.sweep({"eD": [0.1, 0.2]})
    # At load time too (the build's own check).
    with pytest.raises(momenta.UsageError) as e:
        momenta.load(CARRIER, params={"eD": 0.5})
    assert "parameter eD: no parameter of that name in CarrierCollision (did you mean" in str(e.value)


def test_a_value_the_model_refuses_names_the_parameter(carrier):
    with pytest.raises(momenta.ModelError) as e:
        carrier.simulate(params={"eC": 1.5})
    assert "eC" in str(e.value) and "1.5" in str(e.value) and re.search(r"\bmax", str(e.value)), str(e.value)
    with pytest.raises(momenta.UsageError, match=r"parameter eC: 'high' is not a number"):
        carrier.simulate(params={"eC": "high"})


def test_options_out_of_range_name_the_argument(carrier):
    with pytest.raises(momenta.UsageError, match=r"^stop=-1: the stop time must be a finite number after the start"):
        carrier.simulate(stop=-1)
    with pytest.raises(momenta.UsageError, match=r"^rtol=0: the relative tolerance must be"):
        carrier.simulate(rtol=0)
    with pytest.raises(momenta.UsageError, match=r"^max_order=7: the maximum BDF order"):
        carrier.simulate(max_order=7)
    with pytest.raises(momenta.UsageError, match=r"^linear_solver=lu: the choices are auto, dense and klu"):
        carrier.simulate(linear_solver="lu")
    with pytest.raises(momenta.UsageError, match=r"^error_test=some: the choices are states and all"):
        carrier.simulate(error_test="some")
    with pytest.raises(momenta.UsageError, match=r"^codegen=fast: the choices are auto, native and interp"):
        momenta.load(CARRIER, codegen="fast")
    with pytest.raises(TypeError, match="unexpected keyword"):
        carrier.sweep({"eC": [1]}, stopp=1)


def test_a_solver_failure_keeps_the_rows_before_it(write_model):
    m = momenta.load(write_model("riccati.yaml", RICCATI))
    # x = 1/(1 - k t) blows up at t = 1/k = 1.
    with pytest.raises(momenta.SimulationError) as e:
        m.simulate(params={"k": 1})
    text = str(e.value)
    assert text.startswith(m.path + ": simulation failed at t = "), text
    r = e.value.result
    assert r is not None and not r.ok and r.error == text
    assert 0.9 <= r.time[-1] < 1.0
    # The default rtol 1e-6 bounds each step's error; the blow-up amplifies it (2e-5 by t = 0.4).
    assert r["b.x"][:5] == pytest.approx(1 / (1 - r.time[:5]), rel=1e-4)
    # The model still runs with a value that does not blow up before the stop time.
    assert m.simulate(params={"k": 0.4})["b.x"][-1] == pytest.approx(5, rel=1e-4)


def test_an_unknown_output(carrier):
    r = carrier.simulate(stop=0.01)
    with pytest.raises(KeyError, match=r"'B\.x' is not an output of this model \(did you mean B\.v, B\.s\?\)"):
        r["B.x"]
