# ruff: noqa: E501 - TOML lines of the templates are kept whole
"""Starter configs written by ``geardyn init TEMPLATE``: commented TOML for the three model
families. Each loads and runs (tests/test_cli_init.py): ``parallel`` (kinematics + gear
geometry and mesh stiffness), ``planetary`` (lumped planetary model: modes and a short
simulation) and ``transmission`` (finite-element shaft lines, seed 002).

Numbers are SI (the unit is in each field's name); any number may also be written as a string
with a unit, e.g. ``normal_module_m = "3 mm"`` or ``motor = "1500 rpm"``. The full reference of
the fields is docs/config.md (``python -m geardyn.config.reference``).
"""

from __future__ import annotations

PARALLEL = '''\
# geardyn starter config: one parallel-axis (spur) gear stage.
# Try:  geardyn kinematics {file}      (ratios and characteristic frequencies)
#       geardyn stiffness {file}       (geometry and mesh stiffness k(theta))
# Numbers are SI, the unit is in the field name (_m, _deg, _rpm, _pa...). A number may also
# be a string with a unit: face_width_m = "25 mm". Reference: docs/config.md;
# editor completion: geardyn schema --out geardyn.schema.json.

name = "Single spur stage"
frame = "housing"                      # the link that does not move
links = ["housing", "input", "output"] # every rigid body (shaft + what it carries)

# A parallel-axis stage: a pinion on "input" meshing with a wheel on "output".
# Shafts turn in the housing through implied turning pairs.
[[parallel]]
name = "stage1"
a = { link = "input", teeth = 31 }
b = { link = "output", teeth = 53 }

# Speeds of the input links (rpm, signed). One per degree of freedom.
[input_speeds_rpm]
input = 1500.0                         # or "25 Hz"

# Rolling bearings: element-pass and cage frequencies (kinematics).
[[bearings]]
name = "output ball"
kind = "ball"
inner = "output"
outer = "housing"
n_elements = 11
element_diameter_m = 0.0127
pitch_diameter_m = 0.080

# Gear geometry of the stage (mesh stiffness, transmission error): ISO 53 rack by default.
[[gear_geometry]]
pair = "stage1"
normal_module_m = 0.003                # 3 mm: a module over 0.1 m is refused
normal_pressure_angle_deg = 20.0
helix_angle_deg = 0.0                  # spur
face_width_m = 0.025
torque_nm = 100.0                      # optional: loaded static transmission error
a = { rim_radius_m = 0.030, youngs_modulus_pa = 206e9, poisson_ratio = 0.3 }
b = { rim_radius_m = 0.030, youngs_modulus_pa = 206e9, poisson_ratio = 0.3 }

# Optional faults (uncomment): a root crack on tooth 0 of the wheel.
# [[gear_geometry.cracks]]
# gear = "b"
# tooth = 0
# depth_m = "1 mm"
# angle_deg = 45.0
'''

PLANETARY = '''\
# geardyn starter config: one planetary stage and its lumped-parameter model (seed 003).
# Try:  geardyn kinematics {file}
#       geardyn modes {file}               (natural frequencies and mode types)
#       geardyn simulate {file} --out run.nc
# Numbers are SI, the unit is in the field name; a string with a unit also works ("65 mm").
# Reference: docs/config.md.

name = "Planetary stage"
frame = "housing"
links = ["housing", "motor", "carrier"]

# Sun on the motor shaft, ring fixed in the housing, output on the carrier.
[[planetary]]
name = "stage"
sun = "motor"
ring = "housing"
carrier = "carrier"
sun_teeth = 16
planet_teeth = 24
ring_teeth = 65
n_planets = 3                          # equally spaced unless planet_angles_deg is given

[input_speeds_rpm]
motor = 1500.0

[planetary_dynamics]
reduction = "torsional"                # "none" (Lin & Parker, 3 DOF/body) or "torsional"

[[planetary_dynamics.stages]]
stage = "stage"
pressure_angle_sun_deg = 20.0
pressure_angle_ring_deg = 15.5907      # r_c cos(alpha) must match the base radii (checked)
carrier_radius_m = 0.08165
planet_bearing_n_per_m = 3.5e6
sun = { mass_kg = 0.485, inertia_kgm2 = 356e-6, base_radius_m = 0.03069, bearing_n_per_m = 8.8e7 }
ring = { mass_kg = 28.1, inertia_kgm2 = 0.697767, base_radius_m = 0.12469, bearing_n_per_m = 2.1e7, torsional_support_nm_per_rad = 7.9e6 }
carrier = { mass_kg = 3.643, inertia_kgm2 = 0.021502, bearing_n_per_m = 4.8e8 }
planet = { mass_kg = 1.225, inertia_kgm2 = 2045e-6, base_radius_m = 0.04604 }
# Mesh stiffness: "constant", "square" (k_max/k_min, contact ratio), "sine" or "seed004".
sun_mesh = { model = "square", k_max_n_per_m = 5.146e8, k_min_n_per_m = 3.431e8, contact_ratio = 1.6 }
ring_mesh = { model = "square", k_max_n_per_m = 7.246e8, k_min_n_per_m = 4.831e8, contact_ratio = 1.6 }

# Time simulation (Newmark / HHT-alpha). Keep dt_s well below the shortest mesh period.
[planetary_dynamics.simulation]
t_end_s = 0.02
dt_s = 2e-5
rayleigh_beta = 2e-6
initial_speed_rpm = { "sun" = 1000.0 }
torques = [ { body = "carrier", torque_nm = -100.0 } ]
# Speed-controlled motor: profile [[t_s, rpm], ...] with increasing times.
speed_controls = [ { body = "sun", profile_rpm = [[0.0, 1000.0], [0.02, 1500.0]], stiffness_nm_per_rad = 2e4, damping_nms_per_rad = 5.0 } ]
'''

TRANSMISSION = '''\
# geardyn starter config: finite-element transmission (seed 002): two shaft lines, one spur
# stage, four rolling bearings, a speed law on the output.
# Try:  geardyn transmission {file} --modes-only
#       geardyn transmission {file} --revolutions 0.5
# Numbers are SI, the unit is in the field name; a string with a unit also works ("60 mm").
# Reference: docs/config.md.

name = "FE single stage"
frame = "housing"
links = ["housing", "input", "output"]

[[parallel]]
name = "stage"
a = { link = "input", teeth = 42 }
b = { link = "output", teeth = 55 }

[input_speeds_rpm]
input = 500.0

[[gear_geometry]]
pair = "stage"
normal_module_m = 0.003
normal_pressure_angle_deg = 20.0
face_width_m = 0.025
a = { tip_radius_m = 0.066, root_radius_m = 0.0585, rim_radius_m = 0.030, tip_round_m = 0.0005, youngs_modulus_pa = 202e9, poisson_ratio = 0.255 }
b = { tip_radius_m = 0.0855, root_radius_m = 0.0768, rim_radius_m = 0.030, tip_round_m = 0.0005, youngs_modulus_pa = 202e9, poisson_ratio = 0.255 }

[transmission]
modal_damping = 0.01
# Torques at shaft nodes (node 0 = first end of the shaft).
drive = { at = { shaft = "input", node = 0 }, torque_nm = 0.0 }
load = { at = { shaft = "output", node = 0 }, torque_nm = 100.0 }
# Imposed speed of a reference node: start -> end rpm over a number of revolutions.
speed_law = { reference = { shaft = "output", node = 0 }, start_rpm = 360.0, end_rpm = 430.0, revolutions = 20.0 }
simulation = { record_rate_hz = 50000.0 }

# Shaft lines: Timoshenko beam elements; positions in the transverse plane (m).
# The centre distance must match the gear pair: m (z1 + z2) / 2 = 145.5 mm.
[[transmission.shafts]]
name = "output"
link = "output"
position_m = [0.0, 0.0]
length_m = 0.5
elements = 5
outer_diameter_m = 0.060
inner_diameter_m = 0.045

[[transmission.shafts]]
name = "input"
link = "input"
position_m = [0.1455, 0.0]
length_m = 0.5
elements = 5
outer_diameter_m = 0.060
inner_diameter_m = 0.045

# Wheels of the gear pair at shaft nodes.
[[transmission.wheels]]
pair = "stage"
gear = "b"
at = { shaft = "output", node = 3 }

[[transmission.wheels]]
pair = "stage"
gear = "a"
at = { shaft = "input", node = 3 }

[[transmission.meshes]]
pair = "stage"
slices = 5
friction_coefficient = 0.03

# Rolling bearings (nonlinear Hertzian contacts).
[[transmission.bearings]]
name = "output ball"
at = { shaft = "output", node = 1 }
kind = "ball"
elements = 11
pitch_diameter_m = 0.080
element_diameter_m = 0.0127
diametral_clearance_m = 45e-6

[[transmission.bearings]]
name = "output roller"
at = { shaft = "output", node = 5 }
kind = "roller"
elements = 18
pitch_diameter_m = 0.0725
element_diameter_m = 0.010
roller_length_m = 0.010
diametral_clearance_m = 40e-6

[[transmission.bearings]]
name = "input ball"
at = { shaft = "input", node = 1 }
kind = "ball"
elements = 11
pitch_diameter_m = 0.080
element_diameter_m = 0.0127
diametral_clearance_m = 45e-6

[[transmission.bearings]]
name = "input roller"
at = { shaft = "input", node = 5 }
kind = "roller"
elements = 18
pitch_diameter_m = 0.0725
element_diameter_m = 0.010
roller_length_m = 0.010
diametral_clearance_m = 40e-6
'''

#: template name → (one-line description, TOML text with ``{file}`` for the written file name).
TEMPLATES: dict[str, tuple[str, str]] = {
    "parallel": ("one spur stage: kinematics, gear geometry, mesh stiffness", PARALLEL),
    "planetary": ("one planetary stage: lumped model, modes, simulation", PLANETARY),
    "transmission": ("FE shaft lines with a spur stage and bearings (seed 002)", TRANSMISSION),
}


def render(name: str, file_name: str) -> str:
    """The TOML text of template ``name`` mentioning ``file_name`` in its usage lines."""
    return TEMPLATES[name][1].replace("{file}", file_name)
