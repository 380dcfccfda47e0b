"""Measurement simulation: encoder/IAS (elapsed time), tacho, accelerometer, planet pass."""

from geardyn.sensors.accelerometer import accelerometer, adc_quantise
from geardyn.sensors.encoder import (
    IASMeasurement,
    elapsed_time_ias,
    pulse_times_from_angle,
    quantisation_bound,
    quantise_clock,
    simulate_ias,
    tacho_pulse_times,
)
from geardyn.sensors.planet_pass import dominant_carrier_orders, planet_pass_signal

__all__ = [
    "IASMeasurement",
    "accelerometer",
    "adc_quantise",
    "dominant_carrier_orders",
    "elapsed_time_ias",
    "planet_pass_signal",
    "pulse_times_from_angle",
    "quantisation_bound",
    "quantise_clock",
    "simulate_ias",
    "tacho_pulse_times",
]
