"""Strict JSON output: numpy values and NaN."""

import json

import numpy as np
import pytest

from gearsim.io.jsonout import strict_json


def test_numpy_and_nonfinite_values_become_strict_json():
    doc = {"a": np.float64("nan"), "b": [1.5, np.inf, np.int64(3)], "c": np.arange(3),
           "d": {"e": (np.bool_(True), -np.inf)}, 4: "x"}
    text = strict_json(doc)
    assert "NaN" not in text and "Infinity" not in text
    assert json.loads(text) == {"a": None, "b": [1.5, None, 3], "c": [0, 1, 2],
                                "d": {"e": [True, None]}, "4": "x"}


def test_unknown_objects_are_refused():
    with pytest.raises(TypeError):
        strict_json({"x": object()})
