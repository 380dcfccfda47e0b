"""Diagnosis: machine components from kinematics, features and condition indicators per
component, healthy baselines, thresholds, verdicts and the HTML report.

``diagnose(cfg, out_dir)`` runs the whole chain (docs/diagnosis.md); the pieces are
:func:`healthy_variant` / :func:`fault_list` (faults of a config), :func:`thresholds` with a
:class:`ThresholdRule` (baseline), :func:`judge` → :class:`Verdict` and :func:`write_report`.
"""

from geardyn.diagnosis.baseline import ThresholdRule, thresholds
from geardyn.diagnosis.faults import ConfiguredFault, fault_list, healthy_variant
from geardyn.diagnosis.pipeline import diagnose, diagnose_files
from geardyn.diagnosis.report import write_report
from geardyn.diagnosis.verdict import Verdict, judge, read_verdict

__all__ = [
    "ConfiguredFault",
    "ThresholdRule",
    "Verdict",
    "diagnose",
    "diagnose_files",
    "fault_list",
    "healthy_variant",
    "judge",
    "read_verdict",
    "thresholds",
    "write_report",
]
