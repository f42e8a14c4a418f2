"""Gearboxes whose power branches, as TOML text (tests/system/test_branching.py and the
property test of tests/system/test_config_fuzz.py)."""

HEAD = """
[material]
youngs_modulus = "206 GPa"
poisson_ratio = 0.3
density = "7850 kg/m^3"
[common]
normal_module = "3 mm"
normal_pressure_angle = "20 deg"
face_width = "20 mm"
[operating]
speed = "1500 rpm"
torque = "100 N*m"
[stiffness]
positions_per_cycle = 40
"""

#: One pinion driving two gears: a quarter of the power to out-a, three quarters to out-b.
GEAR_SPLIT = HEAD + """
[[shafts]]
name = "input"
[[shafts]]
name = "out-a"
power_share = 0.25
[[shafts]]
name = "out-b"
power_share = 0.75
[[gears]]
name = "pinion"
shaft = "input"
teeth = 20
[[gears]]
name = "gear-a"
shaft = "out-a"
teeth = 40
[[gears]]
name = "gear-b"
shaft = "out-b"
teeth = 60
[[meshes]]
gears = ["pinion", "gear-a"]
angle = "0 deg"
[[meshes]]
gears = ["pinion", "gear-b"]
angle = "120 deg"
"""

#: An intermediate shaft receiving in the middle and driving at both ends (0.4 / 0.6).
SHAFT_SPLIT = HEAD + """
[[shafts]]
name = "input"
[[shafts]]
name = "mid"
torsional_stiffness = "2e5 N*m/rad"
[[shafts]]
name = "out-a"
power_share = 0.4
[[shafts]]
name = "out-b"
power_share = 0.6
[[gears]]
name = "p1"
shaft = "input"
teeth = 24
[[gears]]
name = "p2"
shaft = "mid"
teeth = 20
[[gears]]
name = "g1"
shaft = "mid"
teeth = 48
[[gears]]
name = "p3"
shaft = "mid"
teeth = 25
[[gears]]
name = "g2"
shaft = "out-a"
teeth = 50
[[gears]]
name = "g3"
shaft = "out-b"
teeth = 40
[[meshes]]
gears = ["p1", "g1"]
[[meshes]]
gears = ["p2", "g2"]
angle = "90 deg"
[[meshes]]
gears = ["p3", "g3"]
angle = "-90 deg"
"""

#: An idler (turning clockwise) driving two gears.
IDLER_SPLIT = HEAD + """
[[shafts]]
name = "input"
[[shafts]]
name = "idler"
[[shafts]]
name = "out-a"
power_share = 0.5
[[shafts]]
name = "out-b"
power_share = 0.5
[[gears]]
name = "pinion"
shaft = "input"
teeth = 21
[[gears]]
name = "idler"
shaft = "idler"
teeth = 31
[[gears]]
name = "gear-a"
shaft = "out-a"
teeth = 26
[[gears]]
name = "gear-b"
shaft = "out-b"
teeth = 43
[[meshes]]
gears = ["pinion", "idler"]
[[meshes]]
gears = ["idler", "gear-a"]
angle = "70 deg"
[[meshes]]
gears = ["idler", "gear-b"]
angle = "-95 deg"
"""
