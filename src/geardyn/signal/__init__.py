"""Signal processing for diagnosis: angular resampling, spectra, TSA, cepstrum, envelope,
wavelets, condition indicators, GTDT transfer path analysis and spectrum annotation.

Plain functions: arrays in, arrays / ``xarray.DataArray`` out; SI units (s, Hz, rad, rad/s) or
orders (events per revolution) as documented per function.
"""

from geardyn.signal.annotate import annotate_axes, spectral_markers
from geardyn.signal.cepstrum import power_cepstrum, real_cepstrum
from geardyn.signal.envelope import envelope, envelope_spectrum
from geardyn.signal.indicators import (
    crest_factor,
    energy_ratio,
    fm0,
    fm4,
    gear_indicators,
    kurtosis,
    m6a,
    m8a,
    na4,
    nb4,
    peak,
    rms,
    sideband_level_factor,
    signal_indicators,
    skewness,
)
from geardyn.signal.resample import (
    AngleSignal,
    angle_from_pulses,
    angle_from_speed,
    distant_shaft,
    link_ratio,
    lowpass,
    resample_ias_to_angle,
    resample_to_angle,
    speed_from_angle,
    speed_from_pulses,
)
from geardyn.signal.spectra import (
    amplitude_spectrum,
    angular_spectrogram,
    order_spectrum,
    order_speed_map,
    psd,
    stft,
)
from geardyn.signal.tpa import (
    GTDT,
    external_responses,
    frf_from_mck,
    gtdt,
    path_contributions,
    reconstruct,
)
from geardyn.signal.tsa import (
    difference_signal,
    planetary_tsa,
    regular_signal,
    residual_signal,
    tsa,
    tsa_from_tacho,
)
from geardyn.signal.wavelet import cwt_morlet

__all__ = [
    "GTDT",
    "AngleSignal",
    "amplitude_spectrum",
    "angle_from_pulses",
    "angle_from_speed",
    "angular_spectrogram",
    "annotate_axes",
    "crest_factor",
    "cwt_morlet",
    "difference_signal",
    "distant_shaft",
    "energy_ratio",
    "envelope",
    "envelope_spectrum",
    "external_responses",
    "fm0",
    "fm4",
    "frf_from_mck",
    "gear_indicators",
    "gtdt",
    "kurtosis",
    "link_ratio",
    "lowpass",
    "m6a",
    "m8a",
    "na4",
    "nb4",
    "order_spectrum",
    "order_speed_map",
    "path_contributions",
    "peak",
    "planetary_tsa",
    "power_cepstrum",
    "psd",
    "real_cepstrum",
    "reconstruct",
    "regular_signal",
    "resample_ias_to_angle",
    "resample_to_angle",
    "residual_signal",
    "rms",
    "sideband_level_factor",
    "signal_indicators",
    "skewness",
    "spectral_markers",
    "speed_from_angle",
    "speed_from_pulses",
    "stft",
    "tsa",
    "tsa_from_tacho",
]
