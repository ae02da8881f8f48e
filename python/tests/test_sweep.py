"""Model.sweep: grids run on threads without rebuilding, against the collision's closed form."""

import threading

import numpy as np
import pytest

from conftest import VA0, carrier_closed_form

TOL = 1e-12 * VA0  # rounding only (test_simulate.py says why)


def test_200_values_of_eC_against_the_closed_form(carrier):
    # From 0.25: below about 0.22, A would catch B again after B hits the suitcase.
    eCs = np.linspace(0.25, 1.0, 200)
    s = carrier.sweep({"eC": eCs}, jobs=2)
    assert len(s) == 200 and s.names == ["eC"] and not s.errors and s.ok.all()
    assert s.values[:, 0] == pytest.approx(eCs, abs=0)
    vB, vS = carrier_closed_form(eCs, 0.3)
    assert s.final("B.v") == pytest.approx(vB, abs=TOL)
    assert s.final("S.v") == pytest.approx(vS, abs=TOL)
    assert s.final("A.v") == pytest.approx(VA0 * (1 - eCs) / 2, abs=TOL)
    assert all(r.stats["impacts"] == 2 for r in s)


def test_200_values_of_eS_against_the_closed_form(carrier):
    eSs = np.linspace(0.0, 1.0, 200)
    s = carrier.sweep({"eS": eSs}, jobs=2)
    assert not s.errors
    vB, vS = carrier_closed_form(0.8, eSs)
    assert s.final("B.v") == pytest.approx(vB, abs=TOL)
    assert s.final("S.v") == pytest.approx(vS, abs=TOL)
    # Every run has its whole trajectory, with the impacts' rows.
    assert all(len(r) == 105 and r.time[-1] == pytest.approx(0.5) for r in s)


def test_a_grid_runs_every_combination_the_first_name_slowest(carrier):
    eCs, eSs = [0.5, 0.8, 1.0], [0.0, 0.5, 1.0]
    s = carrier.sweep({"eC": eCs, "eS": eSs}, jobs=2)
    assert s.names == ["eC", "eS"]
    assert s.values.tolist() == [[eC, eS] for eC in eCs for eS in eSs]
    for r in s:
        assert r["B.v"][-1] == pytest.approx(carrier_closed_form(r.params["eC"], r.params["eS"])[0], abs=TOL)
    # A list of runs is run as given.
    t = carrier.sweep([{"eC": 0.5}, {"eC": 1.0, "eS": 1.0}], jobs=1)
    assert t.names == ["eC", "eS"]
    assert np.isnan(t.values[0, 1])
    assert t[1]["B.v"][-1] == pytest.approx(carrier_closed_form(1.0, 1.0)[0], abs=TOL)


def test_the_threads_change_nothing(carrier):
    grid = {"eC": np.linspace(0.3, 1, 12), "eS": [0.1, 0.9]}
    one, two = carrier.sweep(grid, jobs=1), carrier.sweep(grid, jobs=2)
    for a, b in zip(one, two):
        assert np.array_equal(a.time, b.time) and np.array_equal(a.values, b.values)


def test_a_failing_run_does_not_stop_the_others(carrier):
    s = carrier.sweep({"eC": [0.5, 1.5, 1.0]}, jobs=2)
    assert s.ok.tolist() == [True, False, True]
    assert [k for k, _ in s.errors] == [1]
    assert "eC" in s.errors[0][1] and "1.5" in s.errors[0][1]
    assert np.isnan(s.final("B.v")[1])
    assert s.final("B.v")[2] == pytest.approx(carrier_closed_form(1.0, 0.3)[0], abs=TOL)


def test_the_gil_is_released_while_the_runs_simulate(carrier):
    # While a sweep runs on another Python thread, this one keeps running Python code; with the
    # GIL held through the sweep it would not run at all until the sweep returned.
    done = threading.Event()
    worker = threading.Thread(target=lambda: (carrier.sweep({"eC": np.linspace(0.3, 1, 100)}, jobs=1), done.set()))
    worker.start()
    turns = 0
    while not done.is_set() and worker.is_alive():
        turns += 1
    worker.join()
    assert done.is_set()
    assert turns > 1000
