"""to_pandas: a DataFrame when pandas is installed, a clear ImportError when it is not."""

import sys

import numpy as np
import pytest


def test_without_pandas_the_error_says_what_is_missing(carrier, monkeypatch):
    r = carrier.simulate(stop=0.01)
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas now raises ImportError
    with pytest.raises(ImportError, match=r"Result.to_pandas\(\) needs pandas, which is not installed"):
        r.to_pandas()
    with pytest.raises(ImportError, match=r"SweepResult.to_pandas\(\) needs pandas"):
        carrier.sweep({"eC": [0.5]}).to_pandas()


def test_a_result_as_a_data_frame(carrier):
    pytest.importorskip("pandas")
    r = carrier.simulate()
    df = r.to_pandas()
    assert list(df.columns) == ["time"] + carrier.outputs
    assert len(df) == len(r.time)
    assert np.array_equal(df["B.v"].to_numpy(), r["B.v"])


def test_a_sweep_as_a_data_frame(carrier):
    pytest.importorskip("pandas")
    s = carrier.sweep({"eC": [0.5, 1.5]})
    df = s.to_pandas()
    assert list(df.columns[:2]) == ["eC", "A.v"]
    assert list(df.columns[-4:]) == ["steps", "events", "status", "message"]
    assert df["status"].tolist() == [0, 1]
    assert np.isnan(df["B.v"][1]) and "1.5" in df["message"][1]
