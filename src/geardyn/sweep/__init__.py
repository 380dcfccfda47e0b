"""Parameter sweeps and fault data sets on ``dask.distributed`` (docs/sweeps.md).

- :func:`load_spec` reads and checks a sweep spec (TOML): base config, axes, outputs.
- :func:`run` runs it on a LocalCluster or an existing cluster into a Zarr store; re-running
  resumes.
- :func:`open_dataset` opens the store as an xarray data set (one ``case`` dimension);
  :func:`verify` names the stored cases whose data no longer match their checksums.
- :func:`plot_detectability` draws an indicator against fault severity with error bars.
"""

from geardyn.sweep.plot import detectability, plot_detectability
from geardyn.sweep.runner import SweepProgress, SweepSummary, run
from geardyn.sweep.spec import Sweep, SweepSpec, case_seed, from_dict, load_spec
from geardyn.sweep.store import open_dataset, verify

__all__ = [
    "Sweep",
    "SweepProgress",
    "SweepSpec",
    "SweepSummary",
    "case_seed",
    "detectability",
    "from_dict",
    "load_spec",
    "open_dataset",
    "plot_detectability",
    "run",
    "verify",
]
