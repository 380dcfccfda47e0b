"""Rolling-element bearings: characteristic frequencies (and, later, force models)."""

from geardyn.bearings.frequencies import BearingFrequencies, bearing_frequencies

__all__ = ["BearingFrequencies", "bearing_frequencies"]
