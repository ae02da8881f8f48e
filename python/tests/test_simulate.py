"""momenta.load and Model.simulate on the carrier collision, against its closed form."""

import numpy as np
import pytest

import momenta
from conftest import CARRIER, VA0, carrier_closed_form

# Exact impacts, then free motion: the velocities are linear solves, so rounding is the only
# error (1e-12 of A's initial speed is generous; tests/app/sweep_test.cc uses the same).
TOL = 1e-12 * VA0


def test_the_collision_ends_at_the_seeds_velocities(carrier):
    r = carrier.simulate()
    assert isinstance(r.time, np.ndarray) and isinstance(r["B.v"], np.ndarray)
    assert r["B.v"].shape == r.time.shape
    vB2, vS2 = carrier_closed_form(0.8, 0.3)
    assert vB2 == pytest.approx(2.9045454545454545, abs=1e-15)
    assert r["B.v"][-1] == pytest.approx(vB2, abs=TOL)
    assert r["S.v"][-1] == pytest.approx(vS2, abs=TOL)
    assert r["A.v"][-1] == pytest.approx(0.5, abs=TOL)
    assert r.final("B.v") == r["B.v"][-1]
    # The experiment's grid (0 to 0.5 s every 5 ms) plus a left and a right limit at each impact.
    assert r.time[0] == 0 and r.time[-1] == pytest.approx(0.5, abs=1e-15)
    assert len(r) == 101 + 4
    # Two impacts: A hits B after 1 m at 5 m/s, B's wall the suitcase after 0.3 m at 4.5 m/s.
    assert r.impacts == pytest.approx([0.2, 0.2 + 0.3 / 4.5], abs=1e-10)
    assert r.events == pytest.approx(r.impacts, abs=0)
    assert r.stats["impacts"] == 2 and r.stats["steps"] > 10
    assert r.error is None and r.ok


def test_names_outputs_and_parameters(carrier):
    assert carrier.name == "CarrierCollision"
    assert carrier.outputs == ["A.v", "B.v", "S.v", "A.s", "B.s", "S.s", "carriers.v_J1", "carriers.v_K1",
                               "suitcase.v_J1", "suitcase.v_K1"]
    r = carrier.simulate()
    assert r.names == carrier.outputs
    assert r.keys() == ["time"] + carrier.outputs
    assert r["time"] is r.time
    assert carrier.units["B.v"] == "m/s" and carrier.units["A.s"] == "m"
    assert carrier.parameters["eC"] == momenta.Parameter(0.8, "", "coefficient of restitution between the carriers")
    assert carrier.parameters["mA"] == (40.0, "kg", "mass of carrier A")
    # Component parameters too, as -p names them.
    assert carrier.parameters["A.m"].value == 40.0
    assert carrier.experiment["stop"] == 0.5 and carrier.experiment["interval"] == 0.005


def test_parameters_of_a_run_leave_the_model_as_it_was(carrier):
    for eC in (0.5, 1.0):
        r = carrier.simulate(params={"eC": eC})
        assert r["B.v"][-1] == pytest.approx(carrier_closed_form(eC, 0.3)[0], abs=TOL)
        assert r.params == {"eC": eC}
    # The next run without parameters has the file's values again.
    assert carrier.simulate()["B.v"][-1] == pytest.approx(2.9045454545454545, abs=TOL)
    assert carrier.parameters["eC"].value == 0.8


def test_parameters_given_at_load_are_the_models_defaults():
    m = momenta.load(CARRIER, params={"eS": 1})
    assert m.parameters["eS"].value == 1.0
    assert m.simulate()["B.v"][-1] == pytest.approx(carrier_closed_form(0.8, 1.0)[0], abs=TOL)
    # A run's own value goes over the load's.
    assert m.simulate(params={"eS": 0.3})["B.v"][-1] == pytest.approx(2.9045454545454545, abs=TOL)


def test_options_stop_interval_and_tolerances(carrier):
    r = carrier.simulate(stop=0.1, interval=0.01)
    assert r.time == pytest.approx(np.linspace(0, 0.1, 11), abs=1e-15)
    assert len(r.impacts) == 0  # A reaches B at 0.2 s
    assert r["A.v"][-1] == VA0
    loose = carrier.simulate(rtol=1e-4, atol=1e-6)
    assert loose["B.v"][-1] == pytest.approx(2.9045454545454545, abs=1e-6)
    assert loose.stats["steps"] < carrier.simulate().stats["steps"]


def test_a_run_that_keeps_no_trajectory_keeps_its_last_row(carrier):
    s = carrier.sweep({"eC": [0.8]}, trajectories=False)
    assert len(s[0]) == 1
    assert s[0].time[0] == pytest.approx(0.5, abs=1e-15)
    assert s[0]["B.v"][0] == pytest.approx(2.9045454545454545, abs=TOL)
