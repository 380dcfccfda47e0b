"""Trends of measured records: ``geardyn trend CONFIG RECORDS… --store history.zarr``.

Each record (any format of :func:`geardyn.io.read_record`, mapped by the config's
``[measurement]`` section) gives its indicators per component (the diagnosis' feature
extraction, median over blocks); they are appended once to one Zarr store
(:mod:`geardyn.trend.store`), warning and alarm levels come from the first healthy records (or
simulated healthy runs) at stated false-alarm probabilities (:mod:`geardyn.trend.levels`), and
the first record crossing each level is named in a report (:mod:`geardyn.trend.report`).
docs/measured.md.
"""

from geardyn.trend.levels import Levels, judge_records, trend_levels
from geardyn.trend.run import expand_records, update_store
from geardyn.trend.store import TrendStore

__all__ = ["Levels", "TrendStore", "expand_records", "judge_records", "trend_levels",
           "update_store"]
