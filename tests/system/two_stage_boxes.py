"""Gearboxes of two planetary stages in series shared by tests/system (not a test module).

TOML: 24/24/72 x 3, ring held, sun in at 3000 rpm and 200 N m, its carrier driving the
sun of 20/40/100 x 4 through 3e6 N m/rad. TOML_CHAINS: the same stages between gears,
20/60 driving stage 1's sun (2e6 N m/rad) and 50/25 on stage 2's carrier (5e7 N m/rad),
at 1500 rpm. TOML_CHAINS_GRAPH: TOML_CHAINS as a graph. ``refused_in_one_line``: the
check of a bad file (one line naming the parameter, exit 2, no result file).
"""

from __future__ import annotations

from gearsim.cli import run as cli_run

TOML = """
name = "two planetary stages in series"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[[stages]]
sun_teeth = 24
planet_teeth = 24
ring_teeth = 72
planets = 3
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
ring_addendum_coefficient = 0.8
[[stages]]
fixed = "ring"
input = "sun"
shaft_stiffness = "3e6 N*m/rad"
sun_teeth = 20
planet_teeth = 40
ring_teeth = 100
planets = 4
normal_module = "4 mm"
normal_pressure_angle = "20 deg"
face_width = "40 mm"
ring_addendum_coefficient = 0.8
[operating]
fixed = "ring"
input = "sun"
speed = "3000 rpm"
torque = "200 N*m"
[dynamics]
duration = 0.2
fs = 20000
"""

TOML_CHAINS = TOML.replace('speed = "3000 rpm"', 'speed = "1500 rpm"') + """
[input_chain]
shaft_stiffness = "2e6 N*m/rad"
[input_chain.common]
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[input_chain.gears]]
name = "input-pinion"
teeth = 20
[[input_chain.gears]]
name = "sun-drive-gear"
teeth = 60
[chain]
shaft_stiffness = "5e7 N*m/rad"
[chain.common]
normal_module = "5 mm"
normal_pressure_angle = "20 deg"
face_width = "60 mm"
[[chain.gears]]
name = "carrier-gear"
teeth = 50
[[chain.gears]]
name = "output-pinion"
teeth = 25
"""

#: TOML_CHAINS as a graph (gearsim.model.graph_form): the shafts between the parts carry
#: the torsional stiffnesses.
TOML_CHAINS_GRAPH = """name = "two planetary stages in series"
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[[shafts]]
name = "in"
[[shafts]]
name = "sun-shaft"
torsional_stiffness = "2e6 N*m/rad"
[[shafts]]
name = "between"
torsional_stiffness = "3e6 N*m/rad"
[[shafts]]
name = "out"
torsional_stiffness = "5e7 N*m/rad"
[[shafts]]
name = "output"
[[gears]]
name = "input-pinion"
shaft = "in"
teeth = 20
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[gears]]
name = "sun-drive-gear"
shaft = "sun-shaft"
teeth = 60
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
[[gears]]
name = "carrier-gear"
shaft = "out"
teeth = 50
normal_module = "5 mm"
normal_pressure_angle = "20 deg"
face_width = "60 mm"
[[gears]]
name = "output-pinion"
shaft = "output"
teeth = 25
normal_module = "5 mm"
normal_pressure_angle = "20 deg"
face_width = "60 mm"
[[meshes]]
gears = ["input-pinion", "sun-drive-gear"]
[[meshes]]
gears = ["carrier-gear", "output-pinion"]
[[stages]]
sun = "sun-shaft"
carrier = "between"
ring = "housing"
sun_teeth = 24
planet_teeth = 24
ring_teeth = 72
planets = 3
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "30 mm"
ring_addendum_coefficient = 0.8
[[stages]]
sun = "between"
carrier = "out"
ring = "housing"
sun_teeth = 20
planet_teeth = 40
ring_teeth = 100
planets = 4
normal_module = "4 mm"
normal_pressure_angle = "20 deg"
face_width = "40 mm"
ring_addendum_coefficient = 0.8
[operating]
speed = "1500 rpm"
torque = "200 N*m"
[dynamics]
duration = 0.2
fs = 20000
"""


def refused_in_one_line(text: str, tmp_path, capsys, parameter: str) -> str:
    """``gearsim simulate`` of ``text``: exit 2, exactly one line on standard error,
    ``gearsim: error: PARAMETER = ...``, and no result file; returns the line."""
    path, out = tmp_path / "box.toml", tmp_path / "never.nc"
    path.write_text(text)
    code = cli_run(["simulate", str(path), "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert err[0].startswith(f"gearsim: error: {parameter} = "), err
    assert not out.exists()
    return err[0]
