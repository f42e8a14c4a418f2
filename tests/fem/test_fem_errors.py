"""Bad input to the FE model: clear InputError messages (CLI exit status 2)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gearsim.errors import InputError
from gearsim.fem.geometry import (
    CrackLine,
    SectorOptions,
    crack_line,
    mesh_sector,
    sector_outline_check,
)
from gearsim.fem.tooth import fe_tooth_compliance
from gearsim.geometry.profile import ToothProfile


def test_fem_mesh_too_coarse_for_crack(spur):
    gear = spur.gears[0]  # m = 3.2 mm: level 0 has 0.8 mm elements, crack 1 mm deep
    cl = crack_line(ToothProfile(gear), spur.cracks[0], 1e-3, 1)
    with pytest.raises(InputError, match="mesh too coarse for the crack") as exc:
        mesh_sector(gear, crack=cl, options=SectorOptions(level=0))
    assert exc.value.parameter == "fem.level"
    assert "use level >= 1" in str(exc.value)


def test_fem_crack_cutting_off_the_tooth(spur):
    gear = spur.gears[0]
    c = dataclasses.replace(spur.cracks[0], depth=6e-3)  # past the centre line
    with pytest.raises(InputError, match="deeper than the tooth") as exc:
        fe_tooth_compliance(gear, [gear.tip_radius], crack=c, side=1,
                            options=SectorOptions(level=1))
    assert exc.value.parameter == "crack.depth"


def test_fem_crack_crossing_the_centre_line_or_leaving_the_tooth(spur):
    gear = spur.gears[0]
    geo = crack_line(ToothProfile(gear), spur.cracks[0], 1e-3, 1)
    across = CrackLine(start=geo.start, tip=(-0.5e-3, geo.tip[1]))
    with pytest.raises(InputError, match="crosses the tooth centre line"):
        mesh_sector(gear, crack=across, options=SectorOptions(level=2))
    s = np.asarray(geo.start)
    outward = CrackLine(start=geo.start, tip=tuple(s + [1e-3, 0.2e-3]))
    with pytest.raises(InputError, match="outside the tooth"):
        mesh_sector(gear, crack=outward, options=SectorOptions(level=2))


def test_fem_unmeshable_outline_is_refused(spur):
    gear = spur.gears[0]
    half = ToothProfile(gear).outline(24, 32)
    with pytest.raises(InputError, match="overlap"):  # too many teeth on the circle
        sector_outline_check(half, 60, 5, gear.bore_radius_value)
    bad = half.copy()
    bad[10:20, 0] *= -3.0  # flank folded across the centre line
    with pytest.raises(InputError, match="gmsh cannot"):
        sector_outline_check(bad, gear.teeth, 5, gear.bore_radius_value)
    with pytest.raises(InputError, match="bore_radius"):
        sector_outline_check(half, gear.teeth, 5, 1.0)


def test_fem_radius_off_the_involute(spur):
    gear = spur.gears[0]
    with pytest.raises(InputError, match="involute"):
        fe_tooth_compliance(gear, [gear.root_radius], options=SectorOptions(level=0))


def test_fem_bad_options():
    with pytest.raises(InputError, match="odd"):
        SectorOptions(n_teeth=4)
    with pytest.raises(InputError, match="fixed"):
        SectorOptions(n_teeth=5, sides="glued")
    with pytest.raises(InputError, match="level"):
        SectorOptions(level=-1)
    assert SectorOptions().teeth_in(19) == 19
    assert SectorOptions(n_teeth=5).teeth_in(19) == 5
    assert math.isfinite(SectorOptions().growth)


def test_fem_cli_exit_status_2_on_bad_input(gearsim_here):
    """``gearsim fe-check`` in this process (``gearsim_here`` of tests/conftest.py)."""
    proc = gearsim_here("fe-check", "spur-19-48", "--crack", "working", "--level", "0")
    assert proc.returncode == 2, proc.stderr
    assert "mesh too coarse for the crack" in proc.stderr
    proc = gearsim_here("fe-check", "spur-19-48", "--crack", "sideways")
    assert proc.returncode == 2
    assert "--crack" in proc.stderr
