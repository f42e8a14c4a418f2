"""What the analysis of a gearsim stage result says when it skips a tier: the result's
shaft names, not the analysis' labels (before: "(shaft shaft1)" for a mast), and why a
stage whose ring turns has no planetary tier (before: dropped without a word)."""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from gearsim.studies.batch import analyze_file

FS = 10_000.0
#: A star stage 20/31/82 x 3, carrier held, sun in at 3000 rpm: the ring turns at
#: -50 x 20/82 = -12.195 Hz, f_m = 20 x 50 = 1000 Hz; the ring's shaft is named "drum".
F_RING = 50.0 * 20 / 82
PARTS = {"stages": [{"z_sun": 20, "z_planet": 31, "z_ring": 82, "planets": 3,
                     "carrier_frequency": 0.0, "ring_frequency": -F_RING,
                     "carrier_phase": 0.0, "tacho": "drum", "frequency": F_RING,
                     "teeth": [82, 20, 31]}], "chains": []}


def test_a_star_stage_names_its_shaft_and_says_why_no_planetary_tier(tmp_path):
    # 0.3 s: 3.7 revolutions of the drum, short of the 4 / 12.195 = 0.328 s its sidebands
    # need (4 Hann bins)
    t = np.arange(int(0.3 * FS)) / FS
    path = tmp_path / "star.nc"
    xr.Dataset({"sensor": ("time", np.cos(2 * np.pi * 1000.0 * t))}, coords={"time": t},
               attrs={"kind": "planetary", "fs": FS, "sensor_angle": 0.0,
                      "analysis_parts": json.dumps(PARTS)}).to_netcdf(path, engine="h5netcdf")
    (row,), problems = analyze_file(str(path), channels=["sensor"])
    assert not problems
    rec = row["record"]
    assert rec["speed_hz"] == F_RING and rec["teeth"] == [82, 20, 31]
    why = {s["tier"]: s["reason"] for s in rec["skipped"]}
    assert "must be >= 0.328 s" in why["gear"] and "(shaft drum)" in why["gear"]
    assert not any("shaft1" in r for r in why.values())
    assert why["planetary"] == ("reads a sensor on a held ring; this stage's ring turns at "
                                "12.195 Hz (its carrier held)")
