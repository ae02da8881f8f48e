"""Shared set-up of the Python module's tests: run them with the module built and on the path,

    PYTHONPATH=build/python python3 -m pytest python/tests

(scripts/test.sh does so in its Release stage)."""

import os

import pytest

try:
    import momenta
except ImportError as e:  # pragma: no cover - says what to do rather than a bare traceback
    raise ImportError("the momenta module is not importable (%s): build it (cmake ... && ninja -C build) and "
                      "run pytest with PYTHONPATH=build/python" % e) from e

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CARRIER = os.path.join(ROOT, "models", "carrier_collision.yaml")

# The carrier collision's data (models/carrier_collision.yaml): masses [kg], A's speed [m/s].
MA, MB, MS, VA0 = 40.0, 40.0, 15.0, 5.0


def carrier_closed_form(eC, eS):
    """B's and S's velocities after both impacts (A hits B, then B's rear wall hits the
    suitcase): momentum and Newton's restitution law at each. For eC >= 0.22 (with eS = 0.3) A
    never catches B again, so these are the final values."""
    vB1 = MA * (1 + eC) * VA0 / (MA + MB)
    vB2 = (MB - eS * MS) * vB1 / (MB + MS)
    vS2 = MB * (1 + eS) * vB1 / (MB + MS)
    return vB2, vS2


@pytest.fixture(scope="session")
def carrier():
    """The carrier collision, loaded and built once for every test that uses it."""
    return momenta.load(CARRIER)


@pytest.fixture
def write_model(tmp_path):
    """Writes a model file into the test's own folder and returns its path."""

    def write(name, text):
        path = tmp_path / name
        path.write_text(text)
        return str(path)

    return write
