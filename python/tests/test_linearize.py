"""Model.linearize: the state-space form as `momenta linearize` computes it, against closed forms."""

import math
import os

import numpy as np
import pytest

import momenta

from conftest import ROOT

# m x'' + d x' + c x = 0: A = [[0, 1], [-c/m, -d/m]]. (A model with an unconnected signal input
# does not load in Python: Model.linearize's inputs are for models loaded, so none here.)
DRIVEN = """model: Oscillator
parameters: {m: 2, c: 8, d: 0.4}
components:
  wall: {type: Fixed}
  spring: {type: Spring, c: c}
  damper: {type: Damper, d: d}
  mass: {type: Mass, m: m, s: {start: 0.1, fixed: true}, v: {start: 0, fixed: true}}
connections:
  - [wall.flange, spring.flange_a]
  - [spring.flange_b, mass.flange_a]
  - [wall.flange, damper.flange_a]
  - [damper.flange_b, mass.flange_a]
outputs: [mass.s, mass.v]
experiment: {stop: 2}
"""


@pytest.fixture(scope="module")
def driven(tmp_path_factory):
    path = tmp_path_factory.mktemp("lin") / "driven.yaml"
    path.write_text(DRIVEN)
    return momenta.load(str(path))


def test_mass_spring_damper_against_the_closed_form(driven):
    lin = driven.linearize()
    assert lin.inputs == []
    assert lin.outputs == ["mass.s", "mass.v"]
    # The states in the order the build chose: the position one and the velocity one.
    pos = 0 if lin.states[0] in ("mass.s", "damper.s_rel", "spring.s_rel") else 1
    vel = 1 - pos
    m, c, d = 2.0, 8.0, 0.4
    assert lin.A[pos, vel] == pytest.approx(1.0, abs=1e-12)
    assert lin.A[vel, pos] == pytest.approx(-c / m, rel=1e-12)
    assert lin.A[vel, vel] == pytest.approx(-d / m, rel=1e-12)
    assert lin.B.shape == (2, 0)
    # The outputs are the states: C picks them.
    assert lin.C[0, pos] == pytest.approx(1.0) and lin.C[1, vel] == pytest.approx(1.0)
    # Eigenvalues -d/2m ± i sqrt(c/m - (d/2m)^2).
    wd = math.sqrt(c / m - (d / (2 * m)) ** 2)
    assert sorted(lin.eigenvalues, key=lambda z: z.imag) == pytest.approx([-d / (2 * m) - 1j * wd,
                                                                         -d / (2 * m) + 1j * wd], abs=1e-10)
    # A parameter of this call only: c = 18 gives c/m = 9; later at t = 1 (linear: the same A).
    assert driven.linearize({"c": 18}).A[vel, pos] == pytest.approx(-9.0, rel=1e-12)
    later = driven.linearize(at=1.0)
    assert later.time == 1.0
    assert later.A == pytest.approx(lin.A, abs=1e-9)
    assert abs(later.x0[pos]) < 0.1  # the mass has moved towards the wall


def test_cartesian_pendulum_at_rest_has_the_closed_form_eigenvalues():
    # Index 3, in x and y with a rod force: at rest at the bottom, ±i sqrt(g/L).
    model = momenta.load(os.path.join(ROOT, "models", "pendulum_cartesian.yaml"), {"theta0": 0})
    lin = model.linearize()
    g = model.parameters["g"].value if "g" in model.parameters else 9.81
    L = model.parameters["L"].value
    omega = math.sqrt(g / L)
    nonzero = [z for z in lin.eigenvalues if abs(z) > 1e-6]
    assert sorted(z.imag for z in nonzero) == pytest.approx([-omega, omega], rel=1e-8)
    assert all(abs(z.real) < 1e-8 for z in nonzero)


def test_linearize_errors_name_the_argument(driven):
    with pytest.raises(momenta.UsageError, match=r"at=99"):
        driven.linearize(at=99)
    with pytest.raises(momenta.UsageError, match="nosuch"):
        driven.linearize(outputs=["nosuch.v"])
    with pytest.raises(momenta.UsageError, match="mass.v"):
        driven.linearize(inputs=["mass.v"])
    with pytest.raises(momenta.UsageError, match="nosuch"):
        driven.linearize({"nosuch": 1})
