# ruff: noqa: E501 - TOML lines of the templates are kept whole
"""Starter configs written by ``geardyn init TEMPLATE``: commented TOML for four machines,
each with a dynamic model, ``[[sensors]]`` and ``[diagnosis]``, so that ``init`` →
``simulate`` → ``diagnose`` reaches a verdict as written (tests/test_cli_init.py):
``parallel`` (one spur stage, torsional-lateral model of docs/dynamics.md), ``planetary``
(lumped planetary model, Lin & Parker 1999), ``transmission`` (finite-element shaft lines and
bearings, Thibault et al. 2024) and ``differential`` (car differential, Penaud et al. 2012).
The simulated durations are short (about a second) so that a first diagnosis takes seconds.

Numbers are SI (the unit is in each field's name); any number may also be written as a string
with a unit, e.g. ``normal_module_m = "3 mm"`` or ``motor = "1500 rpm"``. The full reference of
the fields is docs/config.md (``python -m geardyn.config.reference``).
"""

from __future__ import annotations

PARALLEL = '''\
# geardyn starter config: one parallel-axis (spur) gear stage.
# Try:  geardyn kinematics {file}      (ratios and characteristic frequencies)
#       geardyn stiffness {file}       (geometry and mesh stiffness k(theta))
#       geardyn simulate {file} --out run.nc
#       geardyn diagnose {file} --out diagnosis   (healthy baseline, thresholds, verdict)
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
# 1470 rpm: a four-pole induction motor at its rated slip.
[input_speeds_rpm]
input = 1470.0                         # or "24.5 Hz"

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

# Optional faults (uncomment): a root crack on tooth 0 of the wheel. The dynamic model uses
# it once [[dynamics.meshes]] below says model = "gear_geometry".
# [[gear_geometry.cracks]]
# gear = "b"
# tooth = 0
# depth_m = "1 mm"
# angle_deg = 45.0

# Dynamic model (docs/dynamics.md): torsional plus lateral (x, y) motion of each shaft on its
# bearings (Lin & Parker 1999), so that an accelerometer on a bearing sees the mesh forces.
[dynamics]
module_m = 0.003
face_width_m = 0.025
lateral = true

[[dynamics.meshes]]
pair = "stage1"
model = "square"                       # k(t) square wave from the contact ratio; or "gear_geometry"

[[dynamics.links]]
link = "input"
inertia_kgm2 = 0.01                    # pinion, shaft and motor rotor
bearing_n_per_m = 1e8

[[dynamics.links]]
link = "output"
inertia_kgm2 = 0.05                    # wheel, shaft and load
bearing_n_per_m = 1e8

# Time simulation (Newmark): the motor holds 1470 rpm, the load brakes the output with 100 N m.
# 1 s = 24 input revolutions; longer runs give steadier indicators.
[dynamics.simulation]
t_end_s = 1.0
dt_s = 2e-5                            # well below the mesh period (1/760 Hz)
save_every = 2
initial_state = "static"               # start deflected by the load: no start transient
initial_speed_rpm = { input = 1470.0 }
speed_controls = [ { body = "input", profile_rpm = [[0.0, 1470.0], [10.0, 1470.0]], stiffness_nm_per_rad = 1e4, damping_nms_per_rad = 10.0 } ]
torques = [ { body = "output", torque_nm = -100.0 } ]

# Sensors (geardyn simulate writes their channels): an accelerometer on the output bearing
# (one housing mode at 3 kHz) and a once-per-revolution tacho on the input shaft.
[[sensors]]
name = "acc_output"
kind = "accelerometer"
location = "output"                    # the bearing of link "output"
sample_rate_hz = 20000.0
transfer_path = [ { frequency_hz = 3000.0, damping_ratio = 0.05, modal_mass_kg = 2.0 } ]
noise_rms = 0.05                       # m/s^2

[[sensors]]
name = "tacho_input"
kind = "tacho"
shaft = "input"

# geardyn diagnose: simulates the healthy machine (faults removed) over an ensemble of speeds,
# loads and sensor mountings, then this config, and judges every shaft, wheel and bearing.
[diagnosis]
channel = "acc_output"
skip_s = 0.2                           # start discarded (s)
'''

PLANETARY = '''\
# geardyn starter config: one planetary stage and its lumped-parameter model (Lin & Parker
# 1999; numbers of the back-to-back test bench of Hammami 2015, Table 3.1).
# Try:  geardyn kinematics {file}
#       geardyn modes {file}               (natural frequencies and mode types)
#       geardyn simulate {file} --out run.nc
#       geardyn diagnose {file} --out diagnosis   (healthy baseline, thresholds, verdict)
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

# 1470 rpm: a four-pole induction motor at its rated slip.
[input_speeds_rpm]
motor = 1470.0

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
# 1.2 s = 5.9 carrier revolutions; longer runs give steadier indicators.
[planetary_dynamics.simulation]
t_end_s = 1.2
dt_s = 2e-5
rayleigh_beta = 2e-6
initial_speed_rpm = { "sun" = 1470.0 }
torques = [ { body = "carrier", torque_nm = -100.0 } ]
# Speed-controlled motor: profile [[t_s, rpm], ...] with increasing times (a run-up works too,
# e.g. [[0.0, 1000.0], [1.2, 1500.0]]).
speed_controls = [ { body = "sun", profile_rpm = [[0.0, 1470.0], [10.0, 1470.0]], stiffness_nm_per_rad = 2e4, damping_nms_per_rad = 5.0 } ]
# Optional fault (uncomment, in [[planetary_dynamics.stages]] above): a 20 % crack on a sun
# tooth, faults = [ { kind = "crack", gear = "sun", crack_fraction = 0.2 } ]

# Sensors: an accelerometer on the ring (it sees each planet pass by) and a once-per-revolution
# tacho on the motor shaft.
[[sensors]]
name = "ring_acc"
kind = "accelerometer"
location = "ring"
sample_rate_hz = 20000.0
transfer_path = [ { frequency_hz = 3000.0, damping_ratio = 0.05, modal_mass_kg = 20.0 } ]
noise_rms = 0.01                       # m/s^2

[[sensors]]
name = "motor_tacho"
kind = "tacho"
shaft = "motor"

# geardyn diagnose: simulates the healthy stage over an ensemble of speeds, loads, pin errors
# and sensor mountings, then this config, and judges sun, ring, planets and shafts.
[diagnosis]
channel = "ring_acc"
skip_s = 0.2                           # start discarded (s)
'''

TRANSMISSION = '''\
# geardyn starter config: finite-element transmission (Thibault et al. 2024): two shaft lines,
# one spur stage, four rolling bearings, a speed law on the output.
# Try:  geardyn transmission {file} --modes-only
#       geardyn simulate {file} --out run.nc
#       geardyn diagnose {file} --out diagnosis   (healthy baseline, thresholds, verdict)
# Numbers are SI, the unit is in the field name; a string with a unit also works ("60 mm").
# Reference: docs/config.md.

name = "FE single stage"
frame = "housing"
links = ["housing", "input", "output"]

[[parallel]]
name = "stage"
a = { link = "input", teeth = 42 }
b = { link = "output", teeth = 55 }

# Input speed at the speed law's 400 rpm of the output: 400 × 55 / 42.
[input_speeds_rpm]
input = 523.8095238

# The output ball bearing, for its fault frequencies in the diagnosis.
[[bearings]]
name = "output ball"
kind = "ball"
inner = "output"
outer = "housing"
n_elements = 11
element_diameter_m = 0.0127
pitch_diameter_m = 0.080

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
# Imposed speed of a reference node: start -> end rpm over a number of revolutions (a run-up:
# start_rpm = 360.0, end_rpm = 430.0). 5 revolutions = 0.75 s at 400 rpm.
speed_law = { reference = { shaft = "output", node = 0 }, start_rpm = 400.0, end_rpm = 400.0, revolutions = 5.0 }
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
# Optional fault (uncomment, in the "output ball" entry above): an outer-race spall
# outer_spall = { angle_deg = 110.0, angular_length_deg = 10.9, depth_m = 100e-6 }

# Sensors: an accelerometer on the output ball-bearing housing (one housing mode at 3 kHz)
# and a once-per-revolution tacho on the output shaft.
[[sensors]]
name = "acc_output"
kind = "accelerometer"
location = "output ball"
direction = "y"
sample_rate_hz = 25000.0
transfer_path = [ { frequency_hz = 3000.0, damping_ratio = 0.05, modal_mass_kg = 2.0 } ]
noise_rms = 0.05                       # m/s^2

[[sensors]]
name = "tacho_output"
kind = "tacho"
shaft = "output"

# geardyn diagnose: simulates the healthy transmission over an ensemble of speeds, loads,
# bearing clearances and sensor mountings, then this config, and judges shafts, wheels and
# the output ball bearing.
[diagnosis]
channel = "acc_output"
skip_s = 0.1                           # start discarded (s)
blocks = 2                             # 5 revolutions: 2 blocks of 2 revolutions
'''

DIFFERENTIAL = '''\
# geardyn starter config: a car differential (Penaud, Alazard & Amiez 2012, Table 1): drive
# pinion, crown wheel on the cage, two planet pinions and two side gears. Two degrees of
# freedom: the speeds of both road wheels are given.
# Try:  geardyn kinematics {file}      (ratios at this operating point)
#       geardyn modes {file}           (natural frequencies of the torsional-lateral model)
#       geardyn simulate {file} --out run.nc
#       geardyn diagnose {file} --out diagnosis   (healthy baseline, thresholds, verdict)
# Numbers are SI, the unit is in the field name; a string with a unit also works ("5 mm").
# Reference: docs/config.md.

name = "Car differential"
frame = "housing"
links = ["housing", "drive_pinion", "left_wheel", "right_wheel", "pinion_a", "pinion_b", "cage"]

# Turning pairs by axis: 1 the wheel axis, 2 the planet pinions' pin (radial), 3 the drive shaft.
turning_pairs = [
    { links = ["housing", "left_wheel"], axis = 1 },
    { links = ["housing", "cage"], axis = 1 },
    { links = ["housing", "right_wheel"], axis = 1 },
    { links = ["pinion_a", "cage"], axis = 2 },
    { links = ["pinion_b", "cage"], axis = 2 },
    { links = ["housing", "drive_pinion"], axis = 3 },
]

# Gear pairs (bevel/hypoid) with the pitch angles of Penaud et al. 2012, Table 1 (deg).
[[gear_pairs]]
name = "2-7"
a = { link = "drive_pinion", teeth = 13, pitch_angle_deg = 0 }
b = { link = "cage", teeth = 65, pitch_angle_deg = 0 }

[[gear_pairs]]
name = "3-5"
a = { link = "left_wheel", teeth = 14, pitch_angle_deg = -45, wheel = "left_side_gear" }
b = { link = "pinion_a", teeth = 10, pitch_angle_deg = 45 }

[[gear_pairs]]
name = "3-6"
a = { link = "left_wheel", teeth = 14, pitch_angle_deg = 45, wheel = "left_side_gear" }
b = { link = "pinion_b", teeth = 10, pitch_angle_deg = -45 }

[[gear_pairs]]
name = "4-5"
a = { link = "right_wheel", teeth = 14, pitch_angle_deg = 45, wheel = "right_side_gear" }
b = { link = "pinion_a", teeth = 10, pitch_angle_deg = -45 }

[[gear_pairs]]
name = "4-6"
a = { link = "right_wheel", teeth = 14, pitch_angle_deg = -45, wheel = "right_side_gear" }
b = { link = "pinion_b", teeth = 10, pitch_angle_deg = 45 }

# The operating point: the car turns right at 30 km/h, wheels at 26 and 30 rad/s
# (Penaud et al. 2012, eq 8).
[input_speeds_rpm]
left_wheel = "26 rad/s"
right_wheel = "30 rad/s"

# Dynamic model (docs/dynamics.md): illustrative passenger-car values. Crown pair 13/65 with
# a 4.5 mm module, differential bevels 14/10 with a 5 mm mean module. Each side gear carries
# its road wheel, tyre and half shaft: 1.2 kg m^2; the propeller shaft seen by the pinion:
# 0.05 kg m^2. Mesh stiffness c_gamma b (ISO 6336-1), damping ratio 0.05. Lateral motion of
# the cage on its bearings, so that an accelerometer there sees the mesh forces.
[dynamics]
module_m = 0.005
face_width_m = 0.020
lateral = true

[[dynamics.meshes]]
pair = "2-7"
module_m = 0.0045
face_width_m = 0.030
model = "square"

[[dynamics.links]]
link = "left_wheel"
inertia_kgm2 = 1.2

[[dynamics.links]]
link = "right_wheel"
inertia_kgm2 = 1.2

[[dynamics.links]]
link = "drive_pinion"
inertia_kgm2 = 0.05

[[dynamics.links]]
link = "cage"
bearing_n_per_m = 5e8                  # cage bearings, lateral stiffness

# The road imposes both wheel speeds (tyre grip as a stiff speed control); the engine drives
# the pinion with 200 N m. 2 s = 9 cage revolutions.
[dynamics.simulation]
t_end_s = 2.0
dt_s = 2e-5
save_every = 5
initial_speed_rpm = { left_wheel = "26 rad/s", right_wheel = "30 rad/s" }
speed_controls = [
    { body = "left_wheel", profile_rpm = [[0.0, 248.2817112], [100.0, 248.2817112]], stiffness_nm_per_rad = 1e5, damping_nms_per_rad = 1e3 },
    { body = "right_wheel", profile_rpm = [[0.0, 286.4788976], [100.0, 286.4788976]], stiffness_nm_per_rad = 1e5, damping_nms_per_rad = 1e3 },
]
torques = [ { body = "drive_pinion", torque_nm = -200.0 } ]

# Sensors: an accelerometer on the cage bearing and a once-per-revolution tacho on the drive
# pinion's shaft.
[[sensors]]
name = "acc_cage"
kind = "accelerometer"
location = "cage"                      # the bearing of link "cage"
sample_rate_hz = 10000.0
transfer_path = [ { frequency_hz = 2000.0, damping_ratio = 0.05, modal_mass_kg = 5.0 } ]
noise_rms = 0.01                       # m/s^2

[[sensors]]
name = "tacho_pinion"
kind = "tacho"
shaft = "drive_pinion"

# geardyn diagnose: simulates the healthy differential over an ensemble of speeds, loads and
# sensor mountings, then this config, and judges shafts and wheels.
[diagnosis]
channel = "acc_cage"
skip_s = 0.2                           # start discarded (s)
'''

#: template name → (one-line description, TOML text with ``{file}`` for the written file name).
TEMPLATES: dict[str, tuple[str, str]] = {
    "parallel": ("one spur stage: mesh stiffness, dynamics, diagnosis", PARALLEL),
    "planetary": ("one planetary stage: lumped model, modes, simulation, diagnosis", PLANETARY),
    "transmission": ("FE shaft lines with a spur stage and bearings", TRANSMISSION),
    "differential": ("car differential: two degrees of freedom, bevel gears", DIFFERENTIAL),
}


def render(name: str, file_name: str) -> str:
    """The TOML text of template ``name`` mentioning ``file_name`` in its usage lines."""
    return TEMPLATES[name][1].replace("{file}", file_name)
