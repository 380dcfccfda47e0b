"""Studies over many simulated machines: the detectability study of the diagnosis (issue 18).

:mod:`geardyn.studies.runner` diagnoses the records of many machine configurations (each with
its own baseline ensemble) on Dask; :mod:`geardyn.studies.detectability` is the study's design,
its statistics and the page it writes (docs/detectability.md).
"""
