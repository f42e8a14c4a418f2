"""Speed must not change numbers: a fixed study against the features of the tree before.

Issue 26 asks that the throughput work leave a fixed study's results as they were, to
1e-12. The reference (``data/fixed_study_before.json``) was computed by the tree at
commit c2b6069, before the last change of the order in which ``simulate`` forms its
records (5ddcb89: around the decimation instead of after it), with this file's study:
the Table-1 train healthy and with a working-flank root crack (the ``faults`` study's
classes ``none`` and ``working`` at severity 1, 2000 N m), each record noise-free and
with noise at 10 % of its RMS, every feature of the built-in ``faults`` study (62).

The noise-free records are the hard part: the spread statistics of a sideband family
(``sb_cv_*``, ``sb_flatness_*``) read sidebands about 1e-4 below the record's peak, so a
change of the record's last bits (4e-14 of its peak, what forming the record before or
after the filter makes) moves them by up to 2e-9 of their value. The tree that formed a
study's record like ``simulate`` does fails this test by that much; a study's records
are formed in the former order (``simulate_record``) and agree to round-off of the
analysis (measured 6.3e-16).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

from gearsim.studies.sweep import loads_study
from gearsim.studies.sweep_run import run_study

#: Issue 26: "Results identical to before (1e-12) on a fixed study", relative to each
#: feature's value.
IDENTITY_RTOL = 1e-12

REFERENCE = Path(__file__).parent / "data" / "fixed_study_before.json"

#: The SIMD code paths numpy dispatches to on this CPU: its sin, cos, exp and log give
#: other last bits on another path, and the noise-free spread features follow them, so
#: the reference holds on a CPU with the paths it was computed with.
SIMD = sorted(k for k in __cpu_dispatch__ if __cpu_features__.get(k))

STUDY = """
[study]
name = "fixed"
config = "idler-table1"
sampling = "grid"
seed = 2026
replicates = 1
signal = "acceleration[input,y]"
shafts = "all"
store_signals = false
[study.dynamics]
duration = "0.6 s"
fs = "20 kHz"
[parameters]
fault = ["none", "working"]
severity = [1.0]
closure = ["contact"]
torque = ["2000 N*m"]
noise = [0.0, 0.1]
"""


def test_fixed_study_features_equal_those_before_the_speed_work(tmp_path):
    ref = json.loads(REFERENCE.read_text())
    if SIMD != ref["_numpy_simd"]:
        pytest.skip(f"the reference was computed with numpy's SIMD paths {ref['_numpy_simd']}, "
                    f"this CPU takes {SIMD}: other last bits of the elementary functions")
    run_study(loads_study(STUDY), tmp_path / "s.nc", workers=1, progress=False)
    with xr.open_dataset(tmp_path / "s.nc") as ds:
        ds = ds.load()
    assert [str(x) for x in ds.fault.values] == ref["fault"]
    assert [float(x) for x in ds.noise.values] == ref["noise"]
    names = sorted(k for k in ref if not k.startswith("_") and k not in ("fault", "noise"))
    floats = sorted(v for v in ds.data_vars if ds[v].dtype.kind == "f")
    assert floats == names  # no feature added or lost
    assert len(names) == 62
    for name in names:
        want = np.array(ref[name])
        got = ds[name].values
        np.testing.assert_allclose(got, want, rtol=IDENTITY_RTOL, atol=0.0, err_msg=name)
