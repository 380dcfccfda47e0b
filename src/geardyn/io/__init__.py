"""Reading measured records: one entry point, :func:`read_record`, for every format.

A file (CSV/TSV, WAV/FLAC, NPY/NPZ, MAT v5/v7.3, TDMS, UFF 58/58b, MDF4, HDF5, NetCDF) and
the config's ``[measurement]`` channel mapping give an :class:`xarray.Dataset` in the result
layout of docs/results.md, with units: what ``geardyn analyze`` and ``geardyn diagnose`` read
for simulated runs. :func:`read_raw` gives the file's channels as they are. docs/measured.md.
"""

from geardyn.io.raw import RawChannel, RawRecord, read_raw
from geardyn.io.record import RecordWarning, read_record

__all__ = ["RawChannel", "RawRecord", "RecordWarning", "read_raw", "read_record"]
