"""Studies over many simulated machines: the detectability study of the diagnosis (issue 18).

:mod:`geardyn.studies.detectability` is the study's design, its statistics and the page it
writes (docs/detectability.md); :mod:`geardyn.studies.sweeps` turns its configurations into
``geardyn sweep`` specs (``[outputs.diagnosis]``: each record judged against the baseline
ensemble of its own healthy config) and reads the stores back into rows.
:mod:`geardyn.studies.runner` holds the configuration and record types and the earlier
runner (one Dask task per configuration, rows in ``OUT/rows``).
"""
